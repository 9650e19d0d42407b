"""Compiled loops of the full model's circumferential harmonics (:mod:`model.full.harmonic`):
the force of a state that is not axisymmetric, and its forced motion by fixed-step RK4.

The coordinates are blocks of ``order`` Legendre-Galerkin coefficients (over ``Re``), one per
field of one harmonic ``k`` and parity: ``U_k`` of ``u = sum U_k(s) e_k(theta)``, ``V_k`` of
``v = sum V_k(s) o_k(theta)`` and ``W_k`` of ``w = sum W_k(s) e_k(theta)``, with the angular
factors ``(e_k, o_k) = (cos k theta, sin k theta)`` of the cosine blocks or
``(sin k theta, -cos k theta)`` of their companions (:class:`model.full.harmonic.HarmonicFull`),
so that ``e_k' = -k o_k`` and ``o_k' = k e_k`` for both.  A
material point at ``(s, theta)`` moves to ``(r_o + u) e_r + v e_theta + w e_z`` in the frame of
its angle, so the columns of the deformation gradient are

    a1 = (r_o' + u_s, v_s, w_s),    a2 = ((u_theta - v) / s, (r_o + u + v_theta) / s, w_theta / s),

and the energy over ``2 pi h C1 Re^2`` is ``(1 / 2 pi) int int W s ds dtheta``.  Its gradient is
the first Piola stress of :func:`model.full.surface.gradient` projected on the coordinates'
variations (those of :mod:`model.full.family_kernels`, the components even under
``theta -> -theta`` times ``e_k``, the odd ones times ``o_k``).  The angular rule is given as
points and weights: the midpoint rule on ``[0, pi]`` for the cosine blocks alone (their states
are even under the reflection, and so is every integrand: the rule is then the trapezoidal
rule on the circle), on the whole circle with the companions.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from model import material_kernels  # noqa: F401  (the laws' overloads for compiled code)
from model.damping_kernels import add_matrix_damping
from model.materials import metric_derivatives
from model.rk4 import combine, stage_offset, step_factor

from .axisymmetric_kernels import OMEGA, PRESSURE
from .family_kernels import FIELD_U, FIELD_V


@nb.njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _radial_values(phi, dphi, q, p, value, slope):
    # each block's field and its s-derivative at quadrature point p
    order = phi.shape[1]
    for b in range(value.size):
        v0 = 0.0
        d0 = 0.0
        for j in range(order):
            v0 += q[b * order + j] * phi[p, j]
            d0 += q[b * order + j] * dphi[p, j]
        value[b] = v0
        slope[b] = d0


@nb.njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _columns_at(fields, wave, even_t, odd_t, value, slope, r0, dr0, inv_s, t):
    """The columns ``a1``, ``a2`` (6 components) at the angular point ``t`` from the blocks'
    radial ``value`` and ``slope`` at one radius (``r0``, ``dr0``: the pre-stretch there)."""
    u = 0.0
    u_s = 0.0
    u_t = 0.0
    v = 0.0
    v_s = 0.0
    v_t = 0.0
    w_s = 0.0
    w_t = 0.0
    for b in range(fields.size):
        c = even_t[b, t]
        sn = odd_t[b, t]
        k = wave[b]
        if fields[b] == FIELD_U:
            u += value[b] * c
            u_s += slope[b] * c
            u_t -= k * value[b] * sn
        elif fields[b] == FIELD_V:
            v += value[b] * sn
            v_s += slope[b] * sn
            v_t += k * value[b] * c
        else:
            w_s += slope[b] * c
            w_t -= k * value[b] * sn
    return dr0 + u_s, v_s, w_s, (u_t - v) * inv_s, (r0 + u + v_t) * inv_s, w_t * inv_s


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def harmonic_gradient(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, q, out,
                      value, slope, along1, along2):
    """``out[:] = d((1 / 2 pi) int int W/C1 s ds dtheta)/dq`` for the block coordinates ``q``.

    Parameters
    ----------
    law, phi, dphi, s, sw, w, r0, dr0
        The axisymmetric model's tables (:attr:`model.full.axisymmetric.AxisymmetricFull.kernel_tables`):
        the basis at the quadrature points ``(points, order)``.
    fields, wave : (B,) arrays
        Each block's field code (:data:`model.full.family_kernels.FIELD_U`, ...) and harmonic ``k`` (float).
    even_t, odd_t : (B, T) arrays
        The angular factors ``e_k(theta_t)``, ``o_k(theta_t)`` of each block at the angular points.
    theta_weight : (T,) array
        The angular weights (their sum is 1: the mean over the circle).
    q, out : (B order,) arrays
    value, slope, along1, along2 : (B,) work arrays
    """
    points, order = phi.shape
    blocks = fields.size
    angles = theta_weight.size
    out[:] = 0.0
    for p in range(points):
        _radial_values(phi, dphi, q, p, value, slope)
        along1[:] = 0.0
        along2[:] = 0.0
        inv_s = 1.0 / s[p]
        for t in range(angles):
            a1r, a1t, a1z, a2r, a2t, a2z = _columns_at(fields, wave, even_t, odd_t, value, slope, r0[p], dr0[p],
                                                       inv_s, t)
            n1 = a1r * a1r + a1t * a1t + a1z * a1z
            n2 = a2r * a2r + a2t * a2t + a2z * a2z
            c12 = a1r * a2r + a1t * a2t + a1z * a2z
            delta = n1 * n2 - c12 * c12
            w_T, w_D, _, _, _ = metric_derivatives(law, n1 + n2, delta, 1.0 / delta)
            f1 = 2.0 * (w_T + w_D * n2)
            f2 = 2.0 * (w_T + w_D * n1)
            cross = -2.0 * w_D * c12
            p1r = (f1 * a1r + cross * a2r) * theta_weight[t]
            p1t = (f1 * a1t + cross * a2t) * theta_weight[t]
            p1z = (f1 * a1z + cross * a2z) * theta_weight[t]
            p2r = (f2 * a2r + cross * a1r) * theta_weight[t]
            p2t = (f2 * a2t + cross * a1t) * theta_weight[t]
            p2z = (f2 * a2z + cross * a1z) * theta_weight[t]
            for b in range(blocks):
                c = even_t[b, t]
                sn = odd_t[b, t]
                k = wave[b]
                if fields[b] == FIELD_U:
                    along1[b] += p1r * c
                    along2[b] += p2t * c - k * p2r * sn
                elif fields[b] == FIELD_V:
                    along1[b] += p1t * sn
                    along2[b] += k * p2t * c - p2r * sn
                else:
                    along1[b] += p1z * c
                    along2[b] -= k * p2z * sn
        # a1 moves by phi' (weight s ds), a2 by phi / s (weight s ds: the plain weight)
        for b in range(blocks):
            g1 = along1[b] * sw[p]
            g2 = along2[b] * w[p]
            for j in range(order):
                out[b * order + j] += g1 * dphi[p, j] + g2 * phi[p, j]


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def _acceleration(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, inv_mass,
                  inv_scale, omega0_2, bias, rate, damping_matrix, load, load_block, pressure, y, out, g,
                  value, slope, along1, along2):
    # out = (q', q'') at the state y under the pressure `pressure` (Pa) at this instant
    dof = g.size
    order = phi.shape[1]
    harmonic_gradient(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, y[:dof], g,
                      value, slope, along1, along2)
    for i in range(dof):
        out[i] = y[dof + i]
    for b in range(fields.size):
        scale = omega0_2 * inv_scale[b]
        for i in range(order):
            acc = 0.0
            for j in range(order):
                acc += inv_mass[i, j] * g[b * order + j]
            out[dof + b * order + i] = bias[b * order + i] - scale * acc - rate * y[dof + b * order + i]
    for i in range(order):
        out[dof + load_block * order + i] += pressure * load[i]
    if damping_matrix is not None:
        add_matrix_damping(damping_matrix, y[dof:], out[dof:])


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def harmonic_motion(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, inv_mass,
                    inv_scale, omega0_2, bias, rate, damping_matrix, load, load_block, P0, Omega, y0, dt, steps,
                    every, record):
    """``steps`` RK4 steps of ``dt`` (s) from ``y0`` at ``t = 0`` of
    ``q'' = bias - omega_0^2 M^-1 g(q) - D q' + P0 cos(Omega t) load``, the state every
    ``every`` steps into the rows of ``record`` (``(steps // every + 1, 2 dof)``, the first
    row ``y0``); returns the last state.

    ``inv_mass`` is ``M^-1`` of one field ``(order, order)`` and ``inv_scale`` (``(B,)``) the
    inverse of each block's angular mean of ``cos^2`` or ``sin^2`` (1 for ``k = 0``, 2
    otherwise); ``bias`` the constant accelerations (s-2); ``D`` the rate ``rate`` (s-1) plus
    ``damping_matrix`` (None for none); ``load`` the accelerations per Pa of block
    ``load_block`` (``W_0``); the other arguments as :func:`harmonic_gradient`."""
    n = y0.size
    dof = n // 2
    blocks = fields.size
    y = y0.copy()
    k = np.empty((4, n))
    stage = np.empty(n)
    g = np.empty(dof)
    value = np.empty(blocks)
    slope = np.empty(blocks)
    along1 = np.empty(blocks)
    along2 = np.empty(blocks)
    record[0] = y
    for step in range(steps):
        for i in range(4):
            if i == 0:
                stage[:] = y
            else:
                for j in range(n):
                    stage[j] = y[j] + stage_offset(i, dt) * k[i - 1, j]
            pressure = P0 * np.cos(Omega * (step * dt + stage_offset(i, dt)))
            _acceleration(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, inv_mass,
                          inv_scale, omega0_2, bias, rate, damping_matrix, load, load_block, pressure, stage, k[i],
                          g, value, slope, along1, along2)
        for j in range(n):
            y[j] += step_factor(dt) * combine(k[0, j], k[1, j], k[2, j], k[3, j])
        if (step + 1) % every == 0:
            record[(step + 1) // every] = y
    return y


@nb.njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _moduli(law, a, dD, A):
    """``A[:, :] = d^2(W/C1)/dF^2`` at the columns ``a = (a1, a2)`` (6 components, any state:
    :func:`model.full.surface.hessian` written out); ``dD`` (6) a work array, left holding
    ``dDelta/dF`` (``dT/dF = 2 a``)."""
    n1 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
    n2 = a[3] * a[3] + a[4] * a[4] + a[5] * a[5]
    c = a[0] * a[3] + a[1] * a[4] + a[2] * a[5]
    delta = n1 * n2 - c * c
    w_t, w_d, w_tt, w_td, w_dd = metric_derivatives(law, n1 + n2, delta, 1.0 / delta)
    for i in range(3):
        dD[i] = 2.0 * n2 * a[i] - 2.0 * c * a[3 + i]
        dD[3 + i] = 2.0 * n1 * a[3 + i] - 2.0 * c * a[i]
    for i in range(6):
        ti = 2.0 * a[i]
        for j in range(6):
            tj = 2.0 * a[j]
            A[i, j] = w_tt * ti * tj + w_td * (ti * dD[j] + dD[i] * tj) + w_dd * dD[i] * dD[j]
        A[i, i] += 2.0 * w_t
    # W_D times the Hessian of Delta
    for i in range(3):
        for j in range(3):
            A[i, j] -= 2.0 * w_d * a[3 + i] * a[3 + j]
            A[3 + i, 3 + j] -= 2.0 * w_d * a[i] * a[j]
            cross = w_d * (4.0 * a[i] * a[3 + j] - 2.0 * a[3 + i] * a[j])
            A[i, 3 + j] += cross
            A[3 + j, i] += cross
        A[i, i] += 2.0 * w_d * n2
        A[3 + i, 3 + i] += 2.0 * w_d * n1
        A[i, 3 + i] -= 2.0 * w_d * c
        A[3 + i, i] -= 2.0 * w_d * c


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def harmonic_hessian(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, var_index,
                     var_value, q, out):
    """``out[:, :] = d^2((1 / 2 pi) int int W/C1 s ds dtheta)/dq^2`` for the block coordinates
    ``q``.  What a coefficient of block ``b`` moves in ``F`` at the angular point ``t`` per
    ``phi'`` (``alpha = 0``) and per ``phi / s`` (``alpha = 1``) -- the family's variation
    vectors of :mod:`model.full.family_kernels` times ``e_k(theta_t)`` or ``o_k(theta_t)`` --
    has at most two components: ``var_index`` (``(B, 2, 2)``) names them, ``var_value``
    (``(B, T, 2, 2)``) gives their values (zero for an unused second one); the other arguments
    as :func:`harmonic_gradient`.

    Per radius the angular sum ``C_bc = sum_t w_t g_b^T A g_c`` (``2 x 2`` per block pair, four
    products of the moduli ``A`` each) is formed first, then the radial products
    ``[phi', phi/s] C_bc [phi', phi/s]^T s ds``."""
    points, order = phi.shape
    blocks = fields.size
    angles = theta_weight.size
    out[:, :] = 0.0
    # the blocks' rows and columns as axes: offset indices (b order + j) would carry numba's
    # test for negative indices in the innermost loop
    blocks4 = out.reshape((blocks, order, blocks, order))
    value = np.empty(blocks)
    slope = np.empty(blocks)
    a = np.empty(6)
    dD = np.empty(6)
    A = np.empty((6, 6))
    C = np.empty((blocks, blocks, 2, 2))
    for p in range(points):
        _radial_values(phi, dphi, q, p, value, slope)
        inv_s = 1.0 / s[p]
        C[:, :, :, :] = 0.0
        for t in range(angles):
            a[0], a[1], a[2], a[3], a[4], a[5] = _columns_at(fields, wave, even_t, odd_t, value, slope, r0[p], dr0[p],
                                                             inv_s, t)
            _moduli(law, a, dD, A)
            for b in range(blocks):
                for alpha in range(2):
                    i0 = var_index[b, alpha, 0]
                    i1 = var_index[b, alpha, 1]
                    v0 = var_value[b, t, alpha, 0] * theta_weight[t]
                    v1 = var_value[b, t, alpha, 1] * theta_weight[t]
                    for c in range(b, blocks):
                        for beta in range(2):
                            j0 = var_index[c, beta, 0]
                            j1 = var_index[c, beta, 1]
                            u0 = var_value[c, t, beta, 0]
                            u1 = var_value[c, t, beta, 1]
                            C[b, c, alpha, beta] += (v0 * (A[i0, j0] * u0 + A[i0, j1] * u1)
                                                     + v1 * (A[i1, j0] * u0 + A[i1, j1] * u1))
        f = phi[p]
        df = dphi[p]
        for b in range(blocks):
            for c in range(b, blocks):
                c11 = C[b, c, 0, 0] * sw[p]
                c12 = C[b, c, 0, 1] * w[p]  # phi / s times s ds: the plain weight
                c21 = C[b, c, 1, 0] * w[p]
                c22 = C[b, c, 1, 1] * w[p] * inv_s
                for j in range(order):
                    left1 = c11 * df[j] + c21 * f[j]
                    left2 = c12 * df[j] + c22 * f[j]
                    for m in range(order):
                        blocks4[b, j, c, m] += left1 * df[m] + left2 * f[m]
    for b in range(blocks):
        for c in range(b + 1, blocks):
            for j in range(order):
                for m in range(order):
                    out[c * order + m, b * order + j] = out[b * order + j, c * order + m]


@nb.njit(cache=True, error_model="numpy")
def harmonic_variational(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, var_index,
                         var_value, inv_mass, inv_scale, omega0_2, bias, rate, damping_matrix, load, load_block, P0,
                         Omega, parameter, y0, dt, steps):
    """``steps`` RK4 steps of ``dt`` (s) of the motion of :func:`harmonic_motion` from ``y0`` at
    ``t = 0`` with its variational equations: the final state and ``(2 dof, 2 dof + 1)``, the
    flow's derivative in ``y0`` and, in the last column, in ``parameter`` (:data:`OMEGA`,
    :data:`PRESSURE` of :mod:`model.full.axisymmetric_kernels`; zero for another value),
    exact for the discrete scheme (as :func:`model.full.axisymmetric_kernels.rk4_variational`)."""
    # The stage loop repeats rk4_variational's. One driver taking the force and Hessian as
    # compiled arguments would miss numba's on-disk cache in every new process (a function
    # with a dispatcher-typed argument is keyed by the dispatcher's identity; numba 0.68:
    # a miss at every start), so every rank of every run would compile it again.
    n = y0.size
    dof = n // 2
    order = phi.shape[1]
    blocks = fields.size
    cols = n + 1
    y = y0.copy()
    big = np.zeros((n, cols))
    for i in range(n):
        big[i, i] = 1.0
    k = np.empty((4, n))
    kp = np.empty((4, n, cols))
    stage = np.empty(n)
    pstage = np.empty((n, cols))
    g = np.empty(dof)
    value = np.empty(blocks)
    slope = np.empty(blocks)
    along1 = np.empty(blocks)
    along2 = np.empty(blocks)
    hess = np.empty((dof, dof))
    hess_blocks = hess.reshape((blocks, order, dof))  # each block's rows, contiguous for '@'
    stiff = np.empty((dof, dof))
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
            _acceleration(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, inv_mass,
                          inv_scale, omega0_2, bias, rate, damping_matrix, load, load_block, P0 * cosine, stage,
                          k[i], g, value, slope, along1, along2)
            harmonic_hessian(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, var_index,
                             var_value, stage[:dof], hess)
            for b in range(blocks):
                stiff[b * order:(b + 1) * order, :] = (-omega0_2 * inv_scale[b]) * (inv_mass @ hess_blocks[b])
            kp[i, :dof, :] = pstage[dof:]
            kp[i, dof:, :] = stiff @ pstage[:dof] - rate * pstage[dof:]
            if damping_matrix is not None:
                kp[i, dof:, :] -= damping_matrix @ pstage[dof:]
            if parameter == OMEGA:  # the phase's stages do not move, the step does
                for j in range(n):
                    kp[i, j, n] -= k[i, j] / Omega
            elif parameter == PRESSURE:
                for j in range(order):
                    kp[i, dof + load_block * order + j, n] += cosine * load[j]
        for j in range(n):
            y[j] += step_factor(dt) * combine(k[0, j], k[1, j], k[2, j], k[3, j])
        big += step_factor(dt) * (kp[0] + 2.0 * kp[1] + 2.0 * kp[2] + kp[3])
    return y, big
