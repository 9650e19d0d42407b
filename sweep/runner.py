"""The MPI sweep: hand chunks of tasks out dynamically, compute, append them to part logs.

Every rank computes, rank 0 included.  Chunks are claimed one at a time from a shared
counter (:class:`~sweep.counter.ChunkCounter`), so uneven task costs do not idle ranks;
each rank appends its finished chunks to its own log (:mod:`sweep.partlog`).

A task whose computation raises is data: it is stored with status failed and the
exception's type and message, and the sweep goes on.  What stops a run is a fault of the
run itself (an analysis returning something else than it declares, a file that cannot be
written): every rank then finishes the chunk it holds, the ranks agree on the failures in
one ``allgather`` and all of them raise the same :class:`~sweep.errors.RunError`.  Results
do not depend on the rank: a task's values are a function of the job and the task index.
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

from sweep import partlog
from sweep.storage.files import file_error
from sweep.storage.lock import Lock
from sweep.storage.netcdf import CollectReport, collect
from sweep.storage.parts import log_path, parts_dir
from sweep.storage.resume import Plan, prepare
from sweep.analyses.base import STATUS_FAILED, STATUS_SKIPPED, TaskError, Variable, check_result
from sweep.counter import ChunkCounter
from sweep.errors import RunError
from sweep.jobspec import Job
from sweep.progress import Progress



@dataclass
class RunSummary:
    """The outcome of :func:`run`, the same on every rank.

    Parameters
    ----------
    report : sweep.storage.netcdf.CollectReport or None
        What the final collect wrote (None for a run of one piece, which does not collect).
    tasks_computed : int
        Tasks computed by this run (all ranks).
    tasks_failed : int
        Of those, the tasks with status failed.
    notes : list of str
        What the preparation found (rejected parts, a resume with changed code).
    seconds : float
        Wall time of the computation, s.
    peak_rss_mib : list of float
        Peak resident memory of each rank after the computation, before the collect, MiB.
    peak_rss_collect_mib : float
        Peak resident memory of rank 0 after the collect, MiB.
    """

    report: CollectReport | None
    tasks_computed: int
    tasks_failed: int
    notes: list[str]
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

    The calls of the analysis' ``warmups`` are spread over the ranks of each node (call
    ``i`` on node rank ``i`` modulo the node's ranks), which compile and fill the numba
    cache while the node's other ranks wait; then every rank loads the compiled kernels
    from the cache.
    """
    node = comm.Split_type(MPI.COMM_TYPE_SHARED)
    failure = None
    try:
        for call in job.analysis.warmups(job.options)[node.rank::node.size]:
            call()
    except Exception as exc:
        failure = (f"warmup of analysis {job.analysis_name!r} failed on rank {comm.rank}: "
                   f"{type(exc).__name__}: {exc}", traceback.format_exc())
    node.Free()
    _agree(comm, failure)


def _store(result: object, variables: list[Variable], arrays: dict[str, np.ndarray],
           i: int) -> tuple[int, str]:
    """Copy one task's result into row ``i`` of the chunk arrays; returns its status and
    message."""
    check_result(result, variables)
    for v in variables:
        arrays[v.name][i] = np.asarray(result[v.name])
    return int(result["status"]), result.get("message", "")


def compute_chunk(job: Job, k: int) -> tuple[range, dict[str, np.ndarray], np.ndarray, dict[int, str]]:
    """Compute the tasks of chunk ``k``.

    A task whose computation raises gets status failed, the fill values, and the message
    ``"<ExceptionType>: <message>"``.

    Returns
    -------
    tasks : range
        Task indices.
    arrays : dict of str to numpy.ndarray
        Each variable, shape ``(len(tasks), *shape)``.
    status : numpy.ndarray
        int8 status of each task.
    messages : dict of int to str
        Message of the tasks that have one, by position in the chunk.

    Raises
    ------
    TaskError
        When the analysis returns something else than it declares, naming the task.
    """
    variables = job.analysis.variables(job.options)
    tasks = job.layout.chunk_tasks(k)
    arrays = {v.name: np.full((len(tasks), *v.shape), v.fill, dtype=v.dtype) for v in variables}
    status = np.empty(len(tasks), dtype=np.int8)
    messages: dict[int, str] = {}
    for i, t in enumerate(tasks):
        point, subtask = job.point(t)
        if not job.layout.in_cases(point.grid):
            status[i] = STATUS_SKIPPED  # the arrays keep the fill values
            continue
        try:
            result = job.analysis.compute(point, job.options, subtask)
        except TaskError as exc:  # a wrapped analysis broke its declarations: a bug, not data
            raise TaskError(f"{job.layout.describe(t)}: {exc}") from exc
        except Exception as exc:  # noqa: BLE001 - a failing task is data (status failed)
            for v in variables:
                arrays[v.name][i] = v.fill
            status[i], messages[i] = STATUS_FAILED, f"{type(exc).__name__}: {exc}"
            continue
        try:
            status[i], message = _store(result, variables, arrays, i)
        except TaskError as exc:
            raise TaskError(f"{job.layout.describe(t)}: {exc}") from exc
        if message:
            messages[i] = message
    return tasks, arrays, status, messages


def _compute(job: Job, log: Path, plan: Plan, comm: MPI.Intracomm,
             progress: Progress | None) -> tuple[int, int]:
    """Compute the chunks of ``plan``, appending them to this rank's ``log``; collective
    over comm.

    Returns the numbers of tasks computed and of those that failed, by all ranks.
    """
    counter = ChunkCounter(comm)
    failure, mine, failed, writer = None, 0, 0, None
    try:
        writer = partlog.Writer(log, job.analysis.variables(job.options))
        while (k := counter.claim()) < job.layout.n_chunks:
            if not plan.computes(k):
                continue
            tasks, arrays, status, messages = compute_chunk(job, k)
            writer.append(k, tasks, status, arrays, messages)
            mine += len(tasks)
            failed += int(np.count_nonzero(status == STATUS_FAILED))
            n = counter.add_done(len(tasks))
            if progress is not None:
                progress.update(n)
    except Exception as exc:  # noqa: BLE001 - agreed below, so that no rank hangs
        counter.stop()
        if isinstance(exc, OSError):
            cause = file_error(exc, f"writing {log}").message
        elif isinstance(exc, TaskError):
            cause = str(exc)
        else:
            cause = f"{type(exc).__name__}: {exc}"
        failure = (f"{cause} (on rank {comm.rank})", "" if isinstance(exc, OSError) else traceback.format_exc())
    finally:
        if writer is not None:
            try:
                writer.close()
            except OSError as exc:
                failure = failure or (file_error(exc, f"closing {log}").message, "")
    counter.free()
    _agree(comm, failure)
    return comm.allreduce(mine), comm.allreduce(failed)


def run(job: Job, out: Path, comm: MPI.Intracomm, *, resume: bool = False,
        overwrite: bool = False, allow_code_change: bool = False, break_lock: bool = False,
        piece: tuple[int, int] | None = None, progress_stream=sys.stderr,
        progress_bar: bool | None = None) -> RunSummary:
    """Run a job and write its merged NetCDF file; collective over comm.

    Parameters
    ----------
    job : Job
        The validated job (the same on every rank).
    out : pathlib.Path
        Output NetCDF path; part logs go to ``OUT.nc.parts/``.
    comm : mpi4py.MPI.Intracomm
        The ranks taking part.
    resume : bool
        Compute only the chunks missing from the part logs (the job file and the code
        must be unchanged).
    overwrite : bool
        Delete earlier results at ``out`` first.
    allow_code_change : bool
        Resume although the code changed (recorded in the result).
    break_lock : bool
        Remove a lock left by a run that cannot be checked from this host.
    piece : (int, int), optional
        ``(I, N)``: compute piece I of N of the job (every N-th chunk, from chunk I - 1)
        and do not collect; ``collect`` merges the pieces once all have run.
    progress_stream : file or None
        Where rank 0 reports progress (default stderr; None: no report).
    progress_bar : bool, optional
        Redraw a bar in place (default: when the stream is a terminal).

    Returns
    -------
    RunSummary

    Raises
    ------
    RunError
        On every rank, when the run is refused or cannot write its files.
    """
    parts = parts_dir(out)
    lock = Lock(parts, "run", piece)
    try:
        plan = _on_root(comm, lambda: prepare(job, out, lock, resume=resume, overwrite=overwrite,
                                                     allow_code_change=allow_code_change,
                                                     break_lock=break_lock, ranks=comm.size, piece=piece),
                        f"preparing {parts}/")
        _warmup(job, comm)
        layout = job.layout
        total, done = layout.n_tasks, plan.done.tasks(layout.chunk, layout.n_tasks)
        if piece is not None:  # this piece's chunks only
            own = np.arange(piece[0] - 1, layout.n_chunks, piece[1])
            total = int(np.minimum(layout.chunk, layout.n_tasks - own * layout.chunk).sum())
            done = sum(len(layout.chunk_tasks(int(k))) for k in own if int(k) in plan.done)
        progress = (Progress(total, done, progress_stream, progress_bar)
                    if comm.rank == 0 and progress_stream is not None else None)
        start = time.perf_counter()
        computed, failed = _compute(job, log_path(parts, plan.run, comm.rank), plan, comm, progress)
        seconds = time.perf_counter() - start
        if progress is not None:
            progress.finish(computed)
        rss = comm.allgather(peak_rss_mib())
        report = None if piece else _on_root(comm, lambda: collect(out, lock_held=True),
                                             f"collecting {out}")
    finally:
        lock.release()
    return RunSummary(report, computed, failed, plan.notes, seconds, rss, comm.bcast(peak_rss_mib(), root=0))
