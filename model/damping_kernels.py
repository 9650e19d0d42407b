"""The matrix part of a damping law in the compiled kernels (:mod:`model.damping`).

``q'' = ... - (rate I + matrix) q'``: the kernels apply the scalar ``rate`` themselves, in
the loop that forms the acceleration, and call these helpers for ``matrix`` only when it
is not empty (:data:`model.damping.NO_MATRIX`), so a scalar law costs them nothing.
"""

from __future__ import annotations

import numba as nb


@nb.njit(cache=True, inline="always")
def add_matrix_damping(matrix, v, out):
    """``out[k] -= sum_j matrix[k, j] v[j]``: the matrix part of a law's damping force in
    acceleration form (nothing for :data:`model.damping.NO_MATRIX`)."""
    K = matrix.shape[0]
    for k in range(K):
        s = 0.0
        for j in range(K):
            s += matrix[k, j] * v[j]
        out[k] -= s


@nb.njit(cache=True, inline="always")
def add_matrix_damping_columns(matrix, vs, count, out):
    """:func:`add_matrix_damping` for the first ``count`` columns of ``vs`` ``(K, B)`` at
    once (lock-step batches), into ``out[k, b]``: loops over the columns innermost."""
    K = matrix.shape[0]
    for k in range(K):
        for j in range(K):
            d = matrix[k, j]
            for b in range(count):
                out[k, b] -= d * vs[j, b]
