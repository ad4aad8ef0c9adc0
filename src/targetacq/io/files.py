"""Writing result files and JSON text.

Files
-----
The output path is checked before any work (:func:`output_path`), and the file appears whole or
not at all (:func:`write_atomically`): it is written to a temporary file in the target's folder,
then renamed onto the target.

- **Failures.** Any failure to write (a folder as the output, a read-only folder, a full file
  system, a file-size limit) raises :class:`OutputError`, a ``ValueError`` whose one-line message
  names the path and the reason: ``cannot write 'out.csv': No space left on device``.
- **Temporary files.** Named ``.NAME.targetacq-tmp-HOST-PID-RANDOM.SUFFIX`` next to the target
  (hidden, recognisable), and removed on any exception, including the ``SystemExit`` the command
  line raises on SIGTERM. A process killed outright (SIGKILL, power loss) cannot clean up: its
  temporaries are removed by the next write of the same target on the same machine, once their
  process no longer runs.
- **Permissions.** A new file gets the mode the umask gives any new file (``0o666 & ~umask``,
  e.g. 0644 under umask 022). A replaced file keeps its permission bits (not its owner or group:
  the new file belongs to whoever writes it), as ``cp`` onto an existing file would.
- **Symbolic links.** A link at the output path is written through: the link stays, and its
  target is replaced atomically (the temporary file is created next to the target). A folder,
  a device, a pipe or a socket at the path (or at the link's end) is refused, not replaced.
- **Folders.** An output that is a folder (a Zarr store) is written to a temporary folder
  next to the target (mode ``0o777`` less the umask) and renamed onto it
  (:func:`write_directory_atomically`); a previous store there is renamed aside first and then
  removed. A folder that is not a Zarr store is refused, not replaced.

JSON
----
JSON has no infinity and no NaN, and Python's ``json`` would write the invalid literals
``Infinity`` and ``NaN``. Every JSON output of targetacq (the command line's ``--format json``
and ``.json`` result files) goes through :func:`json_text`: NaN (no value, e.g. outside the
model's domain) becomes ``null``, +inf becomes the string ``"inf"`` and -inf ``"-inf"`` (e.g. a
first-detection time never reached), so the output is strict JSON and an infinity is never
mistaken for a missing value.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import secrets
import shutil
import socket
import stat
import zlib
from collections.abc import Callable, Collection, Mapping
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "OutputError",
    "json_records",
    "json_text",
    "json_value",
    "output_path",
    "write_atomically",
    "write_directory_atomically",
]


class OutputError(ValueError):
    """An output file cannot be written; the message names the file and the reason."""

    def __init__(self, path: str | os.PathLike[str], reason: str) -> None:
        super().__init__(f"cannot write {str(path)!r}: {reason}")


def output_path(
    path: str | Path, formats: Collection[str], what: str, *, directories: Collection[str] = ()
) -> tuple[Path, str]:
    """Check an output file name before any work: its suffix is one of ``formats``, it is not a
    folder (unless its format is one of ``directories``, written as a folder, and the folder
    there is a previous output of that format: a Zarr store), and its folder exists and is
    writable.

    Returns
    -------
    path, format : (Path, str)
        The path and its format (the suffix without the dot, lower case).

    Raises
    ------
    ValueError
        Naming the file and what it should end in, or (:class:`OutputError`) why it cannot be
        written.
    """
    out = Path(path)
    kind = out.suffix.lower().lstrip(".")
    if kind not in formats:
        names = [f".{f}" for f in formats]
        allowed = names[0] if len(names) == 1 else f"{', '.join(names[:-1])} or {names[-1]}"
        raise ValueError(f"{what} must end in {allowed}; got {str(out)!r}")
    target = _resolved(out)
    if kind in directories:
        _check_replaceable_folder(out, target)
    else:
        _check_replaceable(out, target)
    if not target.parent.is_dir():
        raise ValueError(f"the folder of {str(out)!r} does not exist")
    if not os.access(target.parent, os.W_OK | os.X_OK):
        raise OutputError(out, "its folder is not writable")
    return out, kind


def write_atomically(out: Path, write: Callable[[Path], object]) -> Path:
    """Call ``write(temporary_path)``, then rename the temporary file onto ``out``.

    See the module docstring for the temporary file's name, its permissions and symbolic links.

    Parameters
    ----------
    out : Path
        The file to write (a symbolic link is written through).
    write : callable
        Writes the whole content to the path it is given.

    Returns
    -------
    Path
        ``out``.

    Raises
    ------
    OutputError
        If the file cannot be written (any ``OSError``); nothing is left behind.
    """
    target = _resolved(out)
    _check_replaceable(out, target)
    _remove_stale_temporaries(target)
    temporary = target.with_name(f"{_temporary_prefix(target)}{os.getpid()}-{_random()}")
    temporary = temporary.with_name(temporary.name + _short_suffix(target))
    try:
        # 0o666 and the kernel applies the umask, as for any new file (mkstemp would give 0600).
        flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
        os.close(os.open(temporary, flags, 0o666))
        write(temporary)
        existing_mode = _permission_bits(target)
        if existing_mode is not None:
            os.chmod(temporary, existing_mode)
        os.replace(temporary, target)
    except BaseException as error:
        temporary.unlink(missing_ok=True)
        if isinstance(error, OSError):
            raise OutputError(out, _reason(error)) from error
        raise
    return out


def write_directory_atomically(out: Path, write: Callable[[Path], object]) -> Path:
    """Call ``write(temporary_folder)``, then rename the folder onto ``out`` (a Zarr store).

    The temporary folder is made next to the target with mode ``0o777`` less the umask (0755
    under umask 022), as ``mkdir`` would, and the files in it get the umask's mode too. A
    previous store at ``out`` is renamed aside, the new one renamed in, and the old one removed:
    a reader sees the old store or the new one, never half of one.

    Raises
    ------
    OutputError
        If the folder cannot be written (any ``OSError``); nothing is left behind.

    Examples
    --------
    >>> import tempfile
    >>> store = Path(tempfile.mkdtemp()) / "s.zarr"
    >>> _ = write_directory_atomically(store, lambda p: (p / ".zgroup").write_text("{}"))
    >>> sorted(q.name for q in store.iterdir())
    ['.zgroup']
    """
    target = _resolved(out)
    _check_replaceable_folder(out, target)
    _remove_stale_temporaries(target)
    temporary = target.with_name(f"{_temporary_prefix(target)}{os.getpid()}-{_random()}")
    old = None
    try:
        os.mkdir(temporary, 0o777)
        write(temporary)
        if target.is_dir():
            old = target.with_name(f"{_temporary_prefix(target)}{os.getpid()}-{_random()}")
            os.rename(target, old)
        os.rename(temporary, target)
    except BaseException as error:
        shutil.rmtree(temporary, ignore_errors=True)
        if old is not None and not target.exists():
            os.rename(old, target)
            old = None
        if isinstance(error, OSError):
            raise OutputError(out, _reason(error)) from error
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    return out


def json_value(value: Any) -> Any:
    """``value`` with every non-finite number spelled for strict JSON, recursively.

    NaN → ``None`` (``null``), +inf → ``"inf"``, -inf → ``"-inf"``; NumPy scalars and arrays
    become Python numbers and lists; mappings, lists and tuples are converted element by element.

    Examples
    --------
    >>> json_value({"t50_s": float("inf"), "p": [0.5, float("nan")]})
    {'t50_s': 'inf', 'p': [0.5, None]}
    """
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, float | np.floating):
        number = float(value)
        if math.isfinite(number):
            return number
        return None if math.isnan(number) else ("inf" if number > 0 else "-inf")
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.ndarray):
        return json_value(value.tolist())
    if isinstance(value, Mapping):
        return {key: json_value(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [json_value(item) for item in value]
    return value


def json_text(document: Any, indent: int | None = 2) -> str:
    """``document`` as strict JSON text (no trailing newline), non-finite numbers spelled as in
    :func:`json_value`.

    Examples
    --------
    >>> json_text({"range_m": float("inf"), "snr_db": float("-inf"), "p": float("nan")}, None)
    '{"range_m": "inf", "snr_db": "-inf", "p": null}'
    """
    return json.dumps(json_value(document), indent=indent, allow_nan=False)


def json_records(frame: Any, indent: int = 1) -> str:
    """A pandas DataFrame as strict JSON text: a list of one object per row, non-finite numbers
    spelled as in :func:`json_value`.

    Written by pandas' fast encoder (15 significant digits); only the columns that hold an
    infinity go through :func:`json_value`, element by element.

    Examples
    --------
    >>> import pandas as pd
    >>> json_records(pd.DataFrame({"t50_s": [12.5, float("inf"), float("nan")]}), indent=0)
    '[{"t50_s":12.5},{"t50_s":"inf"},{"t50_s":null}]'
    """
    spelled = frame.copy(deep=False)
    for name in frame.columns:
        column = frame[name]
        floats = column.dtype.kind == "f"
        if floats and np.isinf(column.to_numpy(dtype=float, na_value=np.nan)).any():
            spelled[name] = column.map(json_value).astype(object)
    # pandas writes NaN as null and never the literals NaN or Infinity: the text is strict JSON.
    return str(spelled.to_json(orient="records", indent=indent, double_precision=15))


_TEMPORARY_MARK = ".targetacq-tmp-"
# Temporaries are told apart by the machine that writes them, so that a folder shared over the
# network never loses another machine's write in progress to a stale-file cleanup.
_HOST = f"{zlib.crc32(socket.gethostname().encode()):08x}"
_NAME_BYTES = 80  # of the target's name kept in a temporary's name (file names are ≤ 255 bytes)


def _resolved(out: Path) -> Path:
    """``out``, or the file a symbolic link at ``out`` points to (links followed to the end)."""
    return Path(os.path.realpath(out)) if out.is_symlink() else out


def _check_replaceable(out: Path, target: Path) -> None:
    """Refuse a folder, and a device, pipe or socket, which a rename would replace (not fill)."""
    try:
        mode = os.stat(target).st_mode
    except OSError:
        return  # no such file yet (or an unreadable one: the write reports it)
    if stat.S_ISDIR(mode):
        raise OutputError(out, "it is a folder")
    if not stat.S_ISREG(mode):
        raise OutputError(out, "it is not a regular file (a device, a pipe or a socket)")


def _check_replaceable_folder(out: Path, target: Path) -> None:
    """Refuse a file, or a folder that is not a Zarr store, at a folder output's path."""
    try:
        mode = os.stat(target).st_mode
    except OSError:
        return
    if not stat.S_ISDIR(mode):
        raise OutputError(out, "it exists and is not a folder")
    if not any((target / name).exists() for name in (".zgroup", "zarr.json")):
        raise OutputError(out, "it is a folder that is not a Zarr store")


def _temporary_prefix(target: Path) -> str:
    name = os.fsdecode(os.fsencode(target.name)[:_NAME_BYTES])
    return f".{name}{_TEMPORARY_MARK}{_HOST}-"


def _short_suffix(target: Path) -> str:
    # Writers that infer a format or a compression from the suffix see the target's.
    return target.suffix if len(target.suffix) <= 16 else ""


def _random() -> str:
    return secrets.token_hex(4)


def _permission_bits(path: Path) -> int | None:
    try:
        return stat.S_IMODE(os.stat(path).st_mode) & 0o777
    except FileNotFoundError:
        return None


def _reason(error: OSError) -> str:
    return error.strerror or str(error) or type(error).__name__


def _remove_stale_temporaries(target: Path) -> None:
    """Remove this machine's temporaries of ``target`` whose writing process no longer runs."""
    prefix = _temporary_prefix(target)
    try:
        entries = list(os.scandir(target.parent))
    except OSError:
        return  # the write itself will report the folder's problem
    for entry in entries:
        if not entry.name.startswith(prefix):
            continue
        pid = entry.name[len(prefix) :].partition("-")[0]
        if pid.isdigit() and not _running(int(pid)):
            # Another run may be cleaning up too; the write itself reports a folder's problem.
            with contextlib.suppress(OSError):
                if entry.is_dir(follow_symlinks=False):
                    shutil.rmtree(entry.path)
                else:
                    Path(entry.path).unlink(missing_ok=True)


def _running(pid: int) -> bool:
    if os.name != "posix":
        return True  # os.kill(pid, 0) would end the process on Windows: never clean up there
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True  # another user's process, or not a pid of ours to judge
    return True
