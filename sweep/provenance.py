"""What produced a result: package version, source hash, git commit, library versions.

A run records :func:`provenance` in its manifest and its NetCDF file.  ``--resume`` compares
the recorded provenance with the running code (:func:`differences`) and refuses a change
of the source or of a library that enters the numbers, so that one result file never
mixes tasks computed by two versions of the code.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import inspect
import platform
import subprocess
from pathlib import Path

#: Root of the source tree: the directory holding ``model/`` and ``sweep/``.
ROOT = Path(__file__).resolve().parents[1]
#: Libraries whose version changes the numbers a task computes (a resume compares them).
NUMERIC_LIBRARIES = ("numpy", "scipy", "numba")
#: Libraries recorded for the record only.
OTHER_LIBRARIES = ("mpi4py", "h5py", "netCDF4", "xarray")


def package_version() -> str:
    """Installed version of the ``membrane-sweep`` distribution."""
    try:
        return importlib.metadata.version("membrane-sweep")
    except importlib.metadata.PackageNotFoundError:
        return "unknown (not installed)"


def source_files(analysis=None) -> list[Path]:
    """The Python sources of ``model/`` and ``sweep/``, and the module of ``analysis`` when it
    lives elsewhere (an analysis registered through ``SWEEP_EXTRA_ANALYSES``)."""
    files = sorted([*(ROOT / "model").rglob("*.py"), *(ROOT / "sweep").rglob("*.py")])
    if analysis is not None:
        # a mode-set sweep (sweep.analyses.mode_sets) wraps the analysis that matters
        extra = Path(inspect.getfile(type(getattr(analysis, "inner", analysis)))).resolve()
        if extra not in files:
            files.append(extra)
    return files


def source_sha256(analysis=None) -> str:
    """SHA-256 over the relative paths and contents of :func:`source_files`."""
    digest = hashlib.sha256()
    for path in source_files(analysis):
        name = path.relative_to(ROOT) if path.is_relative_to(ROOT) else Path(path.name)
        digest.update(str(name).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def git_commit() -> str | None:
    """``HEAD`` of the checkout the sources run from (``-dirty`` when ``model/`` or
    ``sweep/`` differ from it), or None outside a git checkout."""
    if not (ROOT / ".git").exists():
        return None
    try:
        head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True,
                              text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--", "model", "sweep"],
                               capture_output=True, text=True, timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return head + ("-dirty" if dirty else "")


def library_versions() -> dict[str, str]:
    """Versions of Python, the numerical libraries, MPI and the I/O libraries."""
    versions = {"python": platform.python_version()}
    for name in (*NUMERIC_LIBRARIES, *OTHER_LIBRARIES):
        try:
            versions[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            versions[name] = "not installed"
    try:
        from mpi4py import MPI

        versions["MPI"] = MPI.Get_library_version().strip().splitlines()[0]
    except Exception:  # noqa: BLE001 - an MPI that cannot say is recorded as such
        versions["MPI"] = "unknown"
    return versions


def provenance(analysis=None) -> dict:
    """Everything :mod:`sweep.storage` records about the code of a run (JSON-able)."""
    return {"package_version": package_version(), "source_sha256": source_sha256(analysis),
            "git_commit": git_commit(), "versions": library_versions()}


def differences(recorded: dict, current: dict) -> list[str]:
    """What differs between two provenances in a way that changes the numbers.

    Returns
    -------
    list of str
        ``"source sha256 1a2b3c4d5e6f -> 7a8b9c0d1e2f"``, ``"numba 0.60.0 -> 0.61.0"``, ...;
        empty when a resume may go on.
    """
    out = []
    if recorded.get("source_sha256") != current["source_sha256"]:
        out.append(f"source sha256 {str(recorded.get('source_sha256'))[:12]} -> "
                   f"{current['source_sha256'][:12]} (model/ or sweep/ changed"
                   + (f"; git {recorded.get('git_commit')} -> {current['git_commit']}"
                      if recorded.get("git_commit") != current["git_commit"] else "") + ")")
    old, new = recorded.get("versions", {}), current["versions"]
    for name in ("python", *NUMERIC_LIBRARIES):
        if old.get(name) != new[name]:
            out.append(f"{name} {old.get(name)} -> {new[name]}")
    return out


def describe(record: dict) -> str:
    """One line: ``membrane-sweep 0.1.0, source sha256 1a2b3c4d5e6f, git abc123, numpy 2.4``."""
    v = record["versions"]
    git = f", git {record['git_commit']}" if record.get("git_commit") else ""
    libs = ", ".join(f"{name} {v[name]}" for name in ("python", *NUMERIC_LIBRARIES))
    return f"membrane-sweep {record['package_version']}, source sha256 {record['source_sha256'][:12]}{git}, {libs}"
