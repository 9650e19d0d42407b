"""Figure helpers shared by the analyses, and the ``static``/``linear`` figures (Figs. 2-7).

Every function takes the published Dataset and an output directory and returns the list
of PNG paths it wrote.  matplotlib is imported lazily (Agg backend).
"""

from __future__ import annotations

import itertools
from pathlib import Path


def pyplot():
    """matplotlib.pyplot with the Agg backend and the house style."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"figure.dpi": 120, "axes.grid": True, "grid.alpha": 0.3,
                         "font.size": 10, "legend.fontsize": 8, "savefig.bbox": "tight"})
    return plt


def save_figure(fig, outdir, name) -> Path:
    """Save ``fig`` as ``outdir/name`` (directories created), close it, return the path."""
    path = Path(outdir) / name
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    import matplotlib.pyplot as plt

    plt.close(fig)
    return path


def _label(ds, **sel) -> str:
    return ", ".join(f"{k} = {float(v):g}" for k, v in sel.items())


def grid_points(ds, exclude):
    """Iterate over the grid points of ``ds`` other than the dims in ``exclude``."""
    dims = [d for d in ("delta", "delta_o", "Omega", "P0", "c") if d in ds.dims and d not in exclude]
    for values in itertools.product(*(ds[d].values for d in dims)):
        yield dict(zip(dims, values))


def static_figures(ds, outdir) -> list[Path]:
    """Fig. 2 (deformed radius) and Fig. 3 (principal stresses) versus ``rho``."""
    plt = pyplot()
    paths = []
    fig, ax = plt.subplots(figsize=(5, 4))
    for sel in grid_points(ds, ("rho",)):
        ax.plot(ds.rho, ds.r_o.sel(sel), label=_label(ds, **sel))
    ax.set(xlabel=r"undeformed radius $\rho$ (m)", ylabel=r"deformed radius $r_o$ (m)",
           title=f"Pre-stretch ({ds.attrs.get('prestretch', '')})".replace(" ()", ""))
    ax.legend()
    paths.append(save_figure(fig, outdir, "fig02_radius.png"))
    fig, axes = plt.subplots(1, 2, figsize=(9, 4), sharex=True)
    for sel in grid_points(ds, ("rho",)):
        for ax, var in zip(axes, ("sigma_1", "sigma_2")):
            ax.plot(ds.rho, ds[var].sel(sel) / 1e6, label=_label(ds, **sel))
    for ax, sym in zip(axes, ("1", "2")):
        ax.set(xlabel=r"undeformed radius $\rho$ (m)", ylabel=rf"$\sigma_{sym}$ (MPa)")
    axes[0].legend()
    paths.append(save_figure(fig, outdir, "fig03_stresses.png"))
    return paths


def linear_figures(ds, outdir) -> list[Path]:
    """Frequency spectra (Fig. 4) and frequencies versus delta (Fig. 5) and delta_o (Fig. 6)."""
    plt = pyplot()
    paths = []
    modes = list(zip(ds.m.values.tolist(), ds.n.values.tolist()))
    for dim, name, xlabel in (("delta", "fig05_frequency_vs_delta.png", r"stretch ratio $\delta$"),
                              ("delta_o", "fig06_frequency_vs_delta_o.png", r"inner radius ratio $\delta_o$")):
        if ds.sizes.get(dim, 1) < 2:
            continue
        panels = list(itertools.islice(grid_points(ds, (dim,)), 4))
        fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4), sharey=True, squeeze=False)
        for ax, sel in zip(axes[0], panels):
            for k, (m, n) in enumerate(modes):
                line, = ax.plot(ds[dim], ds.omega.sel(sel).isel(mode=k), marker=".", label=f"m={m}, n={n}")
                ax.plot(ds[dim], ds.omega_bound.sel(sel).isel(mode=k), ls="--", color=line.get_color(), lw=0.8)
            ax.set(xlabel=xlabel, title=_label(ds, **sel))
        axes[0, 0].set_ylabel(r"$\omega_{mn}$ (rad/s)")
        axes[0, -1].legend(loc="center left", bbox_to_anchor=(1.02, 0.5), title="dashed: Eq. 29")
        paths.append(save_figure(fig, outdir, name))
    ns = sorted(set(n for _, n in modes))
    if len(modes) > 1:
        fig, ax = plt.subplots(figsize=(5, 4))
        for sel in itertools.islice(grid_points(ds, ()), 4):
            for n in ns:
                idx = [k for k, (_, nn) in enumerate(modes) if nn == n]
                ax.plot([modes[k][0] for k in idx], ds.omega.sel(sel).isel(mode=idx), marker="o",
                        label=f"n={n}, {_label(ds, **sel)}")
        ax.set(xlabel="radial index m", ylabel=r"$\omega_{mn}$ (rad/s)", title="Frequency spectrum")
        ax.legend()
        paths.append(save_figure(fig, outdir, "fig04_spectrum.png"))
    return paths + mode_figure(ds, outdir)


def mode_figure(ds, outdir) -> list[Path]:
    """Fig. 7: the three lowest vibration modes (Eq. 26) on the undeformed annulus."""
    import numpy as np

    from model.modes import bessel_roots, mode_shape

    plt = pyplot()
    sel = next(grid_points(ds, ("delta",)))
    first = {k: v for k, v in sel.items() if k != "delta_o"}
    omega = ds.omega.sel(first).isel(delta=0) if "delta" in ds.dims else ds.omega.sel(first)
    delta_o = float(sel.get("delta_o", ds.attrs.get("delta_o", 0.2)))
    if "delta_o" in ds.dims:
        omega = omega.sel(delta_o=delta_o)
    order = np.argsort(omega.values)[:3]
    rho = np.linspace(delta_o, 1.0, 60)
    theta = np.linspace(0, 2 * np.pi, 121)
    fig, axes = plt.subplots(1, len(order), figsize=(3.6 * len(order), 3.4),
                             subplot_kw={"projection": "polar"}, squeeze=False)
    for ax, k in zip(axes[0], order):
        m, n = int(ds.m[k]), int(ds.n[k])
        phi = mode_shape(rho, bessel_roots(n, delta_o, m)[-1], n, 1.0, delta_o)[0]
        w = np.outer(np.cos(n * theta), phi)
        ax.pcolormesh(theta, rho, w.T / np.abs(w).max(), cmap="RdBu_r", vmin=-1, vmax=1, shading="auto")
        ax.set_ylim(0, 1)
        ax.set_yticklabels([])
        ax.set_xticklabels([])
        ax.set_title(f"m={m}, n={n}: {float(omega[k]):.2f} rad/s", fontsize=9)
    delta = float(ds.delta[0]) if "delta" in ds.dims else float("nan")
    fig.suptitle(rf"Vibration modes, $\delta_o$ = {delta_o:g}, $\delta$ = {delta:g} (normalised $w$)", y=1.04)
    return [save_figure(fig, outdir, "fig07_modes.png")]
