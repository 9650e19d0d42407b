"""Figures of the ``basins`` analysis: basins of attraction (Fig. 19), erosion profiles."""

from __future__ import annotations

import numpy as np

from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import point_label


def basins_figures(ds, outdir) -> list:
    """Basins of attraction (Fig. 19), one figure per grid point, and, over one swept grid
    key, the erosion profile of the integrity measures."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    from sweep.analyses.basins import NOT_COMPUTED

    plt = pyplot()
    written = []
    grid_dims = [d for d in ds["label"].dims if d not in ("ic_x", "ic_y")]
    colours = ["#555555", "#c8c8c8", "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd"]
    cmap = ListedColormap(["#ffffff", "#d62728"] + colours)
    x, y = ds["ic_x"].values, ds["ic_y"].values
    for g in np.ndindex(*(ds.sizes[d] for d in grid_dims)):
        sel = dict(zip(grid_dims, g))
        lab = ds["label"].isel(sel).values
        if np.all(lab == NOT_COMPUTED):
            continue
        fig, ax = plt.subplots(figsize=(5.4, 5.4))
        ax.pcolormesh(x, y, np.clip(lab, -2, len(colours) - 1).T + 2, cmap=cmap, vmin=0,
                      vmax=len(colours) + 1, shading="nearest", rasterized=True)
        j = int(ds["label"].attrs["lattice_mode"])
        handles = []
        markers = "XPD^v<>"
        for a in range(ds["n_attractors"].isel(sel).values.item()):
            at = {**sel, "attractor": a}
            k = ds["attractor_period"].isel(at).values.item()
            q = ds["attractor_coordinate"].isel(at).values[:k, j]
            v = ds["attractor_velocity"].isel(at).values[:k, j]
            shade = colours[a % len(colours)]
            handles.append(Patch(facecolor=shade, edgecolor="k", lw=0.5,
                                 label=f"basin of attractor {a} ({ds['basin_fraction'].isel(at).values.item():.2f} "
                                       "of the window)"))
            handles.append(ax.plot(q, v, ls="none", marker=markers[a % len(markers)], ms=9,
                                   mfc="white" if a == 0 else "k", mec="k", mew=1.5,
                                   label=f"attractor {a}: amplitude "
                                         f"{ds['attractor_amplitude'].isel(at).values.item() * 1e3:.1f} mm, "
                                         f"period {k}")[0])
        if np.any(lab == -1):
            handles.append(Patch(facecolor="#d62728", label=f"unclassified ({np.mean(lab == -1):.3f})"))
        ax.set_xlabel(f"{ds['ic_x'].attrs.get('long_name', 'ic_x')} (m)")
        ax.set_ylabel(f"{ds['ic_y'].attrs.get('long_name', 'ic_y')} (m/s)")
        ax.set_title(point_label({d: ds[d].values[i] for d, i in sel.items()}), fontsize=9)
        ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2,
                  frameon=False)
        fig.tight_layout()
        name = "basins_" + "_".join(f"{d}{float(ds[d].values[i]):g}" for d, i in sel.items())
        written.append(save_figure(fig, outdir, f"{name}.png", dpi=150))
    swept = [d for d in grid_dims if ds.sizes[d] > 1]
    if len(swept) == 1 and not np.all(ds["label"].values == NOT_COMPUTED):
        d = swept[0]
        other = {o: 0 for o in grid_dims if o != d}
        fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
        # Basin greys are too light for lines: black, mid grey, then colours.
        lines = ["#000000", "#808080", *colours[2:]]
        markers = "osd^v<"
        for a in range(ds.sizes["attractor"]):
            gim = ds["basin_fraction"].isel({**other, "attractor": a})
            if np.all(np.isnan(gim)):
                continue
            style = dict(color=lines[a % len(lines)], marker=markers[a % len(markers)],
                         label=f"attractor {a}")
            axes[0].plot(ds[d], gim, **style)
            axes[1].plot(ds[d], ds["integrity_factor"].isel({**other, "attractor": a}),
                         **style)
        unit = ds[d].attrs.get("units", "")
        for ax, ylab in zip(axes, ("global integrity measure (basin fraction)",
                                   "integrity factor")):
            ax.set_xlabel(f"{d} ({unit})")
            ax.set_ylabel(ylab)
            ax.set_ylim(-0.02, 1.02)
            ax.legend(fontsize=8)
        axes[0].set_title("attractor 0: largest amplitude", fontsize=9)
        fig.tight_layout()
        written.append(save_figure(fig, outdir, f"erosion_{d}.png", dpi=150))
    return written
