"""Compile the C reference programs of the benchmarks (``benchmarks/c/``).

The benchmarks compare the project's kernels with C programs of the same algorithms,
compiled here with the system compiler and ``-O3 -march=native`` (the hardware limit);
without a compiler the C variants are skipped with a message.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

SOURCES = Path(__file__).resolve().parent / "c"


def compile_reference(name: str, workdir: Path, flags: tuple[str, ...] = ()) -> Path | None:
    """``benchmarks/c/<name>.c`` compiled into ``workdir`` with ``-O3 -march=native`` and
    ``flags``; None, with a message printed, when there is no C compiler (``$CC``, ``cc``
    or ``gcc``) or it fails."""
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        print("C reference skipped: no C compiler (cc, gcc or $CC) found")
        return None
    exe = workdir / name
    proc = subprocess.run([cc, "-O3", "-march=native", *flags, "-o", str(exe), str(SOURCES / f"{name}.c"), "-lm"],
                          capture_output=True, text=True)
    if proc.returncode:
        print(f"C reference skipped: {cc} failed:\n{proc.stderr}")
        return None
    return exe
