"""Periodic responses by shooting on the stroboscopic map (section 4.3): Newton on ``P^k``.

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

:func:`newton_map_power` is the one Newton iteration on ``P^k(y) - y = 0`` of the package:
:func:`shoot` is its ``k = 1`` case with a relative test, and the attractor search of the
basins (:func:`model.attractors.find_periodic_orbit`) its ``k >= 1`` case with an absolute
test and limited steps (with a compiled copy for one-mode ROMs in their force table).
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
    found = newton_map_power(fmap, y, 1, fmap.state_scale(), tol, atol=atol, max_iter=max_iter)
    mu = sorted_multipliers(found.jacobian)
    return PeriodicOrbit(found.state, mu, bool(np.max(np.abs(mu)) < 1.0), fmap.amplitude(found.state),
                         found.residual, found.iterations, found.converged)


class MapPowerSolution(NamedTuple):
    """The outcome of :func:`newton_map_power`.

    Attributes
    ----------
    state : (2K,) array
        The last iterate ``y``.
    points : (k, 2K) array
        ``P^j(y)``, ``j = 0..k-1``: the orbit through ``y``.
    jacobian : (2K, 2K) array
        ``d P^k / dy`` at ``y`` (the product of the monodromy matrices along the orbit).
    residual : float
        The last residual of the test (see :func:`newton_map_power`).
    iterations : int
        Newton steps taken.
    converged : bool
        ``residual <= tol``.
    """

    state: np.ndarray
    points: np.ndarray
    jacobian: np.ndarray
    residual: float
    iterations: int
    converged: bool


def newton_map_power(fmap: StroboscopicMap, y0, k: int, scale, tol: float, *, atol: float | None = None,
                     max_iter: int = 25, max_step: float = np.inf) -> MapPowerSolution:
    """Newton's method on ``F(y) = P^k(y) - y = 0``, ``P`` the stroboscopic map.

    Each iteration integrates ``k`` periods with the variational equations
    (``fmap.monodromy``), so ``dF/dy = dP^k/dy - I`` is the exact derivative of the
    discrete map, and solves for the step.  It stops when the residual meets ``tol``, after
    ``max_iter`` steps, at a state or residual that is not finite, or at a singular system.

    Parameters
    ----------
    fmap : StroboscopicMap
    y0 : (2K,) array
        Starting state at ``t = 0``.
    k : int
        Period of the orbit in forcing periods (>= 1).
    scale : (2K,) array
        Weights ``S`` of the norm.
    tol : float
        The test: ``|S F(y)| / (|S y| + atol) <= tol`` with ``atol`` (relative, with an
        absolute floor), ``|S F(y)| <= tol`` without.
    max_iter : int
        Newton steps allowed.
    max_step : float
        Largest step in the norm ``|S dy|`` (damped Newton); default unlimited.

    Returns
    -------
    MapPowerSolution
    """
    y = np.array(y0, dtype=np.float64)
    eye = np.eye(y.size)
    it = 0
    while True:
        z, phi = fmap.monodromy(y)
        points = [y.copy()]
        for _ in range(k - 1):
            points.append(z.copy())
            z, m = fmap.monodromy(z)
            phi = m @ phi
        f = z - y
        res = float(np.linalg.norm(scale * f))
        if atol is not None:
            res /= float(np.linalg.norm(scale * y)) + atol
        if res <= tol or it >= max_iter or not np.isfinite(res):
            break
        try:
            dy = np.linalg.solve(phi - eye, -f)
        except np.linalg.LinAlgError:
            break
        size = float(np.linalg.norm(dy * scale))
        if size > max_step:
            dy *= max_step / size
        y = y + dy
        it += 1
    return MapPowerSolution(y, np.array(points), phi, res, it, bool(res <= tol))
