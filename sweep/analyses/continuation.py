"""Analysis ``continuation``: bifurcation diagrams of the stroboscopic map (Figs. 14-17).

Per grid point, the branch of periodic responses of the forced ROM is continued by
pseudo-arclength (:func:`model.continuation.continue_orbits`) in one parameter, ``Omega`` or
``P0``, from ``start`` to ``stop``; the other forcing parameters (``P0`` or ``Omega``, and
``c``) come from the grid, and the continued one must not be a grid key.

Option table ``[continuation]``:

``parameter`` (required)
    ``"Omega"`` (rad/s) or ``"P0"`` (Pa).
``start``, ``stop`` (required)
    The range; the branch starts at ``start`` from rest (a unique small response there:
    ``P0 = 0``, or ``Omega`` away from resonance).
``modes``, ``prestretch``
    As everywhere (default ``[[1, 0]]``, ``"numeric"``).
``max_points`` (default 400), ``ds_max`` (default 0.1), ``steps`` (default 128)
    Length of the ``point`` dimension, largest arclength step (scaled unknowns: the whole
    parameter range is 1, 0.05 m of displacement is 1) and RK4 steps per forcing period.

Outputs (a task's branches differ in length: every ``point`` array is padded with NaN,
``stable`` and ``point_type`` with -1):

* ``<parameter>`` (``point``): the continued parameter's value, the variable is named
  after it (``Omega`` in rad/s or ``P0`` in Pa; the dataset attribute
  ``continued_parameter`` names it too);
* ``amplitude`` (``point``): max over one period of ``|w(0.5 Re, 0, t)|`` (m);
* ``stable`` (``point``, int8): 1 stable, 0 unstable (and at located bifurcation points);
* ``point_type`` (``point``, int8): 0 regular, 1 fold (saddle-node), 2 period doubling,
  3 Neimark-Sacker; bifurcation points are located to ~1e-10 in arclength and inserted;
* ``multiplier_real``, ``multiplier_imag`` (``point``, ``multiplier``): Floquet
  multipliers by decreasing modulus, and ``multiplier_modulus`` (``point``) the largest;
* ``fold_value``, ``fold_amplitude`` (``fold``, :data:`MAX_FOLDS` long, NaN padded): the
  saddle-node points in branch order, and ``n_points``, ``n_folds``.

Fold loci versus damping (Fig. 17): put ``c`` in the grid (a dense list).  When ``c`` has
three or more values and ``parameter = "P0"``, :meth:`ContinuationAnalysis.assemble` adds,
per combination of the other grid keys, the cusp where the two folds merge:
``cusp_c`` (N s/m^3) and ``cusp_value`` (Pa).  Near a cusp the two fold amplitudes differ
like ``sqrt(c_cusp - c)``, so the cusp is where the straight line through the squared fold
amplitude differences of the last two ``c`` values with two folds reaches zero (bounded by
the first ``c`` with no fold), and ``cusp_value`` the mean fold value extrapolated linearly
to it.  The status is ``ok`` when the branch reached ``stop``, ``not_converged`` otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from model.continuation import FOLD, KIND_NAMES, continue_orbits
from model.params import Loading
from model.prestretch import solve_prestretch
from model.rom import build_rom
from model.shooting import DEFAULT_STEPS

from . import options as opt
from .base import GRID_KEYS, STATUS_NOT_CONVERGED, STATUS_OK, Analysis, JobError, Variable

#: Length of the ``fold`` dimension.
MAX_FOLDS = 6


@dataclass(frozen=True)
class ContinuationOptions:
    parameter: str
    start: float
    stop: float
    modes: tuple[tuple[int, int], ...]
    prestretch: str
    max_points: int
    ds_max: float
    steps: int



class ContinuationAnalysis(Analysis):
    """Pseudo-arclength continuation of periodic responses in Omega or P0 (Figs. 14-17)."""

    name = "continuation"

    def parse_options(self, table, grid, membrane):
        s = self.name
        opt.check_keys(table, s, {"parameter", "start", "stop", "modes", "prestretch", "max_points",
                                  "ds_max", "steps"})
        parameter = opt.forcing_parameter(table, s, grid, "is continued")
        low = 0.0
        start = opt.number(table, s, "start", low=low, low_open=parameter == "Omega")
        stop = opt.number(table, s, "stop", low=low, low_open=parameter == "Omega")
        if start == stop:
            raise JobError(f"{s}.stop", stop, "must differ from continuation.start")
        return ContinuationOptions(
            parameter, start, stop, opt.modes(table, s), opt.prestretch(table, s),
            opt.number(table, s, "max_points", 400, low=2, high=100_000, integer=True),
            opt.number(table, s, "ds_max", 0.1, low=0.0, low_open=True, high=1.0),
            opt.number(table, s, "steps", DEFAULT_STEPS, low=16, high=4096, integer=True))

    def variables(self, options):
        n, k, p = options.max_points, 2 * len(options.modes), options.parameter
        units, what = GRID_KEYS[p]
        pt = ("point",)
        return [
            Variable(p, pt, (n,), "f8", units, f"continued parameter: {what}"),
            Variable("amplitude", pt, (n,), "f8", "m", "max over one period of |w(0.5 Re, 0, t)|"),
            Variable("stable", pt, (n,), "i1", "1", "1 stable, 0 unstable periodic response", -1),
            Variable("point_type", pt, (n,), "i1", "1",
                     "0 regular, 1 fold (saddle-node), 2 period doubling, 3 Neimark-Sacker", -1),
            Variable("multiplier_real", ("point", "multiplier"), (n, k), "f8", "1",
                     "real part of the Floquet multipliers, by decreasing modulus"),
            Variable("multiplier_imag", ("point", "multiplier"), (n, k), "f8", "1",
                     "imaginary part of the Floquet multipliers, by decreasing modulus"),
            Variable("multiplier_modulus", pt, (n,), "f8", "1", "largest Floquet multiplier modulus"),
            Variable("fold_value", ("fold",), (MAX_FOLDS,), "f8", units, f"{p} at the saddle-node points"),
            Variable("fold_amplitude", ("fold",), (MAX_FOLDS,), "f8", "m", "amplitude at the saddle-node points"),
            Variable("n_points", (), (), "i4", "1", "points on the branch", -1),
            Variable("n_folds", (), (), "i4", "1", "saddle-node points on the branch", -1),
        ]

    def coords(self, options):
        return {
            "point": (("point",), np.arange(options.max_points, dtype=np.int32),
                      {"long_name": "index along the branch", "units": "1"}),
            "multiplier": (("multiplier",), np.arange(2 * len(options.modes), dtype=np.int32),
                           {"long_name": "Floquet multiplier index", "units": "1"}),
            "fold": (("fold",), np.arange(MAX_FOLDS, dtype=np.int32),
                     {"long_name": "saddle-node index along the branch", "units": "1"}),
        }

    def compute(self, point, options, subtask):
        rom = build_rom(solve_prestretch(opt.membrane_from_point(point), options.prestretch), options.modes)
        fixed = {key: point[key] for key in opt.fixed_forcing_keys(options.parameter)}
        fixed[options.parameter] = options.start
        br = continue_orbits(rom, Loading(**fixed), options.parameter, options.start, options.stop,
                             steps=options.steps, ds_max=options.ds_max, max_points=options.max_points)
        n, k = options.max_points, 2 * len(options.modes)
        m = br.value.size
        out = {options.parameter: np.full(n, np.nan), "amplitude": np.full(n, np.nan),
               "stable": np.full(n, -1, np.int8), "point_type": np.full(n, -1, np.int8),
               "multiplier_real": np.full((n, k), np.nan), "multiplier_imag": np.full((n, k), np.nan),
               "multiplier_modulus": np.full(n, np.nan),
               "fold_value": np.full(MAX_FOLDS, np.nan), "fold_amplitude": np.full(MAX_FOLDS, np.nan)}
        out[options.parameter][:m] = br.value
        out["amplitude"][:m] = br.amplitude
        out["stable"][:m] = br.stable
        out["point_type"][:m] = br.kind
        out["multiplier_real"][:m] = br.multipliers.real
        out["multiplier_imag"][:m] = br.multipliers.imag
        out["multiplier_modulus"][:m] = np.abs(br.multipliers).max(axis=1)
        folds = br.special(FOLD)[:MAX_FOLDS]
        out["fold_value"][:folds.size] = br.value[folds]
        out["fold_amplitude"][:folds.size] = br.amplitude[folds]
        out["n_points"] = np.int32(m)
        out["n_folds"] = np.int32(br.special(FOLD).size)
        out["status"] = STATUS_OK if br.complete else STATUS_NOT_CONVERGED
        return out

    def warmup(self, options):
        from model.params import Membrane
        from model.shooting import shoot

        rom = build_rom(solve_prestretch(Membrane(), "analytic"), options.modes)
        shoot(rom, Loading(30.0, 0.1, 0.05), np.zeros(2 * rom.dof), steps=16)

    def assemble(self, raw, options):
        ds = raw.isel(subtask=0, drop=True)
        ds.attrs["continued_parameter"] = options.parameter
        ds["point_type"].attrs.update(flag_values=np.arange(4, dtype=np.int8), flag_meanings=" ".join(KIND_NAMES))
        if options.parameter == "P0" and ds.sizes.get("c", 0) >= 3:
            cusp_c, cusp_v = _cusp(ds)
            ds["cusp_c"] = cusp_c.assign_attrs(units=GRID_KEYS["c"][0],
                                               long_name="damping at which the two saddle-nodes merge (cusp)")
            ds["cusp_value"] = cusp_v.assign_attrs(units=GRID_KEYS["P0"][0], long_name="P0 at the cusp")
        return ds

    def figures(self, ds, outdir):
        return continuation_figures(ds, outdir)


def _cusp_1d(c, value, amp):
    """Cusp from the fold values/amplitudes ``(nc, fold)`` along increasing ``c``."""
    two = np.isfinite(value[:, 0]) & np.isfinite(value[:, 1])
    idx = np.flatnonzero(two)
    if idx.size < 2 or idx[-1] == c.size - 1:
        return np.nan, np.nan
    i, j = idx[-2], idx[-1]
    d2 = np.abs(amp[[i, j], 0] - amp[[i, j], 1]) ** 2
    mean = value[[i, j], :2].mean(axis=1)
    if d2[1] >= d2[0]:
        return np.nan, np.nan
    cc = c[j] + d2[1] * (c[j] - c[i]) / (d2[0] - d2[1])
    cc = min(cc, c[j + 1])
    return cc, mean[1] + (mean[1] - mean[0]) * (cc - c[j]) / (c[j] - c[i])


def _cusp(ds):
    import xarray as xr

    order = np.argsort(ds.c.values)
    sub = ds.isel(c=order)
    return xr.apply_ufunc(
        lambda v, a: _cusp_1d(sub.c.values, v, a), sub.fold_value, sub.fold_amplitude,
        input_core_dims=[["c", "fold"], ["c", "fold"]], output_core_dims=[[], []], vectorize=True)


CONTINUATION = ContinuationAnalysis()


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


def _draw_branch(ax, x, amp, stable, kind, color, label):
    ok = np.isfinite(x)
    x, amp, stable, kind = x[ok], amp[ok], stable[ok], kind[ok]
    first = True
    for i0, i1, st in _runs(stable):
        ax.plot(x[i0:i1 + 1], amp[i0:i1 + 1] * 1e3, color=color, ls="-" if st else "--", lw=1.2,
                label=label if first else None)
        first = False
    for k, marker in ((1, "o"), (2, "s"), (3, "D")):
        sel = kind == k
        ax.plot(x[sel], amp[sel] * 1e3, ls="none", marker=marker, mfc="white", color=color, ms=5)


def _title(sel) -> str:
    symbols = {"delta": r"$\delta$", "delta_o": r"$\delta_o$", "Omega": r"$\Omega$", "P0": "$P_0$"}
    return ", ".join(f"{symbols.get(k, k)} = {float(v):g}" for k, v in sel.items())


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
               Line2D([], [], color="k", ls="none", marker="o", mfc="white", label="saddle-node")]
    return ax.legend(handles=handles, loc="upper left", fontsize=7)


def continuation_figures(ds, outdir) -> list:
    """Bifurcation diagrams (Figs. 14-16) and, with a ``c`` grid in P0, fold loci (Fig. 17).

    One panel per combination of the grid keys other than ``c``; the ``c`` values are
    overlaid (a colour bar when there are more than four).  Stable responses solid,
    unstable dashed, saddle-nodes circles (period doubling squares, Neimark-Sacker
    diamonds).  Continuations in Omega are zoomed on the resonance (:func:`_zoom_omega`).
    The fold-loci figure skips the panels without saddle-nodes.
    """
    from .plots import grid_points, pyplot, save_figure

    plt = pyplot()
    par = ds.attrs.get("continued_parameter", "P0" if "P0" in ds.data_vars else "Omega")
    xlabel = r"forcing frequency $\Omega$ (rad/s)" if par == "Omega" else r"pressure amplitude $P_0$ (Pa)"
    panels = list(grid_points(ds, ("c", "point", "fold", "multiplier")))
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
                         colors[j], None if c is None or many else f"c = {float(c):g} N s/m$^3$")
        if par == "Omega":
            b = ds.sel(sel)
            _zoom_omega(ax, b[par].values.ravel(), b.amplitude.values.ravel())
        ax.set(xlabel=xlabel, ylabel=r"amplitude of $w(0.5, 0)$ (mm)")
        ax.set_title(_title(sel), fontsize=9)
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
                ax.set_title(_title(sel), fontsize=9)
                ax.legend()
            fig.suptitle("Saddle-node loci versus damping", fontsize=11)
            fig.tight_layout()
            paths.append(save_figure(fig, outdir, "fold_loci_damping.png"))
    return paths
