"""Shared counters for dynamic chunk hand-out: one MPI window on rank 0.

The window holds two int64 slots, the next chunk to hand out and the number of tasks
done.  Every rank keeps a passive-target epoch open (``Lock_all``) for the life of the
counter and uses ``Fetch_and_op`` plus ``Flush``: unlike ``mpi4py.util.sync.Counter``,
which locks and unlocks the window per call, this does not wait for rank 0 to enter the
MPI library, so the other ranks get work while rank 0 computes a long task (checked with
MPICH's shared-memory windows; on several nodes an MPI without hardware atomics may need
asynchronous progress, see ``docs/running.md``).
"""

from __future__ import annotations

import numpy as np
from mpi4py import MPI

_NEXT, _DONE = 0, 1
#: Added to the chunk slot to stop the hand-out: every later claim is past the end.
_POISON = 2**52


class ChunkCounter:
    """Dynamic hand-out of chunk numbers ``0, 1, 2, ...`` and a count of tasks done.

    Parameters
    ----------
    comm : mpi4py.MPI.Intracomm
        Communicator; creation is collective over comm.
    """

    def __init__(self, comm: MPI.Intracomm):
        info = MPI.Info.Create()
        info.Set("alloc_shm", "true")
        size = 2 * 8 if comm.rank == 0 else 0
        self._win = MPI.Win.Allocate(size, 8, info, comm)
        info.Free()
        if comm.rank == 0:
            self._win.Lock(0)
            self._win.Put(np.zeros(2, dtype=np.int64), 0)
            self._win.Unlock(0)
        comm.Barrier()
        self._win.Lock_all()

    def _fetch_add(self, slot: int, increment: int) -> int:
        value = np.array([increment], dtype=np.int64)
        previous = np.zeros(1, dtype=np.int64)
        op = MPI.SUM if increment else MPI.NO_OP
        self._win.Fetch_and_op(value, previous, 0, slot, op)
        self._win.Flush(0)
        return int(previous[0])

    def claim(self) -> int:
        """Take the next chunk number (>= the number of chunks once all are handed out)."""
        return self._fetch_add(_NEXT, 1)

    def stop(self) -> None:
        """Make every later :meth:`claim`, on any rank, return past the end."""
        self._fetch_add(_NEXT, _POISON)

    def add_done(self, n_tasks: int) -> int:
        """Count ``n_tasks`` more tasks done; returns the total done so far, them included."""
        return self._fetch_add(_DONE, n_tasks) + n_tasks

    def free(self) -> None:
        """Release the window; collective over the communicator of creation."""
        self._win.Unlock_all()
        self._win.Free()
