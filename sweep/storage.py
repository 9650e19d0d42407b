"""Result storage: append-only part logs per rank and run, merged into one NetCDF file.

Layout next to the output ``OUT.nc``::

    OUT.nc.parts/manifest.json                the job file text and its SHA-256, the chunk layout
    OUT.nc.parts/run-0002.json                run 2: start, host, ranks, chunks, provenance
    OUT.nc.parts/lock                         held by the run or collect writing (host, pid, start);
                                              lock-piece-1-of-4 by a run of one piece
    OUT.nc.parts/run-0002-rank-00001.log      the chunks rank 1 computed in run 2
                                              (:mod:`sweep.partlog`: checksummed records)

A run appends one record per finished chunk to its rank's log, so a sweep leaves a few
files per rank whatever its task count, and a killed rank loses at most the chunk it was
writing.  Every record is verified when read (checksum, task range); a record that fails
is reported by file and offset, never merged, and its chunk is computed again by
``--resume``.  The logs are kept after a successful :func:`collect`: collecting again gives
the same file, ``--resume`` finds nothing to do, ``status`` reads them.

One writer per output: :class:`Lock` (an ``O_EXCL`` file, safe on NFS and Lustre) is held
by a run, or by ``collect``, for as long as it writes; a second one is refused at once
with the holder's host, process and start time.  A job split into pieces (``run --chunks
I/N``, a Slurm array) runs its pieces at once, each holding the lock of its own piece and
computing every N-th chunk; ``collect`` merges them when all are done.  Run numbers are
allocated by creating ``run-RRRR.json`` with ``O_EXCL``, so concurrent pieces never share
one.

:func:`collect` streams: results whose published layout is the raw one (every analysis
but ``basins``) are written window by window of consecutive tasks straight into the
NetCDF file, so rank 0's memory does not grow with the task count.  An analysis with its
own ``assemble`` (basins: tiles into lattices) is merged in memory.

The merged file is identical whatever the rank count and the order in which chunks
finished: values are placed by task index.  Its attributes ``date_created`` and
``history`` change from one collect to the next.
"""

from __future__ import annotations

import datetime
import json
import math
import os
import re
import shutil
import socket
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from sweep import partlog, provenance
from sweep.analyses.base import (GRID_KEYS, STATUS_FAILED, STATUS_MEANINGS, STATUS_NOT_CONVERGED, STATUS_OK,
                                 STATUS_SKIPPED)
from sweep.errors import RunError
from sweep.jobspec import Job, parse_job

#: ``status`` of a task whose chunk has not been computed (a partial collect).
STATUS_MISSING = -1
STATUS_FLAG_VALUES = np.array([STATUS_MISSING, 0, 1, 2, 3], dtype=np.int8)
STATUS_FLAG_MEANINGS = "missing " + STATUS_MEANINGS

MANIFEST = "manifest.json"
LOCK = "lock"
_LOG = re.compile(r"run-(\d+)-rank-(\d+)\.log")
_RUN = re.compile(r"run-(\d+)\.json")
#: Bytes of task data buffered per write window of a streaming collect.
WINDOW_BYTES = 2**20


def parts_dir(out: Path) -> Path:
    """The directory of part logs of the output ``out``: ``OUT.nc.parts``."""
    return out.with_name(out.name + ".parts")


def log_path(parts: Path, run: int, rank: int) -> Path:
    """The part log of ``rank`` in run number ``run``."""
    return parts / f"run-{run:04d}-rank-{rank:05d}.log"


def _logs(parts: Path) -> list[Path]:
    return sorted(p for p in parts.iterdir() if _LOG.fullmatch(p.name))


def file_error(exc: OSError, doing: str) -> RunError:
    """One line for a file-system failure: what was being done, the file, the cause, what to do."""
    where = f": {exc.filename}" if exc.filename else ""
    hint = {28: "free some space", 13: "choose a writable directory with -o",
            30: "choose a writable directory with -o"}.get(exc.errno, "check the path")
    return RunError(f"{doing}{where}: {exc.strerror or exc}; {hint}, then run again "
                    "(with --resume to keep what is done)")


def _replace_atomically(path: Path, write) -> None:
    """Call ``write(tmp_path)`` then rename the temporary file to ``path``."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


# -- the manifest -------------------------------------------------------------------


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
        manifest["job_sha256"], manifest["n_tasks"]  # noqa: B018 - the keys every reader needs
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


def _write_manifest(parts: Path, manifest: dict) -> None:
    _replace_atomically(parts / MANIFEST, lambda tmp: tmp.write_text(json.dumps(manifest, indent=1)))


# -- one writer per output ----------------------------------------------------------


class Lock:
    """The lock file of a parts directory: one writer per output.

    Created with ``O_CREAT | O_EXCL`` (atomic on local file systems, NFSv3+ and Lustre),
    it records the holder's host, process id and start time.  A lock whose holder is a
    process of this host that no longer exists is stale and taken over; a lock held from
    another host is reported (it cannot be checked from here) and only ``break_lock``
    removes it.

    Parameters
    ----------
    parts : pathlib.Path
        The parts directory (it must exist).
    what : str
        What the holder does (``"run"``, ``"collect"``), recorded in the file.
    piece : (int, int), optional
        ``(I, N)``: the lock of piece I of N (``lock-piece-I-of-N``); pieces run side by
        side, and the whole-output lock excludes them all.
    """

    def __init__(self, parts: Path, what: str, piece: tuple[int, int] | None = None):
        name = LOCK if piece is None else f"{LOCK}-piece-{piece[0]}-of-{piece[1]}"
        self.path, self.what, self.piece, self.held = parts / name, what, piece, False

    def _conflicting(self) -> list[Path]:
        """Other locks that exclude this one: all others for the whole output, the
        whole-output lock for a piece."""
        if self.piece is None:
            return sorted(p for p in self.path.parent.glob(f"{LOCK}-piece-*") if p != self.path)
        whole = self.path.parent / LOCK
        return [whole] if whole.exists() else []

    def acquire(self, *, break_lock: bool = False) -> Lock:
        """Take the lock or raise :class:`RunError` naming its holder.

        The lock file is created first, then the conflicting locks are checked: of two
        processes starting at once at least one sees the other and backs off.
        """
        me = {"host": socket.gethostname(), "pid": os.getpid(), "what": self.what,
              "started": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")}
        for _ in range(3):
            try:
                fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                Lock._check_free(self.path, break_lock)
                continue
            except OSError as exc:
                raise file_error(exc, "locking the parts directory") from None
            try:
                with os.fdopen(fd, "w") as f:
                    json.dump(me, f)
            except OSError as exc:
                self.path.unlink(missing_ok=True)
                raise file_error(exc, f"writing {self.path}") from None
            self.held = True
            try:
                for other in self._conflicting():
                    Lock._check_free(other, break_lock)
            except RunError:
                self.release()
                raise
            return self
        raise RunError(f"{self.path}: could not take the lock; try again")

    @staticmethod
    def _check_free(path: Path, break_lock: bool) -> None:
        """Remove the lock file ``path`` if it is stale or broken on request, else raise
        :class:`RunError` naming its holder."""
        holder = Lock.holder(path)
        if not path.exists():
            return
        if break_lock or Lock._stale(holder):
            # Rename, then delete: of two processes taking over one stale lock, only one
            # succeeds, and neither can delete a fresh lock the other just created.
            aside = path.with_name(f".{path.name}.stale-{os.getpid()}")
            try:
                path.rename(aside)
            except FileNotFoundError:
                return
            if Lock.holder(aside) != holder:  # replaced by a fresh lock in between: put it back
                aside.rename(path)
                raise RunError(f"{path}: taken by another process; try again")
            aside.unlink(missing_ok=True)
            return
        piece = f" ({path.name[len(LOCK) + 1:]})" if path.name != LOCK else ""
        raise RunError(
            f"{path.parent}/ is in use by a {holder.get('what', '?')}{piece} on host {holder.get('host', '?')}, "
            f"process {holder.get('pid', '?')}, since {holder.get('started', '?')}: wait for it to finish; if "
            "that process no longer exists (a job killed on another node), run again with --break-lock")

    @staticmethod
    def holder(path: Path) -> dict:
        """The contents of a lock file (empty when it cannot be read)."""
        try:
            return json.loads(path.read_text())
        except (OSError, ValueError):
            return {}

    @staticmethod
    def _stale(holder: dict) -> bool:
        # Only a process of this host can be checked; an unreadable lock is left alone.
        if holder.get("host") != socket.gethostname() or not isinstance(holder.get("pid"), int):
            return False
        try:
            os.kill(holder["pid"], 0)
        except ProcessLookupError:
            return True
        except PermissionError:
            return False
        return False

    def release(self) -> None:
        """Remove the lock file if this object holds it."""
        if self.held:
            self.path.unlink(missing_ok=True)
            self.held = False

    def __enter__(self) -> Lock:
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()


# -- the set of finished chunks -----------------------------------------------------


class ChunkSet:
    """Chunks already computed, as a bitmap (one bit per chunk: 10^8 chunks in 12.5 MB).

    Parameters
    ----------
    n_chunks : int
        Chunks of the job.
    bits : numpy.ndarray, optional
        Packed bitmap (``numpy.packbits`` order); default: none done.
    """

    def __init__(self, n_chunks: int, bits: np.ndarray | None = None):
        self.n_chunks = n_chunks
        self.bits = np.zeros((n_chunks + 7) // 8, np.uint8) if bits is None else bits

    def __contains__(self, k: int) -> bool:
        return bool(self.bits[k >> 3] & (128 >> (k & 7)))

    def count(self) -> int:
        """Number of chunks in the set."""
        return int(np.unpackbits(self.bits, count=self.n_chunks).sum()) if self.n_chunks else 0

    def tasks(self, chunk: int, n_tasks: int) -> int:
        """Number of tasks in the set's chunks (``chunk`` tasks per chunk, ``n_tasks`` in all)."""
        ids = np.flatnonzero(np.unpackbits(self.bits, count=self.n_chunks))
        return int(np.minimum(chunk, n_tasks - ids * chunk).sum())


# -- preparing a run ----------------------------------------------------------------


@dataclass
class Plan:
    """What :func:`prepare` decided for a run (rank 0), broadcast to every rank.

    Parameters
    ----------
    run : int
        Number of this run (1 for the first run on an output).
    done : ChunkSet
        Chunks already computed by earlier runs.
    notes : list of str
        Things the user should know (parts that failed verification, code changes).
    piece : (int, int) or None
        ``(I, N)``: this run computes the chunks ``k`` with ``k % N == I - 1`` only.
    """

    run: int
    done: ChunkSet
    notes: list[str] = field(default_factory=list)
    piece: tuple[int, int] | None = None

    def computes(self, k: int) -> bool:
        """Whether this run computes chunk ``k``."""
        return k not in self.done and (self.piece is None or k % self.piece[1] == self.piece[0] - 1)


def prepare(job: Job, out: Path, lock: Lock, *, resume: bool, overwrite: bool,
            allow_code_change: bool = False, break_lock: bool = False, ranks: int = 1,
            piece: tuple[int, int] | None = None) -> Plan:
    """Set up the parts directory of a run, take its lock, find the chunks still to compute.

    Called on one rank only (rank 0), before any computation.  The lock is taken before
    anything is deleted or written; the caller releases it (:meth:`Lock.release`).

    Parameters
    ----------
    job : Job
        The validated job.
    out : pathlib.Path
        Output NetCDF path.
    lock : Lock
        The lock of ``parts_dir(out)``, acquired here and held on return.
    resume : bool
        Continue the run whose parts are in ``OUT.nc.parts/``; refused if its job file
        text or its code differ.
    overwrite : bool
        Delete ``OUT.nc`` and ``OUT.nc.parts/`` first.
    allow_code_change : bool
        Resume even though the code differs from the earlier runs' (recorded).
    break_lock : bool
        Remove a lock whose holder cannot be checked from this host.
    ranks : int
        Ranks of this run (recorded).
    piece : (int, int), optional
        ``(I, N)``: compute piece I of N (every N-th chunk); implies ``resume`` (pieces
        start side by side on one output) and excludes ``overwrite``.

    Returns
    -------
    Plan

    Raises
    ------
    RunError
        When earlier results would be lost or mixed with this job's, or a file cannot be
        written (one line naming it).
    """
    parts = parts_dir(out)
    try:
        return _prepare(job, out, parts, lock, resume or piece is not None, overwrite, allow_code_change,
                        break_lock, ranks, piece)
    except OSError as exc:
        raise file_error(exc, f"preparing {parts}/") from None


def _prepare(job, out, parts, lock, resume, overwrite, allow_code_change, break_lock, ranks, piece) -> Plan:
    current = provenance.provenance(job.analysis)
    if parts.is_dir() and piece is None and not any(parts.iterdir()):
        parts.rmdir()  # left empty by a run that failed while starting
    if parts.exists():
        lock.acquire(break_lock=break_lock)
        if overwrite:
            # Move the directory aside with our lock in it, so that no other run can start
            # on it while it is deleted.
            doomed = parts.with_name(f".{parts.name}.deleted-{os.getpid()}")
            parts.rename(doomed)
            lock.held = False
            shutil.rmtree(doomed)
    if overwrite:
        out.unlink(missing_ok=True)
    if not parts.exists() and out.exists():
        raise RunError(f"{out} exists: use --overwrite to replace it, or -o to write elsewhere")
    notes: list[str] = []
    if not parts.exists() or (piece is not None and not (parts / MANIFEST).exists()):
        # pieces may start at the same moment: every step is safe to repeat
        parts.mkdir(parents=True, exist_ok=True)
        if not lock.held:
            lock.acquire(break_lock=break_lock)
        if not (parts / MANIFEST).exists():
            _write_manifest(parts, {
                "format": partlog.VERSION, "job_name": job.name, "analysis": job.analysis_name,
                "job_sha256": job.sha256, "job_text": job.text, "n_tasks": job.layout.n_tasks,
                "n_chunks": job.layout.n_chunks, "chunk": job.layout.chunk, "variables": _layout(job)})
    elif not resume:
        raise RunError(f"{parts}/ holds the parts of an earlier run: add --resume to continue "
                       "it, or --overwrite (or delete the directory) to start again")
    manifest = read_manifest(parts)
    if manifest["job_sha256"] != job.sha256:
        raise RunError(f"cannot resume: {parts}/ was written by a different job file (its text "
                       f"has sha256 {manifest['job_sha256'][:12]}..., this one {job.sha256[:12]}...); "
                       "restore that file, or start again with --overwrite or another -o")
    if manifest.get("format") != partlog.VERSION:
        raise RunError(f"cannot resume: {parts}/ was written by an older version of membrane-sweep "
                       "(one HDF5 file per chunk), whose parts this version does not read; start "
                       "again with --overwrite, or finish it with the version that started it")
    runs = read_runs(parts)
    changed = provenance.differences(runs[-1]["provenance"], current) if runs else []
    if changed and not allow_code_change:
        raise RunError(f"cannot resume: the code differs from the run that wrote {parts}/ ("
                       + "; ".join(changed) + "): resuming would mix results of two versions; run "
                       "the code that started it, or start again with --overwrite, or pass "
                       "--allow-code-change to resume anyway (recorded in the result)")
    if changed:
        notes.append("resumed with different code (--allow-code-change, recorded): " + "; ".join(changed))
    if piece is None:
        for tmp in parts.glob(".*.tmp"):
            tmp.unlink()
    check_layout(job, manifest, parts)
    logs = part_logs(job, parts).scan_all()
    notes += logs.problems()
    done = ChunkSet(job.layout.n_chunks, logs.done)
    record = {"started": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
              "host": socket.gethostname(), "ranks": ranks, "chunks": "all" if piece is None else
              f"{piece[0]}/{piece[1]}", "provenance": current, "code_changed": changed}
    return Plan(_new_run(parts, record), done, notes, piece)


def _new_run(parts: Path, record: dict) -> int:
    """Allocate the next run number by creating ``run-RRRR.json`` exclusively; returns it."""
    run = max((int(m.group(1)) for m in map(_RUN.fullmatch, (p.name for p in parts.iterdir())) if m),
              default=0) + 1
    while True:
        try:
            fd = os.open(parts / f"run-{run:04d}.json", os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            run += 1
            continue
        with os.fdopen(fd, "w") as f:
            json.dump({"run": run, **record}, f, indent=1)
        return run


def read_runs(parts: Path) -> list[dict]:
    """The records of the runs on a parts directory, by run number (unreadable ones skipped)."""
    runs = []
    for path in sorted(parts.glob("run-*.json")):
        if _RUN.fullmatch(path.name):
            try:
                runs.append(json.loads(path.read_text()))
            except (OSError, ValueError):
                continue
    return sorted(runs, key=lambda r: r.get("run", 0))


# -- reading the parts --------------------------------------------------------------


def _layout(job: Job) -> list:
    """The variables a task stores, as the manifest records them: ``[name, dtype, shape]``."""
    return [[v.name, np.dtype(v.dtype).str, list(v.shape)] for v in job.analysis.variables(job.options)]


def check_layout(job: Job, manifest: dict, parts: Path) -> None:
    """Refuse to read parts written by code that stores other variables (RunError)."""
    if manifest.get("variables") is not None and manifest["variables"] != _layout(job):
        runs = read_runs(parts)
        commit = runs[-1]["provenance"].get("git_commit") if runs else None
        raise RunError(f"the parts in {parts}/ were written by code that stores other variables than this "
                       "code: read them with the code that wrote them"
                       + (f" (git {commit})" if commit else "") + ", or run the job again with --overwrite")


def part_logs(job: Job, parts: Path) -> partlog.Logs:
    """The part logs of a parts directory, to be streamed (:class:`sweep.partlog.Logs`)."""
    try:
        return partlog.Logs(_logs(parts), job.layout.chunk, job.layout.n_tasks, job.analysis.variables(job.options))
    except OSError as exc:
        raise file_error(exc, "listing the part logs") from None


@dataclass
class CollectReport:
    """What :func:`collect` wrote.

    Parameters
    ----------
    path : pathlib.Path
        The NetCDF file.
    tasks_completed, tasks_total : int
        Tasks found in the parts, tasks of the job.
    counts : collections.Counter
        Tasks per status code.
    reasons : collections.Counter
        ``(status, message)`` of the tasks that are not ok, counted.
    notes : list of str
        Things the user should know (missing tasks, rejected parts, unlabelled variables).
    """

    path: Path
    tasks_completed: int
    tasks_total: int
    counts: Counter = field(default_factory=Counter)
    reasons: Counter = field(default_factory=Counter)
    notes: list[str] = field(default_factory=list)

    @property
    def failed(self) -> int:
        """Tasks with status failed."""
        return self.counts.get(STATUS_FAILED, 0)

    def summary(self) -> str:
        """``"9 / 9 tasks: 4 ok, 5 not converged (5: reached max_points = 40 ...), 0 failed"``."""
        return f"{self.tasks_completed} / {self.tasks_total} tasks: " + summarize(self.counts, self.reasons)


def summarize(counts: Mapping[int, int], reasons: Mapping[tuple[int, str], int], top: int = 3) -> str:
    """Counts per status with the commonest reasons of the tasks that are not ok."""
    out = []
    for code, name in ((STATUS_OK, "ok"), (STATUS_NOT_CONVERGED, "not converged"), (STATUS_FAILED, "failed")):
        n = counts.get(code, 0)
        why = sorted(((c, m) for (s, m), c in reasons.items() if s == code and m), key=lambda x: (-x[0], x[1]))
        detail = "; ".join(f"{c}: {m}" for c, m in why[:top])
        more = "" if len(why) <= top else f"; {len(why) - top} other reason(s)"
        out.append(f"{n} {name}" + (f" ({detail}{more})" if detail else ""))
    if counts.get(STATUS_SKIPPED, 0):
        out.append(f"{counts[STATUS_SKIPPED]} outside the cases")
    return ", ".join(out)


def _grid_coords(job: Job, keep_subtask: bool) -> dict:
    layout = job.layout
    coords = {d: (d, values, {"units": GRID_KEYS[d][0], "long_name": GRID_KEYS[d][1]})
              for d, values in zip(layout.dims, layout.values)}
    if keep_subtask:
        coords["subtask"] = ("subtask", np.arange(layout.n_subtasks),
                             {"units": "1", "long_name": "subtask index within a grid point"})
    coords.update(job.analysis.coords(job.options))
    return coords


_STATUS_ATTRS = {"units": "1", "long_name": "task status", "flag_values": STATUS_FLAG_VALUES,
                 "flag_meanings": STATUS_FLAG_MEANINGS}
_MESSAGE_ATTRS = {"long_name": "why a task is not ok (empty when ok)"}


def merge(job: Job, parts: Path, logs: partlog.Logs | None = None) -> tuple[xr.Dataset, int]:
    """Merge the part logs into the raw Dataset, in memory.

    Returns
    -------
    raw : xarray.Dataset
        Dims ``(*grid_dims, "subtask", *variable_dims)``; tasks without a part hold the
        variables' fill values and ``status`` -1 (missing); ``message`` per task.
    tasks_completed : int
        Number of tasks found.
    """
    layout, analysis = job.layout, job.analysis
    variables = analysis.variables(job.options)
    logs = part_logs(job, parts) if logs is None else logs
    flat = {v.name: np.full((layout.n_tasks, *v.shape), v.fill, dtype=v.dtype) for v in variables}
    status = np.full(layout.n_tasks, STATUS_MISSING, dtype=np.int8)
    message = np.full(layout.n_tasks, "", dtype=object)
    with partlog.Reader(variables) as reader:
        for rec in logs:
            st, arrays, messages = reader.read(rec)
            sl = slice(rec.task_start, rec.task_start + rec.task_count)
            status[sl] = st
            for name, values in arrays.items():
                flat[name][sl] = values
            for i, m in messages.items():
                message[rec.task_start + i] = m
    grid_dims, grid_shape = layout.dims + ("subtask",), layout.shape + (layout.n_subtasks,)
    data = {v.name: ((*grid_dims, *v.dims), flat[v.name].reshape(*grid_shape, *v.shape),
                     {"units": v.units, "long_name": v.long_name, **v.attrs})
            for v in variables}
    data["status"] = (grid_dims, status.reshape(grid_shape), dict(_STATUS_ATTRS))
    data["message"] = (grid_dims, message.reshape(grid_shape), dict(_MESSAGE_ATTRS))
    return xr.Dataset(data, _grid_coords(job, keep_subtask=True)), logs.tasks


def flat_boxes(start: int, stop: int, shape: tuple[int, ...]) -> list[tuple[tuple[int, ...], tuple[int, ...]]]:
    """Split the C-order flat index range ``[start, stop)`` of an array of ``shape`` into boxes.

    Returns
    -------
    list of (corner, extent)
        Rectangular blocks, in increasing flat order, each a contiguous flat range (at most
        ``2 len(shape) - 1`` of them).
    """
    if start >= stop:
        return []
    if len(shape) == 1:
        return [((start,), (stop - start,))]
    inner = math.prod(shape[1:])
    i0, r0 = divmod(start, inner)
    i1, r1 = divmod(stop, inner)
    if i0 == i1:
        return [((i0, *c), (1, *e)) for c, e in flat_boxes(r0, r1, shape[1:])]
    out = []
    if r0:
        out += [((i0, *c), (1, *e)) for c, e in flat_boxes(r0, inner, shape[1:])]
        i0 += 1
    if i1 > i0:
        out.append(((i0, *(0,) * (len(shape) - 1)), (i1 - i0, *shape[1:])))
    if r1:
        out += [((i1, *c), (1, *e)) for c, e in flat_boxes(0, r1, shape[1:])]
    return out


def c_order_chunks(shape: tuple[int, ...], itemsize: int, target: int = 2**20) -> tuple[int, ...]:
    """HDF5 chunk shape of about ``target`` bytes that is a contiguous run of C order: the
    trailing dimensions whole, a part of the next one, ones before it.  Written in task
    order, such chunks are completed one after the other, so the chunk cache holds only
    the one being filled."""
    chunks = [1] * len(shape)
    size = itemsize
    for i in range(len(shape) - 1, -1, -1):
        if size * shape[i] <= target:
            chunks[i] = shape[i]
            size *= shape[i]
        else:
            chunks[i] = max(1, target // size)
            break
    return tuple(chunks)


def _stream(tmp: Path, job: Job, logs: partlog.Logs, attrs: dict, report: CollectReport) -> None:
    """Write the result of a raw-layout analysis window by window (bounded memory); sets
    ``report.tasks_completed``."""
    import netCDF4

    layout, analysis = job.layout, job.analysis
    variables = analysis.variables(job.options)
    keep_subtask = layout.n_subtasks > 1
    dims = layout.dims + (("subtask",) if keep_subtask else ())
    shape = layout.shape + ((layout.n_subtasks,) if keep_subtask else ())
    skeleton = xr.Dataset(coords=_grid_coords(job, keep_subtask), attrs=attrs)
    skeleton.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(skeleton))
    non_dim = [c for c in skeleton.coords if c not in skeleton.dims]
    as_coords = set(analysis.coordinate_variables(job.options))
    per_task = 1 + 8 + sum(np.dtype(v.dtype).itemsize * math.prod(v.shape) for v in variables)  # status, message
    window = layout.chunk * max(1, WINDOW_BYTES // (per_task * layout.chunk))
    with netCDF4.Dataset(tmp, "a") as nc:
        for v in variables:
            for d, n in zip(v.dims, v.shape):
                if d not in nc.dimensions:
                    nc.createDimension(d, n)
        out = {}
        for v in variables:
            floating = np.dtype(v.dtype).kind == "f"
            chunks = c_order_chunks(shape + v.shape, np.dtype(v.dtype).itemsize)
            var = nc.createVariable(v.name, v.dtype, dims + v.dims, zlib=True, complevel=4,
                                    fill_value=np.nan if floating else False, chunksizes=chunks)
            # room for the chunk being filled: written in order, a chunk is never revisited
            var.set_var_chunk_cache(size=2 * np.dtype(v.dtype).itemsize * math.prod(chunks), nelems=11,
                                    preemption=1.0)
            var.setncatts({"units": v.units, "long_name": v.long_name, **v.attrs})
            linked = [c for c in non_dim if set(skeleton[c].dims) <= set(dims + v.dims)]
            linked += [c.name for c in variables if c.name in as_coords and c.name != v.name
                       and set(c.dims) <= set(v.dims)]
            if linked:
                var.setncattr("coordinates", " ".join(linked))
            out[v.name] = var
        out["status"] = nc.createVariable("status", "i1", dims, zlib=True, complevel=4, fill_value=False,
                                          chunksizes=c_order_chunks(shape, 1))
        out["status"].setncatts(_STATUS_ATTRS)
        out["message"] = nc.createVariable("message", str, dims, chunksizes=c_order_chunks(shape, 16))
        out["message"].setncatts(_MESSAGE_ATTRS)
        records = iter(logs)
        rec = next(records, None)
        with partlog.Reader(variables) as reader:
            for w0 in range(0, layout.n_tasks, window):
                w1 = min(w0 + window, layout.n_tasks)
                buf = {v.name: np.full((w1 - w0, *v.shape), v.fill, dtype=v.dtype) for v in variables}
                buf["status"] = np.full(w1 - w0, STATUS_MISSING, np.int8)
                buf["message"] = np.full(w1 - w0, "", dtype=object)
                while rec is not None and rec.task_start < w1:
                    st, arrays, messages = reader.read(rec)
                    sl = slice(rec.task_start - w0, rec.task_start - w0 + rec.task_count)
                    buf["status"][sl] = st
                    for name, values in arrays.items():
                        buf[name][sl] = values
                    for i, m in messages.items():
                        buf["message"][sl.start + i] = m
                    rec = next(records, None)
                _count(report, buf["status"], buf["message"])
                # Messages are rare: unwritten strings read as "", so a window with few of
                # them writes those alone (HDF5 keeps every written string in its heap).
                said = np.flatnonzero(buf["message"] != "")
                few = said.size <= 64
                for i in said if few else ():
                    out["message"][np.unravel_index(w0 + i, shape)] = buf["message"][i]
                for corner, extent in flat_boxes(w0, w1, shape):
                    lo = int(np.ravel_multi_index(corner, shape)) - w0
                    size = math.prod(extent)
                    box = tuple(slice(c, c + e) for c, e in zip(corner, extent))
                    for name, var in out.items():
                        if name == "message" and few:
                            continue
                        values = buf[name][lo:lo + size]
                        var[box] = values.reshape(*extent, *values.shape[1:])
        report.tasks_completed = logs.tasks


def collect(out: Path, *, lock_held: bool = False, break_lock: bool = False) -> CollectReport:
    """Merge the parts of ``OUT.nc.parts/`` into ``out`` (idempotent).

    Written under a temporary name then renamed; temporary files of an interrupted merge
    are removed first.

    Parameters
    ----------
    out : pathlib.Path
        Output NetCDF path.
    lock_held : bool
        The caller holds the parts directory's lock (a run's final collect).
    break_lock : bool
        As for :meth:`Lock.acquire`.

    Returns
    -------
    CollectReport

    Raises
    ------
    RunError
        If there is no parts directory, it is in use, or the file cannot be written.
    """
    parts = parts_dir(out)
    if not parts.is_dir():
        read_manifest(parts)  # says that there is nothing to collect
    lock = None if lock_held else Lock(parts, "collect").acquire(break_lock=break_lock)
    try:
        return _collect(out, parts, read_manifest(parts))
    finally:
        if lock is not None:
            lock.release()


def _collect(out: Path, parts: Path, manifest: dict) -> CollectReport:
    job = parse_job(manifest["job_text"], str(parts / MANIFEST))
    check_layout(job, manifest, parts)
    temporary = re.compile(re.escape(f".{out.name}.") + r"\d+\.tmp")
    for stale in out.parent.glob(f".{out.name}.*.tmp"):
        if temporary.fullmatch(stale.name):
            stale.unlink(missing_ok=True)
    logs = part_logs(job, parts)
    report = CollectReport(out, 0, job.layout.n_tasks)
    attrs, run_attrs = _attributes(job, parts)

    def write(tmp: Path) -> None:
        if job.analysis.assemble is None:
            _stream(tmp, job, logs, attrs, report)
            with xr.open_dataset(tmp, engine="netcdf4") as ds:
                derived = {k: v.load() for k, v in job.analysis.derived(ds, job.options).items()}
            if derived:
                extra = xr.Dataset(derived)
                encoding = {k: v for k, v in _encoding(extra).items() if k in derived}
                extra.to_netcdf(tmp, mode="a", engine="netcdf4", encoding=encoding)
            _write_run_group(tmp, {**run_attrs, "tasks_completed": report.tasks_completed})
            return
        raw, report.tasks_completed = merge(job, parts, logs)
        _count(report, raw["status"].values.ravel(), raw["message"].values.ravel())
        ds = job.analysis.assemble(raw, job.options).set_coords(
            [c for c in job.analysis.coordinate_variables(job.options) if c in raw])
        ds.attrs.update(attrs)
        for name, var in ds.variables.items():
            lacking = [a for a in ("units", "long_name") if a not in var.attrs and name != "message"]
            if lacking:
                report.notes.append(f"analysis {job.analysis_name!r}: variable {name!r} has no "
                                    + " or ".join(lacking))
        ds.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(ds))
        _write_run_group(tmp, {**run_attrs, "tasks_completed": report.tasks_completed})

    try:
        _replace_atomically(out, write)
    except RunError:
        raise
    except OSError as exc:
        raise file_error(exc, f"writing {out}") from None
    except RuntimeError as exc:  # netCDF4 reports a full disk as "NetCDF: HDF error"
        raise RunError(f"writing {out} failed ({exc}); check the free space and the permissions of "
                       f"{out.parent}, then run collect again (the parts are kept)") from None
    report.notes[:0] = logs.problems()
    missing = report.tasks_total - report.tasks_completed
    if missing:
        report.notes.append(f"{missing} of {report.tasks_total} tasks are missing (status "
                            f"{STATUS_MISSING}); run --resume to compute them")
    return report


def _count(report: CollectReport, status: np.ndarray, message: np.ndarray) -> None:
    """Add tasks to the counts per status and the reasons of those not ok."""
    report.counts.update(Counter(status.tolist()))
    for i in np.flatnonzero((status != STATUS_OK) & (status != STATUS_MISSING) & (status != STATUS_SKIPPED)):
        report.reasons[(int(status[i]), str(message[i]))] += 1


#: The netCDF group holding the attributes of the run(s) that wrote a result.
RUN_GROUP = "run"


def _attributes(job: Job, parts: Path) -> tuple[dict, dict]:
    """The global attributes of a result, and those of its ``run`` group.

    The global ones are what results of one analysis computed by the same code on the same
    membrane share (so that ``xarray.combine_by_coords`` and ``open_mfdataset`` combine runs
    over different grid values with their defaults): CF conventions, the analysis and its
    attributes, the package version and source hash, the membrane constants.  What is
    particular to a run (job file, history, dates, task counts, git commit, library
    versions) goes to the group ``run`` (:func:`run_attributes`; ``tasks_completed`` is
    added when the parts have been read).
    """
    runs = read_runs(parts)
    last = runs[-1]["provenance"] if runs else provenance.provenance(job.analysis)
    history = [f"{r['started']}: run {r['run']} ({'chunks ' + r['chunks'] if r.get('chunks', 'all') != 'all' else 'all chunks'})"
               f" on {r['ranks']} rank(s) at {r['host']} with "
               f"{provenance.describe(r['provenance'])}"
               + (f"; resumed with different code: {'; '.join(r['code_changed'])}" if r.get("code_changed") else "")
               for r in runs]
    shared = {
        "Conventions": "CF-1.8",
        "title": f"membrane-sweep results of the {job.analysis_name} analysis",
        "source": f"membrane-sweep {last['package_version']}, source sha256 {last['source_sha256'][:12]}",
        "analysis": job.analysis_name,
        "software": "membrane-sweep",
        "software_version": last["package_version"],
        "source_sha256": last["source_sha256"],
        **{f"membrane_{k}": getattr(job.membrane, k) for k in ("C1", "h", "Gamma", "Re")},
        **job.analysis.attributes(job.options),
    }
    run = {
        "job_name": job.name,
        "job_file": job.text,
        "job_sha256": job.sha256,
        "history": "\n".join(history),
        "provenance": provenance.describe(last),
        "git_commit": last.get("git_commit") or "unknown",
        "library_versions": json.dumps(last["versions"]),
        "code_changed_during_run": int(any(r.get("code_changed") for r in runs)),
        "tasks_total": job.layout.n_tasks,
        "date_created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
    }
    return shared, run


def _write_run_group(path: Path, attrs: dict) -> None:
    import netCDF4

    with netCDF4.Dataset(path, "a") as nc:
        nc.createGroup(RUN_GROUP).setncatts(attrs)


def run_attributes(path: Path) -> dict:
    """The attributes of the run(s) that wrote the result ``path`` (its ``run`` group):
    ``job_name``, ``job_file``, ``job_sha256``, ``history``, ``date_created``,
    ``tasks_total``, ``tasks_completed``, ``git_commit``, ``library_versions``, ...

    Raises
    ------
    RunError
        If ``path`` is not a readable result of this package.
    """
    import netCDF4

    try:
        with netCDF4.Dataset(path) as nc:
            if RUN_GROUP not in nc.groups:
                raise RunError(f"{path} is not a membrane-sweep result (no '{RUN_GROUP}' group)")
            group = nc.groups[RUN_GROUP]
            return {a: group.getncattr(a) for a in group.ncattrs()}
    except OSError as exc:
        raise RunError(f"{path} is not a readable NetCDF result ({type(exc).__name__}); give the "
                       "output file of a run (OUT.nc), not a job file") from None


def _encoding(ds: xr.Dataset) -> dict[str, dict]:
    """zlib on numeric variables; no fill value on integers and coordinates."""
    encoding = {}
    for name, var in ds.variables.items():
        enc = {"zlib": True, "complevel": 4} if var.dtype.kind in "biuf" else {}
        if var.dtype.kind in "biu" or name in ds.coords:
            enc["_FillValue"] = None
        encoding[name] = enc
    return encoding


# -- status -------------------------------------------------------------------------


def describe_status(out: Path) -> str:
    """Completed / total tasks of the run writing ``out``, finished or not, with the
    counts per status, the commonest reasons and any part that failed verification.

    Read from ``OUT.nc.parts/`` when it exists, else from ``out``.

    Raises
    ------
    RunError
        If neither exists, or ``out`` is not a sweep result.
    """
    parts = parts_dir(out)
    if parts.exists():
        m = read_manifest(parts)
        job = parse_job(m["job_text"], str(parts / MANIFEST))
        check_layout(job, m, parts)
        logs = part_logs(job, parts)
        counts: Counter[int] = Counter()
        reasons: Counter = Counter()
        chunks = 0
        with partlog.Reader(job.analysis.variables(job.options)) as reader:
            for rec in logs:
                chunks += 1
                st = reader.read(rec, only_status=True)[0]
                counts.update(Counter(st.tolist()))
                if np.any((st != STATUS_OK) & (st != STATUS_SKIPPED)):
                    messages = reader.read(rec)[2]
                    for i in np.flatnonzero((st != STATUS_OK) & (st != STATUS_SKIPPED)):
                        reasons[(int(st[i]), messages.get(int(i), ""))] += 1
        written = "written" if out.exists() else "not collected yet"
        lines = [f"{m['job_name']} ({m['analysis']}): {logs.tasks} / {m['n_tasks']} tasks "
                 f"completed, {chunks} / {m['n_chunks']} chunks ({summarize(counts, reasons)}); "
                 f"{out}: {written}"]
        for path in sorted(parts.glob(f"{LOCK}*")):
            h = Lock.holder(path)
            lines.append(f"in use ({path.name}) by a {h.get('what')} on host {h.get('host')}, process "
                         f"{h.get('pid')}, since {h.get('started')}")
        return "\n".join(lines + [f"rejected part: {p}" for p in logs.problems()])
    if not out.exists():
        raise RunError(f"no run at {out}: neither {out} nor {parts}/ exists")
    run = run_attributes(out)
    try:
        with xr.open_dataset(out, engine="netcdf4") as ds:
            counts = Counter(ds["status"].values.ravel().tolist()) if "status" in ds else Counter()
            reasons = Counter()
            if "message" in ds:
                for s, msg in zip(ds["status"].values.ravel(), ds["message"].values.ravel()):
                    if s not in (STATUS_OK, STATUS_MISSING, STATUS_SKIPPED):
                        reasons[(int(s), str(msg))] += 1
            return (f"{run['job_name']} ({ds.attrs['analysis']}): {run['tasks_completed']} / "
                    f"{run['tasks_total']} tasks completed ({summarize(counts, reasons)}); "
                    f"{parts}/ deleted")
    except (OSError, ValueError) as exc:
        raise RunError(f"{out} is not a readable NetCDF result ({type(exc).__name__}); give the "
                       "output file of a run (OUT.nc), not a job file") from None
