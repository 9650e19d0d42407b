"""Periodic responses of the forced ROM by shooting on the stroboscopic map (section 4.3).

A ``T``-periodic response (``T = 2 pi / Omega``) of the forced ROM of Eq. (31) is a fixed
point of the stroboscopic (Poincare) map ``P`` (:class:`model.protocol.StroboscopicMap`, e.g.
the ROM's :class:`model.forced.ForcedMap`).
:func:`shoot` solves ``F(y) = P(y) - y = 0`` by Newton's method with the monodromy matrix
``Phi = dP/dy`` (the exact derivative of the discrete RK4 map, built from the ROM's
closed-form Jacobian), so it converges in a few iterations from a good guess however
slowly transients decay (Floquet multipliers of modulus ~0.998 at c = 0.05).  The
eigenvalues of ``Phi`` are the Floquet multipliers; the response is stable when all of
them lie inside the unit circle.  Residuals are measured in the scaled norm ``|S y|`` of
:func:`model.forced.state_scale`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .protocol import StroboscopicMap, sorted_multipliers


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


def shoot(fmap: StroboscopicMap, guess, tol: float = 1e-10, max_iter: int = 25,
          atol: float = 1e-12) -> PeriodicOrbit:
    """Periodic response by Newton's method on ``F(y) = P(y) - y`` (stroboscopic map).

    Parameters
    ----------
    fmap : StroboscopicMap
        The stroboscopic map (ROM, forcing, RK4 steps per period).
    guess : (2K,) array
        Initial guess of ``y(0) = (q, q')`` (m, m s-1).
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
    if y.shape != (2 * fmap.dof,):
        raise ValueError(f"guess.shape = {y.shape} is invalid: expected ({2 * fmap.dof},) = (q, q')")
    s = fmap.state_scale()
    eye = np.eye(y.size)
    res = np.inf
    it = 0
    while True:
        yT, phi = fmap.monodromy(y)
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
    return PeriodicOrbit(y, mu, bool(np.max(np.abs(mu)) < 1.0), fmap.amplitude(y), res, it, converged)
