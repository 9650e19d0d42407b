"""Basins of attraction of the stroboscopic (Poincare) map on a lattice of initial conditions.

Fig. 19 of the paper shows, for the one-mode ROM, which initial conditions
``(A_10, dA_10/dt)`` at ``t = 0`` end on the resonant (large) or on the non-resonant
(small) periodic response.  This module classifies a block ("tile") of such a lattice.

Algorithm (one tile; everything is deterministic and depends only on the tile's inputs):

* The stroboscopic map ``P`` (:class:`model.protocol.StroboscopicMap`) advances a state by one
  forcing period ``T = 2 pi / Omega`` with its RK4 steps (always from ``t = 0``).
* **Proximity** (Attractors.jl's ``AttractorsViaProximity``): a trajectory whose
  stroboscopic point comes within ``radius`` of a point of a known attractor, in the
  scaled norm ``|dy|_s^2 = sum_i (dy_i / L_i)^2`` (``L`` = lattice extent of the
  displacement, resp. velocity, coordinates), takes that attractor's label.
* **Cell recurrence** (Nusse and Yorke's ``Ncheck``, Attractors.jl's
  ``consecutive_basin_steps``): the tile keeps a map of the cells whose fate is known
  (cells visited by a trajectory of known fate); a cell reached by trajectories of two
  fates is marked mixed for good.  A trajectory that falls ``consecutive`` times in a row
  in "clean" cells of one label adopts it.

  - One mode: the stroboscopic map acts on the lattice plane itself, and the map is a
    dense array of the plane refined to about ``cell_resolution`` cells per axis; a cell
    is clean when its whole ``guard`` neighbourhood carries its label.
  - More modes: the map covers the whole state space (Attractors.jl's sparse grid), a
    hash table of the cells ``floor(y_i L_i cell_resolution)`` (cells of width
    ``1 / cell_resolution`` in the scaled norm below, in every coordinate), holding only
    the cells trajectories visited; a cell is clean when it carries one label.  A lattice
    plane of ``2K``-dimensional initial conditions is not invariant, but trajectories of
    neighbouring initial conditions travel together and label each other's way.
* **Discovery**: when a trajectory recurs (``|P^k(y) - y|_s < trigger`` for some
  ``k <= max_period``) and no known attractor is near, a Newton iteration on
  ``P^k(y) - y = 0`` (with the exact derivative of the discrete map,
  ``monodromy`` of the map) locates the periodic orbit; if all its Floquet
  multipliers lie inside the unit circle it becomes a new attractor, given by its ``k``
  Poincare points.  Light damping makes waiting for convergence cost thousands of
  periods; Newton needs a few monodromy evaluations.
* A trajectory that is classified by none of these within ``max_periods`` periods gets
  the label ``-1`` (unclassified: a non-periodic attractor, a periodic one of period
  above ``max_period``, or a transient longer than ``max_periods``).

* **Known orbits are not searched for again**: a search from ``y`` that finds a periodic
  orbit (an attractor, or an unstable orbit such as the saddle between two basins) at
  distance ``d`` explains the recurrences within ``min(trigger, d / 4)`` of ``y``, which
  start no search.  A trajectory creeping towards a known attractor (multiplier 0.998 per
  period) recurs within ``trigger`` long before it is captured: without this, nearly
  every trajectory of the Fig. 19a lattice started a search that found the known
  attractor again; trajectories lingering near the saddle did the same with the saddle
  (454 of the 637 searches of a 5000-point tile of the one-mode Fig. 19a lattice).  The
  radius stays a quarter of the way to the orbit found, so a point much nearer to an
  attractor not yet known is still searched from.  A search that finds nothing (Newton
  does not converge in its iterations: the costliest searches) explains the recurrences
  within ``trigger / 2`` of its start: on a 5000-point tile of the three-mode Fig. 19a
  lattice such searches went from 612 (4.3 s of 48.7 s) to 444 (2.8 s), with the same
  labels.  A radius of ``trigger`` left 197, also with the same labels there, but the
  larger the radius, the likelier that it hides an attractor not yet known (Newton may
  fail near one at a fold, where its Jacobian is nearly singular).
* **Lock-step**: the tile's trajectories are processed in slots of
  :data:`model.integrate.LOCKSTEP_WIDTH`; all occupied slots advance one period together,
  vectorised across the slots (one-mode ROMs: :func:`model.integrate.rk4_one_mode_lockstep`
  from the force table; ROMs without a table: :func:`model.integrate.rk4_quadrature_lockstep`,
  or the scalar loop when too few slots are occupied for it to pay,
  :func:`model.integrate.quadrature_lockstep_pays`), and a slot whose trajectory is
  labelled takes the next initial condition.
  The result depends only on the tile's inputs.

:func:`classify_lattice` with ``use_cells=False`` and ``discover=False`` is the
brute-force reference: plain long integration until the trajectory converges into the
capture disc of an attractor.  :func:`model.attractors.merge_attractors` identifies the attractors that
independently classified tiles of one lattice found.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numba as nb
import numpy as np

from .attractors import find_periodic_orbit, match_attractor
from . import basin_cells
from .basin_cells import (EMPTY_CELL, MAX_CELL_LABEL, UNKNOWN_CELL, CellMap, StateCells, clean_label, lattice_cell,
                          mark_cell, state_cell, state_cell_limit)
from .damping_kernels import matrix_or_none
from .integrate import (LOCKSTEP_WIDTH, lockstep_table, quadrature_lockstep_pays, rk4_one_mode_lockstep,
                        rk4_quadrature_lockstep, rk4_steps)
from .lattice import Lattice, lattice_scale
from .protocol import StroboscopicMap, kernel_arguments

#: Label of an initial condition that could not be classified.
UNCLASSIFIED = -1
_PENDING = -2

#: RK4 steps per forcing period of the basins' map: with 64 the labels of the Fig. 19a
#: lattice agree with converged integration (192 steps) on 99.75 % of a random sample;
#: with 48 steps on 97.75 %.
DEFAULT_STEPS = 64


@dataclass(frozen=True)
class Settings:
    """Settings of the lattice classification (the defaults are those of one mode; for more
    modes take :func:`default_settings`).

    Parameters
    ----------
    max_periods : int
        Forcing periods after which a trajectory is declared unclassified.
    radius : float
        Capture radius around attractor points, scaled norm (fraction of the lattice).
    consecutive : int
        Consecutive hits of cells of one label needed to adopt it.
    guard : int
        One mode: a cell counts as a hit only if every cell within ``guard`` cells of it (a
        ``(2 guard + 1)^2`` block) has the same known label: trajectories are classified
        by cells only deep inside a basin, not near its boundary.
    cell_resolution : int
        Resolution of the cell map: about this many cells per lattice axis (one mode: the
        lattice refined by an integer factor, never coarser than it; more modes: cells of
        width ``1 / cell_resolution`` of the lattice extents in every state coordinate;
        0: the lattice's own spacing).
        Cells are labelled by the stroboscopic points of trajectories of known fate, which
        are dense enough to label a map much finer than the lattice; fine cells resolve
        the thin, interleaved basins of the lightly damped membrane, so a clean cell is
        trustworthy.  Measured on the Fig. 19a window against converged brute force (400
        random points): a 30 x 30 lattice agrees on 84 % with its own 29 cells per axis,
        on 99 % with 174 (``cell_resolution = 200``) or 377 (``400``); 50 x 50: 99.75 %.
    max_period : int
        Largest period (in forcing periods) of the periodic attractors searched for.
    trigger : float
        Recurrence distance (scaled norm) that starts a Newton search.
    cooldown : int
        Periods between two Newton searches of one trajectory.
    newton_tol : float
        Newton tolerance on ``|P^k(y) - y|_s``.
    """

    max_periods: int = 20000
    radius: float = 0.01
    consecutive: int = 8
    guard: int = 2
    cell_resolution: int = 200
    max_period: int = 4
    trigger: float = 0.02
    cooldown: int = 50
    newton_tol: float = 1e-11


def default_settings(n_modes: int) -> Settings:
    """The default :class:`Settings` for a ROM of ``n_modes`` modes.

    More than one mode: the state-space cell map has cells of 1/100 of the lattice extents
    and needs 16 consecutive hits.  Measured on a tile of the 200 x 200 Fig. 19a lattice
    (interleaved rows 0, 8, .., 5000 initial conditions), modes (1..3, 0), 264 RK4 steps:
    with 8 hits 2.6 % of its labels differ from those with 16 and 3 of 200 random points
    from brute force of the same map; with 16, 0 of 200.  Cells of 1/200 with 8 hits cost
    44 % more periods than cells of 1/100 on a 20 x 20 lattice, where both label every
    point like brute force.
    """
    return Settings() if n_modes == 1 else Settings(consecutive=16, cell_resolution=100)



class _Criteria(NamedTuple):
    # The classification criteria of Settings, in the kernel's terms.
    scale: np.ndarray    # (2K,) weights of the scaled norm
    capture2: float      # squared capture radius
    consecutive: int
    trigger2: float      # squared recurrence distance of a Newton search
    cooldown: int
    max_period: int
    max_periods: int


class _Slots(NamedTuple):
    # The trajectories in progress, one per slot, kept across the kernel's returns for a
    # Newton search; the slots advance together one period at a time (lock-step).
    y: np.ndarray        # (B, 2K) current states
    ring: np.ndarray     # (B, max_period, 2K) their last stroboscopic points
    trail: np.ndarray    # (B, max_periods + 1) cells visited
    state: np.ndarray    # (B, _SLOT_FIELDS) int64, indexed by the _SLOT_* constants below
    cursor: np.ndarray   # (_CURSOR_SLOTS,) int64, indexed by the _AT_* constants below


class _Known(NamedTuple):
    # What the tile knows, in the kernel's terms (rows beyond the counts in cursor unused).
    points: np.ndarray    # (cap, max_period, 2K) Poincare points of the known attractors
    period: np.ndarray    # (cap,) int64 their periods
    searched: np.ndarray  # (E, 2K + 1) start of each search (whether it found a periodic
    #                       orbit or not), and the squared radius (scaled norm) it explains


# Fields of _Slots.state.
_SLOT_STATE = 0      # index of the initial state being classified (-1: slot empty)
_SLOT_PERIODS = 1    # periods integrated so far
_SLOT_SEARCH = 2     # period of the last Newton search
_SLOT_TRAIL = 3      # cells recorded in trail
_SLOT_RUN = 4        # consecutive clean-cell hits ...
_SLOT_RUN_LABEL = 5  # ... of this label
_SLOT_QUADRATURE = 6  # 1: the lock-step period left the force table; the caller integrates it again
_SLOT_FIELDS = 7

# Slots of _Slots.cursor.
_AT_NEXT = 0         # next initial state to load into a slot
_AT_SLOT = 1         # slot whose check is pending (a kernel return resumes there)
_AT_SEARCH_K = 2     # period of the requested Newton search (from slot _AT_SLOT)
_AT_KNOWN = 3        # attractors known to the kernel
_AT_SEARCHED = 4     # rows of _Known.searched in use
_CURSOR_SLOTS = 5
#: A search from y that finds a periodic orbit (an attractor or an unstable one) at distance
#: d from y explains the recurrences within min(trigger, d * _EXPLAINED_FRACTION) of y:
#: they start no search.
_EXPLAINED_FRACTION = 0.25
#: A search from y that finds nothing explains the recurrences within
#: _FAILED_FRACTION * trigger of y.
_FAILED_FRACTION = 0.5


def classify_lattice(states, lattice: Lattice, fmap: StroboscopicMap, settings: Settings, attractors=(), *,
                     use_cells: bool = True, discover: bool = True, report: dict | None = None, scale=None):
    """Label initial states by the attractor their trajectory ends on.

    Parameters
    ----------
    states : (N, 2K) array
        Initial states at ``t = 0``, processed in this order.
    lattice : Lattice
        The lattice (distance scaling; cell map when ``use_cells`` is set).
    fmap : StroboscopicMap
        The stroboscopic map (ROM, forcing, RK4 steps per period).
    settings : Settings
    attractors : sequence of Attractor
        Attractors known beforehand (kept first, in this order).
    use_cells : bool
        Use the cell-recurrence shortcut (the lattice plane for one mode, the whole state
        space for more).
    discover : bool
        Look for new attractors (Newton on recurrences).  Without it the method is the
        brute-force reference: integrate until the capture disc of a known attractor.
    scale : (2K,) array, optional
        Weights of the scaled norm of the states (default :func:`model.lattice.lattice_scale`;
        states lifted from modal coordinates: :func:`model.lattice.state_norm_scale`).
    report : dict, optional
        Receives ``"state_cells"``, the cells in the state-space cell map (states of more
        than two coordinates with ``use_cells``; else 0).  At :func:`state_cell_limit` the map takes no new
        cells: trajectories are then classified by the cells already labelled, capture and
        Newton, which costs periods, not correctness.

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
    s = settings
    scale = lattice_scale(lattice, n) if scale is None else np.asarray(scale, float)
    atts = list(attractors)
    cap = max(len(atts), 1) + 8
    known = _Known(np.zeros((cap, s.max_period, n)), np.zeros(cap, np.int64), np.zeros((64, n + 1)))
    for a, att in enumerate(atts):
        known.points[a, :att.period] = att.points
        known.period[a] = att.period
    labels = np.full(N, _PENDING, np.int32)
    periods = np.zeros(N, np.int32)
    nx, ny = lattice.shape
    # The cell map refines the lattice r-fold (about s.cell_resolution cells per axis):
    # lattice point (i, j) is the centre of cell (i r, j r).
    r = max(1, s.cell_resolution // max(nx - 1, ny - 1, 1))
    dx = (lattice.x[-1] - lattice.x[0]) / (nx - 1) if nx > 1 else 1.0
    dy = (lattice.y[-1] - lattice.y[0]) / (ny - 1) if ny > 1 else 1.0
    plane = use_cells and n == 2
    cells = CellMap(np.full(((nx - 1) * r + 1, (ny - 1) * r + 1) if plane else (1, 1), UNKNOWN_CELL,
                             np.int8),
                     float(lattice.x[0]), dx / r, float(lattice.y[0]), dy / r, lattice.ix, lattice.iy,
                     s.guard, plane)
    whole = use_cells and n > 2
    # without the state-space map (one mode, brute force) sc is None, which numba prunes
    # with its branches: a one-mode job does not compile the hash table (0.4 s)
    capacity = basin_cells.STATE_CELL_CAPACITY  # the module attribute, read at each call
    sc = StateCells(np.zeros((capacity, n), np.int16), np.full(capacity, EMPTY_CELL, np.int8),
                     scale * (s.cell_resolution or max(nx - 1, ny - 1, 1)), np.zeros(1, np.int64),
                     state_cell_limit()) if whole else None
    criteria = _Criteria(scale, s.radius**2, s.consecutive, s.trigger**2,
                         s.cooldown if discover else s.max_periods + 1, s.max_period, s.max_periods)
    width = min(LOCKSTEP_WIDTH, max(N, 1))
    slots = _Slots(np.zeros((width, n)), np.zeros((width, s.max_period, n)),
                   np.zeros((width, s.max_periods + 1), np.int64), np.full((width, _SLOT_FIELDS), -1, np.int64),
                   np.zeros(_CURSOR_SLOTS, np.int64))
    slots.cursor[_AT_KNOWN] = len(atts)
    # The table's lock-step loop (coef_t) or the quadrature's (columns: the occupied slots'
    # states, one per column); the other is None, which numba prunes with its branch, so a
    # job compiles only the loop it runs (the quadrature's costs 2.5 s).  A map without
    # kernel_arguments (model.protocol) has neither: the kernel hands every period of the
    # occupied slots back here, to the map's advance_batch (code 2).
    kernel = kernel_arguments(fmap)
    tab = forcing = coef_t = columns = damping_matrix = None
    steps = 0
    if kernel is not None:
        tab, forcing, steps = kernel
        damping_matrix = matrix_or_none(forcing.damping_matrix)  # None: the lock-step loop prunes the term
        table = tab.table_max > 0.0
        coef_t = lockstep_table(tab) if table else None
        columns = None if table else np.empty((n, width))
    h = fmap.period / max(steps, 1)
    while True:
        code = _classify_kernel(states, labels, periods, cells, sc, known, criteria, tab, coef_t, columns,
                                forcing, damping_matrix, h, steps, slots)
        if code == 0:
            break
        if code == 2:  # periods that left the force table (again by rk4_steps), or of a map without kernels
            flagged = np.flatnonzero(slots.state[:, _SLOT_QUADRATURE] == 1)
            slots.y[flagged] = fmap.advance_batch(slots.y[flagged])
            slots.state[flagged, _SLOT_QUADRATURE] = 0
            slots.state[flagged, _SLOT_PERIODS] += 1
            continue
        start = slots.y[slots.cursor[_AT_SLOT]].copy()
        att = find_periodic_orbit(start, int(slots.cursor[_AT_SEARCH_K]), fmap, scale, s.newton_tol)
        stable = att is not None and np.max(np.abs(att.multipliers)) < 1.0
        if stable and match_attractor(att, atts, scale, s.radius) < 0:
            if len(atts) == known.points.shape[0]:
                known = known._replace(points=np.concatenate([known.points, np.zeros_like(known.points)]),
                                       period=np.concatenate([known.period, np.zeros_like(known.period)]))
            known.points[len(atts), :att.period] = att.points
            known.period[len(atts)] = att.period
            atts.append(att)
            slots.cursor[_AT_KNOWN] = len(atts)
        e = slots.cursor[_AT_SEARCHED]
        if e == known.searched.shape[0]:
            known = known._replace(searched=np.concatenate([known.searched, np.zeros_like(known.searched)]))
        if att is not None:
            d = np.min(np.linalg.norm((att.points - start) * scale, axis=1))
            radius = min(s.trigger, _EXPLAINED_FRACTION * d)
        else:
            radius = _FAILED_FRACTION * s.trigger
        known.searched[e, :n] = start
        known.searched[e, n] = radius**2
        slots.cursor[_AT_SEARCHED] = e + 1
    if report is not None:
        report["state_cells"] = int(sc.count[0]) if whole else 0
    return labels, atts, periods



# The tests run on every trajectory at every period, below, allocate nothing and are
# compiled without reference counts (_nrt=False; see the note in model.rom).

@nb.njit(cache=True, _nrt=False)
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

@nb.njit(cache=True, _nrt=False)
def _explained(y, known, n_searched, scale):
    # True when y lies within the radius of the start of an earlier search
    # (_Known.searched).
    n = y.size
    for e in range(n_searched):
        d = 0.0
        for i in range(n):
            x = (y[i] - known.searched[e, i]) * scale[i]
            d += x * x
        if d < known.searched[e, n]:
            return True
    return False


@nb.njit(cache=True, _nrt=False)
def _check(b, slots, cells, flat, sc, known, crit, nx, ny):
    # The tests of slot b at its current stroboscopic point (flat: the lattice-plane cell
    # map, raveled; sc: the state-space cell map, or None without one).
    # Returns its label (>= 0),
    # -1 (unclassified: out of periods or not finite), -2 (go on integrating) or -3 (a
    # Newton search is requested; cursor[_AT_SEARCH_K] holds its period).
    st = slots.state[b]
    y = slots.y[b]
    n = y.size
    nd = st[_SLOT_PERIODS]
    for i in range(n):
        if not np.isfinite(y[i]):
            return -1
    a = _near_attractor(y, known.points, known.period, slots.cursor[_AT_KNOWN], crit.scale, crit.capture2)
    if a >= 0:
        return a
    if nd - st[_SLOT_SEARCH] >= crit.cooldown:
        kmax = crit.max_period
        for k in range(1, min(kmax, nd) + 1):
            d = 0.0
            for j in range(n):
                e = (y[j] - slots.ring[b, (nd - k) % kmax, j]) * crit.scale[j]
                d += e * e
            if d < crit.trigger2:
                st[_SLOT_SEARCH] = nd
                if _explained(y, known, slots.cursor[_AT_SEARCHED], crit.scale):
                    break
                slots.cursor[_AT_SEARCH_K] = k
                return -3
    if cells.enabled or sc is not None:
        if sc is None:
            c = lattice_cell(y, cells, nx, ny)
        else:
            c = state_cell(y, sc)
        if c >= 0 and st[_SLOT_TRAIL] < slots.trail.shape[1]:
            slots.trail[b, st[_SLOT_TRAIL]] = c
            st[_SLOT_TRAIL] += 1
            if sc is None:
                lab = clean_label(flat, c, nx, ny, cells.guard)
            else:
                lab = max(sc.labels[c], -1)
            if lab >= 0:
                if lab == st[_SLOT_RUN_LABEL]:
                    st[_SLOT_RUN] += 1
                else:
                    st[_SLOT_RUN_LABEL] = lab
                    st[_SLOT_RUN] = 1
                if st[_SLOT_RUN] >= crit.consecutive:
                    return lab
            else:
                st[_SLOT_RUN] = 0
        else:
            st[_SLOT_RUN] = 0
    if nd == crit.max_periods:
        return -1
    return -2


@nb.njit(cache=True)
def _classify_kernel(states, labels, periods, cells, sc, known, crit, tab, coef_t, columns, forcing, damping_matrix,
                     h, steps, slots):
    # Returns 0 when every state is labelled, 1 to ask the caller for a Newton search
    # from slots.y[cursor[_AT_SLOT]] with period cursor[_AT_SEARCH_K], 2 to ask it to
    # integrate again, with the map, the periods of the slots flagged _SLOT_QUADRATURE
    # (their lock-step period left the force table: a one-mode job that stays in the
    # table never compiles the quadrature loop; or, with neither coef_t nor columns, a
    # map without compiled loops: every period); the kernel then resumes with that slot's
    # tests.  Slots are refilled with the next
    # initial state as soon as theirs is labelled, and all occupied slots advance one
    # period together.
    N, n = states.shape
    B = slots.y.shape[0]
    nx, ny = cells.labels.shape
    flat = cells.labels.ravel()
    cur = slots.cursor
    kmax = crit.max_period
    q = np.empty(B)
    v = np.empty(B)
    reach = np.empty(B)
    work = np.empty((6, n))
    lanes = np.empty(B, np.int64)  # the slots of the columns
    while True:
        b = cur[_AT_SLOT]
        while b < B:
            st = slots.state[b]
            if st[_SLOT_STATE] < 0:
                if cur[_AT_NEXT] == N:
                    b += 1
                    continue
                st[_SLOT_STATE] = cur[_AT_NEXT]
                cur[_AT_NEXT] += 1
                for i in range(n):  # element by element: no broadcast error path to compile
                    slots.y[b, i] = states[st[_SLOT_STATE], i]
                st[_SLOT_PERIODS] = 0
                st[_SLOT_SEARCH] = 0
                st[_SLOT_TRAIL] = 0
                st[_SLOT_RUN] = 0
                st[_SLOT_RUN_LABEL] = -3
                st[_SLOT_QUADRATURE] = 0
            if st[_SLOT_QUADRATURE] == 1:
                cur[_AT_SLOT] = b
                return 2
            label = _check(b, slots, cells, flat, sc, known, crit, nx, ny)
            if label == -3:
                cur[_AT_SLOT] = b
                return 1
            if label == -2:
                b += 1
                continue
            i = st[_SLOT_STATE]
            labels[i] = label
            periods[i] = st[_SLOT_PERIODS]
            if cells.enabled and 0 <= label <= MAX_CELL_LABEL:
                for j in range(st[_SLOT_TRAIL]):
                    mark_cell(flat, slots.trail[b, j], label)
                c = lattice_cell(states[i], cells, nx, ny)
                if c >= 0:
                    mark_cell(flat, c, label)
            elif sc is not None and 0 <= label <= MAX_CELL_LABEL:
                for j in range(st[_SLOT_TRAIL]):
                    mark_cell(sc.labels, slots.trail[b, j], label)
            st[_SLOT_STATE] = -1  # free: refilled on the next pass of this loop
        cur[_AT_SLOT] = 0
        active = 0
        for b in range(B):
            if slots.state[b, _SLOT_STATE] >= 0:
                active += 1
                nd = slots.state[b, _SLOT_PERIODS]
                for i in range(n):
                    slots.ring[b, nd % kmax, i] = slots.y[b, i]
        if active == 0:
            return 0
        lockstep = False  # (the quadrature's lock-step, when it pays)
        if coef_t is not None:
            for b in range(B):
                busy = slots.state[b, _SLOT_STATE] >= 0
                q[b] = slots.y[b, 0] if busy else 0.0
                v[b] = slots.y[b, 1] if busy else 0.0
            rk4_one_mode_lockstep(q, v, 0.0, h, steps, coef_t, tab.table_max, tab.k_force[0], tab.load[0],
                                  forcing.damping_rate, forcing.P0, forcing.Omega, reach)
        elif columns is not None:
            lockstep = quadrature_lockstep_pays(active)
            if lockstep:
                # the occupied slots packed into the first columns (a tile's last
                # trajectories do not drag empty slots along), zero columns up to a
                # multiple of 8 (a whole number of vectors: no remainder loops)
                m = np.int64(0)  # not a literal: no second compilation of the kernel
                for b in range(B):
                    if slots.state[b, _SLOT_STATE] >= 0:
                        lanes[m] = b
                        for i in range(n):
                            columns[i, m] = slots.y[b, i]
                        m += 1
                width = min(B, (m + 7) // 8 * 8)
                for j in range(m, width):
                    for i in range(n):
                        columns[i, j] = 0.0
                rk4_quadrature_lockstep(columns, width, 0.0, h, steps, tab.weight, tab.inv_rho2, tab.hoop2, tab.radial2,
                                        tab.b_rho, tab.b_theta, tab.axisymmetric, tab.law, tab.k_force, tab.load,
                                        forcing.damping_rate, forcing.P0, forcing.Omega, damping_matrix)
                for j in range(m):
                    for i in range(n):
                        slots.y[lanes[j], i] = columns[i, j]
        for b in range(B):
            if slots.state[b, _SLOT_STATE] < 0:
                continue
            if coef_t is None and columns is None:  # no compiled loop: the caller advances it
                slots.state[b, _SLOT_QUADRATURE] = 1
                continue
            if coef_t is not None:
                if reach[b] >= tab.table_max:
                    slots.state[b, _SLOT_QUADRATURE] = 1
                    continue
                slots.y[b, 0] = q[b]
                slots.y[b, 1] = v[b]
            if columns is not None:
                if not lockstep:
                    rk4_steps(slots.y[b], 0.0, h, steps, tab, forcing, work)
            slots.state[b, _SLOT_PERIODS] += 1
