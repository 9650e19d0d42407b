"""Figures of a result over mode sets: each set's own figures in a subdirectory of its own,
and the sets on one figure."""

from __future__ import annotations

import numpy as np

from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import grid_points, point_label


def per_set_figures(drawer, ds, outdir, analysis: str) -> list:
    """The figures of a result over ``mode_set``: ``drawer(one set's Dataset, directory)``
    per set, each in its own subdirectory (``modes_1_0-2_0/``), then
    :func:`mode_set_figures`."""
    from sweep.analyses.mode_sets import select

    paths = []
    for label in ds["mode_set"].values:
        paths += drawer(select(ds, str(label)), outdir / _slug(str(label)))
    return paths + mode_set_figures(ds, outdir, analysis)


def _slug(label: str) -> str:
    """A directory name for a set label: ``"(1,0)+(2,0)"`` -> ``"modes_1_0-2_0"``."""
    return "modes_" + "-".join(p.strip("()").replace(",", "_") for p in label.split("+"))


def mode_set_figures(ds, outdir, analysis: str) -> list:
    """The mode sets of a result over ``mode_set`` on one figure, per grid point: backbones
    (Fig. 9 as the paper draws it), continued branches, or basin fractions; none for the
    other analyses (each set's own figures are drawn too, see :func:`per_set_figures`)."""
    from sweep.analyses.mode_sets import select

    plt = pyplot()
    sets = [str(label) for label in ds.mode_set.values]
    sels = list(grid_points(ds, ()))
    if analysis == "backbone":
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        for sel in sels:
            for label in sets:
                one = select(ds, label).sel(sel)
                ax.plot(one.omega_nl, one.amplitude, lw=1.5,
                        label=label + (f", {point_label(sel)}" if len(sels) > 1 else ""))
        ax.set(xlabel=r"frequency $\omega$ (rad/s)", ylabel=r"amplitude max $|w(0.5, 0)|$ (m)",
               title="Backbone by mode set", ylim=(0, None))
        ax.legend()
        return [save_figure(fig, outdir, "backbone_mode_sets.png")]
    if analysis == "continuation":
        par = ds.attrs.get("continued_parameter", "Omega")
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        for sel in sels:
            for label in sets:
                one = select(ds, label).sel(sel)
                ax.plot(one[par], one.amplitude, lw=1.3,
                        label=label + (f", {point_label(sel)}" if len(sels) > 1 else ""))
        ax.set(xlabel=f"{par} ({ds[par].attrs.get('units', '')})", ylabel=r"amplitude max $|w(0.5, 0)|$ (m)",
               title="Periodic responses by mode set")
        ax.legend()
        return [save_figure(fig, outdir, f"branch_{par}_mode_sets.png")]
    if analysis == "basins":
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        width = 0.8 / max(len(sels), 1)
        for j, sel in enumerate(sels):
            fractions = [float(select(ds, label).sel(sel).basin_fraction.isel(attractor=0)) for label in sets]
            ax.bar(np.arange(len(sets)) + j * width, fractions, width,
                   label=point_label(sel) if len(sels) > 1 else None)
        ax.set_xticks(np.arange(len(sets)) + 0.4 - width / 2, sets, rotation=20)
        ax.set(ylabel="basin fraction of attractor 0", title="Largest-amplitude basin by mode set", ylim=(0, 1))
        if len(sels) > 1:
            ax.legend()
        return [save_figure(fig, outdir, "basin_fraction_mode_sets.png")]
    return []
