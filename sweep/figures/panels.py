"""Panels of a figure: the grid points of a result, their labels, a grid of axes."""

from __future__ import annotations

import itertools

from sweep.analyses.base import GRID_KEYS, STATUS_SKIPPED

#: Units of the grid keys in axis labels.
GRID_UNITS = {"delta": "", "delta_o": "", "Omega": "rad/s", "P0": "Pa", "c": r"N s/m$^3$", "alpha": r"s$^{-1}$",
              "beta": "s", "zeta": ""}
#: Plot symbols of the grid keys.
SYMBOLS = {"delta": r"$\delta$", "delta_o": r"$\delta_o$", "Omega": r"$\Omega$", "P0": "$P_0$", "c": "$c$",
           "alpha": r"$\alpha$", "beta": r"$\beta$", "zeta": r"$\zeta$"}


def point_label(sel) -> str:
    """``"$\\delta$ = 1.1, $\\Omega$ = 33.5 rad/s"`` for a dict of grid values (with units)."""
    return ", ".join(f"{SYMBOLS.get(k, k)} = {float(v):g}" + (f" {GRID_UNITS[k]}" if GRID_UNITS.get(k) else "")
                     for k, v in sel.items())


def computed_points(ds, exclude):
    """:func:`grid_points` without those left out by the job's ``[grid] cases`` (status 3
    everywhere along the excluded dims)."""
    for sel in grid_points(ds, exclude):
        if "status" not in ds or bool((ds["status"].sel(sel) != STATUS_SKIPPED).any()):
            yield sel


def grid_points(ds, exclude):
    """Iterate over the grid points of ``ds`` other than the dims in ``exclude``."""
    dims = [d for d in GRID_KEYS if d in ds.dims and d not in exclude]
    for values in itertools.product(*(ds[d].values for d in dims)):
        yield dict(zip(dims, values))


def panel_axes(plt, n):
    """A figure with ``n`` axes in rows of at most three, and the axes (flat)."""
    cols = min(n, 3)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(max(4.2 * cols, 6.0), 3.6 * rows + 0.4), squeeze=False)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    return fig, axes.ravel()[:n]
