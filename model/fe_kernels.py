"""Compiled force of the membrane on the two-dimensional finite-element mesh
(:meth:`model.fe_motion.FeMotion.force`, docs/model.md, "The two-dimensional finite-element
check"): one pass over the elements, gathering their nodes' displacements, the deformation
gradient and the law's stress at each quadrature point, scattering the nodal forces.  The
law enters through :func:`model.materials.metric_derivatives` (compiled per law by
:mod:`model.material_kernels`).
"""

from __future__ import annotations

import numba as nb

from model import material_kernels  # noqa: F401  (the laws' overloads for compiled code)
from model.materials import metric_derivatives


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def fe_force(law, element_dofs, grad_x, grad_y, weights, D, out):
    """``out = f(D)``, the gradient of ``int W / C1 dA`` (``(3, nodes)``).

    Parameters
    ----------
    element_dofs : numpy.ndarray
        ``(elements, nodes per element)`` int64: each element's scalar dofs.
    grad_x, grad_y : numpy.ndarray
        ``(elements, points, nodes per element)``: the derivatives ``d phi / dX``, ``d phi / dY``
        of the element's basis functions at its quadrature points.
    weights : numpy.ndarray
        ``(elements, points)``: the quadrature weights (areas).
    D : numpy.ndarray
        ``(3, nodes)``: the Cartesian displacement (over ``Re``).
    """
    elements, points, local = grad_x.shape
    out[:] = 0.0
    for e in range(elements):
        for p in range(points):
            # the columns a1 = e_x + dD/dX, a2 = e_y + dD/dY
            a10 = 1.0
            a11 = 0.0
            a12 = 0.0
            a20 = 0.0
            a21 = 1.0
            a22 = 0.0
            for k in range(local):
                n = element_dofs[e, k]
                gx = grad_x[e, p, k]
                gy = grad_y[e, p, k]
                a10 += gx * D[0, n]
                a11 += gx * D[1, n]
                a12 += gx * D[2, n]
                a20 += gy * D[0, n]
                a21 += gy * D[1, n]
                a22 += gy * D[2, n]
            n1 = a10 * a10 + a11 * a11 + a12 * a12
            n2 = a20 * a20 + a21 * a21 + a22 * a22
            c = a10 * a20 + a11 * a21 + a12 * a22
            delta = n1 * n2 - c * c
            w_t, w_d, _, _, _ = metric_derivatives(law, n1 + n2, delta, 1.0 / delta)
            # P1 = 2 W_T a1 + W_D (2 n2 a1 - 2 c a2), P2 the same with 1 and 2 exchanged (model.full.surface)
            w = weights[e, p]
            f11 = 2.0 * (w_t + w_d * n2) * w
            f12 = -2.0 * w_d * c * w
            f22 = 2.0 * (w_t + w_d * n1) * w
            p10 = f11 * a10 + f12 * a20
            p11 = f11 * a11 + f12 * a21
            p12 = f11 * a12 + f12 * a22
            p20 = f22 * a20 + f12 * a10
            p21 = f22 * a21 + f12 * a11
            p22 = f22 * a22 + f12 * a12
            for k in range(local):
                n = element_dofs[e, k]
                gx = grad_x[e, p, k]
                gy = grad_y[e, p, k]
                out[0, n] += p10 * gx + p20 * gy
                out[1, n] += p11 * gx + p21 * gy
                out[2, n] += p12 * gx + p22 * gy
