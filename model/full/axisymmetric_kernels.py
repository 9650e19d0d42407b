"""Compiled loops of the axisymmetric full model (:mod:`model.full.axisymmetric`): its force and
its forced and free motion by fixed-step RK4, with the variational equations.

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
from model.damping_kernels import add_matrix_damping
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
def _acceleration(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, bias, damping, damping_matrix, load,
                  pressure, y, out, g):
    # out = (q', q'') at the state y under the pressure `pressure` (Pa) at this instant
    dof = g.size
    order = dof // 2
    axisymmetric_gradient(law, phi, dphi, s, sw, w, r0, dr0, y[:dof], g)
    for i in range(dof):
        out[i] = y[dof + i]
    for f in range(2):
        for i in range(order):
            acc = 0.0
            for j in range(order):
                acc += inv_mass[f, i, j] * g[f * order + j]
            out[dof + f * order + i] = bias[f * order + i] - omega0_2 * acc - damping * y[dof + f * order + i]
    for i in range(order):
        out[dof + order + i] += pressure * load[i]
    if damping_matrix is not None:
        add_matrix_damping(damping_matrix, y[dof:], out[dof:])


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def rk4_motion(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, bias, damping, damping_matrix, load, P0,
               Omega, y0, dt, steps, every, record, stages=None):
    """``steps`` RK4 steps of ``dt`` (s) from ``y0`` at ``t = 0`` of ``q'' = bias - omega_0^2
    M^-1 g(q) - D q' + P0 cos(Omega t) load`` (``inv_mass``: ``M^-1`` per field, ``(2, order,
    order)``, ``U`` then ``W``; ``bias``: constant accelerations, s-2; ``load``:
    the ``W`` accelerations per Pa; ``D`` the rate ``damping`` (s-1) plus ``damping_matrix``,
    None for none); the state every ``every`` steps into the rows of ``record``
    (``(steps // every + 1, 2 dof)``, the first row ``y0``).  ``P0 = 0``: the free motion.
    ``stages`` (``(steps, 4, dof)``, optional): the coordinates ``q`` at every stage of every
    step, what the families' variational equations are integrated along
    (:func:`model.full.family_kernels.family_monodromy`)."""
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
            if stages is not None:
                stages[step, i] = stage[:n // 2]
            pressure = P0 * np.cos(Omega * (step * dt + stage_offset(i, dt)))
            _acceleration(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, bias, damping, damping_matrix,
                          load, pressure, stage, k[i], g)
        for j in range(n):
            y[j] += step_factor(dt) * combine(k[0, j], k[1, j], k[2, j], k[3, j])
        if (step + 1) % every == 0:
            record[(step + 1) // every] = y
    return y


@nb.njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def even_moduli(law, x0, x1, x2, tT, tD, d):
    """``d[:, :] = d^2(W/C1)/dx^2`` for ``x = (a1_r, a1_z, a2_theta) = (x0, x1, x2)`` at the
    axisymmetric columns ``a1 = (x0, 0, x1)``, ``a2 = (0, x2, 0)`` (the components of ``F`` even
    under ``theta -> -theta``); ``tT``, ``tD`` (3) are work arrays, left holding ``dT/dx`` and
    ``dDelta/dx``.  Returns ``(W_T, W_D)``, which the odd components' moduli need
    (:mod:`model.full.family_kernels`).

    With ``n1 = |a1|^2``, ``n2 = |a2|^2``, ``T = n1 + n2`` and ``Delta = n1 n2``:
    ``d = W_TT tT tT' + W_TD (tT tD' + tD tT') + W_DD tD tD' + 2 W_T I + W_D d2Delta`` with
    ``tT = 2 x``, ``tD = 2 (x0 n2, x1 n2, x2 n1)``."""
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
    return w_t, w_d


@nb.njit(cache=True, fastmath=True, error_model="numpy", pipeline_class=NoAliasCompiler)
def axisymmetric_hessian(law, phi, dphi, s, sw, w, r0, dr0, q, out):
    """``out[:, :] = d^2(int W/C1 s ds)/dq^2`` for the coordinates ``q = (U, W)`` (the numpy
    :meth:`model.full.axisymmetric.AxisymmetricFull.hessian`, compiled).

    With ``x = (a1_r, a1_z, a2_theta)`` and ``d2W/dx2`` of :func:`even_moduli`: ``U_k`` moves
    ``x`` by ``(phi_k', 0, phi_k / s)`` and ``W_k`` by ``(0, phi_k', 0)``.

    Compiled with :class:`model.noalias.NoAliasCompiler` (``out`` must not overlap the other
    arrays) and writing through the four blocks' rows as views, as the gradient does: offset
    indices (``order + m``) carry numba's test for negative indices and keep the loop over the
    basis scalar."""
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
        even_moduli(law, x0, x1, x2, tT, tD, d)
        c = sw[p]
        inv_s = 1.0 / s[p]
        f = phi[p]
        df = dphi[p]
        # the moduli times the weight, as scalars the loops keep in registers
        d00, d01, d02 = c * d[0, 0], c * d[0, 1], c * d[0, 2]
        d10, d11, d12 = c * d[1, 0], c * d[1, 1], c * d[1, 2]
        d20, d21, d22 = c * d[2, 0], c * d[2, 1], c * d[2, 2]
        for k in range(order):
            ak = df[k]
            bk = f[k] * inv_s
            # row k of U: d/dU_k x = (ak, 0, bk); row k of W: (0, ak, 0)
            ru0 = d00 * ak + d20 * bk
            ru1 = d01 * ak + d21 * bk
            ru2 = d02 * ak + d22 * bk
            rw0 = d10 * ak
            rw1 = d11 * ak
            rw2 = d12 * ak
            uu = out[k, :order]
            uw = out[k, order:]
            wu = out[order + k, :order]
            ww = out[order + k, order:]
            for m in range(order):
                al = df[m]
                bl = f[m] * inv_s
                uu[m] += ru0 * al + ru2 * bl
                uw[m] += ru1 * al
                wu[m] += rw0 * al + rw2 * bl
                ww[m] += rw1 * al


#: What the last column of :func:`rk4_variational` differentiates by: nothing, ``Omega`` (at
#: fixed steps per period ``2 pi / (Omega dt)``) or ``P0``.
NO_PARAMETER, OMEGA, PRESSURE = 0, 1, 2


@nb.njit(cache=True, error_model="numpy")
def rk4_variational(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, bias, damping, damping_matrix, load, P0,
                    Omega, parameter, y0, tangents, dt, steps):
    """``steps`` RK4 steps of ``dt`` (s) of the motion of :func:`rk4_motion` from ``y0`` at
    ``t = 0`` with its variational equations ``dq' = dv``, ``dv' = -omega_0^2 M^-1 H(q) dq - D
    dv``: the final state and ``(2 dof, c + 1)``: the flow's derivative along the ``c``
    columns of ``tangents`` (``(2 dof, c)``: the identity for the whole derivative in ``y0``,
    some of its columns for the derivative in those components) and, in the last column, in
    ``parameter`` (:data:`OMEGA`, :data:`PRESSURE`; zero for :data:`NO_PARAMETER`), exact for
    the discrete scheme.

    In ``Omega`` the step is ``dt = 2 pi / (Omega steps)``: in the phase ``tau = Omega t`` the
    slopes are ``k / Omega`` at stage phases that do not move, so the column gathers, besides
    ``J dy``, ``-k_i / Omega`` at every stage ``i``."""
    n = y0.size
    dof = n // 2
    order = dof // 2
    c = tangents.shape[1]
    cols = c + 1
    y = y0.copy()
    big = np.zeros((n, cols))
    big[:, :c] = tangents
    k = np.empty((4, n))
    kp = np.empty((4, n, cols))
    stage = np.empty(n)
    pstage = np.empty((n, cols))
    g = np.empty(dof)
    hess = np.empty((dof, dof))
    hess_blocks = hess.reshape((2, order, dof))  # the u and w rows, contiguous for '@'
    stiff = np.empty((dof, dof))
    pstage_blocks = pstage.reshape((2, dof, cols))  # the displacement and velocity rows
    for step in range(steps):
        for i in range(4):
            f = stage_offset(i, dt)
            if i == 0:
                stage[:] = y
                pstage[:, :] = big
            else:
                stage[:] = y + f * k[i - 1]
                pstage[:, :] = big + f * kp[i - 1]
            cosine = np.cos(Omega * (step * dt + f))
            _acceleration(law, phi, dphi, s, sw, w, r0, dr0, inv_mass, omega0_2, bias, damping, damping_matrix,
                          load, P0 * cosine, stage, k[i], g)
            axisymmetric_hessian(law, phi, dphi, s, sw, w, r0, dr0, stage[:dof], hess)
            stiff[:order, :] = -omega0_2 * (inv_mass[0] @ hess_blocks[0])
            stiff[order:, :] = -omega0_2 * (inv_mass[1] @ hess_blocks[1])
            kp[i, :dof, :] = pstage_blocks[1]
            kp[i, dof:, :] = stiff @ pstage_blocks[0] - damping * pstage_blocks[1]
            if damping_matrix is not None:
                kp[i, dof:, :] -= damping_matrix @ pstage_blocks[1]
            if parameter == OMEGA:
                for j in range(n):
                    kp[i, j, c] -= k[i, j] / Omega
            elif parameter == PRESSURE:
                for j in range(order):
                    kp[i, dof + order + j, c] += cosine * load[j]
        for j in range(n):
            y[j] += step_factor(dt) * combine(k[0, j], k[1, j], k[2, j], k[3, j])
        big += step_factor(dt) * (kp[0] + 2.0 * kp[1] + 2.0 * kp[2] + kp[3])
    return y, big
