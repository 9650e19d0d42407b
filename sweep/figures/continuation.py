"""Figures of the ``continuation`` analysis: bifurcation diagrams (Figs. 14-16), fold loci
(Fig. 17), the families' stability, stability maps and curves of bifurcation points."""

from __future__ import annotations

import numpy as np

from sweep.analyses.base import GRID_KEYS
from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import GRID_UNITS, SYMBOLS, computed_points, grid_points, panel_axes, point_label


def continuation_figures(ds, outdir) -> list:
    """Bifurcation diagrams (Figs. 14-16) and, with a ``c`` grid in P0, fold loci (Fig. 17).

    One panel per combination of the grid keys other than ``c``; the ``c`` values are
    overlaid (a colour bar when there are more than four).  Stable responses solid,
    unstable dashed, saddle-nodes circles (period doubling squares, Neimark-Sacker
    diamonds); with ``symmetry_breaking`` the responses without the half-period symmetry in
    thin lines.  Continuations in Omega are zoomed on the resonance (:func:`_zoom_omega`).
    The fold-loci figure skips the panels without saddle-nodes.  Of a study in the families'
    radial modes (a ``family_radial`` dimension) the figures show the largest count, but for the
    stability map, which has a panel per count.
    """
    study = ds
    if "family_radial" in ds.dims:
        ds = ds.isel(family_radial=-1)
    plt = pyplot()
    par = ds.attrs.get("continued_parameter", "P0" if "P0" in ds.data_vars else "Omega")
    xlabel = r"forcing frequency $\Omega$ (rad/s)" if par == "Omega" else r"pressure amplitude $P_0$ (Pa)"
    panels = list(computed_points(ds, ("c", "point", "fold", "multiplier", "mode", "curve_point", "cusp",
                                       "family", "family_multiplier")))
    cs = ds.c.values if "c" in ds.dims else [None]
    fig, axes = panel_axes(plt, len(panels))
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
            if f"broken_{par}" in b:  # the responses without the half-period symmetry
                _draw_branch(ax, b[f"broken_{par}"].values, b.broken_amplitude.values, b.broken_stable.values,
                             b.broken_point_type.values, colors[j], None, lw=0.6)
        if par == "Omega":
            b = ds.sel(sel)
            _zoom_omega(ax, b[par].values.ravel(), b.amplitude.values.ravel())
        ax.set(xlabel=xlabel, ylabel=r"amplitude of $w(0.5, 0)$ (mm)")
        ax.set_title(point_label(sel), fontsize=9)
        if len(cs) > 1 and not many:
            ax.add_artist(_style_legend(ax, f"broken_{par}" in ds))
            ax.legend(fontsize=7, loc="lower right")
    if len(cs) <= 1 or many:
        _style_legend(axes[0], f"broken_{par}" in ds)
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
            paths += stability_map_figures(study, outdir, par, rows)
    if "curve_kind" in ds:
        paths += bifurcation_curve_figures(ds, outdir, par)
    if par == "P0" and ds.sizes.get("c", 0) >= 3:
        with_folds = [sel for sel in panels if np.isfinite(ds.fold_value.sel(sel).values).any()]
        if with_folds:
            fig, axes = panel_axes(plt, len(with_folds))
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
        fig, axes = panel_axes(plt, len(cells))
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


def _draw_branch(ax, x, amp, stable, kind, color, label, stopped=False, lw=1.2):
    ok = np.isfinite(x)
    x, amp, stable, kind = x[ok], amp[ok], stable[ok], kind[ok]
    if stopped and x.size:  # the branch ended before its range did: mark where
        ax.plot(x[-1:], amp[-1:] * 1e3, ls="none", marker="X", ms=8, color=color, mec="k")
    first = True
    for i0, i1, st in _runs(stable):
        ax.plot(x[i0:i1 + 1], amp[i0:i1 + 1] * 1e3, color=color, ls="-" if st else "--", lw=lw,
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
    first saddle-node) is unstable to each family, and the saddle-nodes of the row.  A study in
    the families' radial modes has a panel per count (the tongues against the radial modes)."""
    from model.continuation import resonant_end, unstable_points

    plt = pyplot()
    exclude = ("c", rows, "point", "fold", "multiplier", "mode", "family", "family_multiplier", "curve",
               "curve_point", "cusp", "family_radial")
    counts = ds.family_radial.values if "family_radial" in ds.dims else [None]
    panels = [dict(sel, **({"c": c} if "c" in ds.dims else {}), family_radial=M)
              for sel in computed_points(ds, exclude) for c in (ds.c.values if "c" in ds.dims else [None])
              for M in counts]
    families = ds.family.values
    colors = _family_colors(plt, families)
    fig, axes = panel_axes(plt, len(panels))
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
        radial = fixed.pop("family_radial", None)
        ax.set_title(point_label(fixed) + ("" if radial is None else f", M = {int(radial)} radial modes"), fontsize=9)
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
    fig, axes = panel_axes(plt, len(panels))
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


def _style_legend(ax, thin: bool = False):
    """Legend of the line styles (black): stable, unstable, the markers of every kind of
    located point and of a branch stopped early; ``thin``: the responses without the
    half-period symmetry."""
    from matplotlib.lines import Line2D

    from model.continuation import KIND_LABELS

    handles = [Line2D([], [], color="k", ls="-", label="stable"),
               Line2D([], [], color="k", ls="--", label="unstable")]
    handles += [Line2D([], [], color="k", ls="none", marker=marker, mfc="white", label=KIND_LABELS[kind])
                for kind, marker in BIFURCATION_MARKERS.items()]
    handles.append(Line2D([], [], color="k", ls="none", marker="X", label="branch stopped early"))
    if thin:
        handles.append(Line2D([], [], color="k", ls="-", lw=0.6, label="without the half-period symmetry"))
    return ax.legend(handles=handles, loc="upper left", fontsize=7)


def continuation_comparison(datasets, outdir) -> list:
    """Forced branches of several results (ROM against the full model, mode sets): per grid
    point of the first result that every result has (the same continued parameter), each
    result's branch, stable solid and unstable dashed, labelled with its model."""
    from sweep.figures.backbone import result_label

    plt = pyplot()
    first = datasets[0]
    par = first.attrs.get("continued_parameter")
    if any(ds.attrs.get("continued_parameter") != par or "mode_set" in ds.dims for ds in datasets):
        return []
    own = ("point", "fold", "multiplier", "mode", "curve_point", "cusp", "family", "family_multiplier")
    # a grid dimension of one value that another result lacks is no difference; one of several
    # values that the first lacks would merge branches under one label: not compared
    if any(ds.sizes[d] > 1 for ds in datasets[1:] for d in GRID_KEYS if d in ds.dims and d not in first.dims):
        return []
    datasets = [first] + [ds.isel({d: 0 for d in GRID_KEYS if d in ds.dims and d not in first.dims}) for ds in datasets[1:]]
    panels = [sel for sel in computed_points(first, own)
              if all(all((d not in ds.dims and first.sizes[d] == 1) or
                         (d in ds.dims and np.any(np.isclose(ds[d].values, v))) for d, v in sel.items())
                     for ds in datasets[1:])]
    if not panels:
        return []
    fig, axes = panel_axes(plt, len(panels))
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, sel in zip(axes, panels):
        for j, ds in enumerate(datasets):
            b = ds.sel({d: v for d, v in sel.items() if d in ds.dims}, method="nearest")
            _draw_branch(ax, b[par].values.ravel(), b.amplitude.values.ravel(), b.stable.values.ravel(),
                         b.point_type.values.ravel(), cycle[j % len(cycle)], result_label(ds))
        ax.set(xlabel=r"forcing frequency $\Omega$ (rad/s)" if par == "Omega" else r"pressure amplitude $P_0$ (Pa)",
               ylabel=r"amplitude of $w(0.5, 0)$ (mm)")
        ax.set_title(point_label(sel), fontsize=9)
        ax.add_artist(_style_legend(ax))
        ax.legend(fontsize=7, loc="lower right")
    fig.suptitle("Periodic responses of several results", fontsize=11)
    fig.tight_layout()
    paths = [save_figure(fig, outdir, f"bifurcation_{par}_comparison.png")]
    if all("family_multiplier_modulus" in ds for ds in datasets):
        paths += _family_comparison(plt, datasets, panels, par, outdir)
    return paths


def _family_comparison(plt, datasets, panels, par, outdir) -> list:
    """The largest multiplier modulus of each wave number that every result has along its
    branch, one row per wave number, one line per result (a study in radial modes per family:
    its largest count), with the stability limit 1."""
    from sweep.figures.backbone import result_label

    datasets = [ds.isel(family_radial=-1) if "family_radial" in ds.dims else ds for ds in datasets]
    common = sorted(set.intersection(*(set(ds.family.values.tolist()) for ds in datasets)))
    if not common:
        return []
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    fig, axes = plt.subplots(len(common), len(panels), figsize=(max(5.0 * len(panels), 6.0), 1.9 * len(common) + 1.0),
                             squeeze=False, sharex="col")
    for col, sel in enumerate(panels):
        for row, n in enumerate(common):
            ax = axes[row, col]
            for j, ds in enumerate(datasets):
                b = ds.sel({d: v for d, v in sel.items() if d in ds.dims}, method="nearest").sel(family=n)
                ax.plot(b[par].values.ravel(), b.family_multiplier_modulus.values.ravel(), lw=1.0,
                        color=cycle[j % len(cycle)], label=result_label(ds))
            ax.axhline(1.0, color="k", lw=0.6, ls=":")
            ax.set_ylabel(f"n = {n}", fontsize=9)
        axes[0, col].set_title(point_label(sel), fontsize=9)
        axes[-1, col].set_xlabel(f"{SYMBOLS.get(par, par)} ({GRID_UNITS.get(par, '')})")
    axes[0, 0].legend(fontsize=7, loc="lower left")
    fig.suptitle("Largest multiplier modulus of each asymmetric family along the branch\n"
                 "(above 1: the axisymmetric response is unstable to that family)", fontsize=10)
    fig.tight_layout()
    return [save_figure(fig, outdir, f"family_stability_{par}_comparison.png")]
