"""Append-only part logs: the results of finished chunks, one log file per rank and run.

A log is a sequence of records, one per chunk, each written with a single ``write`` call
and synced to disk (``os.fsync``) before the next chunk starts: a killed process or a
power loss loses at most the chunk being written::

    header  <4s H H q q q q I>  magic b"MSWP", format version, 0, chunk number,
                                first task, task count, payload length, CRC-32
    payload                     status (int8 per task), every variable of the analysis in
                                declared order (raw little-endian arrays, task axis first),
                                then the per-task messages as JSON ``{"offset": "text"}``

The CRC-32 covers the header (with its CRC field zero) and the payload, so a flipped
byte, a truncated tail or a record claiming another chunk's tasks are detected when the
log is read.  A process killed while writing leaves at most its last record torn; the
reader stops at it.  HDF5 is not used for the logs on purpose: an HDF5 file whose writer
is killed mid-write can become unreadable as a whole, losing every chunk in it.
"""

from __future__ import annotations

import heapq
import json
import os
import struct
import zlib
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

MAGIC = b"MSWP"
VERSION = 1
_HEADER = struct.Struct("<4sHHqqqqI")
#: Logs a merge keeps open at once: those :class:`Reader` keeps (the least recently used
#: is closed beyond this), and one more while :func:`scan` verifies a batch of records.
MAX_OPEN = 64
#: Records :func:`scan` verifies per opening of a log.
SCAN_BATCH = 256


@dataclass(frozen=True)
class Record:
    """Where one chunk's results lie in a log.

    Parameters
    ----------
    path : pathlib.Path
        The log file.
    offset : int
        Byte offset of the record's payload.
    length : int
        Payload length in bytes.
    chunk, task_start, task_count : int
        The chunk and its tasks ``task_start .. task_start + task_count - 1``.
    """

    path: Path
    offset: int
    length: int
    chunk: int
    task_start: int
    task_count: int


def _fields(variables, count: int):
    """``(name, dtype, shape, nbytes)`` of the payload's arrays for ``count`` tasks."""
    out = [("status", np.dtype("<i1"), (count,))]
    out += [(v.name, np.dtype(v.dtype).newbyteorder("<"), (count, *v.shape)) for v in variables]
    return [(name, dt, shape, dt.itemsize * int(np.prod(shape))) for name, dt, shape in out]


def encode(chunk: int, tasks: range, status: np.ndarray, arrays: Mapping[str, np.ndarray],
           messages: Mapping[int, str], variables: Sequence) -> bytes:
    """The bytes of one record (header and payload)."""
    parts = [np.ascontiguousarray(status, dtype="<i1").tobytes()]
    for v in variables:
        parts.append(np.ascontiguousarray(arrays[v.name], dtype=np.dtype(v.dtype).newbyteorder("<")).tobytes())
    parts.append(json.dumps({str(k): m for k, m in messages.items()}).encode())
    payload = b"".join(parts)
    head = _HEADER.pack(MAGIC, VERSION, 0, chunk, tasks.start, len(tasks), len(payload), 0)
    crc = zlib.crc32(payload, zlib.crc32(head))
    return _HEADER.pack(MAGIC, VERSION, 0, chunk, tasks.start, len(tasks), len(payload), crc) + payload


class Writer:
    """Appends records to one log file (a rank's log of one run).

    Parameters
    ----------
    path : pathlib.Path
        The log; created, or appended to.
    variables : sequence of Variable
        The analysis' variables, in declared order.
    """

    def __init__(self, path: Path, variables: Sequence):
        self.path, self.variables = path, list(variables)
        self._fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
        # the new file's directory entry, without which its synced records are lost too
        directory = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(directory)
        finally:
            os.close(directory)

    def append(self, chunk: int, tasks: range, status: np.ndarray, arrays: Mapping[str, np.ndarray],
               messages: Mapping[int, str]) -> None:
        """Write one chunk's record in one ``write`` call and sync it to disk."""
        data = encode(chunk, tasks, status, arrays, messages, self.variables)
        view = memoryview(data)
        while view:
            view = view[os.write(self._fd, view):]
        os.fsync(self._fd)

    def close(self) -> None:
        """Close (every record is on disk already); a log with no record is removed."""
        if self._fd >= 0:
            empty = os.fstat(self._fd).st_size == 0
            os.close(self._fd)
            self._fd = -1
            if empty:
                self.path.unlink(missing_ok=True)


def scan(path: Path, chunk_size: int, n_tasks: int, problems: list) -> Iterator[Record]:
    """The verified records of one log, in file order; what is wrong goes to ``problems``.

    Each record's CRC is checked and its task range compared with the job's chunk layout
    (``chunk_size`` tasks per chunk, ``n_tasks`` in all); a rank writes its chunks in
    increasing order, so a record out of that order is rejected too.  A rejected record
    is skipped; an unreadable header ends the scan (nothing after it can be located).
    ``problems`` receives ``(chunk or -1, one line naming the file and the offset)``.

    The log is open only while a batch of :data:`SCAN_BATCH` records is verified, never
    while they are yielded: a merge of many logs (:class:`Logs`) holds none of them open
    between its records.
    """
    size = path.stat().st_size
    pos, last, ended = 0, -1, False
    while pos < size and not ended:
        with open(path, "rb") as f:
            f.seek(pos)
            batch, pos, last, ended = _verify(f, path, pos, size, last, chunk_size, n_tasks, problems)
        yield from batch


def _verify(f, path, pos, size, last, chunk_size, n_tasks, problems):
    """Verify up to :data:`SCAN_BATCH` records of the open log ``f`` from byte ``pos`` (see
    :func:`scan`); returns ``(records, next pos, last chunk, whether the scan ended)``."""
    batch = []
    while pos < size and len(batch) < SCAN_BATCH:
        head = f.read(_HEADER.size)
        if len(head) < _HEADER.size:
            problems.append((-1, f"{path}: truncated record header at byte {pos} (a run killed "
                                 "while writing); its chunk will be recomputed"))
            return batch, pos, last, True
        magic, version, _, chunk, start, count, length, crc = _HEADER.unpack(head)
        if magic != MAGIC or version != VERSION or length < 0 or count < 0:
            problems.append((-1, f"{path}: unreadable record header at byte {pos}; the rest of the "
                                 "file is ignored and its chunks will be recomputed"))
            return batch, pos, last, True
        if length > size - pos - _HEADER.size:
            problems.append((chunk, f"{path}: chunk {chunk} truncated at byte {pos} (a run killed "
                                    "while writing, or a damaged length); it will be recomputed"))
            return batch, pos, last, True
        payload = f.read(length)
        zero = _HEADER.pack(magic, version, 0, chunk, start, count, length, 0)
        if zlib.crc32(payload, zlib.crc32(zero)) != crc:
            problems.append((chunk, f"{path}: chunk {chunk} at byte {pos} fails its checksum "
                                    "(corrupted); it is not merged and will be recomputed"))
        elif start != chunk * chunk_size or count != min(chunk_size, n_tasks - start) or count <= 0:
            problems.append((-1, f"{path}: record at byte {pos} claims chunk {chunk} with tasks "
                                 f"{start}..{start + count - 1}, which is not that chunk of this job; "
                                 "ignored"))
        elif chunk <= last:
            problems.append((-1, f"{path}: record at byte {pos} (chunk {chunk}) is out of order "
                                 "(a rank writes its chunks in increasing order); ignored"))
        else:
            last = chunk
            batch.append(Record(path, pos + _HEADER.size, length, chunk, start, count))
        pos += _HEADER.size + length
    return batch, pos, last, False


class Logs:
    """The verified records of a set of logs, streamed in chunk order.

    Iterating merges the logs (each is in increasing chunk order) and yields every chunk
    once: a chunk found twice (two runs computed it) keeps its first verified record,
    results being a function of the task only.  Memory does not grow with the number of
    records (one bit per chunk records what was found, at most :data:`SCAN_BATCH` records
    per log are held), nor do open files with the number of logs (at most :data:`MAX_OPEN`
    + 1 with a :class:`Reader`).  After an iteration, :attr:`done`
    (a packed bitmap) holds the chunks found, :attr:`tasks` their tasks, and
    :meth:`problems` what was rejected (except chunks with a verified copy elsewhere).

    Parameters
    ----------
    paths : sequence of pathlib.Path
        The log files.
    chunk_size, n_tasks : int
        The job's chunk layout.
    """

    def __init__(self, paths, chunk_size: int, n_tasks: int):
        self.paths, self.chunk_size, self.n_tasks = list(paths), chunk_size, n_tasks
        self.n_chunks = -(-n_tasks // chunk_size)
        self.done = np.zeros((self.n_chunks + 7) // 8, np.uint8)
        self.tasks = 0
        self._problems: list[tuple[int, str]] = []

    def __iter__(self) -> Iterator[Record]:
        self.done[:] = 0
        self.tasks = 0
        self._problems = []
        streams = [scan(p, self.chunk_size, self.n_tasks, self._problems) for p in self.paths]
        last = -1
        for rec in heapq.merge(*streams, key=lambda r: r.chunk):
            if rec.chunk == last:
                continue
            last = rec.chunk
            self.done[rec.chunk >> 3] |= 128 >> (rec.chunk & 7)
            self.tasks += rec.task_count
            yield rec

    def found(self, k: int) -> bool:
        """Whether chunk ``k`` was found by the last iteration."""
        return bool(self.done[k >> 3] & (128 >> (k & 7)))

    def problems(self) -> list[str]:
        """What the last iteration rejected, without the chunks found elsewhere."""
        return [text for k, text in self._problems if k < 0 or not self.found(k)]

    def scan_all(self) -> Logs:
        """Iterate once (verify everything, fill :attr:`done`); returns self."""
        for _ in self:
            pass
        return self


class Reader:
    """Reads records, keeping each log open once (the records of a collect alternate
    between the ranks' logs), at most :data:`MAX_OPEN` of them.  Use as a context manager."""

    def __init__(self, variables: Sequence):
        self.variables = list(variables)
        self._files: dict[Path, object] = {}

    def __enter__(self) -> Reader:
        return self

    def __exit__(self, *exc) -> None:
        for f in self._files.values():
            f.close()
        self._files.clear()

    def read(self, record: Record, *, only_status: bool = False):
        """The contents of one record.

        Returns
        -------
        status : (count,) int8 array
        arrays : dict of str to numpy.ndarray
            Each variable, ``(count, *shape)`` (empty with ``only_status``).
        messages : dict of int to str
            Message of the tasks that have one, by offset in the chunk (empty with
            ``only_status``).
        """
        f = self._files.pop(record.path, None)
        if f is None:
            if len(self._files) >= MAX_OPEN:
                self._files.pop(next(iter(self._files))).close()
            f = open(record.path, "rb")
        self._files[record.path] = f  # most recently used last
        f.seek(record.offset)
        fields = _fields(self.variables, record.task_count)
        if only_status:
            return np.frombuffer(f.read(record.task_count), np.int8), {}, {}
        payload = f.read(record.length)
        pos, out = 0, {}
        for name, dt, shape, nbytes in fields:
            out[name] = np.frombuffer(payload, dt, int(np.prod(shape)), pos).reshape(shape)
            pos += nbytes
        messages = {int(k): m for k, m in json.loads(payload[pos:].decode()).items()}
        return out.pop("status"), out, messages
