"""Hyperelastic laws of the incompressible membrane, written once (docs/model.md, "Material laws").

A law is a strain energy per unit undeformed volume ``W(I1, I2)``, given here divided by
the constant ``C1`` that every law has (the kernels carry ``C1`` in their force factors):

* :class:`NeoHookean` -- the paper's Eq. (1), ``W = C1 (I1 - 3)``;
* :class:`MooneyRivlin` -- ``W = C1 (I1 - 3) + C2 (I2 - 3)``;
* :class:`Gent` -- ``W = -C1 Jm ln(1 - (I1 - 3)/Jm)``, strain-stiffening, the neo-Hookean
  law as ``Jm -> infinity``; finite only for ``I1 - 3 < Jm``.

Each law is a small ``NamedTuple`` of its constants relative to ``C1`` with two functions,
``energy(law, i1, i2)`` (``W / C1``) and ``derivatives(law, i1, i2)`` (``W_1, W_2, W_11,
W_12, W_22`` of ``W / C1``, subscripts the invariants), in plain arithmetic: the same
source serves numpy arrays and the compiled kernels, where numba compiles one
specialisation per law type (:mod:`model.material_kernels` dispatches on it at compile
time, so a kernel of the neo-Hookean law does only the neo-Hookean arithmetic).  This
module imports no numba.

Every model composes a law with its kinematics through the in-plane metric ``C`` of the
mid-surface (``F^T F`` of the surface's deformation gradient): with ``T = tr C`` and
``Delta = det C`` the incompressible membrane has ``lambda_3^2 = 1/Delta`` and

    I1 = T + 1/Delta,        I2 = Delta + T/Delta,

so that :func:`metric_derivatives` gives the derivatives of ``W`` in ``(T, Delta)`` for any
law, and :func:`stretch_derivatives` those in the principal stretches of a planar state
(the pre-stretch: ``T = lambda_1^2 + lambda_2^2``, ``Delta = lambda_1^2 lambda_2^2``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class NeoHookean(NamedTuple):
    """``W / C1 = I1 - 3`` (the paper's law, no further constant)."""

    @classmethod
    def from_constants(cls, C1, C2, Jm):
        return cls()

    def neo_hookean(law):
        return True

    def energy(law, i1, i2):
        return i1 - 3.0

    def derivatives(law, i1, i2):
        return 1.0, 0.0, 0.0, 0.0, 0.0


class MooneyRivlin(NamedTuple):
    """``W / C1 = I1 - 3 + c2 (I2 - 3)``, ``c2 = C2 / C1``."""

    c2: float

    @classmethod
    def from_constants(cls, C1, C2, Jm):
        return cls(C2 / C1)

    def neo_hookean(law):
        return law.c2 == 0.0

    def energy(law, i1, i2):
        return i1 - 3.0 + law.c2 * (i2 - 3.0)

    def derivatives(law, i1, i2):
        return 1.0, law.c2, 0.0, 0.0, 0.0


class Gent(NamedTuple):
    """``W / C1 = -Jm ln(1 - (I1 - 3)/Jm)``, stored as ``inv_jm = 1/Jm`` (0: neo-Hookean)."""

    inv_jm: float

    @classmethod
    def from_constants(cls, C1, C2, Jm):
        return cls(1.0 / Jm)

    def neo_hookean(law):
        return law.inv_jm == 0.0

    def extensibility(law, i1):
        return 1.0 - (i1 - 3.0) * law.inv_jm

    def energy(law, i1, i2):
        x = (i1 - 3.0) * law.inv_jm
        # -ln(1 - x)/x -> 1 as Jm -> inf; log1p keeps it accurate for small x
        return i1 - 3.0 if law.inv_jm == 0.0 else -np.log1p(-x) / law.inv_jm

    def derivatives(law, i1, i2):
        # beyond the locking limit I1 - 3 = Jm the energy is infinite: W_1 = inf there
        w1 = 1.0 / np.maximum(1.0 - (i1 - 3.0) * law.inv_jm, 0.0)
        return w1, 0.0, w1 * w1 * law.inv_jm, 0.0, 0.0


#: The law records by the name ``[membrane] law`` gives.
LAWS = {"neo-hookean": NeoHookean, "mooney-rivlin": MooneyRivlin, "gent": Gent}
#: The constants (fields of :class:`model.params.Membrane`) each law reads besides ``C1``.
LAW_CONSTANTS = {"neo-hookean": (), "mooney-rivlin": ("C2",), "gent": ("Jm",)}


def is_neo_hookean(law) -> bool:
    """Whether the law record ``law`` is the neo-Hookean law (Mooney-Rivlin with ``C2 = 0``,
    Gent with ``Jm = inf`` included)."""
    return type(law).neo_hookean(law)


def has_limit(law) -> bool:
    """Whether the law has a limit of extensibility (Gent with a finite ``Jm``)."""
    return hasattr(type(law), "extensibility") and not is_neo_hookean(law)


def extensibility(law, i1):
    """How far the invariant ``I1`` is from the law's limit of extensibility: ``1 - (I1 - 3)/Jm``
    for Gent (0 at chain locking, where ``W`` becomes infinite), 1 for the laws without a
    limit.  A continuous margin, for the events of an integration."""
    return type(law).extensibility(law, i1) if has_limit(law) else 1.0 + 0.0 * i1


def invariant_derivatives(law, i1, i2):
    """``(W_1, W_2, W_11, W_12, W_22)`` of ``W / C1`` at the invariants ``(i1, i2)``."""
    return type(law).derivatives(law, i1, i2)


def invariant_energy(law, i1, i2):
    """``W / C1`` at the invariants ``(i1, i2)`` (scalars or arrays)."""
    return type(law).energy(law, i1, i2)


def metric_derivatives(law, T, delta, inv_delta):
    """Derivatives of ``W / C1`` in the trace ``T`` and determinant ``Delta`` of the
    in-plane metric: ``(W_T, W_D, W_TT, W_TD, W_DD)`` (``D`` for ``Delta``).

    ``inv_delta`` is ``1 / delta``, passed so that a kernel that has it from its one
    division needs no other.  With ``I1 = T + 1/Delta``, ``I2 = Delta + T/Delta``::

        W_T  = W_1 + W_2 / Delta
        W_D  = -W_1 / Delta^2 + W_2 (1 - T / Delta^2)
        W_TT = W_11 + 2 W_12 / Delta + W_22 / Delta^2
        W_TD = -W_11 / Delta^2 + W_12 (1 - T/Delta^2 - 1/Delta^3)
               + W_22 (1 - T/Delta^2) / Delta - W_2 / Delta^2
        W_DD = W_11 / Delta^4 - 2 W_12 (1 - T/Delta^2) / Delta^2 + W_22 (1 - T/Delta^2)^2
               + 2 W_1 / Delta^3 + 2 W_2 T / Delta^3

    Terms of a law's zero derivatives vanish at compile time in the kernels.
    """
    i1 = T + inv_delta
    i2 = delta + T * inv_delta
    w1, w2, w11, w12, w22 = invariant_derivatives(law, i1, i2)
    e2 = inv_delta * inv_delta
    e3 = e2 * inv_delta
    g = 1.0 - T * e2  # dI2/dDelta
    w_t = w1 + w2 * inv_delta
    w_d = -w1 * e2 + w2 * g
    w_tt = w11 + 2.0 * w12 * inv_delta + w22 * e2
    w_td = -w11 * e2 + w12 * (g - e3) + w22 * g * inv_delta - w2 * e2
    w_dd = w11 * e2 * e2 - 2.0 * w12 * g * e2 + w22 * g * g + 2.0 * (w1 + w2 * T) * e3
    return w_t, w_d, w_tt, w_td, w_dd


def metric_energy(law, T, delta, inv_delta):
    """``W / C1`` as a function of the in-plane metric's trace and determinant."""
    return invariant_energy(law, T + inv_delta, delta + T * inv_delta)


def invariants(l1, l2):
    """``(I1, I2)`` of the incompressible planar state of principal stretches ``l1``, ``l2``."""
    a, b = l1 * l1, l2 * l2
    return a + b + 1.0 / (a * b), a * b + 1.0 / a + 1.0 / b


def stretch_derivatives(law, l1, l2):
    """Derivatives of ``W / C1`` in the principal in-plane stretches of a planar state,
    ``(W_1, W_2, W_11, W_12, W_22)`` with subscripts ``lambda_1``, ``lambda_2`` here.

    With ``T = l1^2 + l2^2``, ``Delta = l1^2 l2^2``: ``W_1 = 2 l1 (W_T + W_D l2^2)``,
    ``W_11 = 2 (W_T + W_D l2^2) + 4 l1^2 (W_TT + 2 W_TD l2^2 + W_DD l2^4)``, ``W_12 = 4 l1 l2
    (W_TT + W_TD T + W_DD Delta + W_D)`` and the same with 1 and 2 exchanged.  The
    membrane's Cauchy stresses are ``sigma_i = C1 l_i W_i`` (plane stress,
    incompressible).  Scalars or arrays.
    """
    a, b = l1 * l1, l2 * l2
    T, delta = a + b, a * b
    w_t, w_d, w_tt, w_td, w_dd = metric_derivatives(law, T, delta, 1.0 / delta)
    s1, s2 = w_t + w_d * b, w_t + w_d * a
    return (2.0 * l1 * s1, 2.0 * l2 * s2,
            2.0 * s1 + 4.0 * a * (w_tt + 2.0 * w_td * b + w_dd * b * b),
            4.0 * l1 * l2 * (w_tt + w_td * T + w_dd * delta + w_d),
            2.0 * s2 + 4.0 * b * (w_tt + 2.0 * w_td * a + w_dd * a * a))


def kernel_law(name: str, C1: float, C2: float = 0.0, Jm: float = np.inf):
    """The law record ``name`` (a key of :data:`LAWS`) for the constants of a membrane."""
    return LAWS[name].from_constants(C1, C2, Jm)
