"""Figures of the ``linear`` analysis: spectra and frequencies (Figs. 4-6), modes (Fig. 7)."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np

from sweep.analyses.base import GEOMETRY_KEYS, GRID_KEYS, MEMBRANE_KEYS
from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import grid_points, point_label


def linear_figures(ds, outdir) -> list[Path]:
    """Frequency spectra (Fig. 4) and frequencies versus delta (Fig. 5) and delta_o (Fig. 6);
    for a convergence study in the basis size (a ``basis`` dimension) its convergence, and
    the other figures with the largest basis."""
    plt = pyplot()
    paths = []
    if "basis" in ds.dims:
        paths.append(_basis_convergence(ds, outdir))
        ds = ds.isel(basis=-1)
    modes = list(zip(ds.m.values.tolist(), ds.n.values.tolist()))
    if ds.sizes.get("delta", 1) >= 2:
        panels = list(itertools.islice(grid_points(ds, ("delta",)), 4))
        fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4), sharey=True, squeeze=False)
        for ax, sel in zip(axes[0], panels):
            for k, (m, n) in enumerate(modes):
                line, = ax.plot(ds.delta, ds.omega.sel(sel).isel(mode=k), marker=".", label=f"m={m}, n={n}")
                ax.plot(ds.delta, ds.omega_bound.sel(sel).isel(mode=k), ls="--", color=line.get_color(), lw=0.8)
            ax.set(xlabel=r"stretch ratio $\delta$", title=point_label(sel))
        axes[0, 0].set_ylabel(r"$\omega_{mn}$ (rad/s)")
        axes[0, -1].legend(loc="center left", bbox_to_anchor=(1.02, 0.5), title="dashed: Eq. 29")
        paths.append(save_figure(fig, outdir, "fig05_frequency_vs_delta.png"))
    if ds.sizes.get("delta_o", 1) >= 2 and (1, 0) in modes:
        paths.append(_fig06(ds, outdir, modes.index((1, 0))))
    if len(modes) > 1:
        paths.append(_spectrum(ds, outdir, modes))
    return paths + mode_figure(ds, outdir)


def _basis_convergence(ds, outdir) -> Path:
    # relative difference of each frequency from the largest basis' against the basis size,
    # at the first grid point
    plt = pyplot()
    first = next(iter(grid_points(ds, ())))
    omega = ds.omega.sel(first).transpose("basis", "mode")
    sizes = ds.basis.values[:-1]
    fig, ax = plt.subplots(figsize=(5, 4))
    for k, (m, n) in enumerate(zip(ds.m.values, ds.n.values)):
        change = np.abs(omega.values[:-1, k] / omega.values[-1, k] - 1)
        ax.loglog(sizes, np.where(change > 0, change, np.nan), marker="o", label=f"m={m}, n={n}")
    ax.set(xlabel="Bessel functions per wave number",
           ylabel=f"relative difference from {int(ds.basis.values[-1])} functions", title=point_label(first))
    ax.legend()
    return save_figure(fig, outdir, "linear_basis_convergence.png")


def _fig06(ds, outdir, k) -> Path:
    """Fig. 6: omega_10 versus delta for each delta_o (a) and the Eq. 29 bound versus delta_o (b).

    The bound depends on delta_o only (through alpha_10), so panel (b) draws it as a curve
    from Eq. 27/29 and marks the values stored in the result.
    """
    from model.linear import frequency_bound
    from model.modes import bessel_roots
    from model.params import Membrane

    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9.5, 4))
    other = {d: ds[d].values[0] for d in GRID_KEYS if d not in GEOMETRY_KEYS and d in ds.dims}
    for do in ds.delta_o.values:
        sel = dict(other, delta_o=do)
        if "delta" in ds.dims and ds.sizes["delta"] >= 2:
            line, = ax.plot(ds.delta, ds.omega.sel(sel).isel(mode=k), marker=".", label=rf"$\delta_o$ = {do:g}")
            ax.axhline(float(ds.omega_bound.sel(sel).isel(mode=k).max()), ls="--", lw=0.8, color=line.get_color())
    ax.set(xlabel=r"stretch ratio $\delta$", ylabel=r"$\omega_{10}$ (rad/s)", title="(a) m = 1, n = 0; dashed: Eq. 29")
    if ax.lines:
        ax.legend()

    mem = Membrane(**{key: ds.attrs[f"membrane_{key}"] for key in MEMBRANE_KEYS if f"membrane_{key}" in ds.attrs})
    fine = np.linspace(0.05, 0.9, 60)
    bx.plot(fine, [frequency_bound(mem, bessel_roots(0, d, 1)[0]) for d in fine], "k-", lw=1.2, label="Eq. 29")
    bound = ds.omega_bound.isel(mode=k)
    bound = bound.max([d for d in bound.dims if d != "delta_o"]) if bound.ndim > 1 else bound
    bx.plot(ds.delta_o, bound, "o", mfc="white", label="this run")
    bx.set(xlabel=r"inner radius ratio $\delta_o$", ylabel=r"upper bound of $\omega_{10}$ (rad/s)",
           title="(b) Eq. 29 bound versus inner radius")
    bx.legend()
    fig.tight_layout()
    return save_figure(fig, outdir, "fig06_frequency_vs_delta_o.png")


def _spectrum(ds, outdir, modes) -> Path:
    """Fig. 4: omega_mn versus m, one line per n, at two stretch ratios (the grid's delta values
    nearest 1.1 and 2.0, solid and dashed) and the first delta_o (0.2 if present)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    sel = {d: ds[d].values[0] for d in GRID_KEYS if d not in GEOMETRY_KEYS and d in ds.dims}
    if "delta_o" in ds.dims:
        values = ds.delta_o.values
        sel["delta_o"] = values[np.argmin(np.abs(values - 0.2))]
    deltas = [None]
    if "delta" in ds.dims:
        deltas = list(dict.fromkeys(float(ds.delta.sel(delta=d, method="nearest")) for d in (1.1, 2.0)))
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for j, d in enumerate(deltas):
        s = dict(sel, **({} if d is None else {"delta": d}))
        for i, n in enumerate(sorted(set(n for _, n in modes))):
            idx = [k for k, (_, nn) in enumerate(modes) if nn == n]
            ax.plot([modes[k][0] for k in idx], ds.omega.sel(s).isel(mode=idx), marker="o",
                    ls="-" if j == 0 else "--", color=cycle[i % len(cycle)],
                    label=f"n = {n}" + ("" if d is None else rf", $\delta$ = {d:g}"))
    ax.set(xlabel="radial wave number m", ylabel=r"$\omega_{mn}$ (rad/s)",
           title="Frequency spectrum" + (rf", $\delta_o$ = {float(sel['delta_o']):g}" if "delta_o" in sel else ""))
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return save_figure(fig, outdir, "fig04_spectrum.png")


def mode_figure(ds, outdir) -> list[Path]:
    """Fig. 7: the shapes of Eq. (26) of the three modes of lowest frequency on the undeformed
    annulus (the paper's figure; the converged eigenfunctions differ from them a little, for
    every model), titled with the frequencies of the result."""
    from model.modes import bessel_roots, mode_shape

    plt = pyplot()
    sel = next(grid_points(ds, ("delta",)))
    first = {k: v for k, v in sel.items() if k != "delta_o"}
    omega = ds.omega.sel(first).isel(delta=0) if "delta" in ds.dims else ds.omega.sel(first)
    delta_o = float(sel.get("delta_o", ds.attrs.get("delta_o", 0.2)))
    if "delta_o" in ds.dims:
        omega = omega.sel(delta_o=delta_o)
    order = np.argsort(omega.values)[:3]
    rho = np.linspace(delta_o, 1.0, 40)
    theta = np.linspace(0, 2 * np.pi, 97)
    R, T = np.meshgrid(rho, theta)
    fig, axes = plt.subplots(1, len(order), figsize=(3.8 * len(order), 3.6),
                             subplot_kw={"projection": "3d"}, squeeze=False)
    for ax, k in zip(axes[0], order):
        m, n = int(ds.m[k]), int(ds.n[k])
        phi = mode_shape(rho, bessel_roots(abs(n), delta_o, m)[-1], abs(n), 1.0, delta_o)[0]
        w = (np.cos(n * T) if n >= 0 else np.sin(-n * T)) * phi  # n < 0: sine companion
        w = w / np.abs(w).max()
        ax.plot_surface(R * np.cos(T), R * np.sin(T), w, cmap="RdBu_r", vmin=-1, vmax=1, rstride=2, cstride=1,
                        linewidth=0, antialiased=True)
        ax.set(xticks=[], yticks=[], zticks=[], zlim=(-1, 1))
        ax.set_box_aspect((1, 1, 0.45))
        ax.set_title(f"m={m}, n={n}: {float(omega[k]):.2f} rad/s", fontsize=9)
    delta = float(ds.delta[0]) if "delta" in ds.dims else float("nan")
    fig.suptitle(rf"Mode shapes of Eq. 26, $\delta_o$ = {delta_o:g}, $\delta$ = {delta:g} (normalised $w$; "
                 f"frequencies: {ds.attrs.get('model', 'rom')} model)", y=1.04)
    return [save_figure(fig, outdir, "fig07_modes.png")]
