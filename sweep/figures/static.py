"""Figures of the ``static`` analysis: Fig. 2 (deformed radius), Fig. 3 (stresses)."""

from __future__ import annotations

from pathlib import Path

from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import grid_points, point_label


def static_figures(ds, outdir) -> list[Path]:
    """Fig. 2 (deformed radius) and Fig. 3 (principal stresses) versus ``rho``."""
    plt = pyplot()
    paths = []
    fig, ax = plt.subplots(figsize=(5, 4))
    for sel in grid_points(ds, ("rho",)):
        ax.plot(ds.rho, ds.r_o.sel(sel), label=point_label(sel))
    ax.set(xlabel=r"undeformed radius $\rho$ (m)", ylabel=r"deformed radius $r_o$ (m)",
           title=f"Pre-stretch ({ds.attrs.get('prestretch', '')})".replace(" ()", ""))
    ax.legend()
    paths.append(save_figure(fig, outdir, "fig02_radius.png"))
    fig, axes = plt.subplots(1, 2, figsize=(9, 4), sharex=True)
    for sel in grid_points(ds, ("rho",)):
        for ax, var in zip(axes, ("sigma_1", "sigma_2")):
            ax.plot(ds.rho, ds[var].sel(sel) / 1e6, label=point_label(sel))
    for ax, sym in zip(axes, ("1", "2")):
        ax.set(xlabel=r"undeformed radius $\rho$ (m)", ylabel=rf"$\sigma_{sym}$ (MPa)")
    axes[0].legend()
    paths.append(save_figure(fig, outdir, "fig03_stresses.png"))
    return paths
