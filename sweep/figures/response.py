"""Figures of the ``response`` analysis: brute-force resonance curves (Figs. 13, 18) and,
with Poincare points, bifurcation diagrams."""

from __future__ import annotations

import numpy as np

from model.lyapunov import KIND_NAMES

from sweep.analyses.base import GRID_KEYS
from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import computed_points, panel_axes, point_label


def response_figures(ds, outdir) -> list:
    """Brute-force resonance curves (Figs. 13, 18): up and down sweeps per grid point.

    Up sweeps solid with upward triangles, down sweeps dashed with downward triangles,
    values that did not settle crossed, located jumps thin vertical lines.  Up to four grid
    points share one axes; with more, the grid key with the most values is overlaid in each
    panel and the others make one panel each.
    """
    plt = pyplot()
    par = ds.attrs["swept_parameter"]
    xlabel = r"forcing frequency $\Omega$ (rad/s)" if par == "Omega" else r"pressure amplitude $P_0$ (Pa)"
    points = list(computed_points(ds, (par, "direction")))
    swept = [k for k in GRID_KEYS if k != par and ds.sizes.get(k, 1) > 1]
    overlay = max(swept, key=lambda k: ds.sizes[k]) if len(points) > 4 and swept else None
    panels = list(computed_points(ds, (par, "direction", overlay))) if overlay else [{}]
    fig, axes = panel_axes(plt, len(panels))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, panel in zip(axes, panels):
        members = [sel for sel in points if all(sel[k] == v for k, v in panel.items())]
        for j, sel in enumerate(members):
            b = ds.sel(sel)
            color = colors[j % len(colors)]
            label = point_label({k: v for k, v in sel.items() if k not in panel and ds.sizes.get(k, 1) > 1})
            for d, ls, marker in (("up", "-", "^"), ("down", "--", "v")):
                a = b.amplitude.sel(direction=d)
                ax.plot(b[par], a * 1e3, ls=ls, marker=marker, ms=3, color=color, label=f"{label} {d}".strip())
                bad = b.converged.sel(direction=d) == 0
                ax.plot(b[par].values[bad.values], a.values[bad.values] * 1e3, "x", color="k")
                for x in b.jump_value.sel(direction=d).values:
                    if np.isfinite(x):
                        ax.axvline(x, ls=ls, lw=0.8, color=color, alpha=0.6)
                        ax.annotate(f"{x:.4g}", (x, 1.0), xycoords=("data", "axes fraction"), fontsize=7,
                                    ha="center", va="bottom", color=color)
        ax.set(xlabel=xlabel, ylabel=r"amplitude of $w(0.5, 0)$ (mm)")
        if panel:
            ax.set_title(point_label(panel), fontsize=9, pad=14)
        ax.legend(ncol=2, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), frameon=False)
    fixed = {k: float(ds[k][0]) for k in GRID_KEYS
             if k != par and ds.sizes.get(k, 0) == 1}
    fig.suptitle("Steady states stepped up and down (brute force); thin lines: located jumps\n"
                 + point_label(fixed), fontsize=10)
    fig.tight_layout()
    paths = [save_figure(fig, outdir, f"response_{par}.png")]
    if "response_kind" in ds:
        paths += [diagram_figure(ds.sel(sel), par, xlabel, outdir, j, len(points)) for j, sel in enumerate(points)]
    return paths


#: Colours of the kinds of response in a bifurcation diagram (model.lyapunov.KIND_NAMES).
KIND_COLORS = {"periodic": "tab:blue", "quasi_periodic": "tab:orange", "chaotic": "tab:red",
               "diverged": "k", "unsettled": "tab:gray"}


def diagram_figure(b, par, xlabel, outdir, index, count):
    """A bifurcation diagram of one grid point: each modal coordinate's Poincare points
    against the parameter (up sweep dots, down sweep crosses, coloured by the kind of
    response), and the largest Lyapunov exponent with its error bar."""
    plt = pyplot()
    K = b.sizes["mode"]
    fig, axes = plt.subplots(K + 1, 1, figsize=(7.0, 2.0 * (K + 1) + 0.6), sharex=True, squeeze=False)
    axes = axes[:, 0]
    x = b[par].values
    for d, marker, shift in (("up", ".", -0.1), ("down", "x", 0.1)):
        s = b.sel(direction=d)
        kind = s.response_kind.values
        step = np.diff(x).min() if x.size > 1 else 1.0
        for k, name in enumerate(KIND_NAMES):
            pick = kind == k
            if not pick.any():
                continue
            for j in range(K):
                pts = s.poincare_coordinate.isel(mode=j).values[pick] * 1e3  # (values, samples)
                xx = np.repeat(x[pick] + shift * step, pts.shape[1])
                axes[j].plot(xx, pts.ravel(), marker, ms=1.5, color=KIND_COLORS[name], lw=0,
                             label=f"{d}: {name.replace('_', '-')}")
        lam = s.lyapunov_exponent.isel(exponent=0).values
        err = s.lyapunov_error.isel(exponent=0).values
        axes[K].errorbar(x + shift * step, lam, yerr=3 * err, fmt=marker, ms=3, color="k" if d == "up" else "tab:gray",
                         lw=0.6, label=f"{d}")
    for j in range(K):
        axes[j].set_ylabel(f"$q_{{{int(b.m[j])}{int(b.n[j])}}}$ (mm)")
    axes[0].legend(fontsize=7, ncol=3, loc="upper left", markerscale=4)
    axes[K].axhline(0.0, color="k", lw=0.6)
    axes[K].set(ylabel=r"$\lambda_1$ (1/s), $\pm 3\sigma$", xlabel=xlabel)
    axes[K].legend(fontsize=7)
    fixed = {k: float(b[k]) for k in GRID_KEYS if k != par and k in b.coords and b[k].size == 1}
    fig.suptitle("Bifurcation diagram (brute force): Poincare points after the transient\n" + point_label(fixed),
                 fontsize=10)
    fig.tight_layout()
    suffix = f"_{index}" if count > 1 else ""
    return save_figure(fig, outdir, f"bifurcation_diagram_{par}{suffix}.png")
