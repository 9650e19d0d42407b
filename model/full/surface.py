"""Energy density of the deformed mid-surface and its derivatives, any law
(docs/model.md, "The full model").

The mid-surface deformation gradient is written by its two columns in the orthonormal
frame ``(e_r, e_theta, e_z)`` of the material point's angle: ``a1 = dx/drho`` and
``a2 = (1/rho) dx/dtheta`` (3-vectors).  With ``T = |a1|^2 + |a2|^2`` and
``Delta = |a1|^2 |a2|^2 - (a1 . a2)^2`` the trace and determinant of the metric ``C = F^T F``,
the law's ``W(I1, I2) / C1`` with ``I1 = T + 1/Delta``, ``I2 = Delta + T/Delta``
(:func:`model.materials.metric_derivatives`) is a function of ``(a1, a2)``; this module gives
it with its gradient ``P = dW/dF`` and Hessian ``A = d^2W/dF^2`` (the first Piola stress and
the tangent moduli of the membrane, divided by ``C1``).  The six components of ``F`` are
ordered ``(a1_r, a1_theta, a1_z, a2_r, a2_theta, a2_z)``.  Arrays of points broadcast over
leading axes; the last axis holds the vector components.
"""

from __future__ import annotations

import numpy as np

from model.materials import metric_derivatives, metric_energy

#: Positions of the components of ``F`` in the 6-vectors and 6x6 matrices of this module.
A1_R, A1_THETA, A1_Z, A2_R, A2_THETA, A2_Z = range(6)


def _metric(a1, a2):
    n1 = np.einsum("...i,...i", a1, a1)
    n2 = np.einsum("...i,...i", a2, a2)
    c = np.einsum("...i,...i", a1, a2)
    return n1, n2, c, n1 + n2, n1 * n2 - c * c


def energy(law, a1, a2):
    """``W / C1`` (1) at the columns ``a1``, ``a2`` of the deformation gradient."""
    *_, T, delta = _metric(a1, a2)
    return metric_energy(law, T, delta, 1.0 / delta)


def gradient(law, a1, a2):
    """``dW/da1``, ``dW/da2`` of ``W / C1`` (``(..., 3)`` each).

    ``dT/da1 = 2 a1`` and ``dDelta/da1 = 2 |a2|^2 a1 - 2 (a1 . a2) a2`` (1 and 2 exchanged for
    ``a2``).
    """
    n1, n2, c, T, delta = _metric(a1, a2)
    w_t, w_d, *_ = metric_derivatives(law, T, delta, 1.0 / delta)
    w_t, w_d = np.asarray(w_t)[..., None], np.asarray(w_d)[..., None]
    t1, t2 = _delta_gradient(a1, a2, n1, n2, c)
    return 2.0 * w_t * a1 + w_d * t1, 2.0 * w_t * a2 + w_d * t2


def _delta_gradient(a1, a2, n1, n2, c):
    return (2.0 * n2[..., None] * a1 - 2.0 * c[..., None] * a2,
            2.0 * n1[..., None] * a2 - 2.0 * c[..., None] * a1)


def hessian(law, a1, a2):
    """``d^2 (W / C1) / dF^2`` as ``(..., 6, 6)`` matrices in the component order of the module.

    The second derivatives of the metric's invariants are ``d^2T = 2 I`` and
    ``d^2Delta/da1^2 = 2 |a2|^2 I - 2 a2 a2^T``, ``d^2Delta/da2^2 = 2 |a1|^2 I - 2 a1 a1^T``,
    ``d^2Delta/da1 da2 = 4 a1 a2^T - 2 a2 a1^T - 2 (a1 . a2) I``; the law enters through
    ``W_T, W_D, W_TT, W_TD, W_DD``.
    """
    n1, n2, c, T, delta = _metric(a1, a2)
    w_t, w_d, w_tt, w_td, w_dd = (np.asarray(x, float)[..., None, None]
                                  for x in metric_derivatives(law, T, delta, 1.0 / delta))
    t1, t2 = _delta_gradient(a1, a2, n1, n2, c)
    dt = np.concatenate([2.0 * a1, 2.0 * a2], axis=-1)  # dT/dF
    dd = np.concatenate([t1, t2], axis=-1)  # dDelta/dF
    outer = lambda x, y: x[..., :, None] * y[..., None, :]  # noqa: E731
    eye = np.eye(3)
    hd = np.empty(np.broadcast_shapes(a1.shape, a2.shape)[:-1] + (6, 6))
    hd[..., :3, :3] = 2.0 * n2[..., None, None] * eye - 2.0 * outer(a2, a2)
    hd[..., 3:, 3:] = 2.0 * n1[..., None, None] * eye - 2.0 * outer(a1, a1)
    hd[..., :3, 3:] = 4.0 * outer(a1, a2) - 2.0 * outer(a2, a1) - 2.0 * c[..., None, None] * eye
    hd[..., 3:, :3] = np.swapaxes(hd[..., :3, 3:], -1, -2)
    return (w_tt * outer(dt, dt) + w_td * (outer(dt, dd) + outer(dd, dt)) + w_dd * outer(dd, dd)
            + 2.0 * w_t * np.eye(6) + w_d * hd)
