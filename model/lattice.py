"""Lattices of initial conditions over two coordinates of a model's state (basins).

A :class:`Lattice` spans a rectangle of two state coordinates (a displacement and a
velocity: ``ix``, ``iy``), the others at rest; its extents weigh the scaled norm in which
the classifier measures distances (:func:`lattice_scale`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .integrate import rk4_steps
from .protocol import StroboscopicMap, kernel_arguments, modal_lift


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

def lattice_states(lattice: Lattice, rows, n_state: int) -> np.ndarray:
    """Initial states of lattice rows ``rows`` (a slice or index array), row-major.

    Returns shape ``(len(rows) * ny, n_state)``.
    """
    xs = lattice.x[rows]
    out = np.zeros((xs.size * lattice.y.size, n_state))
    out[:, lattice.ix] = np.repeat(xs, lattice.y.size)
    out[:, lattice.iy] = np.tile(lattice.y, xs.size)
    return out


def window_states(lattice: Lattice, fmap: StroboscopicMap, periods: int = 4, per_period: int = 8) -> np.ndarray:
    """States along the trajectories from the corners and edge midpoints of the lattice
    window (its most energetic initial conditions), ``per_period`` per forcing period over
    the first ``periods`` periods: a sample of the largest states a lattice's trajectories
    reach, for :func:`model.rom.lean_radial_points` (the basins analysis checks the rule
    again on the attractors found).  Returns shape ``(S (periods per_period + 1), 2K)``,
    ``S = 8`` starts (fewer on a lattice of fewer than 3 points per axis).
    """
    kernel = kernel_arguments(fmap)
    if kernel is None:
        raise ValueError("window_states needs a map with kernel_arguments (a ROM): it samples within periods")
    n = 2 * fmap.dof
    xs, ys = lattice.x[[0, lattice.x.size // 2, -1]], lattice.y[[0, lattice.y.size // 2, -1]]
    starts = np.unique([(xs[i], ys[j]) for i in range(3) for j in range(3) if (i, j) != (1, 1)], axis=0)
    out = []
    work = np.empty((6, n))
    steps = max(1, kernel.steps // per_period)
    h = fmap.period / (steps * per_period)
    for x, y in starts:
        z = np.zeros(n)
        z[lattice.ix], z[lattice.iy] = x, y
        out.append(z.copy())
        for j in range(periods * per_period):
            rk4_steps(z, j * steps * h, h, steps, kernel.tables, kernel.forcing, work)
            out.append(z.copy())
    return np.array(out)


def lattice_scale(lattice: Lattice, n_state: int) -> np.ndarray:
    """Inverse lattice extents per state component (displacements, then velocities): the
    weights of the scaled norm in which capture radii and recurrences are measured."""
    lx, ly = lattice.extent()
    K = n_state // 2
    return np.concatenate([np.full(K, 1.0 / lx), np.full(K, 1.0 / ly)])


def state_norm_scale(lattice: Lattice, fmap: StroboscopicMap, n_modal: int) -> np.ndarray:
    """:func:`lattice_scale` for the states ``fmap`` lifts a lattice of ``n_modal`` modal
    coordinates to (:func:`model.protocol.modal_lift`): its weights divided by the length of
    the lifted unit displacement of the lattice's coordinate, so that a displacement along the
    lattice's mode measures in the state what it measures in the modal coordinates (1 for a
    map whose state is its modal coordinates: :func:`lattice_scale` itself)."""
    unit = np.zeros(n_modal)
    unit[lattice.ix] = 1.0
    state = modal_lift(fmap, unit)
    return lattice_scale(lattice, state.size) / np.linalg.norm(state)
