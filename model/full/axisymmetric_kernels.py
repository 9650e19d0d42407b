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


@nb.njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _fields_at(phi, dphi, qu, qw, p):
    """``(u', u, w')`` (over ``Re``) at quadrature point ``p`` from the coefficients ``qu``, ``qw``."""
    du = 0.0
    u = 0.0
    dw = 0.0
    for k in range(qu.size):
        du += qu[k] * dphi[p, k]
        u += qu[k] * phi[p, k]
        dw += qw[k] * dphi[p, k]
    return du, u, dw


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
        du, u, dw = _fields_at(phi, dphi, qu, qw, p)
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


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def axisymmetric_hessian(law, phi, dphi, s, sw, w, r0, dr0, q, out):
    """``out[:, :] = d^2(int W/C1 s ds)/dq^2`` for the coordinates ``q = (U, W)`` (the numpy
    :meth:`model.full.axisymmetric.AxisymmetricFull.hessian`, compiled).

    With ``x = (a1_r, a1_z, a2_theta)``, ``n1 = |a1|^2``, ``n2 = |a2|^2``, ``T = n1 + n2`` and
    ``Delta = n1 n2``: ``d2W/dx2 = W_TT tT tT' + W_TD (tT tD' + tD tT') + W_DD tD tD' + 2 W_T I
    + W_D d2Delta`` with ``tT = 2 x``, ``tD = 2 (a1_r n2, a1_z n2, a2_theta n1)``; ``U_k``
    moves ``x`` by ``(phi_k', 0, phi_k / s)`` and ``W_k`` by ``(0, phi_k', 0)``."""
    points, order = phi.shape
    out[:, :] = 0.0
    qu, qw = q[:order], q[order:]
    tT = np.empty(3)
    tD = np.empty(3)
    d = np.empty((3, 3))
    for p in range(points):
        du, u, dw = _fields_at(phi, dphi, qu, qw, p)
        x0 = dr0[p] + du
        x1 = dw
        x2 = (r0[p] + u) / s[p]
        n1 = x0 * x0 + x1 * x1
        n2 = x2 * x2
        delta = n1 * n2
        w_t, w_d, w_tt, w_td, w_dd = metric_derivatives(law, n1 + n2, delta, 1.0 / delta)
        tT[0] = 2.0 * x0
        tT[1] = 2.0 * x1
        tT[2] = 2.0 * x2
        tD[0] = 2.0 * x0 * n2
        tD[1] = 2.0 * x1 * n2
        tD[2] = 2.0 * x2 * n1
        for i in range(3):
            for j in range(3):
                d[i, j] = w_tt * tT[i] * tT[j] + w_td * (tT[i] * tD[j] + tD[i] * tT[j]) + w_dd * tD[i] * tD[j]
            d[i, i] += 2.0 * w_t
        d[0, 0] += w_d * 2.0 * n2
        d[1, 1] += w_d * 2.0 * n2
        d[2, 2] += w_d * 2.0 * n1
        d[0, 2] += w_d * 4.0 * x0 * x2
        d[2, 0] += w_d * 4.0 * x0 * x2
        d[1, 2] += w_d * 4.0 * x1 * x2
        d[2, 1] += w_d * 4.0 * x1 * x2
        c = sw[p]
        inv_s = 1.0 / s[p]
        for k in range(order):
            ak = dphi[p, k]
            bk = phi[p, k] * inv_s
            # row k of U: d/dU_k x = (ak, 0, bk); row k of W: (0, ak, 0)
            ru0 = c * (d[0, 0] * ak + d[2, 0] * bk)
            ru1 = c * (d[0, 1] * ak + d[2, 1] * bk)
            ru2 = c * (d[0, 2] * ak + d[2, 2] * bk)
            rw0 = c * d[1, 0] * ak
            rw1 = c * d[1, 1] * ak
            rw2 = c * d[1, 2] * ak
            for m in range(order):
                al = dphi[p, m]
                bl = phi[p, m] * inv_s
                out[k, m] += ru0 * al + ru2 * bl
                out[k, order + m] += ru1 * al
                out[order + k, m] += rw0 * al + rw2 * bl
                out[order + k, order + m] += rw1 * al


@nb.njit(cache=True, error_model="numpy")
def rk4_variational(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, y0, dt, steps):
    """``steps`` RK4 steps of ``dt`` (s) of the undamped free motion from ``y0`` with the
    variational equations ``dq' = dv``, ``dv' = -omega_0^2 M^-1 H(q) dq``: the final state
    and its derivative in ``y0`` (``(2 dof, 2 dof)``, exact for the discrete scheme)."""
    n = y0.size
    dof = n // 2
    order = dof // 2
    y = y0.copy()
    big = np.eye(n)
    k = np.empty((4, n))
    kp = np.empty((4, n, n))
    stage = np.empty(n)
    pstage = np.empty((n, n))
    g = np.empty(dof)
    hess = np.empty((dof, dof))
    hess_blocks = hess.reshape((2, order, dof))  # the u and w rows, contiguous for '@'
    stiff = np.empty((dof, dof))
    pstage_blocks = pstage.reshape((2, dof, n))  # the displacement and velocity rows
    for step in range(steps):
        for i in range(4):
            if i == 0:
                stage[:] = y
                pstage[:, :] = big
            else:
                f = stage_offset(i, dt)
                stage[:] = y + f * k[i - 1]
                pstage[:, :] = big + f * kp[i - 1]
            axisymmetric_gradient(law, phi, dphi, s, sw, w, r0, dr0, stage[:dof], g)
            axisymmetric_hessian(law, phi, dphi, s, sw, w, r0, dr0, stage[:dof], hess)
            stiff[:order, :] = -omega0_2 * (inv_mass @ hess_blocks[0])
            stiff[order:, :] = -omega0_2 * (inv_mass @ hess_blocks[1])
            k[i, :dof] = stage[dof:]
            k[i, dof:order + dof] = -omega0_2 * (inv_mass @ g[:order])
            k[i, dof + order:] = -omega0_2 * (inv_mass @ g[order:])
            kp[i, :dof, :] = pstage_blocks[1]
            kp[i, dof:, :] = stiff @ pstage_blocks[0]
        for j in range(n):
            y[j] += step_factor(dt) * combine(k[0, j], k[1, j], k[2, j], k[3, j])
        big += step_factor(dt) * (kp[0] + 2.0 * kp[1] + 2.0 * kp[2] + kp[3])
    return y, big
