"""The classical fourth-order Runge-Kutta scheme (Kutta 1901), written once.

Every fixed-step integrator of the package (:mod:`model.integrate`, :mod:`model.families`)
takes its tableau from here: stage ``s = 0..3`` is evaluated at ``t + stage_offset(s, h)``
from ``y + stage_offset(s, h) k_{s-1}``, and the step is
``y += step_factor(h) * combine(k_0, k_1, k_2, k_3)``, i.e. ``h/6 (k_0 + 2 k_1 + 2 k_2 + k_3)``
(accumulated stage by stage with :func:`stage_weight` where a kernel keeps no four stages).
The kernels are specialised for speed (one mode from a force table, lock-step batches,
the quadrature, the variational equations), not their scheme: these functions inline into
them (``inline="always"``), so the arithmetic is exactly that of the tableau written out.
"""

from __future__ import annotations

import numba as nb


@nb.njit(cache=True, inline="always")
def stage_offset(s, h):
    """Time (and slope) offset of stage ``s`` within a step of size ``h``: 0, h/2, h/2, h."""
    return 0.0 if s == 0 else (h if s == 3 else 0.5 * h)


@nb.njit(cache=True, inline="always")
def stage_weight(s):
    """Weight of stage ``s`` in the step, in units of ``h/6``: 1, 2, 2, 1."""
    return 1.0 if (s == 0 or s == 3) else 2.0


@nb.njit(cache=True, inline="always")
def combine(k0, k1, k2, k3):
    """``k0 + 2 k1 + 2 k2 + k3``: the stages' slopes combined (times :func:`step_factor`)."""
    return k0 + 2.0 * k1 + 2.0 * k2 + k3


@nb.njit(cache=True, inline="always")
def step_factor(h):
    """``h / 6``: the factor of :func:`combine` in the step."""
    return h / 6.0


@nb.njit(cache=True, inline="always")
def stage_matrix(phi, kp, s, h, out):
    """``out = phi + stage_offset(s, h) kp[s - 1]`` (``out = phi`` at ``s = 0``): the state of
    stage ``s`` of a matrix ``phi`` (a variational block) whose stage slopes are ``kp``."""
    f = stage_offset(s, h)
    for a in range(phi.shape[0]):
        for b in range(phi.shape[1]):
            out[a, b] = phi[a, b] + f * kp[s - 1, a, b] if s > 0 else phi[a, b]


@nb.njit(cache=True, inline="always")
def step_matrix(phi, kp, h):
    """``phi += step_factor(h) combine(kp[0], .., kp[3])``: the step of a matrix ``phi``."""
    for a in range(phi.shape[0]):
        for b in range(phi.shape[1]):
            phi[a, b] += step_factor(h) * combine(kp[0, a, b], kp[1, a, b], kp[2, a, b], kp[3, a, b])


def amplification(z):
    """RK4's amplification factor ``R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24`` of one step on
    ``y' = lambda y`` with ``z = lambda h`` (numpy, complex): ``R(z)^N`` after ``N`` steps."""
    return 1.0 + z * (1.0 + z / 2.0 * (1.0 + z / 3.0 * (1.0 + z / 4.0)))


def stable(eigenvalues, h: float) -> bool:
    """Whether RK4 steps of ``h`` (s) keep every mode ``exp(lambda t)`` of a linear system with
    ``eigenvalues`` (s-1) from growing: ``|R(lambda h)| <= 1`` for all (the stability region
    reaches 2.83 along the imaginary axis, 2.79 along the negative real one and 2.6 between)."""
    import numpy as np

    return bool(np.all(np.abs(amplification(np.asarray(eigenvalues) * h)) <= 1.0 + 1e-12))
