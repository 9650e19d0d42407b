"""Fixed-step integration of the ROM for stroboscopic (Poincare) sampling.

The classical fourth-order Runge-Kutta scheme with an integer number of steps per forcing
period ``2 pi / Omega``, so that every ``steps``-th state is a point of the stroboscopic
map.  :func:`rk4_period` advances one state by one period in place (the building block of
basins and brute-force sweeps); :func:`strobe_many` advances a batch of trajectories;
:func:`monodromy` integrates the state together with the variational equations and returns
the monodromy matrix of the stroboscopic map (shooting, Floquet multipliers).

All kernels take the :class:`model.rom.RomTables` and scalars only: ``c_damp = c/(Gamma h)``
(s-1), ``p_load = P0`` (Pa), ``omega = Omega`` (rad s-1).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from .rom import force_jacobian, rhs


@nb.njit(cache=True)
def rk4_period(y, t0, h, steps, tab, c_damp, p_load, omega, work):
    """Advance ``y`` (in place) by ``steps`` RK4 steps of size ``h`` from ``t0``.

    ``work`` is a ``(6, 2K)`` scratch array (``K`` = number of modes).
    """
    n = y.size
    K = n // 2
    k1 = work[0]
    k2 = work[1]
    k3 = work[2]
    k4 = work[3]
    tmp = work[4]
    g = work[5, :K]
    t = t0
    for _ in range(steps):
        rhs(t, y, tab, c_damp, p_load, omega, g, k1)
        for i in range(n):
            tmp[i] = y[i] + 0.5 * h * k1[i]
        rhs(t + 0.5 * h, tmp, tab, c_damp, p_load, omega, g, k2)
        for i in range(n):
            tmp[i] = y[i] + 0.5 * h * k2[i]
        rhs(t + 0.5 * h, tmp, tab, c_damp, p_load, omega, g, k3)
        for i in range(n):
            tmp[i] = y[i] + h * k3[i]
        rhs(t + h, tmp, tab, c_damp, p_load, omega, g, k4)
        for i in range(n):
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        t += h
    return t


@nb.njit(cache=True)
def strobe_many(y0, periods, steps, tab, c_damp, p_load, omega, out):
    """Integrate a batch of trajectories and record their stroboscopic points.

    Parameters
    ----------
    y0 : (N, 2K) array
        Initial states at ``t = 0`` (the phase of the forcing ``cos(Omega t)``).
    periods : int
        Number of forcing periods.
    steps : int
        RK4 steps per period.
    out : (N, periods + 1, 2K) array
        Receives the states at ``t = j 2 pi / Omega``, ``j = 0..periods``.
    """
    N, n = y0.shape
    period = 2.0 * np.pi / omega
    h = period / steps
    work = np.empty((6, n))
    y = np.empty(n)
    for i in range(N):
        y[:] = y0[i]
        out[i, 0] = y
        for j in range(periods):
            rk4_period(y, j * period, h, steps, tab, c_damp, p_load, omega, work)
            out[i, j + 1] = y


@nb.njit(cache=True)
def _aug_rhs(t, z, n, tab, c_damp, p_load, omega, g, jac, out):
    # z = (y, Phi.ravel()); Phi' = A Phi with A = [[0, I], [-diag(k) J(q), -c I]].
    K = n // 2
    rhs(t, z[:n], tab, c_damp, p_load, omega, g, out[:n])
    force_jacobian(z[:K], tab, jac)
    for col in range(n):
        for i in range(K):
            out[n + i * n + col] = z[n + (K + i) * n + col]
        for i in range(K):
            acc = -c_damp * z[n + (K + i) * n + col]
            for l in range(K):
                acc -= tab.k_force[i] * jac[i, l] * z[n + l * n + col]
            out[n + (K + i) * n + col] = acc


@nb.njit(cache=True)
def monodromy(y0, t0, period, steps, tab, c_damp, p_load, omega):
    """State after one period and the monodromy matrix ``d y(t0+T) / d y(t0)``.

    The variational equations are integrated with the same RK4 steps as the state, so
    the matrix is the exact derivative of the discrete stroboscopic map.

    Returns
    -------
    yT : (2K,) array
    phi : (2K, 2K) array
    """
    n = y0.size
    K = n // 2
    m = n + n * n
    z = np.zeros(m)
    z[:n] = y0
    for i in range(n):
        z[n + i * n + i] = 1.0
    k1 = np.empty(m)
    k2 = np.empty(m)
    k3 = np.empty(m)
    k4 = np.empty(m)
    tmp = np.empty(m)
    g = np.empty(K)
    jac = np.empty((K, K))
    h = period / steps
    t = t0
    for _ in range(steps):
        _aug_rhs(t, z, n, tab, c_damp, p_load, omega, g, jac, k1)
        for i in range(m):
            tmp[i] = z[i] + 0.5 * h * k1[i]
        _aug_rhs(t + 0.5 * h, tmp, n, tab, c_damp, p_load, omega, g, jac, k2)
        for i in range(m):
            tmp[i] = z[i] + 0.5 * h * k2[i]
        _aug_rhs(t + 0.5 * h, tmp, n, tab, c_damp, p_load, omega, g, jac, k3)
        for i in range(m):
            tmp[i] = z[i] + h * k3[i]
        _aug_rhs(t + h, tmp, n, tab, c_damp, p_load, omega, g, jac, k4)
        for i in range(m):
            z[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        t += h
    return z[:n].copy(), z[n:].reshape(n, n).copy()
