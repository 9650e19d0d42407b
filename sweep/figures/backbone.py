"""Figures of the ``backbone`` analysis: backbone curves (Figs. 10-12), modal amplitudes (Fig. 9)
or, for a model with in-plane motion, the in-plane displacements against the transverse
ones (Fig. 8's question)."""

from __future__ import annotations

import numpy as np

from sweep.analyses.base import GRID_KEYS
from sweep.figures.output import pyplot, save_figure
from sweep.figures.panels import grid_points, point_label


def backbone_figures(ds, outdir) -> list:
    """Backbone curves (Figs. 10-12) with the branch's turning point, and the modal amplitudes
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
    ax.plot([], [], "k-", label="periodic orbits (continuation)")
    ax.plot([], [], "ko", mfc="none", ms=3.5, ls="none", label="peak-to-peak (damped decay)")
    ax.plot([], [], "k--", lw=1.0, label="bound, Eq. 29")
    ax.plot([], [], "kx", ms=7, ls="none", label="branch turns back")
    ax.set(xlabel=r"frequency $\omega$ (rad/s)", ylabel=r"amplitude max $|w(0.5, 0)|$ (m)",
           title="Frequency-amplitude relation", ylim=(0, None))
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    paths.append(save_figure(fig, outdir, "backbone.png"))

    if "modal_amplitude" in ds:
        paths.append(_modal_figure(plt, ds, sels, label, outdir))
    if "max_abs_u" in ds:
        paths.append(_inplane_figure(plt, ds, sels, label, outdir))
    return paths


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
