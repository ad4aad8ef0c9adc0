"""Writing result files: the output path is checked before any work, and the file appears whole
or not at all (written to a temporary file in the same folder, then renamed)."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

__all__ = ["output_path", "write_atomically"]


def output_path(path: str | Path, formats: Sequence[str], what: str) -> tuple[Path, str]:
    """Check an output file name: its suffix is one of ``formats`` and its folder exists.

    Returns
    -------
    path, format : (Path, str)
        The path and its format (the suffix without the dot, lower case).

    Raises
    ------
    ValueError
        Naming the file, what it should end in, or its missing folder.
    """
    out = Path(path)
    kind = out.suffix.lower().lstrip(".")
    if kind not in formats:
        names = [f".{f}" for f in formats]
        allowed = names[0] if len(names) == 1 else f"{', '.join(names[:-1])} or {names[-1]}"
        raise ValueError(f"{what} must end in {allowed}; got {str(out)!r}")
    if not out.parent.is_dir():
        raise ValueError(f"the folder of {str(out)!r} does not exist")
    return out, kind


def write_atomically(out: Path, write: Callable[[Path], object]) -> Path:
    """Call ``write(temporary_path)``, then rename the temporary file to ``out``.

    A failure leaves no partial file behind.
    """
    handle, temporary = tempfile.mkstemp(dir=out.parent, prefix=".", suffix=out.suffix)
    os.close(handle)
    try:
        write(Path(temporary))
        os.replace(temporary, out)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return out
