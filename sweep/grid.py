"""The task set of a sweep: a flat, ordered list of tasks plus a shape, cut into chunks.

Task ``t`` is the C-order flat index into ``(*grid_shape, n_subtasks)``: the grid keys
vary in the canonical order of :data:`~sweep.analyses.base.GRID_KEYS` (the last one
fastest), the subtask fastest of all.  Chunk ``k`` holds tasks ``k*chunk`` up to
``(k+1)*chunk - 1``.  All of it is a pure function of the job, never of the rank count,
which is what makes ``--resume`` and rank-count independent results possible.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: A default chunk size keeps the number of part files at or below this.
MAX_DEFAULT_CHUNKS = 1024


def default_chunk(n_tasks: int) -> int:
    """Tasks per chunk when the job does not say.

    Parameters
    ----------
    n_tasks : int
        Number of tasks of the job.

    Returns
    -------
    int
        The smallest chunk size giving at most :data:`MAX_DEFAULT_CHUNKS` chunks.
    """
    return max(1, math.ceil(n_tasks / MAX_DEFAULT_CHUNKS))


@dataclass(frozen=True, eq=False)
class TaskLayout:
    """Tasks and chunks of a sweep.

    Parameters
    ----------
    dims : tuple of str
        Grid keys present in the job, in canonical order.
    values : tuple of numpy.ndarray
        1-D float64 values of each grid key, in the same order.
    n_subtasks : int
        Subtasks per grid point.
    chunk : int
        Tasks per chunk (the last chunk may be shorter).
    cases : tuple of tuples of (str, float)
        ``[grid] cases``: the grid points computed are those matching one case (every key
        of a case equal to the point's value); empty: the whole product.
    """

    dims: tuple[str, ...]
    values: tuple[np.ndarray, ...]
    n_subtasks: int
    chunk: int
    cases: tuple[tuple[tuple[str, float], ...], ...] = ()

    def in_cases(self, point: dict[str, float]) -> bool:
        """Whether the grid point ``point`` (grid key -> value) is computed."""
        return not self.cases or any(all(math.isclose(point[k], v, rel_tol=1e-12) for k, v in case)
                                     for case in self.cases)

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the grid (without the subtask axis)."""
        return tuple(len(v) for v in self.values)

    @property
    def n_tasks(self) -> int:
        """Number of tasks: grid points times subtasks."""
        return math.prod(self.shape) * self.n_subtasks

    @property
    def n_chunks(self) -> int:
        """Number of chunks."""
        return math.ceil(self.n_tasks / self.chunk)

    def chunk_tasks(self, k: int) -> range:
        """Task indices of chunk ``k``."""
        return range(k * self.chunk, min((k + 1) * self.chunk, self.n_tasks))

    def task(self, t: int) -> tuple[dict[str, float], int]:
        """Grid values and subtask index of task ``t``.

        Returns
        -------
        point : dict of str to float
            The grid value of each grid key.
        subtask : int
            The subtask index.
        """
        *index, subtask = np.unravel_index(t, (*self.shape, self.n_subtasks))
        point = {d: float(v[i]) for d, v, i in zip(self.dims, self.values, index)}
        return point, int(subtask)

    def describe(self, t: int) -> str:
        """``"task 5 of 64 (delta=1.5, delta_o=0.3, subtask 0)"``, for messages."""
        point, subtask = self.task(t)
        values = ", ".join(f"{k}={v!r}" for k, v in point.items())
        return f"task {t} of {self.n_tasks} ({values}, subtask {subtask})"
