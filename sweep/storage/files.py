"""File-system helpers of the result storage: one-line errors, atomic replacement."""

from __future__ import annotations

import os
from pathlib import Path

from sweep.errors import RunError


def file_error(exc: OSError, doing: str) -> RunError:
    """One line for a file-system failure: what was being done, the file, the cause, what to do."""
    where = f": {exc.filename}" if exc.filename else ""
    hint = {28: "free some space", 13: "choose a writable directory with -o",
            30: "choose a writable directory with -o"}.get(exc.errno, "check the path")
    return RunError(f"{doing}{where}: {exc.strerror or exc}; {hint}, then run again "
                    "(with --resume to keep what is done)")


def replace_atomically(path: Path, write) -> None:
    """Call ``write(tmp_path)`` then rename the temporary file to ``path``."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
