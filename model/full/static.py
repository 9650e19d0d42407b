"""The full model's pre-stretch: the axisymmetric planar state of least energy
(docs/model.md, "The full model", "Static state").

The radius ``r(s)`` (scaled, ``s = rho / Re``) is the straight line through the edge values
``r(delta_o) = delta_o``, ``r(1) = delta`` plus a combination of the Legendre-Galerkin
basis (:mod:`model.full.radial`), and minimises the membrane's energy
``2 pi h C1 int W(a1, a2) s ds`` with ``a1 = (r', 0, 0)``, ``a2 = (0, r/s, 0)`` -- the same
energy as the ROM's pre-stretch (Eq. 14), discretised differently: the ROM collocates the
Euler-Lagrange equation (Eq. 15) on Chebyshev points (:mod:`model.prestretch`), this module
makes the energy stationary in the Galerkin sense with the gradient and Hessian of
:mod:`model.full.surface`, the full model's own kinematics.  Newton from the Eq. (21)
approximation, with the step halved while it raises the energy or makes a stretch
non-positive.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from model.params import Membrane
from model.prestretch import PlanarState, _analytic_coef, check_extensibility

from . import surface
from .radial import RadialBasis

#: Default number of radial basis functions of the full model (the pre-stretch converges to
#: round-off well below it: tests/test_full_model.py, docs/validation.md).
DEFAULT_ORDER = 48


@dataclass(frozen=True, eq=False)
class FullPrestretch(PlanarState):
    """The full model's pre-stretched state ``r(rho)``; build it with :func:`solve_full_prestretch`.

    Attributes
    ----------
    membrane : Membrane
    basis : RadialBasis
        The radial basis on ``[delta_o, 1]`` (scaled radii).
    coef : numpy.ndarray
        ``(order,)`` coefficients of ``r/Re`` minus the straight line on the basis.
    last_step : float
        Largest coefficient change of the last Newton step (a measure of convergence).
    """

    membrane: Membrane
    basis: RadialBasis
    coef: np.ndarray
    last_step: float

    def scaled(self, s):
        """``(r/Re, r')`` at scaled radii ``s``."""
        line, dline = _line(self.membrane, s)
        v, dv = self.basis.evaluate(self.coef, s)
        return line + v, dline + dv

    def radius(self, rho):
        """Deformed radius (m) at undeformed radius ``rho`` (m)."""
        return self.membrane.Re * self.scaled(np.asarray(rho, float) / self.membrane.Re)[0]

    def slope(self, rho):
        """Radial stretch ``lambda_1 = dr/drho`` (1) at ``rho`` (m)."""
        return self.scaled(np.asarray(rho, float) / self.membrane.Re)[1]


def _line(m: Membrane, s):
    k = (m.delta - m.delta_o) / (1.0 - m.delta_o)
    return m.delta_o + k * (np.asarray(s, float) - m.delta_o), k + 0.0 * np.asarray(s, float)


def planar_columns(r, dr, s):
    """The columns ``a1 = (r', 0, 0)``, ``a2 = (0, r/s, 0)`` of a planar axisymmetric state."""
    zero = np.zeros_like(s)
    return np.stack([dr, zero, zero], axis=-1), np.stack([zero, r / s, zero], axis=-1)


def axisymmetric_energy(membrane: Membrane, basis: RadialBasis, coef):
    """``int W/C1 s ds`` of the planar state ``coef`` (the energy over ``2 pi h C1 Re^2``)."""
    line, dline = _line(membrane, basis.s)
    r, dr = line + coef @ basis.phi, dline + coef @ basis.dphi
    if np.any(dr <= 0.0) or np.any(r <= 0.0):
        return np.inf
    a1, a2 = planar_columns(r, dr, basis.s)
    with np.errstate(divide="ignore", invalid="ignore"):  # beyond Gent's limit: not finite, refused
        e = float(np.sum(surface.energy(membrane.material, a1, a2) * basis.s * basis.weights))
    return e if np.isfinite(e) else np.inf


def _gradient_hessian(membrane, basis, coef):
    s, w = basis.s, basis.weights
    line, dline = _line(membrane, s)
    r, dr = line + coef @ basis.phi, dline + coef @ basis.dphi
    a1, a2 = planar_columns(r, dr, s)
    p1, p2 = surface.gradient(membrane.material, a1, a2)
    A = surface.hessian(membrane.material, a1, a2)
    # a variation phi of r moves a1_r by phi' and a2_theta by phi / s
    g = basis.dphi @ (p1[:, 0] * s * w) + basis.phi @ (p2[:, 1] * w)
    rr, rt, tt = A[:, surface.A1_R, surface.A1_R], A[:, surface.A1_R, surface.A2_THETA], A[:, surface.A2_THETA, surface.A2_THETA]
    cross = (basis.dphi * (rt * w)) @ basis.phi.T
    H = (basis.dphi * (rr * s * w)) @ basis.dphi.T + cross + cross.T + (basis.phi * (tt * w / s)) @ basis.phi.T
    return g, H


def solve_full_prestretch(membrane: Membrane, order: int = DEFAULT_ORDER, points: int | None = None) -> FullPrestretch:
    """The pre-stretch of ``membrane`` on ``order`` radial functions.

    Raises
    ------
    ValueError
        When the outer edge alone is beyond the law's limit of extensibility
        (:func:`model.prestretch.check_extensibility`).
    ArithmeticError
        When the Eq. (21) seed is beyond that limit, or Newton does not converge in 60
        steps (the message says how far it got).
    """
    check_extensibility(membrane)
    basis = RadialBasis.build(membrane.delta_o, 1.0, order, points)
    s, w = basis.s, basis.weights
    a, b = _analytic_coef(membrane.delta, membrane.delta_o)
    mass = (basis.phi * (s * w)) @ basis.phi.T
    coef = np.linalg.solve(mass, basis.phi @ ((a * s + b / s - _line(membrane, s)[0]) * s * w))
    e = axisymmetric_energy(membrane, basis, coef)
    if not np.isfinite(e):
        raise ArithmeticError(f"full-model pre-stretch not found at delta = {membrane.delta}, delta_o = "
                              f"{membrane.delta_o}: its Eq. (21) seed is beyond the law's limit of extensibility")
    step = np.inf
    for _ in range(60):
        g, H = _gradient_hessian(membrane, basis, coef)
        dc = -np.linalg.solve(H, g)
        step = float(np.abs(dc).max())  # the full Newton step: the measure of convergence
        if step < 1e-14 * (1.0 + np.abs(coef).max()):
            break
        t = 1.0
        while True:  # halve the step while it raises the energy (infinite where a stretch is not positive)
            trial = coef + t * dc
            e_trial = axisymmetric_energy(membrane, basis, trial)
            # near the minimum the energy changes by O(step^2) only, below its round-off
            if e_trial <= e + 1e-14 * abs(e):
                break
            t *= 0.5
            if t < 1e-6:
                raise ArithmeticError(f"full-model pre-stretch not found at delta = {membrane.delta}, delta_o = "
                                      f"{membrane.delta_o}: no descent along the Newton step (|step| = {step:.1e})")
        coef, e = trial, e_trial
    if not step < 1e-11:
        raise ArithmeticError(f"full-model pre-stretch did not converge at delta = {membrane.delta}, delta_o = "
                              f"{membrane.delta_o} with order = {order} (last Newton step {step:.1e})")
    return FullPrestretch(membrane, basis, coef, step)
