"""Dynamic integrity measures of attractors from a labelled lattice of initial conditions.

Two measures from the literature on the erosion of safe basins, as used by Goncalves and
co-authors (the paper's section 4.3 cites Goncalves and Santee 2008a and Goncalves et
al. 2011 for the use of basins as integrity measures):

* **Global integrity measure** (GIM; Soliman and Thompson, "Integrity measures quantifying
  the erosion of smooth and fractal basins of attraction", J. Sound Vib. 135 (1989)
  453-475): the normalised hypervolume of the basin of an attractor.  Here: the fraction
  of the lattice's initial conditions whose label is that attractor, i.e. the basin area
  inside the lattice window divided by the window area.
* **Integrity factor** (IF; Lenci and Rega, "Optimal control of homoclinic bifurcation:
  theoretical treatment and practical reduction of safe basin erosion in the Helmholtz
  oscillator", J. Vib. Control 9 (2003) 281-315; Rega and Lenci, "Identifying,
  evaluating, and controlling dynamical integrity measures in non-linear mechanical
  oscillators", Nonlinear Anal. 63 (2005) 902-914): the radius of the largest circle
  lying entirely in the basin.  As in Goncalves et al., the circle is
  centred at the attractor (for a period-k attractor: the smallest such radius over its k
  Poincare points).  Distances are measured in the lattice window mapped to the unit
  square (each coordinate divided by its lattice extent), the circle may not leave the
  window (the basin outside it is unknown), and the radius is normalised by 1/2, the
  radius of the circle inscribed in the window: IF = 1 for an attractor at the window's
  centre whose basin covers the window, as for the single attractor of the unforced
  system, which is Lenci and Rega's reference case.  The circle is resolved to one
  lattice spacing: the radius is the distance to the nearest lattice point of another
  label (or unclassified), or to the window edge.
"""

from __future__ import annotations

import numpy as np


def global_integrity_measure(labels, attractor: int) -> float:
    """Fraction of the lattice in the basin of ``attractor`` (GIM, Soliman and Thompson 1989).

    Parameters
    ----------
    labels : (nx, ny) int array
        Attractor index of every initial condition (``-1``: unclassified).
    attractor : int
        Attractor index.

    Returns
    -------
    float
        Basin area over window area, in [0, 1].
    """
    labels = np.asarray(labels)
    return float(np.count_nonzero(labels == attractor)) / labels.size


def integrity_factor(labels, x, y, points, attractor: int) -> float:
    """Integrity factor of ``attractor`` (Lenci and Rega 2003), normalised as in the module doc.

    Parameters
    ----------
    labels : (nx, ny) int array
        Attractor index of every initial condition (``-1``: unclassified).
    x : (nx,) array
        First lattice coordinate (e.g. displacement, m); increasing, at least 2 values.
    y : (ny,) array
        Second lattice coordinate (e.g. velocity, m s-1); increasing, at least 2 values.
    points : (k, 2) array
        The attractor's Poincare points projected on ``(x, y)``.
    attractor : int
        Attractor index.

    Returns
    -------
    float
        ``2 r`` where ``r`` is the radius, in the window mapped to the unit square, of the
        largest circle centred at the attractor that lies in the window and in its basin;
        0 when a point of the attractor lies outside the window.
    """
    labels = np.asarray(labels)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if labels.shape != (x.size, y.size) or x.size < 2 or y.size < 2:
        raise ValueError(f"labels of shape {labels.shape} is invalid: need (len(x), len(y)) "
                         f"= ({x.size}, {y.size}) with at least 2 values each")
    u = (x - x[0]) / (x[-1] - x[0])
    v = (y - y[0]) / (y[-1] - y[0])
    fi, fj = np.nonzero(labels != attractor)
    fu, fv = u[fi], v[fj]
    radius = np.inf
    for px, py in np.asarray(points, dtype=float).reshape(-1, 2):
        pu = (px - x[0]) / (x[-1] - x[0])
        pv = (py - y[0]) / (y[-1] - y[0])
        edge = min(pu, 1.0 - pu, pv, 1.0 - pv)
        if edge <= 0.0:
            return 0.0
        foreign = np.sqrt(np.min((fu - pu) ** 2 + (fv - pv) ** 2)) if fu.size else np.inf
        radius = min(radius, edge, foreign)
    return 2.0 * float(radius)
