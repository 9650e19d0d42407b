"""Preparing a run: the parts directory set up, its lock taken, the chunks still to compute."""

from __future__ import annotations

import datetime
import json
import os
import shutil
import socket
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from sweep import partlog, provenance
from sweep.errors import RunError
from sweep.jobspec import Job
from sweep.storage.files import file_error
from sweep.storage.lock import Lock
from sweep.storage.parts import (MANIFEST, RUN, check_layout, layout, part_logs, parts_dir, read_manifest, read_runs,
                                 write_manifest)


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
            write_manifest(parts, {
                "format": partlog.VERSION, "job_name": job.name, "analysis": job.analysis_name,
                "job_sha256": job.sha256, "job_text": job.text, "n_tasks": job.layout.n_tasks,
                "n_chunks": job.layout.n_chunks, "chunk": job.layout.chunk, "variables": layout(job)})
    elif not resume:
        raise RunError(f"{parts}/ holds the parts of an earlier run: add --resume to continue "
                       "it, or --overwrite (or delete the directory) to start again")
    manifest = read_manifest(parts)
    if manifest["job_sha256"] != job.sha256:
        raise RunError(f"cannot resume: {parts}/ was written by a different job file (its text "
                       f"has sha256 {manifest['job_sha256'][:12]}..., this one {job.sha256[:12]}...); "
                       "restore that file, or start again with --overwrite or another -o")
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
    run = max((int(m.group(1)) for m in map(RUN.fullmatch, (p.name for p in parts.iterdir())) if m),
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
