"""The transverse kinematics of the u = v = 0 membrane composed with a material law.

The ROM, its families and its lock-step kernels (and the linear problem as the small-slope
limit) evaluate the exact strain energy of a transverse deflection ``w(rho, theta)`` of the
pre-stretched membrane (docs/model.md, "Transverse energy") at quadrature points, from the
slopes ``a = w_rho``, ``b = w_theta`` and the pre-stretch there: ``1 / rho^2`` and the
squared principal stretches ``lambda_2^2 = (r_o / rho)^2`` (``hoop2``) and ``lambda_1^2 =
r_o'^2`` (``radial2``).  The in-plane metric of the deflected surface has

    T     = lambda_1^2 + lambda_2^2 + a^2 + b^2 / rho^2
    Delta = lambda_2^2 (lambda_1^2 + a^2) + lambda_1^2 b^2 / rho^2

(``Delta = D / rho^2`` with the ``D`` of docs/model.md) and the energy per unit undeformed
area is ``C1 h W(T, Delta) / C1`` with the law's derivatives from
:func:`model.materials.metric_derivatives`.  The functions below are the one home of this
composition: plain arithmetic that runs on numpy arrays and inlines into the compiled
kernels (one division per point, ``1 / Delta``), specialised per law.  In these variables
the neo-Hookean force costs what its hand-written formula did (``benchmarks/bench_force.py``).
"""

from __future__ import annotations

from numba.extending import overload

from . import material_kernels  # noqa: F401  (the laws' overloads, before any kernel compiles)
from .materials import metric_derivatives, metric_energy


def _metric(a, b, inv_rho2, hoop2, radial2):
    # T, Delta and 1/Delta at one point, with the one division
    bt2 = b * b * inv_rho2
    delta = hoop2 * (radial2 + a * a) + radial2 * bt2
    return radial2 + hoop2 + a * a + bt2, delta, 1.0 / delta


@overload(_metric, inline="always")
def _metric_overload(a, b, inv_rho2, hoop2, radial2):
    return _metric


def first_invariant(a, b, inv_rho2, hoop2, radial2):
    """``I1 = T + 1/Delta`` (1) at the slopes ``a``, ``b`` of a point (arrays broadcast)."""
    T, _, inv_delta = _metric(a, b, inv_rho2, hoop2, radial2)
    return T + inv_delta


def energy_density(law, a, b, inv_rho2, hoop2, radial2):
    """``W / C1`` (1) at slopes ``a = w_rho`` (1), ``b = w_theta`` (m) of a point with
    ``1 / rho^2`` (m-2), ``(r_o / rho)^2`` and ``r_o'^2`` (1)."""
    T, delta, inv_delta = _metric(a, b, inv_rho2, hoop2, radial2)
    return metric_energy(law, T, delta, inv_delta)


@overload(energy_density, inline="always")
def _energy_density(law, a, b, inv_rho2, hoop2, radial2):
    return energy_density


def slope_factors(law, a, b, inv_rho2, hoop2, radial2):
    """``(c_a, c_b)`` with ``dW/da = a c_a`` (1) and ``dW/db = b c_b`` (m-2), ``W / C1``:

        c_a = 2 (W_T + W_D r_o^2 / rho^2),    c_b = 2 (W_T + W_D r_o'^2) / rho^2

    At ``a = b = 0`` these are twice the coefficients ``1 + L1``, ``1/rho^2 + L3`` of the
    linear problem (Eq. 25).
    """
    T, delta, inv_delta = _metric(a, b, inv_rho2, hoop2, radial2)
    w_t, w_d, _, _, _ = metric_derivatives(law, T, delta, inv_delta)
    return 2.0 * (w_t + w_d * hoop2), 2.0 * (w_t + w_d * radial2) * inv_rho2


@overload(slope_factors, inline="always")
def _slope_factors(law, a, b, inv_rho2, hoop2, radial2):
    return slope_factors


def slope_hessian(law, a, b, inv_rho2, hoop2, radial2):
    """:func:`slope_factors` and the second derivatives of ``W / C1`` in the slopes,
    ``(c_a, c_b, W_aa, W_ab, W_bb)`` (1, m-2, 1, m-1, m-2)."""
    T, delta, inv_delta = _metric(a, b, inv_rho2, hoop2, radial2)
    w_t, w_d, w_tt, w_td, w_dd = metric_derivatives(law, T, delta, inv_delta)
    ta, tb = 2.0 * a, 2.0 * b * inv_rho2          # dT/da, dT/db
    da, db = hoop2 * ta, radial2 * tb             # dDelta/da, dDelta/db
    ca = 2.0 * (w_t + w_d * hoop2)
    cb = 2.0 * (w_t + w_d * radial2) * inv_rho2
    waa = w_tt * ta * ta + 2.0 * w_td * ta * da + w_dd * da * da + ca
    wab = w_tt * ta * tb + w_td * (ta * db + tb * da) + w_dd * da * db
    wbb = w_tt * tb * tb + 2.0 * w_td * tb * db + w_dd * db * db + cb
    return ca, cb, waa, wab, wbb


@overload(slope_hessian, inline="always")
def _slope_hessian(law, a, b, inv_rho2, hoop2, radial2):
    return slope_hessian
