"""Figures of the ``backbone`` analysis: backbone curves (Figs. 10-12), modal amplitudes (Fig. 9)
or, for a model with in-plane motion, the in-plane displacements against the transverse
ones (Fig. 8's question) and, with ``orbit_samples``, the displacement fields of the largest
orbit (Fig. 8)."""

from __future__ import annotations

import numpy as np

from sweep.analyses.base import GRID_KEYS
from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import grid_points, point_label


def backbone_figures(ds, outdir) -> list:
    """Backbone curves (Figs. 10-12) with the branch's turning point and the branch as followed
    through its turns, and the modal amplitudes
    (Fig. 9) or the ratios ``max |u| / max |w|`` and ``max |v| / max |w|``."""
    plt = pyplot()
    sels = list(grid_points(ds, ()))
    swept = [d for d in GRID_KEYS if ds.sizes.get(d, 1) > 1]

    def label(sel):
        return point_label({d: sel[d] for d in (swept or ["delta", "delta_o"]) if d in sel})

    paths = []
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for sel in sels:
        line, = ax.plot(ds.omega_nl.sel(sel), ds.amplitude.sel(sel), lw=1.6, label=label(sel))
        ax.plot(ds.omega_peak.sel(sel), ds.amplitude.sel(sel), ls="none", marker="o", ms=3.5,
                mfc="none", color=line.get_color())
        if np.isfinite(ds.omega_bound.sel(sel)):
            ax.axvline(float(ds.omega_bound.sel(sel)), ls="--", lw=1.0, color=line.get_color())
        ax.plot(ds.turn_omega.sel(sel), ds.turn_amplitude.sel(sel), ls="none", marker="x", ms=7,
                color=line.get_color())
        if "branch_omega" in ds:  # the branch as followed, through its turns
            ax.plot(ds.branch_omega.sel(sel), ds.branch_amplitude.sel(sel), lw=0.7, ls=":", color=line.get_color())
    ax.plot([], [], "k-", label="periodic orbits (continuation)")
    ax.plot([], [], "ko", mfc="none", ms=3.5, ls="none", label="peak-to-peak (damped decay)")
    ax.plot([], [], "k--", lw=1.0, label="bound, Eq. 29")
    ax.plot([], [], "kx", ms=7, ls="none", label="branch turns back")
    if "branch_omega" in ds:
        ax.plot([], [], "k:", lw=0.7, label="branch as followed")
    ax.set(xlabel=r"frequency $\omega$ (rad/s)", ylabel=r"amplitude max $|w(0.5, 0)|$ (m)",
           title="Frequency-amplitude relation", ylim=(0, None))
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    paths.append(save_figure(fig, outdir, "backbone.png"))

    if "modal_amplitude" in ds:
        paths.append(_modal_figure(plt, ds, sels, label, outdir))
    if "max_abs_u" in ds:
        paths.append(_inplane_figure(plt, ds, sels, label, outdir))
    if "orbit_u" in ds:
        paths.append(_orbit_figure(plt, ds, sels, label, outdir))
    return paths


#: The radius of Fig. 8b over Re (the paper's point (rho, theta) = (0.55, 0)).
FIG8_RHO = 0.55


def _orbit_figure(plt, ds, sels, label, outdir):
    """Fig. 8: per grid point, the largest orbit's u, v, w along the radius at its largest
    deflection (a) and at rho = 0.55 Re over one period (b)."""
    fig, axes = plt.subplots(2, len(sels), figsize=(4.6 * len(sels), 6.4), squeeze=False, layout="constrained")
    for (top, bottom), sel in zip(axes.T, sels):
        point = ds.sel(sel)
        done = np.flatnonzero(np.isfinite(point.orbit_w.values[:, 0, 0]))
        if done.size == 0:
            top.set_title(f"{label(sel)}: no orbit")
            continue
        j = done[-1]
        delta_o = float(sel.get("delta_o", ds.attrs.get("delta_o", np.nan)))
        rho = delta_o + (1.0 - delta_o) * ds.orbit_radius.values  # rho / Re
        u, w = point.orbit_u.values[j], point.orbit_w.values[j]
        for values, name, style in ((u, "u", "-"), (np.zeros_like(u), "v", ":"), (w, "w", "--")):
            top.plot(rho, values[0], ls=style, label=name)
        top.set(xlabel=r"$\rho / R_e$", ylabel="displacement (m)",
                title=f"{label(sel)}, A = {float(point.amplitude[j]):.3g} m: at rest (largest $w$)")
        k = int(np.argmin(np.abs(rho - FIG8_RHO)))
        t = ds.orbit_phase.values * 2 * np.pi / float(point.omega_nl[j])
        for values, name, style in ((u, "u", "-"), (np.zeros_like(u), "v", ":"), (w, "w", "--")):
            bottom.plot(t, values[:, k], ls=style, label=name)
        bottom.set(xlabel="t (s)", ylabel="displacement (m)", title=rf"at $\rho$ = {rho[k]:.3g} $R_e$, $\theta$ = 0")
        top.legend()
    fig.suptitle("Displacements during a large free vibration (v = 0: axisymmetric orbit)")
    return save_figure(fig, outdir, "fig08_inplane.png")


def _modal_figure(plt, ds, sels, label, outdir):
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
    return save_figure(fig, outdir, "modal_amplitudes.png")


def _inplane_figure(plt, ds, sels, label, outdir):
    fig, ax = plt.subplots(figsize=(5.5, 4.2), layout="constrained")
    for sel in sels:
        w = ds.max_abs_w.sel(sel)
        line, = ax.plot(w, ds.max_abs_u.sel(sel) / w, label=f"|u|, {label(sel)}")
        ax.plot(w, ds.max_abs_v.sel(sel) / w, ls="--", color=line.get_color(), label=f"|v|, {label(sel)}")
    ax.set(xlabel=r"max $|w|$ over the orbit and the membrane (m)", ylabel=r"max $|u|$ / max $|w|$, max $|v|$ / max $|w|$",
           title="In-plane displacements along the backbone")
    ax.legend()
    return save_figure(fig, outdir, "inplane_displacements.png")


def result_label(ds) -> str:
    """The model of a result in a legend: ``rom, 3 modes``, ``full, order 16``, ``full, u = v = 0,
    order 24``."""
    model = ds.attrs.get("model", "rom")
    if "model_order" in ds.attrs:
        held = "" if int(ds.attrs.get("model_inplane", 1)) else " u = v = 0,"
        return f"{model},{held} order {int(ds.attrs['model_order'])}"
    if "mode" in ds.dims:
        return f"{model}, {ds.sizes['mode']} mode{'s' if ds.sizes['mode'] > 1 else ''}"
    return str(model)


def backbone_comparison(datasets, outdir) -> list:
    """Fig. 10 across models: per grid point of the first result that every result has, the
    backbones (top) and each result's frequency relative to the first one's at the first
    one's target amplitudes (bottom; linear interpolation in amplitude)."""
    plt = pyplot()
    first = datasets[0]
    sels = [sel for sel in grid_points(first, ())
            if all(all(d in ds.dims and np.any(np.isclose(ds[d].values, v)) for d, v in sel.items())
                   for ds in datasets[1:])]
    if not sels:
        return []
    fig, axes = plt.subplots(2, len(sels), figsize=(4.6 * len(sels), 6.6), squeeze=False, layout="constrained",
                             sharex="col")
    for (top, bottom), sel in zip(axes.T, sels):
        ref = first.sel(sel, method="nearest")
        a_ref, w_ref = ref.amplitude.values, ref.omega_nl.values
        for ds in datasets:
            point = ds.sel(sel, method="nearest")
            amp, omega = point.amplitude.values, point.omega_nl.values
            ok = np.isfinite(omega)
            line, = top.plot(omega[ok], amp[ok], label=result_label(ds))
            if ds is not first and ok.sum() >= 2:
                order = np.argsort(amp[ok])
                inside = (a_ref >= amp[ok].min()) & (a_ref <= amp[ok].max()) & np.isfinite(w_ref)
                at = np.interp(a_ref[inside], amp[ok][order], omega[ok][order])
                bottom.plot(w_ref[inside], at / w_ref[inside] - 1, color=line.get_color(), label=result_label(ds))
        top.set(ylabel=r"amplitude max $|w(0.5, 0)|$ (m)", title=point_label(sel), ylim=(0, None))
        bottom.set(xlabel=r"frequency $\omega$ (rad/s) of " + result_label(first),
                   ylabel=f"frequency / that of {result_label(first)} - 1")
        bottom.axhline(0.0, color="k", lw=0.6)
        top.legend()
    fig.suptitle("Backbones of several results (Fig. 10)")
    return [save_figure(fig, outdir, "backbone_comparison.png")]
