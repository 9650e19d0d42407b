"""Result storage: one part file per finished chunk, merged into one NetCDF file.

Layout next to the output ``OUT.nc``::

    OUT.nc.parts/manifest.json        the job file text and its SHA-256, the chunk layout
    OUT.nc.parts/chunk-000017.h5      tasks of chunk 17: ``task`` indices, ``status`` and
                                      one ``(n_tasks_in_chunk, *shape)`` array per variable

Every file is written under a temporary name in the same directory, then renamed with
:func:`os.replace`, so a part file that exists is complete.  The parts are kept after a
successful :func:`collect`: collecting again gives the same file, ``--resume`` finds
nothing to do, and ``status`` reads them.  Delete the directory to reclaim the space.

The merged file is identical whatever the rank count and the order in which chunks
finished: values are placed by task index.  Its only attribute that changes from one
collect to the next is ``date_created``.
"""

from __future__ import annotations

import datetime
import importlib.metadata
import json
import os
import re
import shutil
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np
import xarray as xr

from sweep.analyses.base import GRID_KEYS, STATUS_MEANINGS
from sweep.errors import RunError
from sweep.jobspec import Job, parse_job

#: ``status`` of a task whose chunk has not been computed (a partial collect).
STATUS_MISSING = -1
STATUS_FLAG_VALUES = np.array([STATUS_MISSING, 0, 1, 2], dtype=np.int8)
STATUS_FLAG_MEANINGS = "missing " + STATUS_MEANINGS

MANIFEST = "manifest.json"
_PART = re.compile(r"chunk-(\d+)\.h5")


def software_version() -> str:
    """Installed version of the ``membrane-sweep`` distribution."""
    try:
        return importlib.metadata.version("membrane-sweep")
    except importlib.metadata.PackageNotFoundError:
        return "unknown (not installed)"


def parts_dir(out: Path) -> Path:
    """The directory of part files of the output ``out``: ``OUT.nc.parts``."""
    return out.with_name(out.name + ".parts")


def _part_path(parts: Path, k: int) -> Path:
    return parts / f"chunk-{k:06d}.h5"


def _replace_atomically(path: Path, write) -> None:
    """Call ``write(tmp_path)`` then rename the temporary file to ``path``."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def read_manifest(parts: Path) -> dict:
    """The manifest of a parts directory.

    Raises
    ------
    RunError
        If the directory or its manifest does not exist.
    """
    try:
        return json.loads((parts / MANIFEST).read_text())
    except FileNotFoundError:
        if parts.is_dir():
            raise RunError(f"{parts}/ has no {MANIFEST}: it is not the parts directory of "
                           "a sweep run") from None
        raise RunError(f"{parts}/ does not exist: nothing to collect or resume") from None


def completed_chunks(parts: Path, n_chunks: int) -> list[int]:
    """Sorted numbers of the chunks whose part file exists."""
    found = (_PART.fullmatch(p.name) for p in parts.iterdir())
    return sorted(k for k in (int(m.group(1)) for m in found if m) if k < n_chunks)


def prepare(job: Job, out: Path, *, resume: bool, overwrite: bool) -> list[int]:
    """Set up the parts directory of a run and find the chunks still to compute.

    Called on one rank only (rank 0), before any computation.

    Parameters
    ----------
    job : Job
        The validated job.
    out : pathlib.Path
        Output NetCDF path.
    resume : bool
        Continue the run whose parts are in ``OUT.nc.parts/``; refused if its job file
        text differs from ``job.text``.
    overwrite : bool
        Delete ``OUT.nc`` and ``OUT.nc.parts/`` first.

    Returns
    -------
    list of int
        Numbers of the chunks without a part file, ascending.

    Raises
    ------
    RunError
        When earlier results would be lost or mixed with this job's.
    """
    parts = parts_dir(out)
    if overwrite:
        shutil.rmtree(parts, ignore_errors=True)
        out.unlink(missing_ok=True)
    if parts.exists():
        if not resume:
            raise RunError(f"{parts}/ holds the parts of an earlier run: add --resume to "
                           "continue it, or --overwrite (or delete the directory) to start "
                           "again")
        manifest = read_manifest(parts)
        if manifest["job_sha256"] != job.sha256:
            raise RunError(f"cannot resume: {parts}/ was written by a different job file "
                           f"(its text has sha256 {manifest['job_sha256'][:12]}..., this one "
                           f"{job.sha256[:12]}...); restore that file, or start again with "
                           "--overwrite or another -o")
        for tmp in parts.glob(".*.tmp"):
            tmp.unlink()
    else:
        if out.exists():
            raise RunError(f"{out} exists: use --overwrite to replace it, or -o to write "
                           "elsewhere")
        parts.mkdir(parents=True)
        manifest = {
            "job_name": job.name, "analysis": job.analysis_name,
            "job_sha256": job.sha256, "job_text": job.text,
            "n_tasks": job.layout.n_tasks, "n_chunks": job.layout.n_chunks,
            "chunk": job.layout.chunk, "software_version": software_version(),
        }
        _replace_atomically(parts / MANIFEST,
                            lambda tmp: tmp.write_text(json.dumps(manifest, indent=1)))
    done = set(completed_chunks(parts, job.layout.n_chunks))
    return [k for k in range(job.layout.n_chunks) if k not in done]


def write_part(parts: Path, k: int, tasks: range, arrays: Mapping[str, np.ndarray],
               status: np.ndarray) -> None:
    """Write the results of chunk ``k`` atomically.

    Parameters
    ----------
    parts : pathlib.Path
        The parts directory.
    k : int
        Chunk number.
    tasks : range
        Task indices of the chunk.
    arrays : mapping of str to numpy.ndarray
        Each variable, shape ``(len(tasks), *variable.shape)``.
    status : numpy.ndarray
        int8 status of each task.
    """
    def write(tmp: Path) -> None:
        with h5py.File(tmp, "w", locking=False) as f:
            f["task"] = np.arange(tasks.start, tasks.stop, dtype=np.int64)
            f["status"] = status
            for name, values in arrays.items():
                f.create_dataset(f"variables/{name}", data=values)

    _replace_atomically(_part_path(parts, k), write)


@dataclass
class CollectReport:
    """What :func:`collect` wrote.

    Parameters
    ----------
    path : pathlib.Path
        The NetCDF file.
    tasks_completed, tasks_total : int
        Tasks found in the parts, tasks of the job.
    notes : list of str
        Things the user should know (missing tasks, unlabelled variables).
    """

    path: Path
    tasks_completed: int
    tasks_total: int
    notes: list[str] = field(default_factory=list)


def merge(job: Job, parts: Path) -> tuple[xr.Dataset, int]:
    """Merge the part files into the raw Dataset.

    Returns
    -------
    raw : xarray.Dataset
        Dims ``(*grid_dims, "subtask", *variable_dims)``; tasks without a part file hold
        the variables' fill values and ``status`` -1 (missing).
    tasks_completed : int
        Number of tasks found.
    """
    layout, analysis = job.layout, job.analysis
    variables = analysis.variables(job.options)
    flat = {v.name: np.full((layout.n_tasks, *v.shape), v.fill, dtype=v.dtype)
            for v in variables}
    status = np.full(layout.n_tasks, STATUS_MISSING, dtype=np.int8)
    completed = 0
    for k in completed_chunks(parts, layout.n_chunks):
        with h5py.File(_part_path(parts, k), "r", locking=False) as f:
            tasks = f["task"][:]
            status[tasks] = f["status"][:]
            for v in variables:
                flat[v.name][tasks] = f[f"variables/{v.name}"][:]
        completed += len(tasks)

    grid_dims, grid_shape = layout.dims + ("subtask",), layout.shape + (layout.n_subtasks,)
    coords = {d: (d, values, {"units": GRID_KEYS[d][0], "long_name": GRID_KEYS[d][1]})
              for d, values in zip(layout.dims, layout.values)}
    coords["subtask"] = ("subtask", np.arange(layout.n_subtasks),
                         {"units": "1", "long_name": "subtask index within a grid point"})
    coords.update(analysis.coords(job.options))
    data = {v.name: ((*grid_dims, *v.dims), flat[v.name].reshape(*grid_shape, *v.shape),
                     {"units": v.units, "long_name": v.long_name})
            for v in variables}
    data["status"] = (grid_dims, status.reshape(grid_shape),
                      {"units": "1", "long_name": "task status",
                       "flag_values": STATUS_FLAG_VALUES,
                       "flag_meanings": STATUS_FLAG_MEANINGS})
    return xr.Dataset(data, coords), completed


def collect(out: Path) -> CollectReport:
    """Merge the parts of ``OUT.nc.parts/`` into ``out`` (idempotent).

    The raw merged Dataset goes through the analysis' ``assemble``; the result is written
    with the netCDF4 engine, zlib-compressed, under a temporary name then renamed.

    Parameters
    ----------
    out : pathlib.Path
        Output NetCDF path.

    Returns
    -------
    CollectReport

    Raises
    ------
    RunError
        If there is no parts directory.
    """
    parts = parts_dir(out)
    manifest = read_manifest(parts)
    job = parse_job(manifest["job_text"], str(parts / MANIFEST))
    raw, completed = merge(job, parts)
    ds = job.analysis.assemble(raw, job.options)
    ds.attrs.update({
        "Conventions": "CF-1.8",
        "title": f"membrane-sweep job {job.name!r}, analysis {job.analysis_name!r}",
        "job_name": job.name,
        "analysis": job.analysis_name,
        "job_file": job.text,
        "job_sha256": job.sha256,
        "software": "membrane-sweep",
        "software_version": software_version(),
        "tasks_total": job.layout.n_tasks,
        "tasks_completed": completed,
        "date_created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
    })
    report = CollectReport(out, completed, job.layout.n_tasks)
    if completed < job.layout.n_tasks:
        report.notes.append(f"{job.layout.n_tasks - completed} of {job.layout.n_tasks} tasks "
                            f"are missing (status {STATUS_MISSING}); run --resume to "
                            "compute them")
    for name, var in ds.variables.items():
        lacking = [a for a in ("units", "long_name") if a not in var.attrs]
        if lacking:
            report.notes.append(f"analysis {job.analysis_name!r}: variable {name!r} has no "
                                + " or ".join(lacking))
    _replace_atomically(out, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4",
                                                       encoding=_encoding(ds)))
    return report


def _encoding(ds: xr.Dataset) -> dict[str, dict]:
    """zlib on numeric variables; no fill value on integers and coordinates."""
    encoding = {}
    for name, var in ds.variables.items():
        enc = {"zlib": True, "complevel": 4} if var.dtype.kind in "biuf" else {}
        if var.dtype.kind in "biu" or name in ds.coords:
            enc["_FillValue"] = None
        encoding[name] = enc
    return encoding


def describe_status(out: Path) -> str:
    """One line: completed / total tasks of the run writing ``out``, finished or not.

    Read from ``OUT.nc.parts/`` when it exists, else from the attributes of ``out``.

    Raises
    ------
    RunError
        If neither exists, or ``out`` is not a sweep result.
    """
    parts = parts_dir(out)
    if parts.exists():
        m = read_manifest(parts)
        chunks = completed_chunks(parts, m["n_chunks"])
        counts: Counter[int] = Counter()
        for k in chunks:
            with h5py.File(_part_path(parts, k), "r", locking=False) as f:
                counts.update(f["status"][:].tolist())
        written = "written" if out.exists() else "not collected yet"
        return (f"{m['job_name']} ({m['analysis']}): {sum(counts.values())} / {m['n_tasks']} "
                f"tasks completed, {len(chunks)} / {m['n_chunks']} chunks "
                f"({_status_counts(counts)}); {out}: {written}")
    if not out.exists():
        raise RunError(f"no run at {out}: neither {out} nor {parts}/ exists")
    with xr.open_dataset(out, engine="netcdf4") as ds:
        if "tasks_total" not in ds.attrs:
            raise RunError(f"{out} is not a membrane-sweep result (no tasks_total attribute)")
        statuses = (f" ({_status_counts(Counter(ds['status'].values.ravel().tolist()))})"
                    if "status" in ds else "")
        return (f"{ds.attrs['job_name']} ({ds.attrs['analysis']}): "
                f"{ds.attrs['tasks_completed']} / {ds.attrs['tasks_total']} tasks completed"
                f"{statuses}; {parts}/ deleted")


def _status_counts(counts: Mapping[int, int]) -> str:
    names = STATUS_FLAG_MEANINGS.split()
    return ", ".join(f"{name} {counts.get(int(value), 0)}"
                     for value, name in zip(STATUS_FLAG_VALUES, names)
                     if value != STATUS_MISSING)
