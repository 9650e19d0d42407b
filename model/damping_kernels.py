"""The matrix part of a damping law in the compiled kernels (:mod:`model.damping`).

``q'' = ... - (rate I + matrix) q'``: the kernels apply the scalar ``rate`` themselves, in
the loop that forms the acceleration, and call these helpers for ``matrix`` only when it
is not empty (:data:`model.damping.NO_MATRIX`), so a scalar law costs them nothing.  The
kernels called from Python take the matrix as an argument that is None for a scalar law
(:func:`matrix_or_none`): numba prunes the branch of the matrix term with it, and the
scalar law runs the very code it ran before laws existed (the lock-step quadrature, the
variational equations and the family blocks measured 10-30 % slower with a zero-trip loop
in their inner loops).
"""

from __future__ import annotations

import numba as nb


def matrix_or_none(matrix):
    """``matrix``, or None when it is empty (a scalar law): what the kernels taking the
    damping matrix as an argument expect."""
    return matrix if matrix.shape[0] > 0 else None


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
