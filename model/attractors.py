"""Attractors of the stroboscopic map: periodic orbits found by Newton, and their matching.

:func:`find_periodic_orbit` locates a periodic orbit ``P^k(y) = y`` from a recurrence of a
trajectory (the basins classifier's discovery, :mod:`model.basins`), with the exact
derivative of the discrete map; one-mode ROMs run the whole iteration compiled.
:func:`match_attractor` and :func:`merge_attractors` identify the attractors that
separately classified tiles of one lattice found.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

from .integrate import NO_PARAMETER, monodromy_one_mode
from .protocol import StroboscopicMap, kernel_arguments
from .shooting import newton_map_power


@dataclass(frozen=True)
class Attractor:
    """A stable periodic orbit of the stroboscopic map.

    Parameters
    ----------
    points : (k, 2K) array
        Its ``k`` Poincare points, in orbit order, starting with the point of smallest
        first modal coordinate.
    multipliers : (2K,) complex array
        Floquet multipliers of the ``k``-th iterate.
    found_at : int
        Index in ``points`` of the point a search converged to (:func:`find_periodic_orbit`:
        the phase of its start); 0 otherwise.
    jacobian : (2K, 2K) array or None
        The derivative of ``P^k`` at ``points[found_at]``, from the search's last iteration
        (its Newton matrix is this minus the identity); None where the orbit was not found by
        a search (read back from a result file).
    """

    points: np.ndarray
    multipliers: np.ndarray
    found_at: int = 0
    jacobian: np.ndarray | None = None

    @property
    def period(self) -> int:
        """Period in forcing periods."""
        return self.points.shape[0]

def match_attractor(att: Attractor, attractors, scale, tol: float) -> int:
    """Index of the attractor of ``attractors`` equal to ``att`` (or -1).

    Two attractors are equal when they have the same period and every point of one lies
    within ``tol`` (scaled norm) of a point of the other.
    """
    for j, other in enumerate(attractors):
        if other.period != att.period:
            continue
        d = (att.points[:, None, :] - other.points[None, :, :]) * scale
        if np.all(np.min(np.sqrt((d**2).sum(axis=-1)), axis=1) < tol):
            return j
    return -1


def merge_attractors(tiles, scale, tol: float):
    """Identify the attractors that separately classified tiles of one lattice found.

    Two attractors are the same when :func:`match_attractor` says so (same period, every
    point within ``tol`` of a point of the other, scaled norm).  The merged attractors are
    numbered by decreasing amplitude (ties: by their first Poincare point), so attractor 0
    is the largest response.

    Parameters
    ----------
    tiles : sequence of sequences of (Attractor, float)
        Per tile, its attractors in the tile's own numbering, each with its amplitude (m).
    scale : (2K,) array
        Weights of the scaled norm (:func:`model.lattice.lattice_scale`).
    tol : float
        Matching distance in the scaled norm (the capture radius).

    Returns
    -------
    merged : list of (Attractor, float)
        The distinct attractors and their amplitudes, largest amplitude first; each keeps
        the Poincare points of its first finder (tiles in order).
    index : list of (A_t,) int arrays
        Per tile, the merged index of each of its attractors.
    """
    found, where = [], []
    for tile in tiles:
        idx = np.empty(len(tile), np.int64)
        for a, (att, amp) in enumerate(tile):
            j = match_attractor(att, [f[0] for f in found], scale, tol)
            if j < 0:
                found.append((att, amp))
                j = len(found) - 1
            idx[a] = j
        where.append(idx)
    order = sorted(range(len(found)), key=lambda j: (-found[j][1], tuple(found[j][0].points[0])))
    rank = np.empty(len(found), np.int64)
    rank[order] = np.arange(len(found))
    return [found[j] for j in order], [rank[idx] for idx in where]


def find_periodic_orbit(y0, k: int, fmap: StroboscopicMap, scale, tol: float, max_iter: int = 30,
                        max_step: float = 0.05):
    """Newton iteration on ``P^k(y) - y = 0`` from ``y0`` (:func:`model.shooting.newton_map_power`,
    with the absolute test ``|scale (P^k(y) - y)| <= tol`` and steps of at most ``max_step``).

    A one-mode ROM with a force table (a map with ``kernel_arguments``,
    :mod:`model.protocol`) runs the whole iteration compiled (the 2 x 2
    systems in closed form; 85 us a search at Fig. 19a against 250 us in Python, measured
    on the 1968 searches of the 200 x 200 lattice); if a stage leaves the table, the
    iteration starts again here on the general map.

    Parameters
    ----------
    y0 : (2K,) array
        Starting state at ``t = 0``.
    k : int
        Period in forcing periods.
    fmap : StroboscopicMap
        The stroboscopic map ``P``.
    scale : (2K,) array
        Inverse lattice extents of the state components (norm of the steps).
    tol : float
        Convergence tolerance on ``|P^k(y) - y|`` in the scaled norm.
    max_step : float
        Largest Newton step in the scaled norm (damped Newton).

    Returns
    -------
    Attractor or None
        The orbit (even when unstable: check ``multipliers``), or None when Newton did
        not converge or the orbit's least period is below ``k``.
    """
    y = np.array(y0, dtype=np.float64)
    if y.shape != (2 * fmap.dof,):
        raise ValueError(f"y0 shape {y.shape} is invalid: need ({2 * fmap.dof},), a state of the map")
    scale = np.asarray(scale, dtype=np.float64)
    if scale.shape != y.shape:
        raise ValueError(f"scale shape {scale.shape} is invalid: need {y.shape}, one weight per state component")
    kernel = kernel_arguments(fmap)
    if kernel is not None and kernel.tables.table_max > 0.0:  # one mode: the iteration compiled, in the table
        pts, phi = np.empty((k + 1, 2)), np.empty((2, 2))
        code = _newton_one_mode(y, k, fmap.period / kernel.steps, kernel.steps, kernel.tables, kernel.forcing,
                                scale, tol, max_iter, max_step, pts, phi)
        if code == _NEWTON_CONVERGED:
            return _orbit(pts[:k], phi)
        if code == _NEWTON_FAILED:
            return None
        # a stage left the table: the iteration below, whose map falls back to the quadrature
    found = newton_map_power(fmap, y, k, scale, tol, max_iter=max_iter, max_step=max_step)
    if not found.converged:
        return None
    pts = found.points
    if k > 1 and any(np.linalg.norm((pts[j] - pts[0]) * scale) < 1e3 * tol for j in range(1, k)):
        return None  # its least period is below k
    return _orbit(pts, found.jacobian)


def _orbit(pts, phi) -> Attractor:
    # The Attractor of a converged search: its points from the one of smallest first
    # coordinate, the multipliers of P^k, where the converged point (pts[0]) went, and the
    # derivative of P^k there
    first = int(np.argmin(pts[:, 0]))
    return Attractor(np.roll(pts, -first, axis=0), np.linalg.eigvals(phi), (-first) % pts.shape[0], phi)


# Outcomes of _newton_one_mode.
_NEWTON_CONVERGED, _NEWTON_FAILED, _NEWTON_LEFT_TABLE = 0, 1, 2


@nb.njit(cache=True)
def _newton_one_mode(y, k, h, steps, tab, forcing, scale, tol, max_iter, max_step, pts, phi):
    # find_periodic_orbit for a one-mode ROM from its force table (the iteration of
    # model.shooting.newton_map_power compiled, the 2 x 2 systems solved in closed form; pts is (k + 1, 2)).  Returns _NEWTON_CONVERGED
    # (pts[:k]: the points of the orbit from the converged y, phi: the derivative of P^k),
    # _NEWTON_FAILED (no convergence in max_iter, a singular system, a state not finite or
    # a least period below k) or _NEWTON_LEFT_TABLE (a stage left the table's range).
    y0 = y[0]
    y1 = y[1]
    for it in range(max_iter + 1):  # max_iter steps, each followed by its test
        if not _map_power_one_mode(y0, y1, k, h, steps, tab, forcing, pts, phi):
            return _NEWTON_LEFT_TABLE
        r0 = pts[k, 0] - y0
        r1 = pts[k, 1] - y1
        if not (np.isfinite(r0) and np.isfinite(r1)):
            return _NEWTON_FAILED
        if np.sqrt((r0 * scale[0]) ** 2 + (r1 * scale[1]) ** 2) <= tol:
            for j in range(1, k):
                if np.sqrt(((pts[j, 0] - y0) * scale[0]) ** 2 + ((pts[j, 1] - y1) * scale[1]) ** 2) < 1e3 * tol:
                    return _NEWTON_FAILED
            return _NEWTON_CONVERGED
        if it == max_iter:
            return _NEWTON_FAILED
        a00 = phi[0, 0] - 1.0
        a11 = phi[1, 1] - 1.0
        det = a00 * a11 - phi[0, 1] * phi[1, 0]
        if det == 0.0 or not np.isfinite(det):
            return _NEWTON_FAILED
        d0 = (-r0 * a11 + r1 * phi[0, 1]) / det
        d1 = (-r1 * a00 + r0 * phi[1, 0]) / det
        size = np.sqrt((d0 * scale[0]) ** 2 + (d1 * scale[1]) ** 2)
        if size > max_step:
            d0 *= max_step / size
            d1 *= max_step / size
        y0 += d0
        y1 += d1
    return _NEWTON_FAILED


@nb.njit(cache=True)
def _map_power_one_mode(y0, y1, k, h, steps, tab, forcing, pts, phi):
    # P^j(y), j = 0..k, of a one-mode ROM from its force table into pts[:k + 1] and the
    # derivative of P^k into phi: the product of the monodromy matrices along the orbit,
    # the latest on the left (chain rule).  False when a stage leaves the table's range.
    m = np.empty((2, 2))
    dparam = np.empty(2)
    z = np.empty(2)
    z[0] = y0
    z[1] = y1
    p00, p01, p10, p11 = 1.0, 0.0, 0.0, 1.0
    pts[0, 0] = y0
    pts[0, 1] = y1
    for j in range(k):
        # (the constant compiles a version of its own, specialised on the literal)
        zq, zv, ok = monodromy_one_mode(z, 0.0, h, steps, tab, forcing, NO_PARAMETER, m, dparam)
        if not ok:
            return False
        p00, p01, p10, p11 = (m[0, 0] * p00 + m[0, 1] * p10, m[0, 0] * p01 + m[0, 1] * p11,
                              m[1, 0] * p00 + m[1, 1] * p10, m[1, 0] * p01 + m[1, 1] * p11)
        z[0] = zq
        z[1] = zv
        pts[j + 1, 0] = zq
        pts[j + 1, 1] = zv
    phi[0, 0] = p00
    phi[0, 1] = p01
    phi[1, 0] = p10
    phi[1, 1] = p11
    return True
