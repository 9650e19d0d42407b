"""The parts directory ``OUT.nc.parts/``: its paths, manifest, run records and part logs."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from sweep import partlog
from sweep.errors import RunError
from sweep.jobspec import Job
from sweep.storage.files import file_error, replace_atomically

#: The manifest's file name in the parts directory.
MANIFEST = "manifest.json"
_LOG = re.compile(r"run-(\d+)-rank-(\d+)\.log")
#: File names of the run records, ``run-RRRR.json``.
RUN = re.compile(r"run-(\d+)\.json")


def parts_dir(out: Path) -> Path:
    """The directory of part logs of the output ``out``: ``OUT.nc.parts``."""
    return out.with_name(out.name + ".parts")


def log_path(parts: Path, run: int, rank: int) -> Path:
    """The part log of ``rank`` in run number ``run``."""
    return parts / f"run-{run:04d}-rank-{rank:05d}.log"


def _logs(parts: Path) -> list[Path]:
    return sorted(p for p in parts.iterdir() if _LOG.fullmatch(p.name))


def read_manifest(parts: Path) -> dict:
    """The manifest of a parts directory.

    Raises
    ------
    RunError
        If the directory or its manifest does not exist or cannot be read.
    """
    path = parts / MANIFEST
    try:
        manifest = json.loads(path.read_text())
        manifest["job_sha256"], manifest["n_tasks"], manifest["variables"]  # noqa: B018 - the keys every reader needs
        return manifest
    except FileNotFoundError:
        if parts.is_dir():
            raise RunError(f"{parts}/ has no {MANIFEST}: it is not the parts directory of "
                           "a sweep run") from None
        raise RunError(f"{parts}/ does not exist: nothing to collect or resume") from None
    except (ValueError, KeyError, TypeError) as exc:
        raise RunError(f"{path} is corrupt ({type(exc).__name__}: {exc}); restore it, or start "
                       "again with --overwrite (the parts cannot be used without it)") from None
    except OSError as exc:
        raise file_error(exc, "reading the manifest") from None


def write_manifest(parts: Path, manifest: dict) -> None:
    replace_atomically(parts / MANIFEST, lambda tmp: tmp.write_text(json.dumps(manifest, indent=1)))


def read_runs(parts: Path) -> list[dict]:
    """The records of the runs on a parts directory, by run number (unreadable ones skipped)."""
    runs = []
    for path in sorted(parts.glob("run-*.json")):
        if RUN.fullmatch(path.name):
            try:
                runs.append(json.loads(path.read_text()))
            except (OSError, ValueError):
                continue
    return sorted(runs, key=lambda r: r.get("run", 0))


def layout(job: Job) -> list:
    """The variables a task stores, as the manifest records them: ``[name, dtype, shape]``."""
    return [[v.name, np.dtype(v.dtype).str, list(v.shape)] for v in job.analysis.variables(job.options)]


def check_layout(job: Job, manifest: dict, parts: Path) -> None:
    """Refuse to read parts written by code that stores other variables (RunError)."""
    if manifest["variables"] != layout(job):
        runs = read_runs(parts)
        commit = runs[-1]["provenance"].get("git_commit") if runs else None
        raise RunError(f"the parts in {parts}/ were written by code that stores other variables than this "
                       "code: read them with the code that wrote them"
                       + (f" (git {commit})" if commit else "") + ", or run the job again with --overwrite")


def part_logs(job: Job, parts: Path) -> partlog.Logs:
    """The part logs of a parts directory, to be streamed (:class:`sweep.partlog.Logs`)."""
    try:
        return partlog.Logs(_logs(parts), job.layout.chunk, job.layout.n_tasks)
    except OSError as exc:
        raise file_error(exc, "listing the part logs") from None
