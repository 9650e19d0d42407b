"""Compiled loops of the full model's asymmetric families (:mod:`model.full.families`): the
tangent stiffness of one circumferential harmonic about an axisymmetric state, and the
monodromy block of its perturbations along an axisymmetric orbit.

At an axisymmetric state ``a1 = (x0, 0, x1)``, ``a2 = (0, x2, 0)`` (``x0 = r_o' + u'``,
``x1 = w'``, ``x2 = (r_o + u) / s``) the tangent moduli ``A = d^2W/dF^2`` of
:func:`model.full.surface.hessian` couple no component of ``F`` that is even under the
reflection ``theta -> -theta`` (``a1_r``, ``a1_z``, ``a2_theta``) with an odd one (``a1_theta``,
``a2_r``, ``a2_z``).  With ``n1 = |a1|^2``, ``n2 = |a2|^2``, ``dT/dF = 2 (x0, 0, x1, 0, x2, 0)``
and ``dDelta/dF = 2 (n2 x0, 0, n2 x1, 0, n1 x2, 0)``::

    A = W_TT dT dT' + W_TD (dT dDelta' + dDelta dT') + W_DD dDelta dDelta' + 2 W_T I + W_D H

where the Hessian ``H`` of ``Delta`` has, in the even block, ``2 n2`` at ``(a1_r, a1_r)`` and
``(a1_z, a1_z)``, ``2 n1`` at ``(a2_theta, a2_theta)``, ``4 x0 x2`` at ``(a1_r, a2_theta)``
and ``4 x1 x2`` at ``(a1_z, a2_theta)``; in the odd block ``2 x1^2`` at ``(a2_r, a2_r)``,
``2 x0^2`` at ``(a2_z, a2_z)``, ``-2 x0 x1`` at ``(a2_r, a2_z)``, ``-2 x0 x2`` at
``(a1_theta, a2_r)`` and ``-2 x1 x2`` at ``(a1_theta, a2_z)`` (symmetric).

A coefficient of the perturbation field ``f`` on basis function ``k`` moves ``F`` by
``phi_k' g1_f + (phi_k / s) g2_f`` with, for the harmonic ``n``,
``g1_U = e(a1_r)``, ``g2_U = -n e(a2_r) + e(a2_theta)``; ``g1_V = e(a1_theta)``,
``g2_V = -e(a2_r) + n e(a2_theta)``; ``g1_W = e(a1_z)``, ``g2_W = -n e(a2_z)``
(:mod:`model.full.linear`), so the stiffness block of fields ``f, g`` is
``int [phi_k', phi_k/s] C_fg [phi_l', phi_l/s]^T s ds`` with the 2x2 matrices
``C_fg = [g_f . A g_g]``.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from model.rk4 import combine, stage_offset, step_factor

from .axisymmetric_kernels import even_moduli

#: Field codes of a family's perturbation fields (``fields`` arrays of the kernels).
FIELD_U, FIELD_V, FIELD_W = 0, 1, 2


@nb.njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _tangent_moduli(law, x0, x1, x2, tT, tD, d, A):
    """``A[:, :] = d^2(W/C1)/dF^2`` (6x6, component order of :mod:`model.full.surface`) at the
    axisymmetric columns ``a1 = (x0, 0, x1)``, ``a2 = (0, x2, 0)``; ``tT``, ``tD``, ``d``: the
    work arrays of :func:`model.full.axisymmetric_kernels.even_moduli`."""
    w_t, w_d = even_moduli(law, x0, x1, x2, tT, tD, d)
    A[:, :] = 0.0
    for i in range(3):
        for j in range(3):
            A[2 * i, 2 * j] = d[i, j]  # the even components a1_r, a1_z, a2_theta are 0, 2, 4
    A[1, 1] += 2.0 * w_t
    A[3, 3] += 2.0 * w_t
    A[5, 5] += 2.0 * w_t
    # the odd block: a1_theta (1), a2_r (3), a2_z (5)
    A[3, 3] += w_d * 2.0 * x1 * x1
    A[5, 5] += w_d * 2.0 * x0 * x0
    A[3, 5] -= w_d * 2.0 * x0 * x1
    A[5, 3] -= w_d * 2.0 * x0 * x1
    A[1, 3] -= w_d * 2.0 * x0 * x2
    A[3, 1] -= w_d * 2.0 * x0 * x2
    A[1, 5] -= w_d * 2.0 * x1 * x2
    A[5, 1] -= w_d * 2.0 * x1 * x2


@nb.njit(cache=True, error_model="numpy")
def tangent_moduli(law, x0, x1, x2):
    """:func:`_tangent_moduli` as a new ``(6, 6)`` array (for the tests)."""
    A = np.empty((6, 6))
    _tangent_moduli(law, x0, x1, x2, np.empty(3), np.empty(3), np.empty((3, 3)), A)
    return A


@nb.njit(cache=True, error_model="numpy")
def variation_vectors(n, fields):
    """``(F, 2, 6)``: ``g1_f``, ``g2_f`` of each field of ``fields`` for the harmonic ``n``."""
    g = np.zeros((fields.size, 2, 6))
    for a in range(fields.size):
        f = fields[a]
        if f == FIELD_U:
            g[a, 0, 0] = 1.0
            g[a, 1, 3] = -n
            g[a, 1, 4] = 1.0
        elif f == FIELD_V:
            g[a, 0, 1] = 1.0
            g[a, 1, 3] = -1.0
            g[a, 1, 4] = n
        else:
            g[a, 0, 2] = 1.0
            g[a, 1, 5] = -n
    return g


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def family_stiffness(law, phi, dphi, s, sw, r0, dr0, q, fam_phi, fam_dphi, g, A, C, out):
    """``out[:, :] = K_n(q)``: the second variation of ``int W/C1 s ds`` in the family's
    coordinates (field by field, ``M`` basis functions each) at the axisymmetric coordinates
    ``q = (U, W)`` (``2 N``, over ``Re``).

    Parameters
    ----------
    law, phi, dphi, s, sw, r0, dr0
        The axisymmetric model's tables (:attr:`model.full.axisymmetric.AxisymmetricFull.kernel_tables`
        without the plain weights): the ``N`` basis functions at the points ``(points, N)``.
    fam_phi, fam_dphi : (points, M) arrays
        The family's first ``M`` basis functions and their derivatives.
    g : (F, 2, 6) array
        :func:`variation_vectors` of the family.
    A, C : work arrays ``(6, 6)`` and ``(F, F, 2, 2)``.
    out : (F M, F M) array
    """
    points, order = phi.shape
    M = fam_phi.shape[1]
    F = g.shape[0]
    tT = np.empty(3)
    tD = np.empty(3)
    d = np.empty((3, 3))
    out[:, :] = 0.0
    qu, qw = q[:order], q[order:]
    for p in range(points):
        du = 0.0
        u = 0.0
        dw = 0.0
        for k in range(order):
            du += qu[k] * dphi[p, k]
            u += qu[k] * phi[p, k]
            dw += qw[k] * dphi[p, k]
        _tangent_moduli(law, dr0[p] + du, dw, (r0[p] + u) / s[p], tT, tD, d, A)
        for a in range(F):
            for b in range(a, F):  # the blocks below the diagonal are their transposes
                for i in range(2):
                    for j in range(2):
                        acc = 0.0
                        for x in range(6):
                            gx = g[a, i, x]
                            if gx != 0.0:
                                for y in range(6):
                                    acc += gx * A[x, y] * g[b, j, y]
                        C[a, b, i, j] = acc * sw[p]
        inv_s = 1.0 / s[p]
        for a in range(F):
            for b in range(a, F):
                c11, c12, c21, c22 = C[a, b, 0, 0], C[a, b, 0, 1], C[a, b, 1, 0], C[a, b, 1, 1]
                for k in range(M):
                    dk = fam_dphi[p, k]
                    pk = fam_phi[p, k] * inv_s
                    left1 = c11 * dk + c21 * pk
                    left2 = c12 * dk + c22 * pk
                    row = out[a * M + k, b * M:(b + 1) * M]
                    for l in range(M):
                        row[l] += left1 * fam_dphi[p, l] + left2 * fam_phi[p, l] * inv_s
    for a in range(F):
        for b in range(a + 1, F):
            for k in range(M):
                for l in range(M):
                    out[b * M + l, a * M + k] = out[a * M + k, b * M + l]


@nb.njit(cache=True, error_model="numpy")
def family_monodromy(law, phi, dphi, s, sw, r0, dr0, stages, fam_phi, fam_dphi, g, inv_mass, omega0_2, rate,
                     matrix, dt):
    """The monodromy block ``(2 F M, 2 F M)`` of a family along an axisymmetric orbit: RK4
    steps of ``dt`` (s) of ``X'' = -omega_0^2 M^-1 K_n(q(t)) X - D X'``, ``q(t)`` read at every
    stage from ``stages`` (``(steps, 4, 2 N)``: the orbit's coordinates at the stages of its
    own RK4 steps, :func:`model.full.axisymmetric_kernels.rk4_motion`), so that the block is
    the exact derivative of the discrete map restricted to the family.

    ``inv_mass``: ``M^-1`` of one field (``(M, M)``); ``D = rate I + matrix`` (s-1;
    ``matrix`` None for a rate alone); the other arguments as :func:`family_stiffness`.
    """
    steps = stages.shape[0]
    F = g.shape[0]
    M = fam_phi.shape[1]
    m = F * M
    n = 2 * m
    big = np.zeros((n, n))
    for i in range(n):
        big[i, i] = 1.0
    kp = np.empty((4, n, n))
    pstage = np.empty((n, n))
    K = np.empty((m, m))
    A = np.empty((6, 6))
    C = np.empty((F, F, 2, 2))
    for step in range(steps):
        for i in range(4):
            f = stage_offset(i, dt)
            if i == 0:
                pstage[:, :] = big
            else:
                pstage[:, :] = big + f * kp[i - 1]
            family_stiffness(law, phi, dphi, s, sw, r0, dr0, stages[step, i], fam_phi, fam_dphi, g, A, C, K)
            force = K @ pstage[:m]
            kp[i, :m] = pstage[m:]
            for a in range(F):
                kp[i, m + a * M:m + (a + 1) * M] = -omega0_2 * (inv_mass @ force[a * M:(a + 1) * M])
            kp[i, m:] -= rate * pstage[m:]
            if matrix is not None:
                kp[i, m:] -= matrix @ pstage[m:]
        big += step_factor(dt) * combine(kp[0], kp[1], kp[2], kp[3])
    return big
