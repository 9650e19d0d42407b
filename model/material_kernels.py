"""The material laws in compiled code: numba overloads of the functions of :mod:`model.materials`.

A kernel that calls :func:`model.materials.metric_derivatives` (or the other functions
below) gets the same plain-arithmetic source compiled inline, and numba compiles one
specialisation of the kernel per law record type: the law's constants are fields of its
``NamedTuple``, its derivatives that are zero are constants that vanish from the
arithmetic.  Import this module before compiling such a kernel (:mod:`model.transverse`
does).
"""

from __future__ import annotations

from numba.extending import overload

from .materials import invariant_derivatives, metric_derivatives, metric_energy, invariant_energy


@overload(invariant_derivatives, inline="always")
def _invariant_derivatives(law, i1, i2):
    return law.instance_class.derivatives


@overload(invariant_energy, inline="always")
def _strain_energy(law, i1, i2):
    return law.instance_class.energy


@overload(metric_derivatives, inline="always")
def _metric_derivatives(law, T, delta, inv_delta):
    return metric_derivatives


@overload(metric_energy, inline="always")
def _metric_energy(law, T, delta, inv_delta):
    return metric_energy
