"""Every figure of ``python -m sweep figures``: one function per analysis (Figs. 2-19).

Each ``<analysis>_figures(ds, outdir)`` takes the published Dataset and an output
directory and returns the list of paths it wrote; the analyses' ``figures`` methods
delegate here.  :func:`draw` is the entry point (the command line's and a script's): it
applies the house style and the chosen format, resolution and style file inside a
``matplotlib.rc_context``, so the caller's ``rcParams`` and backend are left as they
were.  matplotlib is imported lazily.  Grid values are labelled with the symbols of
:data:`SYMBOLS`.
"""

from __future__ import annotations

import contextvars
import itertools
from pathlib import Path

import numpy as np

#: Units of the grid keys in axis labels.
GRID_UNITS = {"delta": "", "delta_o": "", "Omega": "rad/s", "P0": "Pa", "c": r"N s/m$^3$"}
#: Plot symbols of the grid keys.
SYMBOLS = {"delta": r"$\delta$", "delta_o": r"$\delta_o$", "Omega": r"$\Omega$", "P0": "$P_0$", "c": "$c$"}


def point_label(sel) -> str:
    """``"$\\delta$ = 1.1, $\\Omega$ = 33.5 rad/s"`` for a dict of grid values (with units)."""
    return ", ".join(f"{SYMBOLS.get(k, k)} = {float(v):g}" + (f" {GRID_UNITS[k]}" if GRID_UNITS.get(k) else "")
                     for k, v in sel.items())


#: The house style, applied by :func:`draw` (a style file given to it comes on top).
HOUSE_STYLE = {"figure.dpi": 120, "axes.grid": True, "grid.alpha": 0.3, "font.size": 10,
               "legend.fontsize": 8, "savefig.bbox": "tight"}
#: Output formats of :func:`draw`.
FORMATS = ("png", "pdf", "svg")
_OUTPUT = contextvars.ContextVar("figure_output", default=("png", None))
_COLLECT = contextvars.ContextVar("figure_collector", default=None)


def pyplot():
    """``matplotlib.pyplot`` (its backend and ``rcParams`` untouched)."""
    import matplotlib.pyplot as plt

    return plt


def draw(analysis, ds, outdir, *, fmt: str = "png", dpi: float | None = None, style=None) -> list[Path]:
    """The standard figures of a result, written to ``outdir``.

    Parameters
    ----------
    analysis : sweep.analyses.base.Analysis
        The analysis that wrote ``ds`` (``sweep.analyses.get(ds.attrs["analysis"])``).
    ds : xarray.Dataset
        The result.
    outdir : path
        Output directory (created).
    fmt : {"png", "pdf", "svg"}
        File format (PDF and SVG are vector; the basins images are embedded rasters).
    dpi : float, optional
        Resolution of raster output (default 120, basins 150).
    style : str or path, optional
        A matplotlib style (name or ``.mplstyle`` file) applied on top of the house style.

    Returns
    -------
    list of pathlib.Path
    """
    import matplotlib.pyplot as plt

    if fmt not in FORMATS:
        raise ValueError(f"fmt = {fmt!r} is invalid: must be one of {', '.join(FORMATS)}")
    Path(outdir).mkdir(parents=True, exist_ok=True)
    token = _OUTPUT.set((fmt, dpi))
    try:
        with plt.rc_context(HOUSE_STYLE):
            if style is not None:
                plt.style.use(style)
            return _per_result(analysis, ds).figures(ds, Path(outdir))
    finally:
        _OUTPUT.reset(token)


def make(analysis, ds, style=None) -> dict:
    """The standard figures of a result as matplotlib ``Figure`` objects, nothing written.

    Parameters
    ----------
    analysis : sweep.analyses.base.Analysis
        The analysis that wrote ``ds``.
    ds : xarray.Dataset
        The result.
    style : str or path, optional
        A matplotlib style on top of the house style (applied while drawing).

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        By file stem (``"bifurcation_P0"``, ``"backbone"``, ...; ``"modes_1_0-2_0/backbone"``
        for a result over mode sets), for the caller to adjust,
        show or save; the caller's ``rcParams`` and backend are left alone.
    """
    import matplotlib.pyplot as plt

    figures: dict = {}
    token = _COLLECT.set(figures)
    try:
        with plt.rc_context(HOUSE_STYLE):
            if style is not None:
                plt.style.use(style)
            _per_result(analysis, ds).figures(ds, Path("."))
    finally:
        _COLLECT.reset(token)
    return figures


def _per_result(analysis, ds):
    """The analysis that draws ``ds``: a result over mode sets is drawn set by set, each in
    its own subdirectory (:class:`~sweep.analyses.mode_sets.ModeSetSweep`)."""
    from sweep.analyses.mode_sets import ModeSetSweep

    return ModeSetSweep(analysis) if "mode_set" in ds.dims else analysis


def save_figure(fig, outdir, name, dpi: float | None = None) -> Path:
    """Save ``fig`` as ``outdir/name`` in the format of :func:`draw` (the suffix of ``name``
    is replaced), close it, return the path.  ``dpi`` is this figure's default resolution.
    Under :func:`make` the figure is handed back instead (nothing is written)."""
    import matplotlib.pyplot as plt

    collected = _COLLECT.get()
    if collected is not None:
        key = Path(name).stem if Path(outdir) == Path(".") else f"{Path(outdir).as_posix()}/{Path(name).stem}"
        collected[key] = fig
        return Path(name)
    fmt, chosen = _OUTPUT.get()
    path = (Path(outdir) / name).with_suffix("." + fmt)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, format=fmt, **({"dpi": chosen or dpi} if chosen or dpi else {}))
    plt.close(fig)
    return path


def computed_points(ds, exclude):
    """:func:`grid_points` without those left out by the job's ``[grid] cases`` (status 3
    everywhere along the excluded dims)."""
    from sweep.analyses.base import STATUS_SKIPPED

    for sel in grid_points(ds, exclude):
        if "status" not in ds or bool((ds["status"].sel(sel) != STATUS_SKIPPED).any()):
            yield sel


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


def linear_figures(ds, outdir) -> list[Path]:
    """Frequency spectra (Fig. 4) and frequencies versus delta (Fig. 5) and delta_o (Fig. 6)."""
    plt = pyplot()
    paths = []
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
    other = {d: ds[d].values[0] for d in ("Omega", "P0", "c") if d in ds.dims}
    for do in ds.delta_o.values:
        sel = dict(other, delta_o=do)
        if "delta" in ds.dims and ds.sizes["delta"] >= 2:
            line, = ax.plot(ds.delta, ds.omega.sel(sel).isel(mode=k), marker=".", label=rf"$\delta_o$ = {do:g}")
            ax.axhline(float(ds.omega_bound.sel(sel).isel(mode=k).max()), ls="--", lw=0.8, color=line.get_color())
    ax.set(xlabel=r"stretch ratio $\delta$", ylabel=r"$\omega_{10}$ (rad/s)", title="(a) m = 1, n = 0; dashed: Eq. 29")
    if ax.lines:
        ax.legend()

    mem = Membrane(**{key: float(ds.attrs[f"membrane_{key}"]) for key in ("C1", "h", "Gamma", "Re")
                      if f"membrane_{key}" in ds.attrs})
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
    sel = {d: ds[d].values[0] for d in ("Omega", "P0", "c") if d in ds.dims}
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
    """Fig. 7: the three lowest vibration modes (Eq. 26) on the undeformed annulus."""
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
        phi = mode_shape(rho, bessel_roots(abs(n), delta_o, m)[-1], abs(n), 1.0, delta_o)[0]
        w = np.outer(np.cos(n * theta) if n >= 0 else np.sin(-n * theta), phi)  # n < 0: sine companion
        ax.pcolormesh(theta, rho, w.T / np.abs(w).max(), cmap="RdBu_r", vmin=-1, vmax=1, shading="auto")
        ax.set_ylim(0, 1)
        ax.set_yticklabels([])
        ax.set_xticklabels([])
        ax.set_title(f"m={m}, n={n}: {float(omega[k]):.2f} rad/s", fontsize=9)
    delta = float(ds.delta[0]) if "delta" in ds.dims else float("nan")
    fig.suptitle(rf"Vibration modes, $\delta_o$ = {delta_o:g}, $\delta$ = {delta:g} (normalised $w$)", y=1.04)
    return [save_figure(fig, outdir, "fig07_modes.png")]


def _runs(stable):
    """Index ranges ``(i0, i1, stable)`` of consecutive points drawn with one line style.

    A located bifurcation point (stable = 0) closes one run and opens the next.
    """
    n = stable.size
    runs, i0 = [], 0
    for i in range(1, n):
        if stable[i] != stable[i0] or i == n - 1:
            style = bool(stable[i0]) if i > i0 + 1 or stable[i0] == stable[i] else bool(stable[i])
            runs.append((i0, i, style))
            i0 = i
    return runs


def _draw_branch(ax, x, amp, stable, kind, color, label, stopped=False):
    ok = np.isfinite(x)
    x, amp, stable, kind = x[ok], amp[ok], stable[ok], kind[ok]
    if stopped and x.size:  # the branch ended before its range did: mark where
        ax.plot(x[-1:], amp[-1:] * 1e3, ls="none", marker="X", ms=8, color=color, mec="k")
    first = True
    for i0, i1, st in _runs(stable):
        ax.plot(x[i0:i1 + 1], amp[i0:i1 + 1] * 1e3, color=color, ls="-" if st else "--", lw=1.2,
                label=label if first else None)
        first = False
    for k, marker in BIFURCATION_MARKERS.items():
        sel = kind == k
        ax.plot(x[sel], amp[sel] * 1e3, ls="none", marker=marker, mfc="white", color=color, ms=5)


#: Marker of each located point type (``point_type``): fold, period doubling,
#: Neimark-Sacker, branch point.
BIFURCATION_MARKERS = {1: "o", 2: "s", 3: "D", 4: "^"}


def _family_colors(plt, families) -> dict:
    # by wave number, so that a family has one colour in every figure
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    return {0: "k", **{int(n): cycle[int(n) % len(cycle)] for n in families}}


def stability_map_figures(ds, outdir, par: str, rows: str) -> list:
    """Stability maps: per row of the grid parameter ``rows`` (e.g. P0), the intervals of the
    continued parameter where the resonant stretch of the branch (from its start to the
    first saddle-node) is unstable to each family, and the saddle-nodes of the row."""
    from model.continuation import resonant_end, unstable_points

    plt = pyplot()
    exclude = ("c", rows, "point", "fold", "multiplier", "mode", "family", "family_multiplier", "curve",
               "curve_point", "cusp")
    panels = [dict(sel, **({"c": c} if "c" in ds.dims else {})) for sel in computed_points(ds, exclude)
              for c in (ds.c.values if "c" in ds.dims else [None])]
    families = ds.family.values
    colors = _family_colors(plt, families)
    fig, axes = _panel_axes(plt, len(panels))
    step = float(np.min(np.diff(np.sort(ds[rows].values)))) if ds.sizes[rows] > 1 else 1.0
    for ax, sel in zip(axes, panels):
        fixed = {k: v for k, v in sel.items() if v is not None}
        for r in ds[rows].values:
            b = ds.sel(fixed).sel({rows: r})
            kind = b.point_type.values
            n = int(b.n_points)
            if n <= 0:
                continue
            end = resonant_end(kind[:n])
            x = b[par].values[:end]
            mod = b.family_multiplier_modulus.values[:end]
            for j, fam in enumerate(families):
                bad = unstable_points(mod[:, j])
                lo = 0.35 * step * (2 * j / max(len(families) - 1, 1) - 1)
                ax.plot(np.where(bad, x, np.nan), np.full(end, r + lo), color=colors[int(fam)], lw=2.5,
                        solid_capstyle="butt", label=f"unstable to n = {fam}" if r == ds[rows].values[0] else None)
            ax.plot(b[par].values[kind == 1], np.full(int((kind == 1).sum()), r), "ko", mfc="white", ms=5)
        folds = ds.sel(fixed).fold_value.transpose(rows, "fold").values
        for f in range(2):  # the saddle-nodes of the rows joined: the fold curves of the grid
            ax.plot(folds[:, f], ds[rows].values, color="k", lw=0.8, ls="-",
                    label="saddle-nodes" if f == 0 else None)
        ax.set(xlabel=f"{SYMBOLS.get(par, par)} ({GRID_UNITS.get(par, '')})",
               ylabel=f"{SYMBOLS.get(rows, rows)} ({GRID_UNITS.get(rows, '')})")
        ax.set_title(point_label(fixed), fontsize=9)
    axes[0].legend(fontsize=7, loc="upper left")
    fig.suptitle("Stability map of the resonant axisymmetric responses (one row per continuation)", fontsize=10)
    fig.tight_layout()
    return [save_figure(fig, outdir, f"stability_map_{par}.png")]


def bifurcation_curve_figures(ds, outdir, par: str) -> list:
    """Curves of bifurcation points in the plane of the continued and the second parameter,
    coloured by the family of their block (black: axisymmetric), marked by kind."""
    from model.continuation import KIND_LABELS

    plt = pyplot()
    second = next(v[len("curve_"):] for v in ds.data_vars
                  if v.startswith("curve_") and v not in ("curve_amplitude", "curve_kind", "curve_family", f"curve_{par}"))
    families = ds.family.values if "family" in ds.coords else []
    colors = _family_colors(plt, families)
    panels = list(computed_points(ds, ("point", "fold", "multiplier", "mode", "family", "family_multiplier", "curve",
                                       "curve_point", "cusp")))
    fig, axes = _panel_axes(plt, len(panels))
    styles = {1: "-", 2: ":", 3: "--", 4: "-"}
    for ax, sel in zip(axes, panels):
        b = ds.sel(sel)
        seen = set()
        for j in range(b.sizes["curve"]):
            kind, fam = int(b.curve_kind[j]), int(b.curve_family[j])
            if kind < 0:
                continue
            name = KIND_LABELS[kind] + (f", n = {fam}" if fam else "")
            ax.plot(b[f"curve_{par}"][j], b[f"curve_{second}"][j], ls=styles[kind], color=colors.get(fam, "k"),
                    lw=1.4, label=None if name in seen else name)
            seen.add(name)
        ax.set(xlabel=f"{SYMBOLS.get(par, par)} ({GRID_UNITS.get(par, '')})",
               ylabel=f"{SYMBOLS.get(second, second)} ({GRID_UNITS.get(second, '')})")
        ax.set_title(point_label(sel), fontsize=9)
        ax.legend(fontsize=7)
    fig.suptitle("Curves of bifurcation points (two-parameter continuation)", fontsize=10)
    fig.tight_layout()
    return [save_figure(fig, outdir, f"bifurcation_curves_{par}.png")]


def family_figures(ds, outdir, par: str) -> list:
    """Stability of the axisymmetric branches to the asymmetric families.

    Per grid point, two panels: the branch (amplitude versus the continued parameter) with
    each unstable stretch coloured by the family whose multiplier is largest there (grey:
    unstable in the axisymmetric block only), and the largest multiplier modulus of each
    family along the branch, with the stability limit 1.
    """
    plt = pyplot()
    panels = list(computed_points(ds, ("c", "point", "fold", "multiplier", "mode", "family", "family_multiplier",
                                       "curve_point", "cusp")))
    panels = [dict(sel, **({"c": c} if "c" in ds.dims else {})) for sel in panels
              for c in (ds.c.values if "c" in ds.dims else [None])]
    families = ds.family.values
    colors = _family_colors(plt, families)
    fig, axes = plt.subplots(2, len(panels), figsize=(max(4.6 * len(panels), 6.0), 7.0), squeeze=False,
                             sharex="col")
    for j, sel in enumerate(panels):
        b = ds.sel({k: v for k, v in sel.items() if v is not None})
        x, amp = b[par].values, b.amplitude.values * 1e3
        mod = b.family_multiplier_modulus.values
        axi = b.multiplier_modulus.values
        ok = np.isfinite(x)
        top, bottom = axes[0, j], axes[1, j]
        top.plot(x[ok], amp[ok], color="k", lw=0.8)
        worst = np.where(np.isfinite(mod[ok]).all(axis=1), np.nanargmax(np.nan_to_num(mod[ok], nan=-1.0), axis=1), 0)
        unstable_family = mod[ok][np.arange(ok.sum()), worst] > 1.0
        for n in families:
            sel_n = unstable_family & (families[worst] == n)
            top.plot(x[ok][sel_n], amp[ok][sel_n], ls="none", marker=".", ms=4, color=colors[int(n)],
                     label=f"unstable to n = {n}")
            bottom.plot(x[ok], mod[ok][:, list(families).index(n)], lw=1.0, color=colors[int(n)], label=f"n = {n}")
        axi_only = (axi[ok] > 1.0) & ~unstable_family
        top.plot(x[ok][axi_only], amp[ok][axi_only], ls="none", marker=".", ms=4, color="0.6",
                 label="unstable (axisymmetric)")
        kind = b.point_type.values[ok]
        for k, marker in BIFURCATION_MARKERS.items():
            top.plot(x[ok][kind == k], amp[ok][kind == k], ls="none", marker=marker, mfc="white", color="k", ms=5)
        bottom.axhline(1.0, color="k", lw=0.6, ls=":")
        if par == "Omega":
            _zoom_omega(top, x, b.amplitude.values)
        top.set(ylabel=r"amplitude of $w(0.5, 0)$ (mm)")
        top.set_title(point_label({k: v for k, v in sel.items() if v is not None}), fontsize=9)
        bottom.set(xlabel=f"{SYMBOLS.get(par, par)} ({GRID_UNITS.get(par, '')})",
                   ylabel="largest multiplier modulus")
    axes[0, 0].legend(fontsize=7, loc="upper left", markerscale=2)
    axes[1, 0].legend(fontsize=7, loc="upper left", ncol=2)
    fig.suptitle("Stability of the axisymmetric responses to the asymmetric mode families\n"
                 "(triangles: branch points, diamonds: Neimark-Sacker, circles: saddle-nodes)", fontsize=10)
    fig.tight_layout()
    return [save_figure(fig, outdir, f"family_stability_{par}.png")]


def _panel_axes(plt, n):
    cols = min(n, 3)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(max(4.2 * cols, 6.0), 3.6 * rows + 0.4), squeeze=False)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    return fig, axes.ravel()[:n]


def _zoom_omega(ax, x, amp):
    """Limit an Omega axis to the resonance: where the amplitude exceeds 5 % of its maximum,
    widened on each side by half that range and at least 2 rad/s."""
    ok = np.isfinite(x) & np.isfinite(amp)
    if not ok.any():
        return
    x, amp = x[ok], amp[ok]
    peak = x[amp >= 0.05 * amp.max()]
    pad = max(0.5 * (peak.max() - peak.min()), 2.0)
    ax.set_xlim(max(x.min(), peak.min() - pad), min(x.max(), peak.max() + pad))


def _style_legend(ax):
    """Legend of the line styles (black): stable, unstable, bifurcation points present."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color="k", ls="-", label="stable"),
               Line2D([], [], color="k", ls="--", label="unstable"),
               Line2D([], [], color="k", ls="none", marker="o", mfc="white", label="saddle-node"),
               Line2D([], [], color="k", ls="none", marker="^", mfc="white", label="branch point"),
               Line2D([], [], color="k", ls="none", marker="X", label="branch stopped early")]
    return ax.legend(handles=handles, loc="upper left", fontsize=7)


def continuation_figures(ds, outdir) -> list:
    """Bifurcation diagrams (Figs. 14-16) and, with a ``c`` grid in P0, fold loci (Fig. 17).

    One panel per combination of the grid keys other than ``c``; the ``c`` values are
    overlaid (a colour bar when there are more than four).  Stable responses solid,
    unstable dashed, saddle-nodes circles (period doubling squares, Neimark-Sacker
    diamonds).  Continuations in Omega are zoomed on the resonance (:func:`_zoom_omega`).
    The fold-loci figure skips the panels without saddle-nodes.
    """
    plt = pyplot()
    par = ds.attrs.get("continued_parameter", "P0" if "P0" in ds.data_vars else "Omega")
    xlabel = r"forcing frequency $\Omega$ (rad/s)" if par == "Omega" else r"pressure amplitude $P_0$ (Pa)"
    panels = list(computed_points(ds, ("c", "point", "fold", "multiplier", "mode", "curve_point", "cusp",
                                       "family", "family_multiplier")))
    cs = ds.c.values if "c" in ds.dims else [None]
    fig, axes = _panel_axes(plt, len(panels))
    many = len(cs) > 4
    if many:
        import matplotlib as mpl

        norm = mpl.colors.Normalize(float(min(cs)), float(max(cs)))
        colors = [plt.cm.viridis(norm(float(c))) for c in cs]
    else:
        cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        colors = [cycle[j % len(cycle)] for j in range(len(cs))]
    for ax, sel in zip(axes, panels):
        for j, c in enumerate(cs):
            s = dict(sel, **({} if c is None else {"c": c}))
            b = ds.sel(s)
            _draw_branch(ax, b[par].values, b.amplitude.values, b.stable.values, b.point_type.values,
                         colors[j], None if c is None or many else f"c = {float(c):g} N s/m$^3$",
                         stopped="status" in b and int(b.status) in (1, 2))
        if par == "Omega":
            b = ds.sel(sel)
            _zoom_omega(ax, b[par].values.ravel(), b.amplitude.values.ravel())
        ax.set(xlabel=xlabel, ylabel=r"amplitude of $w(0.5, 0)$ (mm)")
        ax.set_title(point_label(sel), fontsize=9)
        if len(cs) > 1 and not many:
            ax.add_artist(_style_legend(ax))
            ax.legend(fontsize=7, loc="lower right")
    if len(cs) <= 1 or many:
        _style_legend(axes[0])
    fig.suptitle("Periodic responses (stroboscopic map)", fontsize=11)
    fig.tight_layout()
    if many:
        fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=list(axes),
                     label=r"damping $c$ (N s/m$^3$)", shrink=0.8)
    paths = [save_figure(fig, outdir, f"bifurcation_{par}.png")]
    if "family_multiplier_modulus" in ds:
        paths += family_figures(ds, outdir, par)
        rows = "P0" if par == "Omega" else "Omega"
        if ds.sizes.get(rows, 0) >= 2:
            paths += stability_map_figures(ds, outdir, par, rows)
    if "curve_kind" in ds:
        paths += bifurcation_curve_figures(ds, outdir, par)
    if par == "P0" and ds.sizes.get("c", 0) >= 3:
        with_folds = [sel for sel in panels if np.isfinite(ds.fold_value.sel(sel).values).any()]
        if with_folds:
            fig, axes = _panel_axes(plt, len(with_folds))
            for ax, sel in zip(axes, with_folds):
                b = ds.sel(sel)
                for f in range(2):
                    ax.plot(b.c, b.fold_value.isel(fold=f), marker=".", label=f"saddle-node {f + 1}")
                if "cusp_c" in b and np.isfinite(b.cusp_c):
                    ax.plot(b.cusp_c, b.cusp_value, marker="*", ms=10, ls="none", color="k", label="cusp")
                ax.set(xlabel=r"damping $c$ (N s/m$^3$)", ylabel=r"$P_0$ at saddle-node (Pa)")
                ax.set_title(point_label(sel), fontsize=9)
                ax.legend()
            fig.suptitle("Saddle-node loci versus damping", fontsize=11)
            fig.tight_layout()
            paths.append(save_figure(fig, outdir, "fold_loci_damping.png"))
    curve = [v for v in ds.data_vars if v.startswith("fold_curve_") and v not in ("fold_curve_amplitude",
                                                                                 f"fold_curve_{par}")]
    if curve:
        second = curve[0][len("fold_curve_"):]
        cells = [sel for sel in grid_points(ds, ("point", "fold", "multiplier", "curve_point", "cusp"))
                 if np.isfinite(ds[f"fold_curve_{par}"].sel(sel).values).any()]
        if not cells:
            return paths
        fig, axes = _panel_axes(plt, len(cells))
        for ax, sel in zip(axes, cells):
            b = ds.sel(sel)
            ax.plot(b[f"fold_curve_{second}"], b[f"fold_curve_{par}"], "k-", lw=1.2, label="saddle-nodes")
            ax.plot(b[f"cusp_{second}"], b[f"cusp_{par}"], "k*", ms=10, ls="none", label="cusp")
            ax.set(xlabel=f"{SYMBOLS.get(second, second)} ({GRID_UNITS.get(second, '')})",
                   ylabel=f"{SYMBOLS.get(par, par)} ({GRID_UNITS.get(par, '')})")
            ax.set_title(point_label({k: v for k, v in sel.items() if k != second}), fontsize=9)
            ax.legend()
        fig.suptitle("Curve of saddle-nodes (two-parameter continuation)", fontsize=11)
        fig.tight_layout()
        paths.append(save_figure(fig, outdir, f"fold_curve_{second}.png"))
    return paths


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
    swept = [k for k in ("delta", "delta_o", "Omega", "P0", "c") if k != par and ds.sizes.get(k, 1) > 1]
    overlay = max(swept, key=lambda k: ds.sizes[k]) if len(points) > 4 and swept else None
    panels = list(computed_points(ds, (par, "direction", overlay))) if overlay else [{}]
    fig, axes = _panel_axes(plt, len(panels))
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
    fixed = {k: float(ds[k][0]) for k in ("delta", "delta_o", "Omega", "P0", "c")
             if k != par and ds.sizes.get(k, 0) == 1}
    fig.suptitle("Steady states stepped up and down (brute force); thin lines: located jumps\n"
                 + point_label(fixed), fontsize=10)
    fig.tight_layout()
    return [save_figure(fig, outdir, f"response_{par}.png")]


def backbone_figures(ds, outdir) -> list:
    """Backbone curves (Figs. 10-12) and modal amplitudes (Fig. 9)."""
    plt = pyplot()
    sels = list(grid_points(ds, ()))
    swept = [d for d in ("delta", "delta_o", "Omega", "P0", "c") if ds.sizes.get(d, 1) > 1]

    def label(sel):
        return point_label({d: sel[d] for d in (swept or ["delta", "delta_o"]) if d in sel})

    paths = []
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for sel in sels:
        line, = ax.plot(ds.omega_nl.sel(sel), ds.amplitude.sel(sel), lw=1.6, label=label(sel))
        ax.plot(ds.omega_peak.sel(sel), ds.amplitude.sel(sel), ls="none", marker="o", ms=3.5,
                mfc="none", color=line.get_color())
        ax.axvline(float(ds.omega_bound.sel(sel)), ls="--", lw=1.0, color=line.get_color())
    ax.plot([], [], "k-", label="periodic orbits (continuation)")
    ax.plot([], [], "ko", mfc="none", ms=3.5, ls="none", label="peak-to-peak (damped decay)")
    ax.plot([], [], "k--", lw=1.0, label="bound, Eq. 29")
    ax.set(xlabel=r"frequency $\omega$ (rad/s)", ylabel=r"amplitude max $|w(0.5, 0)|$ (m)",
           title="Frequency-amplitude relation", ylim=(0, None))
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    paths.append(save_figure(fig, outdir, "backbone.png"))

    K = ds.sizes["mode"]
    fig, axes = plt.subplots(1, K, figsize=(4.2 * K, 3.6), squeeze=False, layout="constrained")
    for k, ax in enumerate(axes[0]):
        m, n = int(ds.m[k]), int(ds.n[k])
        for sel in sels:
            ax.plot(ds.omega_nl.sel(sel), ds.modal_amplitude.sel(sel).isel(mode=k), label=label(sel))
        ax.set(xlabel=r"frequency $\omega$ (rad/s)", ylabel=f"$A_{{{m}{n}}}$ (m)",
               title=f"modal amplitude $A_{{{m}{n}}}$")
    axes[0, 0].legend()
    fig.suptitle("Modal amplitudes along the backbone (Eq. 31 normalisation)")
    paths.append(save_figure(fig, outdir, "modal_amplitudes.png"))
    return paths


def mode_set_figures(ds, outdir, analysis: str) -> list:
    """The mode sets of a result over ``mode_set`` on one figure, per grid point: backbones
    (Fig. 9 as the paper draws it), continued branches, or basin fractions; none for the
    other analyses (each set's own figures are drawn too, see
    :class:`sweep.analyses.mode_sets.ModeSetSweep`)."""
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
