"""The cell maps of the basins classifier (:mod:`model.basins`): which cells of the lattice
plane (one mode) or of the whole state space (more modes) carry a known fate.

The lattice plane is a dense array refined about ``cell_resolution`` times per axis; the
state space a hash table (open addressing) of the cells ``floor(y_i L_i r)`` that
trajectories visited, with an int8 label each (Nusse and Yorke's cell recurrence,
Attractors.jl's sparse grid).  The kernels here run on every trajectory at every period:
they allocate nothing and are compiled without reference counts (``_nrt=False``; see the
note in :mod:`model.rom`).
"""

from __future__ import annotations

from typing import NamedTuple

import numba as nb
import numpy as np

#: A cell of unknown fate, a cell reached by two fates (for good), a free entry of the
#: state-space map; labels above MAX_CELL_LABEL are not recorded (int8 maps).
UNKNOWN_CELL = -2
MIXED_CELL = -3
EMPTY_CELL = -4     # a free entry of the state-space cell map
MAX_CELL_LABEL = 127  # cell maps hold int8 labels: later attractors' cells are not recorded

class CellMap(NamedTuple):
    # The refined cell map of the lattice plane and where it lies (kernel argument).
    labels: np.ndarray   # (cx, cy) int8: a label, UNKNOWN_CELL or MIXED_CELL
    x0: float            # centre of cell (0, 0) on the two lattice coordinates
    dx: float            # cell sizes
    y0: float
    dy: float
    ix: int              # state indices of the two lattice coordinates
    iy: int
    guard: int
    enabled: bool


class StateCells(NamedTuple):
    # The cell map of the whole state space (more than one mode), a hash table with open
    # addressing: cell (c_0 .. c_{2K-1}), c_i = floor(y_i * inv_width_i), is stored at
    # entry hash(c) or after it; entries are never removed.
    keys: np.ndarray       # (cap, 2K) int16 cell coordinates of each entry
    labels: np.ndarray     # (cap,) int8: a label, UNKNOWN_CELL, MIXED_CELL or EMPTY_CELL
    inv_width: np.ndarray  # (2K,) inverse cell widths (1 / m, s / m)
    count: np.ndarray      # (1,) int64 entries in use
    limit: int             # entries in use beyond which no cell is added (the table is then full)


#: Entries of the state-space cell map (:class:`StateCells`), a power of two (the hash is
#: masked): 2**21, 2K int16 coordinates and a label each, 27 MB for three modes; once
#: :func:`state_cell_limit` are in use no new cell is recorded, and trajectories are then
#: classified by the cells already known, by capture or by Newton.
STATE_CELL_CAPACITY = 1 << 21

def state_cell_limit() -> int:
    """Cells the state-space cell map (:data:`STATE_CELL_CAPACITY` entries) takes before it
    is full: three quarters, which keeps the probe sequences of the open addressing short."""
    return 3 * STATE_CELL_CAPACITY // 4

@nb.njit(cache=True, _nrt=False)
def lattice_cell(y, cells, nx, ny):
    cx = int(np.floor((y[cells.ix] - cells.x0) / cells.dx + 0.5))
    cy = int(np.floor((y[cells.iy] - cells.y0) / cells.dy + 0.5))
    if cx < 0 or cx >= nx or cy < 0 or cy >= ny:
        return -1
    return cx * ny + cy


@nb.njit(cache=True, _nrt=False)
def state_cell(y, sc):
    # Entry of the state-space cell of y in sc (added, with an unknown label, when new),
    # or -1 (a coordinate beyond the int16 cell range, or the table full).
    n = y.size
    mask = sc.labels.size - 1
    h = 1469598103934665603
    for i in range(n):
        c = np.floor(y[i] * sc.inv_width[i])
        if not abs(c) < 32767.0:
            return -1
        h = (h ^ (int(c) & 0xFFFF)) * 1099511628211  # FNV-1a over the coordinates (wraps)
    e = (h ^ (h >> 29)) & mask
    while sc.labels[e] != EMPTY_CELL:
        same = True
        for i in range(n):
            if sc.keys[e, i] != int(np.floor(y[i] * sc.inv_width[i])):
                same = False
                break
        if same:
            return e
        e = (e + 1) & mask
    if sc.count[0] >= sc.limit:
        return -1
    for i in range(n):
        sc.keys[e, i] = int(np.floor(y[i] * sc.inv_width[i]))
    sc.labels[e] = UNKNOWN_CELL
    sc.count[0] += 1
    return e


@nb.njit(cache=True, _nrt=False)
def mark_cell(flat, c, label):
    # A cell visited by trajectories of two fates straddles a basin boundary: it is
    # marked mixed for good and never counts as clean.
    if flat[c] == UNKNOWN_CELL:
        flat[c] = label
    elif flat[c] != label:
        flat[c] = MIXED_CELL


@nb.njit(cache=True, _nrt=False)
def clean_label(flat, c, nx, ny, guard):
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
