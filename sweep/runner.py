"""The MPI sweep: hand chunks of tasks out dynamically, compute, stream them to part files.

Every rank computes, rank 0 included.  Chunks are claimed one at a time from a shared
counter (:class:`~sweep.counter.ChunkCounter`), so uneven task costs do not idle ranks.
A task that raises stops the hand-out for everybody; every rank then finishes the chunk
it holds, the ranks agree on the failures in one ``allgather`` and all of them raise the
same :class:`~sweep.errors.RunError`.  Results do not depend on the rank: a task's values
are a function of the job and the task index only.
"""

from __future__ import annotations

import resource
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from mpi4py import MPI

from sweep import storage
from sweep.analyses.base import STATUS_FAILED, STATUS_NOT_CONVERGED, STATUS_OK, Variable
from sweep.counter import ChunkCounter
from sweep.errors import RunError
from sweep.jobspec import Job
from sweep.progress import Progress

_STATUS_CODES = (STATUS_OK, STATUS_NOT_CONVERGED, STATUS_FAILED)


class TaskError(Exception):
    """A task raised, or returned something else than its analysis declares."""


@dataclass
class RunSummary:
    """The outcome of :func:`run`, the same on every rank.

    Parameters
    ----------
    report : storage.CollectReport
        What the final collect wrote.
    tasks_computed : int
        Tasks computed by this run (all ranks).
    seconds : float
        Wall time of the computation, s.
    peak_rss_mib : list of float
        Peak resident memory of each rank after the computation, before the collect, MiB.
    peak_rss_collect_mib : float
        Peak resident memory of rank 0 after the collect, MiB.
    """

    report: storage.CollectReport
    tasks_computed: int
    seconds: float
    peak_rss_mib: list[float]
    peak_rss_collect_mib: float


def peak_rss_mib() -> float:
    """Peak resident memory of this process so far, MiB (Linux ``ru_maxrss`` is KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _on_root(comm: MPI.Intracomm, action: Callable, what: str):
    """Run ``action()`` on rank 0 and broadcast its result; collective over comm.

    If the action raises, every rank raises a :class:`RunError` (a plain message for a
    RunError, the type, message and traceback otherwise), so no rank is left waiting.
    """
    outcome = None
    if comm.rank == 0:
        try:
            outcome = ("ok", action())
        except RunError as exc:
            outcome = ("error", (exc.message, exc.details))
        except Exception as exc:
            outcome = ("error", (f"{what} failed on rank 0: {type(exc).__name__}: {exc}",
                                 traceback.format_exc()))
    kind, value = comm.bcast(outcome, root=0)
    if kind == "error":
        raise RunError(*value)
    return value


def _agree(comm: MPI.Intracomm, failure: tuple[str, str] | None) -> None:
    """Raise the same RunError on every rank if any rank failed; collective over comm.

    ``failure`` is this rank's ``(message, traceback text)`` or None.
    """
    failures = [f for f in comm.allgather(failure) if f is not None]
    if failures:
        details = "".join(tb for _, tb in failures)
        raise RunError("; ".join(msg for msg, _ in failures), details)


def _warmup(job: Job, comm: MPI.Intracomm) -> None:
    """Compile the analysis' kernels once per node before any task; collective over comm.

    The first rank of each node compiles (and fills the numba cache) while the others
    wait, then they load the compiled kernels from the cache.
    """
    node = comm.Split_type(MPI.COMM_TYPE_SHARED)
    failure = None
    if node.rank == 0:
        try:
            job.analysis.warmup(job.options)
        except Exception as exc:
            failure = (f"warmup of analysis {job.analysis_name!r} failed on rank {comm.rank}: "
                       f"{type(exc).__name__}: {exc}", traceback.format_exc())
    node.Free()
    _agree(comm, failure)


def _store(result: object, variables: list[Variable], arrays: dict[str, np.ndarray],
           i: int) -> int:
    """Copy one task's result into row ``i`` of the chunk arrays; returns its status."""
    if not isinstance(result, dict):
        raise TaskError(f"compute returned a {type(result).__name__}, not a dict")
    expected = {v.name for v in variables} | {"status"}
    if set(result) != expected:
        raise TaskError(f"compute returned the keys {sorted(result)}, expected "
                        f"{sorted(expected)}")
    for v in variables:
        value = np.asarray(result[v.name])
        if value.shape != v.shape:
            raise TaskError(f"compute returned {v.name!r} with shape {value.shape}, the "
                            f"analysis declares {v.shape}")
        arrays[v.name][i] = value
    status = result["status"]
    if status not in _STATUS_CODES:
        raise TaskError(f"compute returned status {status!r}, expected one of {_STATUS_CODES}")
    return int(status)


def compute_chunk(job: Job, k: int) -> tuple[range, dict[str, np.ndarray], np.ndarray]:
    """Compute the tasks of chunk ``k``.

    Returns
    -------
    tasks : range
        Task indices.
    arrays : dict of str to numpy.ndarray
        Each variable, shape ``(len(tasks), *shape)``.
    status : numpy.ndarray
        int8 status of each task.

    Raises
    ------
    TaskError
        Naming the task (index and grid values) and the cause.
    """
    variables = job.analysis.variables(job.options)
    tasks = job.layout.chunk_tasks(k)
    arrays = {v.name: np.full((len(tasks), *v.shape), v.fill, dtype=v.dtype) for v in variables}
    status = np.empty(len(tasks), dtype=np.int8)
    for i, t in enumerate(tasks):
        point, subtask = job.point(t)
        try:
            status[i] = _store(job.analysis.compute(point, job.options, subtask),
                               variables, arrays, i)
        except Exception as exc:
            raise TaskError(f"{job.layout.describe(t)} failed: {type(exc).__name__}: "
                            f"{exc}") from exc
    return tasks, arrays, status


def _compute(job: Job, parts: Path, missing: list[int], comm: MPI.Intracomm,
             progress: Progress | None) -> int:
    """Compute the ``missing`` chunks and write their part files; collective over comm.

    Returns the number of tasks computed by all ranks.
    """
    counter = ChunkCounter(comm)
    failure, mine = None, 0
    while (i := counter.claim()) < len(missing):
        try:
            tasks, arrays, status = compute_chunk(job, missing[i])
            storage.write_part(parts, missing[i], tasks, arrays, status)
        except Exception as exc:
            counter.stop()
            cause = (str(exc) if isinstance(exc, TaskError)
                     else f"chunk {missing[i]}: {type(exc).__name__}: {exc}")
            failure = (f"{cause} (on rank {comm.rank})", traceback.format_exc())
            break
        mine += len(tasks)
        done = counter.add_done(len(tasks))
        if progress is not None:
            progress.update(done)
    counter.free()
    _agree(comm, failure)
    return comm.allreduce(mine)


def run(job: Job, out: Path, comm: MPI.Intracomm, *, resume: bool = False,
        overwrite: bool = False, progress_stream=None) -> RunSummary:
    """Run a job and write its merged NetCDF file; collective over comm.

    Parameters
    ----------
    job : Job
        The validated job (the same on every rank).
    out : pathlib.Path
        Output NetCDF path; part files go to ``OUT.nc.parts/``.
    comm : mpi4py.MPI.Intracomm
        The ranks taking part.
    resume : bool
        Compute only the chunks without a part file (the job file must be unchanged).
    overwrite : bool
        Delete earlier results at ``out`` first.
    progress_stream : file, optional
        Where rank 0 reports progress (default: ``sys.stderr``).

    Returns
    -------
    RunSummary

    Raises
    ------
    RunError
        On every rank, when the run is refused or a task fails.
    """
    missing = _on_root(comm, lambda: storage.prepare(job, out, resume=resume,
                                                     overwrite=overwrite),
                       f"preparing {storage.parts_dir(out)}/")
    _warmup(job, comm)
    layout = job.layout
    todo = sum(len(layout.chunk_tasks(k)) for k in missing)
    progress = (Progress(layout.n_tasks, layout.n_tasks - todo, progress_stream or sys.stderr)
                if comm.rank == 0 else None)
    start = time.perf_counter()
    computed = _compute(job, storage.parts_dir(out), missing, comm, progress)
    seconds = time.perf_counter() - start
    if progress is not None:
        progress.finish(computed)
    rss = comm.allgather(peak_rss_mib())
    report = _on_root(comm, lambda: storage.collect(out), f"collecting {out}")
    return RunSummary(report, computed, seconds, rss, comm.bcast(peak_rss_mib(), root=0))
