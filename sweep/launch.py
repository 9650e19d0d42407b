"""Locating the MPI launcher that belongs to this Python environment."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path


def find_mpiexec() -> str | None:
    """Path of ``mpiexec``: next to the running Python (the ``mpich`` wheel puts it in the
    environment's ``bin``), else the first on ``PATH``; None when there is none."""
    local = Path(sys.executable).with_name("mpiexec")
    return str(local) if local.exists() else shutil.which("mpiexec")
