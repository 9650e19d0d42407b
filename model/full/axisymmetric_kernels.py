"""Compiled loops of the axisymmetric full model (:mod:`model.full.axisymmetric`): its force and
its free motion by fixed-step RK4.

For axisymmetric states ``a1 = (r', 0, w')`` and ``a2 = (0, r/s, 0)`` are orthogonal, so the
first Piola stress of :func:`model.full.surface.gradient` reduces to
``P1 = 2 (W_T + W_D |a2|^2) a1`` and ``P2 = 2 (W_T + W_D |a1|^2) a2``; the law enters through
:func:`model.materials.metric_derivatives` (compiled per law by :mod:`model.material_kernels`).
"""

from __future__ import annotations

import numba as nb
import numpy as np

from model import material_kernels  # noqa: F401  (the laws' overloads for compiled code)
from model.materials import metric_derivatives
from model.noalias import NoAliasCompiler
from model.rk4 import combine, stage_offset, step_factor


@nb.njit(cache=True, fastmath=True, error_model="numpy", pipeline_class=NoAliasCompiler)
def axisymmetric_gradient(law, phi, dphi, s, sw, w, r0, dr0, q, out):
    """``out[:] = d(int W/C1 s ds)/dq`` for the coordinates ``q = (U, W)`` (the numpy
    :meth:`model.full.axisymmetric.AxisymmetricFull.gradient`, compiled).  ``phi``, ``dphi``:
    the basis at the quadrature points, ``(points, order)`` (a point's values contiguous).

    Compiled with :class:`model.noalias.NoAliasCompiler`: ``out`` must not overlap the other
    arrays (the accumulation over the basis then vectorises)."""
    points, order = phi.shape
    out[:] = 0.0
    # the two fields as views: offset indices (order + k) would carry numba's wraparound test
    # for negative indices, which keeps the loops over the basis scalar
    qu, qw = q[:order], q[order:]
    gu, gw = out[:order], out[order:]
    for p in range(points):
        du = 0.0
        u = 0.0
        dw = 0.0
        for k in range(order):
            du += qu[k] * dphi[p, k]
            u += qu[k] * phi[p, k]
            dw += qw[k] * dphi[p, k]
        a1r = dr0[p] + du
        a2t = (r0[p] + u) / s[p]
        n1 = a1r * a1r + dw * dw
        n2 = a2t * a2t
        delta = n1 * n2
        w_t, w_d, _, _, _ = metric_derivatives(law, n1 + n2, delta, 1.0 / delta)
        f1 = 2.0 * (w_t + w_d * n2) * sw[p]  # P1 / a1, times the quadrature weight and s
        f2 = 2.0 * (w_t + w_d * n1) * a2t * w[p]  # P2_theta times the weight (the 1/s of phi/s and s cancel)
        g_r = f1 * a1r
        g_z = f1 * dw
        for k in range(order):
            gu[k] += g_r * dphi[p, k] + f2 * phi[p, k]
            gw[k] += g_z * dphi[p, k]


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def _acceleration(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, damping, y, out, g):
    dof = g.size
    order = dof // 2
    axisymmetric_gradient(law, phi, dphi, s, sw, w, r0, dr0, y[:dof], g)
    for i in range(dof):
        out[i] = y[dof + i]
    for f in range(2):
        for i in range(order):
            acc = 0.0
            for j in range(order):
                acc += inv_mass[i, j] * g[f * order + j]
            out[dof + f * order + i] = -omega0_2 * acc - damping * y[dof + f * order + i]


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def rk4_free(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, damping, y0, dt, steps, every, record):
    """``steps`` RK4 steps of ``dt`` (s) of the free motion from ``y0``; the state every
    ``every`` steps into the rows of ``record`` (``(steps // every + 1, 2 dof)``, the first row
    ``y0``)."""
    n = y0.size
    y = y0.copy()
    k = np.empty((4, n))
    stage = np.empty(n)
    g = np.empty(n // 2)
    record[0] = y
    for step in range(steps):
        for i in range(4):
            if i == 0:
                stage[:] = y
            else:
                for j in range(n):
                    stage[j] = y[j] + stage_offset(i, dt) * k[i - 1, j]
            _acceleration(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, damping, stage, k[i], g)
        for j in range(n):
            y[j] += step_factor(dt) * combine(k[0, j], k[1, j], k[2, j], k[3, j])
        if (step + 1) % every == 0:
            record[(step + 1) // every] = y
    return y
