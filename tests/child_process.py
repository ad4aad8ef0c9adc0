"""Starting the command in a child process under a limit, for the tests of every folder."""

from __future__ import annotations

import sys

# Sets a file-size limit, then becomes the command: a preexec_fn would fork a process that has
# imported JAX (multithreaded), which warns, and the warning is an error under pytest -W error.
# Python ignores SIGXFSZ (and the exec keeps it ignored), so a write past the limit fails with
# EFBIG instead of killing the process.
LIMIT_FILE_SIZE_THEN_RUN = (
    "import os, resource, sys; limit = int(sys.argv[1]); "
    "resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit)); "
    "os.execv(sys.executable, [sys.executable, *sys.argv[2:]])"
)


def file_size_limited(command: list[str], limit: int) -> list[str]:
    """``command`` (a ``python`` command line: ``[sys.executable, ...]``) run under a limit of
    ``limit`` bytes per file written."""
    return [sys.executable, "-c", LIMIT_FILE_SIZE_THEN_RUN, str(limit), *command[1:]]
