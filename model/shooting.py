"""Periodic responses of the forced ROM by shooting on the stroboscopic map (section 4.3).

A ``T``-periodic response (``T = 2 pi / Omega``) of the forced ROM of Eq. (31) is a fixed
point of the stroboscopic (Poincare) map ``P(y) = phi_T(y)``, the RK4 flow over one forcing
period from ``t = 0``.  :func:`shoot` solves ``F(y) = P(y) - y = 0`` by Newton's method with
the monodromy matrix ``Phi = dP/dy`` of :func:`model.integrate.monodromy` (the exact
derivative of the discrete map, built from the ROM's closed-form Jacobian), so it converges
in a few iterations from a good guess however slowly transients decay (Floquet multipliers
of modulus ~0.998 at c = 0.05).  The eigenvalues of ``Phi`` are the Floquet multipliers;
the response is stable when all of them lie inside the unit circle.

Scaling: a state ``y = (q, q')`` is measured in the norm ``|S y|`` with
``S = diag(1, ..., 1, 1/Omega, ..., 1/Omega)``, so that displacements and velocities
weigh alike.

Amplitude: ``max_t |w(0.5 Re, 0, t)|`` over one period of the orbit, from the RK4 samples
with a parabolic refinement of the largest one (error ~ (2 pi / steps)^4, ~1e-7 relative at
the default 128 steps).
"""

from __future__ import annotations

from typing import NamedTuple

import numba as nb
import numpy as np

from .integrate import monodromy, rk4_period
from .params import Loading
from .rom import Rom

#: RK4 steps per forcing period.  At delta = 1.1, Omega = 33.5, c = 0.05 the fold values in
#: P0 change by 2e-6 (relative) from 128 to 256 steps and by 3e-5 from 64 to 128 steps
#: (checked in tests/test_shooting.py and docs/performance.md).
DEFAULT_STEPS = 128


class PeriodicOrbit(NamedTuple):
    """A periodic response found by :func:`shoot`.

    Attributes
    ----------
    state : (2K,) array
        ``y(0) = (q, q')`` on the orbit at the forcing phase ``t = 0`` (m, m s-1).
    multipliers : (2K,) complex array
        Floquet multipliers, sorted by decreasing modulus.
    stable : bool
        All multipliers strictly inside the unit circle.
    amplitude : float
        ``max_t |w(0.5 Re, 0, t)|`` over one period (m).
    residual : float
        Final ``|S F(y)| / (|S y| + atol)`` (1).
    iterations : int
        Newton iterations used.
    converged : bool
        ``residual <= tol``.
    """

    state: np.ndarray
    multipliers: np.ndarray
    stable: bool
    amplitude: float
    residual: float
    iterations: int
    converged: bool


def state_scale(dof: int, omega: float) -> np.ndarray:
    """Diagonal of ``S``: 1 for the K displacements, ``1/Omega`` (s) for the K velocities."""
    return np.concatenate([np.ones(dof), np.full(dof, 1.0 / omega)])


@nb.njit(cache=True)
def _period_amplitude(y, steps, tab, c_damp, p_load, omega, work):
    # One RK4 period from t = 0, in place on y, sampling w = probe @ q after every step;
    # the largest |w| is refined by the vertex of the parabola through its neighbours.
    # (The vertex formula holds for |w| when w keeps its sign over the three samples.)
    K = y.size // 2
    h = 2.0 * np.pi / omega / steps
    w = np.empty(steps + 1)
    w[0] = 0.0
    for k in range(K):
        w[0] += tab.probe[k] * y[k]
    t = 0.0
    for i in range(steps):
        t = rk4_period(y, t, h, 1, tab, c_damp, p_load, omega, work)
        s = 0.0
        for k in range(K):
            s += tab.probe[k] * y[k]
        w[i + 1] = s
    # the samples are treated as periodic (w[steps] = w[0] on a periodic orbit)
    best = 0
    for i in range(steps):
        if abs(w[i]) > abs(w[best]):
            best = i
    a = abs(w[best])
    wm = abs(w[best - 1 if best > 0 else steps - 1])
    wp = abs(w[best + 1])
    den = wm - 2.0 * a + wp
    if den < 0.0:
        a = a - 0.125 * (wp - wm) ** 2 / den
    return a


def period_map(rom: Rom, loading: Loading, y, steps: int = DEFAULT_STEPS, periods: int = 1) -> np.ndarray:
    """Apply the stroboscopic map ``periods`` times to ``y`` (returns a new state).

    Parameters
    ----------
    rom : Rom
    loading : Loading
        ``Omega`` (rad s-1), ``P0`` (Pa), ``c`` (N s m-3).
    y : (2K,) array
        State at ``t = 0``.
    steps : int
        RK4 steps per period.
    periods : int
        Number of forcing periods.
    """
    y = np.array(y, dtype=float)
    period = 2.0 * np.pi / loading.Omega
    work = np.empty((6, y.size))
    cd = damping_rate(rom, loading)
    for _ in range(periods):
        rk4_period(y, 0.0, period / steps, steps, rom.tables, cd, loading.P0, loading.Omega, work)
    return y


def damping_rate(rom: Rom, loading: Loading) -> float:
    """``c / (Gamma h)`` (s-1), the damping coefficient the kernels take."""
    return loading.c / (rom.membrane.Gamma * rom.membrane.h)


def orbit_amplitude(rom: Rom, loading: Loading, y, steps: int = DEFAULT_STEPS) -> float:
    """``max |w(probe, t)|`` (m) over one forcing period starting from ``y`` at ``t = 0``."""
    y = np.array(y, dtype=float)
    work = np.empty((6, y.size))
    return float(_period_amplitude(y, steps, rom.tables, damping_rate(rom, loading),
                                   loading.P0, loading.Omega, work))


def floquet(rom: Rom, loading: Loading, y, steps: int = DEFAULT_STEPS) -> tuple[np.ndarray, np.ndarray]:
    """``P(y)`` and the monodromy matrix ``Phi = dP/dy`` (RK4 variational equations).

    Returns
    -------
    yT : (2K,) array
    phi : (2K, 2K) array
    """
    y = np.array(y, dtype=float)
    return monodromy(y, 0.0, 2.0 * np.pi / loading.Omega, steps, rom.tables,
                     damping_rate(rom, loading), loading.P0, loading.Omega)


def sorted_multipliers(phi: np.ndarray) -> np.ndarray:
    """Eigenvalues of ``phi`` sorted by decreasing modulus (then by imaginary part)."""
    mu = np.linalg.eigvals(phi).astype(complex)
    return mu[np.lexsort((-mu.imag, -np.abs(mu)))]


def shoot(rom: Rom, loading: Loading, guess, steps: int = DEFAULT_STEPS, tol: float = 1e-10,
          max_iter: int = 25, atol: float = 1e-12) -> PeriodicOrbit:
    """Periodic response by Newton's method on ``F(y) = P(y) - y`` (stroboscopic map).

    Parameters
    ----------
    rom : Rom
    loading : Loading
        ``Omega`` (rad s-1), ``P0`` (Pa), ``c`` (N s m-3).
    guess : (2K,) array
        Initial guess of ``y(0) = (q, q')`` (m, m s-1).
    steps : int
        RK4 steps per forcing period.
    tol : float
        Convergence: ``|S F(y)| <= tol (|S y| + atol)``.
    max_iter : int
        Newton iterations allowed.
    atol : float
        Absolute floor (m) of the relative test, for responses near ``y = 0``.

    Returns
    -------
    PeriodicOrbit
        ``converged`` is False when Newton did not meet ``tol`` (never raises for that).
    """
    y = np.array(guess, dtype=float)
    if y.shape != (2 * rom.dof,):
        raise ValueError(f"guess.shape = {y.shape} is invalid: expected ({2 * rom.dof},) = (q, q')")
    s = state_scale(rom.dof, loading.Omega)
    eye = np.eye(y.size)
    res = np.inf
    it = 0
    while True:
        yT, phi = floquet(rom, loading, y, steps)
        f = yT - y
        res = float(np.linalg.norm(s * f) / (np.linalg.norm(s * y) + atol))
        if res <= tol or it >= max_iter or not np.isfinite(res):
            break
        try:
            dy = np.linalg.solve(phi - eye, -f)
        except np.linalg.LinAlgError:
            break
        y = y + dy
        it += 1
    mu = sorted_multipliers(phi)
    converged = bool(res <= tol)
    return PeriodicOrbit(y, mu, bool(np.max(np.abs(mu)) < 1.0), orbit_amplitude(rom, loading, y, steps),
                         res, it, converged)
