"""Lyapunov exponents, rotation numbers and the kind of a steady response of the stroboscopic map.

A state is iterated ``N`` periods by the map ``P`` (:class:`model.protocol.StroboscopicMap`)
with a full orthonormal frame of tangent vectors (Benettin's method): each period
``Phi_j Q_{j-1} = Q_j R_j`` (QR, ``Phi_j = dP/dy`` at ``y_{j-1}``, the diagonal of ``R_j``
made positive), and the exponents are::

    lambda_i = (1 / (N T)) sum_j log R_j[i, i]        (s-1; lambda_i T per period)

in decreasing order.  The frame is kept orthonormal in the norm ``|S dy|`` of the map's
``state_scale`` ``S`` (displacements and velocities over ``Omega``): the limits do not
depend on the norm, but the finite-run estimates do, and in this norm a tangent vector
turning with a lightly damped mode near the forcing frequency keeps its length over a
period instead of swinging by the ratio ``Omega`` of its components.  Their sum is the mean of ``log |det Phi_j|`` exactly (``Q`` is
orthogonal), the sum rule the tests check; for a mass-proportional (viscous) damping the
flow contracts phase volume at the rate ``trace = -2 alpha K`` whatever the nonlinearity
(Liouville), so the sum is ``-2 K alpha``.  The statistical error of each exponent is taken
from ``blocks`` consecutive block means: ``sqrt(var / blocks)``.  A zero exponent (a
quasi-periodic response: the direction along the invariant circle) has block means that
telescope, their mean is ``O(1 / N)`` while their spread is ``O(blocks / N)``, so it stays
within a few standard errors of zero; a positive one (chaos) grows out of them.

The kind of the response (:func:`classify`), in this order:

* ``diverged``: a state that is not finite (an escape);
* ``periodic`` of least period ``k <= max_period``: the last points recur after ``k`` periods
  within ``recurrence`` of the response's size, Newton on ``P^k(y) = y`` from the last point
  (:func:`model.attractors.find_periodic_orbit`) converges to a stable orbit, and the run
  approaches it (its last point is nearer to the orbit than its first of the same phase in
  the Lyapunov norm of ``P^k`` there, which a linear approach decreases every ``k`` periods,
  or within 1e-6 of the size): a light damping leaves a transient long after the transient
  periods, and the orbit it tends to is what is reported;
* ``chaotic``: ``lambda_1`` above zero by more than its resolution, the larger of ``sigmas``
  standard errors and ``0.1 / (N T)`` (an exponent below the latter changes a tangent
  vector's length by less than 10 % over the whole run: the run cannot tell it from zero);
* ``quasi_periodic``: ``|lambda_1|`` within its resolution, with its rotation number;
* ``unsettled``: ``lambda_1`` below zero by more than its resolution, yet no periodic
  orbit found: a transient slower than the run (raise the transient).
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np
from scipy.linalg import LinAlgWarning, solve_discrete_lyapunov

from .attractors import find_periodic_orbit
from .protocol import StroboscopicMap

#: The kinds of a response, as stored (``response_kind``; -1 is "not computed").
DIVERGED, PERIODIC, QUASI_PERIODIC, CHAOTIC, UNSETTLED = 0, 1, 2, 3, 4
KIND_NAMES = ("diverged", "periodic", "quasi_periodic", "chaotic", "unsettled")


class LyapunovRecord(NamedTuple):
    """Poincare points of ``N`` periods from a state, and the Lyapunov spectrum along them.

    Attributes
    ----------
    points : (N, 2K) array
        ``y_1 .. y_N``, the state after each period (NaN after a state that is not finite).
    exponents : (2K,) array
        Lyapunov exponents (s-1), decreasing; NaN if a state was not finite.
    standard_error : (2K,) array
        Their statistical error (s-1) from the block means.
    log_det : float
        Mean of ``log |det dP/dy|`` over the periods (per period): the sum rule's right side.
    period : float
        The forcing period ``T`` (s).
    """

    points: np.ndarray
    exponents: np.ndarray
    standard_error: np.ndarray
    log_det: float
    period: float

    @property
    def finite(self) -> bool:
        """Every point finite."""
        return bool(np.all(np.isfinite(self.points)))


def lyapunov_spectrum(fmap: StroboscopicMap, y0, periods: int, blocks: int = 10) -> LyapunovRecord:
    """The Lyapunov spectrum of the stroboscopic map along ``periods`` periods from ``y0``.

    Parameters
    ----------
    fmap : StroboscopicMap
    y0 : (2K,) array
        The starting state (after the transient).
    periods : int
        ``N``, a multiple of ``blocks``.
    blocks : int
        Blocks of the error estimate (>= 2).

    Returns
    -------
    LyapunovRecord
    """
    n = 2 * fmap.dof
    if blocks < 2 or periods < blocks or periods % blocks:
        raise ValueError(f"(periods, blocks) = ({periods}, {blocks}) is invalid: need blocks >= 2 and periods a "
                         "positive multiple of blocks")
    y = np.array(y0, dtype=float)
    if y.shape != (n,):
        raise ValueError(f"y0 shape {y.shape} is invalid: need ({n},), a state of the map")
    T = fmap.period
    scale = fmap.state_scale()
    points = np.full((periods, n), np.nan)
    logs = np.empty((periods, n))
    q = np.eye(n)
    for j in range(periods):
        y, phi = fmap.monodromy(y)
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(phi))):
            nan = np.full(n, np.nan)
            return LyapunovRecord(points, nan, nan, np.nan, T)
        points[j] = y
        q, r = np.linalg.qr((scale[:, None] * phi / scale[None, :]) @ q)
        d = np.diag(r)
        q *= np.sign(d)
        logs[j] = np.log(np.abs(d))
    per_block = logs.reshape(blocks, -1, n).mean(axis=1) / T
    exponents = logs.mean(axis=0) / T
    error = per_block.std(axis=0, ddof=1) / np.sqrt(blocks)
    order = np.argsort(-exponents)  # QR keeps them ordered but for ties along the way
    return LyapunovRecord(points, exponents[order], error[order], float(logs.sum(axis=1).mean()), T)


def rotation_number(points, scale) -> float:
    """The rotation number (in [0, 1/2]) of Poincare points on an invariant circle.

    The points, weighted by ``scale``, are projected on the plane of their two principal
    directions about their centroid; the rotation number is the mean angle advanced per
    period over ``2 pi``, folded into [0, 1/2] (a rotation by ``rho`` and by ``1 - rho`` are
    the same circle traversed the other way).

    Returns
    -------
    float
        NaN when the angle does not advance in one sense at every period (the circle is
        not star-shaped about its centroid in that plane, or the points are not on a circle).
    """
    z = (np.asarray(points, dtype=float) - np.mean(points, axis=0)) * scale
    if z.shape[0] < 3 or not np.all(np.isfinite(z)):
        return np.nan
    plane = z @ np.linalg.svd(z, full_matrices=False)[2][:2].T
    theta = np.arctan2(plane[:, 1], plane[:, 0])
    step = np.angle(np.exp(1j * np.diff(theta)))
    if not (np.all(step > 0) or np.all(step < 0)):
        return np.nan
    rho = abs(step.mean()) / (2 * np.pi)
    return float(min(rho, 1.0 - rho))


class Classification(NamedTuple):
    """The kind of a response (:data:`KIND_NAMES`), its least period (periodic; else 0) and
    rotation number (quasi-periodic; else NaN)."""

    kind: int
    period: int
    rotation_number: float


def classify(fmap: StroboscopicMap, record: LyapunovRecord, max_period: int = 16, recurrence: float = 0.1,
             sigmas: float = 3.0) -> Classification:
    """The kind of the response whose Poincare points and spectrum are ``record`` (module
    docstring: the tests, in order).

    Parameters
    ----------
    fmap : StroboscopicMap
    record : LyapunovRecord
        From :func:`lyapunov_spectrum`, at least ``2 max_period`` points.
    max_period : int
        Longest period looked for (forcing periods).
    recurrence : float
        Largest relative distance ``|S (y_{j+k} - y_j)| / max |S y|`` (``S`` the map's
        ``state_scale``) among the last ``max_period + 1`` points at which period ``k`` is
        tried by Newton.
    sigmas : float
        Standard errors by which ``lambda_1`` must differ from zero.

    Returns
    -------
    Classification
    """
    if not record.finite:
        return Classification(DIVERGED, 0, np.nan)
    scale = fmap.state_scale()
    z = record.points * scale
    size = float(np.max(np.linalg.norm(z, axis=1)))
    last = z[-(max_period + 1):]
    for k in range(1, min(max_period, z.shape[0] - 1) + 1):
        gap = np.max(np.linalg.norm(last[k:] - last[:-k], axis=1)) if last.shape[0] > k else np.inf
        if gap > recurrence * size:
            continue
        orbit = find_periodic_orbit(record.points[-1], k, fmap, scale, tol=1e-10 * max(size, 1e-12))
        if (orbit is not None and np.all(np.abs(orbit.multipliers) < 1.0)
                and _approaches(record.points, orbit, scale)):
            return Classification(PERIODIC, k, np.nan)
    lam = float(record.exponents[0])
    resolution = max(sigmas * float(record.standard_error[0]), 0.1 / (record.points.shape[0] * record.period))
    if lam > resolution:
        return Classification(CHAOTIC, 0, np.nan)
    if lam >= -resolution:
        return Classification(QUASI_PERIODIC, 0, rotation_number(record.points, scale))
    return Classification(UNSETTLED, 0, np.nan)


def _approaches(points, orbit, scale) -> bool:
    # Whether the run's points (N, 2K) tend to the stable orbit (an Attractor found by Newton
    # from the last point, orbit.found_at its phase): its last point within 1e-6 of the run's
    # size of the orbit, or nearer to it than the run's first point of the same phase (the
    # index N - 1 modulo k) in the Lyapunov (Stein) norm x^T X x of P^k there,
    # J^T X J - X = -I (J the derivative of P^k at that orbit point, orbit.jacobian, in
    # scaled coordinates):
    # along a linear approach it falls by |x|^2 every k periods, whatever the eigenvectors.
    # A plain distance swings with the turning of a lightly damped spiral and says "no" at
    # some of its phases; the nearest orbit point may be of another phase far from the orbit.
    k = orbit.points.shape[0]
    z, o = points * scale, orbit.points[orbit.found_at] * scale
    size = float(np.max(np.linalg.norm(z, axis=1)))
    if np.linalg.norm(o - z[-1]) <= 1e-6 * size:
        return True
    jac = scale[:, None] * orbit.jacobian / scale[None, :]
    first, last = z[(z.shape[0] - 1) % k] - o, z[-1] - o
    with warnings.catch_warnings():  # an ill-conditioned solve is caught below
        warnings.simplefilter("ignore", LinAlgWarning)
        stein = solve_discrete_lyapunov(jac.T, np.eye(jac.shape[0]))
    stein = 0.5 * (stein + stein.T)
    residual = np.linalg.norm(jac.T @ stein @ jac - stein + np.eye(jac.shape[0])) / np.linalg.norm(stein)
    try:
        np.linalg.cholesky(stein)
        solved = residual < 1e-8
    except np.linalg.LinAlgError:  # not positive definite: the solve failed
        solved = False
    if solved:
        return float(last @ stein @ last) < float(first @ stein @ first)
    # multipliers so near the unit circle that the solve fails: the norm's series,
    # x^T X x = sum_j |J^j x|^2, summed until its terms no longer count
    pair, total = np.stack([first, last]), np.zeros(2)
    for _ in range(1_000_000):
        terms = np.sum(pair ** 2, axis=1)
        total += terms
        if np.all(terms <= 1e-12 * total):
            break
        pair = pair @ jac.T
    return bool(total[1] < total[0])
