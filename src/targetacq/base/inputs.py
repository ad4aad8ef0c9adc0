"""Reading the user's input files: scenarios, CSV files (boxes, MRTD curves, terrain maps), images.

The counterpart of :mod:`targetacq.io.files`. Every input file is checked before it is opened
(:func:`input_file`): it exists, is a regular file this process may read (not a folder, a
device or a fifo, which could block for ever or never end) and, for text, is at most
:data:`targetacq.base.limits.MAX_INPUT_BYTES`, so that a wrong path (a video, ``/dev/zero``) is
refused with one line naming it instead of being read into memory. Text is UTF-8, with or
without the byte-order mark spreadsheets write (:func:`read_input_text`).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from targetacq.base.limits import MAX_INPUT_BYTES

__all__ = ["input_file", "read_input_text"]


def input_file(path: str | Path, what: str, limit: int | None = MAX_INPUT_BYTES) -> Path:
    """``path`` if it is a regular file this process may read, else ``ValueError`` saying what
    it is instead (missing, a directory, a device or fifo, unreadable, too large).

    A fifo or a device is refused before it is opened: reading one could block for ever.

    Parameters
    ----------
    path : str or Path
    what : str
        What the file should be, for the message (e.g. ``"scenario file"``).
    limit : int or None, optional
        Largest size [bytes], :data:`targetacq.base.limits.MAX_INPUT_BYTES` by default; ``None``
        for no limit (an image, whose reader guards its own size).

    Examples
    --------
    >>> input_file("/dev/null", "scenario file")
    Traceback (most recent call last):
    ...
    ValueError: /dev/null: not a regular file (a device, a fifo or a socket), so not a scenario file
    """
    source = Path(path)
    try:
        info = source.stat()
    except (FileNotFoundError, NotADirectoryError):
        raise ValueError(f"no {what} {str(source)!r} (no such file)") from None
    except OSError as error:
        raise ValueError(f"{source}: cannot read the {what}: {error.strerror}") from None
    if stat.S_ISDIR(info.st_mode):
        raise ValueError(f"{source}: is a directory, not a {what}")
    if not stat.S_ISREG(info.st_mode):
        raise ValueError(
            f"{source}: not a regular file (a device, a fifo or a socket), so not a {what}"
        )
    if not os.access(source, os.R_OK):
        raise ValueError(f"{source}: cannot read the {what}: permission denied")
    if limit is not None and info.st_size > limit:
        raise ValueError(
            f"{source}: {what}s are limited to {limit / 1e6:g} MB; got {info.st_size / 1e6:.1f} MB"
        )
    return source


def read_input_text(path: str | Path, what: str) -> str:
    """The text of a user's input file (UTF-8, a byte-order mark allowed), checked first
    (:func:`input_file`, at most :data:`targetacq.base.limits.MAX_INPUT_BYTES`).

    Parameters
    ----------
    path : str or Path
        The file.
    what : str
        What the file should be, for the messages (e.g. ``"MRTD curve"``).

    Returns
    -------
    str
        Its text, without a leading UTF-8 byte-order mark (spreadsheets write one).

    Raises
    ------
    ValueError
        One line naming the file and why it cannot be read.

    Examples
    --------
    >>> read_input_text("/dev/null", "box file")
    Traceback (most recent call last):
    ...
    ValueError: /dev/null: not a regular file (a device, a fifo or a socket), so not a box file
    """
    limit = MAX_INPUT_BYTES
    source = input_file(path, what, limit)
    try:
        with source.open("rb") as handle:
            data = handle.read(limit + 1)
    except OSError as error:
        raise ValueError(f"{source}: cannot read the {what}: {error.strerror}") from None
    if len(data) > limit:  # it grew since it was looked at
        raise ValueError(f"{source}: {what}s are limited to {limit / 1e6:g} MB")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise ValueError(
            f"{source}: not UTF-8 text (byte {error.start + 1} is {data[error.start]:#04x}), so "
            f"not a {what}"
        ) from None
