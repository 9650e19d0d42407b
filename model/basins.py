"""Basins of attraction of the stroboscopic (Poincare) map on a lattice of initial conditions.

Fig. 19 of the paper shows, for the one-mode ROM, which initial conditions
``(A_10, dA_10/dt)`` at ``t = 0`` end on the resonant (large) or on the non-resonant
(small) periodic response.  This module classifies a block ("tile") of such a lattice.

Algorithm (one tile; everything is deterministic and depends only on the tile's inputs):

* The stroboscopic map ``P`` advances a state by one forcing period ``T = 2 pi / Omega``
  with ``steps`` RK4 steps (:func:`model.integrate.rk4_period`, always from ``t = 0``).
* **Proximity** (Attractors.jl's ``AttractorsViaProximity``): a trajectory whose
  stroboscopic point comes within ``radius`` of a point of a known attractor, in the
  scaled norm ``|dy|_s^2 = sum_i (dy_i / L_i)^2`` (``L`` = lattice extent of the
  displacement, resp. velocity, coordinates), takes that attractor's label.
* **Cell recurrence** (one mode only, where the stroboscopic map acts on the lattice
  plane itself; Nusse and Yorke's ``Ncheck``, Attractors.jl's ``consecutive_basin_steps``):
  the tile keeps a map of the lattice cells whose fate is known (cells visited by a
  trajectory of known fate, and the lattice initial conditions already classified); a
  cell reached by trajectories of two fates is marked mixed for good.  A trajectory
  that falls ``consecutive`` times in a row in "clean" cells of one label (cells whose
  ``guard`` neighbourhood carries that label only) adopts it.
* **Discovery**: when a trajectory recurs (``|P^k(y) - y|_s < trigger`` for some
  ``k <= max_period``) and no known attractor is near, a Newton iteration on
  ``P^k(y) - y = 0`` (with the exact derivative of the discrete map,
  :func:`model.integrate.monodromy`) locates the periodic orbit; if all its Floquet
  multipliers lie inside the unit circle it becomes a new attractor, given by its ``k``
  Poincare points.  Light damping makes waiting for convergence cost thousands of
  periods; Newton needs a few monodromy evaluations.
* A trajectory that is classified by none of these within ``max_periods`` periods gets
  the label ``-1`` (unclassified: a non-periodic attractor, a periodic one of period
  above ``max_period``, or a transient longer than ``max_periods``).

:func:`classify_lattice` with ``cells=False`` and ``discover=False`` is the brute-force
reference: plain long integration until the trajectory converges into the capture disc of
an attractor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

from .integrate import monodromy, rk4_period

#: Label of an initial condition that could not be classified.
UNCLASSIFIED = -1
_PENDING = -2
_UNKNOWN_CELL = -2
_MIXED_CELL = -3


@dataclass(frozen=True)
class Lattice:
    """A rectangular lattice of initial conditions on two state coordinates.

    Parameters
    ----------
    x : (nx,) array
        Values of the first coordinate (``ix``-th state component, a displacement in m).
    y : (ny,) array
        Values of the second coordinate (``iy``-th state component, a velocity in m s-1).
    ix, iy : int
        State indices of the two coordinates (``y = (q, q')``); the other state
        components are zero.
    """

    x: np.ndarray
    y: np.ndarray
    ix: int = 0
    iy: int = 1

    @property
    def shape(self) -> tuple[int, int]:
        """``(nx, ny)``."""
        return self.x.size, self.y.size

    def extent(self) -> tuple[float, float]:
        """Lattice extents ``(Lx, Ly)`` used to scale distances (a single value: 1)."""
        lx = self.x[-1] - self.x[0] if self.x.size > 1 else 1.0
        ly = self.y[-1] - self.y[0] if self.y.size > 1 else 1.0
        return float(lx), float(ly)


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
    """

    points: np.ndarray
    multipliers: np.ndarray

    @property
    def period(self) -> int:
        """Period in forcing periods."""
        return self.points.shape[0]


@dataclass(frozen=True)
class Settings:
    """Settings of the lattice classification.

    Parameters
    ----------
    steps : int
        RK4 steps per forcing period (64: the labels of the Fig. 19a lattice then agree
        with converged integration, 192 steps, on 99.75 % of a random sample; 48 steps:
        97.75 %).
    max_periods : int
        Forcing periods after which a trajectory is declared unclassified.
    radius : float
        Capture radius around attractor points, scaled norm (fraction of the lattice).
    consecutive : int
        Consecutive hits of cells of one label needed to adopt it (one mode only).
    guard : int
        A cell counts as a hit only if every cell within ``guard`` cells of it (a
        ``(2 guard + 1)^2`` block) has the same known label: trajectories are classified
        by cells only deep inside a basin, not near its boundary.
    cells : int
        Resolution of the cell map: about this many cells per lattice axis (the lattice
        refined by an integer factor, never coarser than it; 0: the lattice's own cells).
        Cells are labelled by the stroboscopic points of trajectories of known fate, which
        are dense enough to label a map much finer than the lattice; fine cells resolve
        the thin, interleaved basins of the lightly damped membrane, so a clean cell is
        trustworthy.  Measured on the Fig. 19a window against converged brute force (400
        random points): a 30 x 30 lattice agrees on 84 % with its own 29 cells per axis,
        on 99 % with 174 (``cells = 200``) or 377 (``cells = 400``); 50 x 50: 99.75 %.
    max_period : int
        Largest period (in forcing periods) of the periodic attractors searched for.
    trigger : float
        Recurrence distance (scaled norm) that starts a Newton search.
    cooldown : int
        Periods between two Newton searches of one trajectory.
    newton_tol : float
        Newton tolerance on ``|P^k(y) - y|_s``.
    """

    steps: int = 64
    max_periods: int = 20000
    radius: float = 0.01
    consecutive: int = 8
    guard: int = 2
    cells: int = 200
    max_period: int = 4
    trigger: float = 0.02
    cooldown: int = 50
    newton_tol: float = 1e-11


def lattice_states(lattice: Lattice, rows, n_state: int) -> np.ndarray:
    """Initial states of lattice rows ``rows`` (a slice or index array), row-major.

    Returns shape ``(len(rows) * ny, n_state)``.
    """
    xs = lattice.x[rows]
    out = np.zeros((xs.size * lattice.y.size, n_state))
    out[:, lattice.ix] = np.repeat(xs, lattice.y.size)
    out[:, lattice.iy] = np.tile(lattice.y, xs.size)
    return out


def lattice_scale(lattice: Lattice, n_state: int) -> np.ndarray:
    """Inverse lattice extents per state component (displacements, then velocities): the
    weights of the scaled norm in which capture radii and recurrences are measured."""
    lx, ly = lattice.extent()
    K = n_state // 2
    return np.concatenate([np.full(K, 1.0 / lx), np.full(K, 1.0 / ly)])


def classify_lattice(states, lattice: Lattice, tab, c_damp: float, p_load: float,
                     omega: float, settings: Settings, attractors=(), *, cells: bool = True,
                     discover: bool = True):
    """Label initial states by the attractor their trajectory ends on.

    Parameters
    ----------
    states : (N, 2K) array
        Initial states at ``t = 0``, processed in this order.
    lattice : Lattice
        The lattice (distance scaling; cell map when ``cells`` is set).
    tab : RomTables
        ROM tables (:func:`model.rom.build_rom`).
    c_damp : float
        ``c / (Gamma h)`` (s-1).
    p_load : float
        ``P0`` (Pa).
    omega : float
        ``Omega`` (rad s-1).
    settings : Settings
    attractors : sequence of Attractor
        Attractors known beforehand (kept first, in this order).
    cells : bool
        Use the cell-recurrence shortcut.  Only valid for one mode (``2K = 2``), where
        the lattice plane is the whole state space.
    discover : bool
        Look for new attractors (Newton on recurrences).  Without it the method is the
        brute-force reference: integrate until the capture disc of a known attractor.

    Returns
    -------
    labels : (N,) int32 array
        Index into ``attractors`` (the returned list), or -1 (unclassified).
    attractors : list of Attractor
        The known attractors followed by those discovered, in discovery order.
    periods : (N,) int32 array
        Forcing periods integrated for each initial condition.
    """
    states = np.ascontiguousarray(states, dtype=np.float64)
    N, n = states.shape
    if cells and n != 2:
        raise ValueError(f"cells = True is invalid for {n // 2} modes: the cell recurrence "
                         "needs the one-mode ROM (the lattice plane is its whole state space)")
    s = settings
    scale = lattice_scale(lattice, n)
    period = 2.0 * np.pi / omega
    atts = list(attractors)
    cap = max(len(atts), 1) + 8
    att_pts = np.zeros((cap, s.max_period, n))
    att_per = np.zeros(cap, np.int64)
    for a, att in enumerate(atts):
        att_pts[a, :att.period] = att.points
        att_per[a] = att.period
    labels = np.full(N, _PENDING, np.int32)
    periods = np.zeros(N, np.int32)
    nx, ny = lattice.shape
    # The cell map refines the lattice r-fold (about s.cells cells per axis): lattice
    # point (i, j) is the centre of cell (i r, j r).
    r = max(1, s.cells // max(nx - 1, ny - 1, 1))
    cellmap = np.full(((nx - 1) * r + 1, (ny - 1) * r + 1) if cells else (1, 1), _UNKNOWN_CELL, np.int8)
    dx = (lattice.x[-1] - lattice.x[0]) / (nx - 1) if nx > 1 else 1.0
    dy = (lattice.y[-1] - lattice.y[0]) / (ny - 1) if ny > 1 else 1.0
    geo = np.array([lattice.x[0], dx / r, lattice.y[0], dy / r])
    # Trajectory state kept across the kernel's returns for a Newton search.
    y = np.empty(n)
    ring = np.zeros((s.max_period, n))
    trail = np.zeros(s.max_periods + 1, np.int64)
    ints = np.zeros(6, np.int64)  # i, n_done, last_newton, trail_len, k_request, n_att
    ints[0] = 0
    ints[1] = -1
    ints[5] = len(atts)
    cooldown = s.cooldown if discover else s.max_periods + 1
    while True:
        code = _classify_kernel(states, labels, periods, cellmap, cells, s.guard, geo, lattice.ix,
                                lattice.iy, att_pts, att_per, scale, s.radius**2,
                                s.consecutive, s.trigger**2, cooldown, s.max_period,
                                s.max_periods, tab, c_damp, p_load, omega, s.steps, y, ring,
                                trail, ints)
        if code == 0:
            break
        att = find_periodic_orbit(y, int(ints[4]), period, tab, c_damp, p_load, omega,
                                  s.steps, scale, s.newton_tol)
        if att is None or np.max(np.abs(att.multipliers)) >= 1.0:
            continue
        if match_attractor(att, atts, scale, s.radius) >= 0:
            continue
        if len(atts) == att_pts.shape[0]:
            att_pts = np.concatenate([att_pts, np.zeros_like(att_pts)])
            att_per = np.concatenate([att_per, np.zeros_like(att_per)])
        att_pts[len(atts), :att.period] = att.points
        att_per[len(atts)] = att.period
        atts.append(att)
        ints[5] = len(atts)
    return labels, atts, periods


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


def find_periodic_orbit(y0, k: int, period: float, tab, c_damp: float, p_load: float,
                        omega: float, steps: int, scale, tol: float, max_iter: int = 30,
                        max_step: float = 0.05):
    """Newton iteration on ``P^k(y) - y = 0`` from ``y0``.

    Parameters
    ----------
    y0 : (2K,) array
        Starting state at ``t = 0``.
    k : int
        Period in forcing periods.
    period : float
        Forcing period ``2 pi / Omega`` (s).
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
    n = y.size
    for _ in range(max_iter):
        z = y.copy()
        phi = np.eye(n)
        pts = [y.copy()]
        for j in range(k):
            z, m = monodromy(z, 0.0, period, steps, tab, c_damp, p_load, omega)
            phi = m @ phi
            if j < k - 1:
                pts.append(z.copy())
        res = z - y
        if not np.all(np.isfinite(res)):
            return None
        if np.linalg.norm(res * scale) < tol:
            pts = np.array(pts)
            if k > 1 and any(np.linalg.norm((pts[j] - pts[0]) * scale) < 1e3 * tol
                             for j in range(1, k)):
                return None
            first = int(np.argmin(pts[:, 0]))
            return Attractor(np.roll(pts, -first, axis=0), np.linalg.eigvals(phi))
        try:
            dy = np.linalg.solve(phi - np.eye(n), -res)
        except np.linalg.LinAlgError:
            return None
        size = np.linalg.norm(dy * scale)
        if size > max_step:
            dy *= max_step / size
        y = y + dy
    return None


def orbit_amplitude(att: Attractor, tab, c_damp: float, p_load: float, omega: float,
                    steps: int) -> float:
    """``max |w(probe, t)|`` (m) over the ``k`` periods of a periodic orbit.

    ``w = probe . q`` (the ROM's probe, the paper's point ``(rho, theta) = (0.5, 0)``),
    sampled at every RK4 step.
    """
    return _orbit_amplitude(att.points[0].copy(), att.period, tab, c_damp, p_load, omega,
                            steps)


@nb.njit(cache=True)
def _orbit_amplitude(y, k, tab, c_damp, p_load, omega, steps):
    n = y.size
    K = n // 2
    h = 2.0 * np.pi / omega / steps
    work = np.empty((6, n))
    amp = 0.0
    t = 0.0
    for _ in range(k * steps):
        w = 0.0
        for i in range(K):
            w += tab.probe[i] * y[i]
        amp = max(amp, abs(w))
        t = rk4_period(y, t, h, 1, tab, c_damp, p_load, omega, work)
    return amp


@nb.njit(cache=True)
def _near_attractor(y, att_pts, att_per, n_att, scale, r2):
    n = y.size
    for a in range(n_att):
        for j in range(att_per[a]):
            d = 0.0
            for i in range(n):
                e = (y[i] - att_pts[a, j, i]) * scale[i]
                d += e * e
            if d < r2:
                return a
    return -1


@nb.njit(cache=True)
def _cell(y, geo, ix, iy, nx, ny):
    cx = int(np.floor((y[ix] - geo[0]) / geo[1] + 0.5))
    cy = int(np.floor((y[iy] - geo[2]) / geo[3] + 0.5))
    if cx < 0 or cx >= nx or cy < 0 or cy >= ny:
        return -1
    return cx * ny + cy


@nb.njit(cache=True)
def _mark(flat, c, label):
    # A cell visited by trajectories of two fates straddles a basin boundary: it is
    # marked mixed for good and never counts as clean.
    if flat[c] == _UNKNOWN_CELL:
        flat[c] = label
    elif flat[c] != label:
        flat[c] = _MIXED_CELL


@nb.njit(cache=True)
def _clean_label(flat, c, nx, ny, guard):
    # The label of cell c if every cell within ``guard`` cells of it has that label,
    # else -1: the cell lies deep inside a basin at the lattice's resolution.
    lab = flat[c]
    if lab < 0:
        return -1
    cx = c // ny
    cy = c - cx * ny
    for i in range(max(cx - guard, 0), min(cx + guard + 1, nx)):
        for j in range(max(cy - guard, 0), min(cy + guard + 1, ny)):
            if flat[i * ny + j] != lab:
                return -1
    return lab


@nb.njit(cache=True)
def _classify_kernel(states, labels, periods, cellmap, cells, guard, geo, ix, iy, att_pts,
                     att_per, scale, r2, consecutive, trig2, cooldown, kmax, max_periods,
                     tab, c_damp, p_load, omega, steps, y, ring, trail, ints):
    # Returns 0 when every state is labelled, 1 to ask the caller for a Newton search
    # from y with period ints[4]; the trajectory then resumes where it stopped.
    N, n = states.shape
    nx, ny = cellmap.shape
    h = 2.0 * np.pi / omega / steps
    work = np.empty((6, n))
    flat = cellmap.ravel()
    y_arg = y
    y = y_arg.copy()  # a local array: no aliasing, so LLVM optimises the RK4 loop
    while ints[0] < N:
        i = ints[0]
        if ints[1] < 0:
            y[:] = states[i]
            ints[1] = 0
            ints[2] = 0
            ints[3] = 0
        else:
            y[:] = y_arg
        label = -1
        run_label = -3
        run = 0
        while ints[1] <= max_periods:
            nd = ints[1]
            a = _near_attractor(y, att_pts, att_per, ints[5], scale, r2)
            if a >= 0:
                label = a
                break
            if nd - ints[2] >= cooldown:
                for k in range(1, min(kmax, nd) + 1):
                    d = 0.0
                    for j in range(n):
                        e = (y[j] - ring[(nd - k) % kmax, j]) * scale[j]
                        d += e * e
                    if d < trig2:
                        ints[2] = nd
                        ints[4] = k
                        y_arg[:] = y
                        return 1
            if cells:
                c = _cell(y, geo, ix, iy, nx, ny)
                if c >= 0 and ints[3] < trail.size:
                    trail[ints[3]] = c
                    ints[3] += 1
                    lab = _clean_label(flat, c, nx, ny, guard)
                    if lab >= 0:
                        if lab == run_label:
                            run += 1
                        else:
                            run_label = lab
                            run = 1
                        if run >= consecutive:
                            label = lab
                            break
                    else:
                        run = 0
                else:
                    run = 0
            if nd == max_periods:
                break
            ring[nd % kmax] = y
            rk4_period(y, 0.0, h, steps, tab, c_damp, p_load, omega, work)
            ints[1] = nd + 1
            if not np.isfinite(y[0]):
                break
        labels[i] = label
        periods[i] = ints[1]
        if cells and label >= 0:
            for j in range(ints[3]):
                _mark(flat, trail[j], label)
            c = _cell(states[i], geo, ix, iy, nx, ny)
            if c >= 0:
                _mark(flat, c, label)
        ints[0] = i + 1
        ints[1] = -1
    return 0
