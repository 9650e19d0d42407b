"""Axisymmetric pre-stretch of the annular membrane (paper, section 3).

Three variants of the deformed radius ``r_o(rho)`` share one interface
(:class:`Prestretch`, a :class:`PlanarState`): ``analytic`` (linearised solution, Eq. 21, the same for every law:
the small-strain displacement of an incompressible disc under edge displacements),
``numeric`` (Chebyshev collocation of the nonlinear equilibrium of the membrane's law,
Eq. 15 for the neo-Hookean law; shooting only seeds it where Eq. 21 does not) and ``fit``
(least-squares fit Eq. 18 of the numeric solution, used by the paper's Appendix A).  Radii
are in metres; internally the problem is scaled by ``Re`` (Eq. 20).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.polynomial import chebyshev as C
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from .materials import extensibility, has_limit, invariants, stretch_derivatives
from .params import Membrane

KINDS = ("analytic", "numeric", "fit")

#: Relative and absolute tolerance of the shooting integration (scaled variables).
_SHOOT_TOL = 1e-13
#: Imaginary step of the complex-step derivatives of the collocation's Jacobian.
_COMPLEX_STEP = 1e-30


def equilibrium_residual(law, rho, r, dr, d2r):
    """Residual of the radial equilibrium of the axisymmetric planar state, any law.

    ``d/drho (rho W_1) - W_2 = 0`` (the paper's Eq. 15 for the neo-Hookean law, up to a
    factor), with ``W_i = dW/dlambda_i / C1`` at ``lambda_1 = r'``, ``lambda_2 = r/rho``
    (:func:`model.materials.stretch_derivatives`), written out as
    ``rho W_11 r'' + W_12 (r' - r/rho) + W_1 - W_2``.

    Parameters
    ----------
    law : NamedTuple
        A law record of :mod:`model.materials` (``Membrane.material``).
    rho, r, dr, d2r : array_like
        Undeformed radius, deformed radius and its first two derivatives (scaled by
        ``Re``, or any consistent length unit; the residual is dimensionless).  Complex
        values are allowed (the collocation's complex-step derivatives).
    """
    l2 = r / rho
    w1, w2, w11, w12, _ = stretch_derivatives(law, dr, l2)
    return rho * w11 * d2r + w12 * (dr - l2) + w1 - w2


def _equilibrium_rhs(law, rho, state):
    """First-order form of the equilibrium (:func:`equilibrium_residual` solved for
    ``r''``): ``state = (r, y)`` with ``y = dr/drho``; returns ``(y, dy/drho)``."""
    r, y = state
    l2 = r / rho
    w1, w2, w11, w12, _ = stretch_derivatives(law, y, l2)
    return np.array([y, (w2 - w1 - w12 * (y - l2)) / (rho * w11)])


class PlanarState:
    """What every axisymmetric planar state ``r(rho)`` of a membrane gives from its radius and
    slope: stretches, stresses and edge traction.  Subclasses have ``membrane`` and
    ``radius(rho)``, ``slope(rho)``: :class:`Prestretch` (the ROM's) and
    :class:`model.full.static.FullPrestretch` (the full model's)."""

    def stretches(self, rho):
        """Principal stretches ``(lambda_1, lambda_2, lambda_3)`` of Eq. (12) at ``rho`` (m)."""
        rho = np.asarray(rho, dtype=float)
        r, dr = self.radius(rho), self.slope(rho)
        return dr, r / rho, rho / (r * dr)

    def stresses(self, rho):
        """Cauchy principal stresses ``(sigma_1, sigma_2)`` (Pa), Eq. (22) for any law.

        ``sigma_i = lambda_i dW/dlambda_i`` for the incompressible membrane in plane
        stress (:func:`model.materials.stretch_derivatives`); for the neo-Hookean law
        ``2 C1 (lambda_i^2 - lambda_3^2)``, Eq. (22).
        """
        l1, l2, _ = self.stretches(rho)
        w1, w2, *_ = stretch_derivatives(self.membrane.material, l1, l2)
        c1 = self.membrane.C1
        return c1 * l1 * w1, c1 * l2 * w2

    def traction(self) -> float:
        """Edge traction ``f = h dW/dlambda_1`` (N m-1 of undeformed edge) that holds the
        stretch at ``rho = Re``, Eq. (16)."""
        m = self.membrane
        l1, l2 = float(self.slope(m.Re)), m.Rf / m.Re
        return m.h * m.C1 * float(stretch_derivatives(m.material, l1, l2)[0])


@dataclass(frozen=True)
class Prestretch(PlanarState):
    """The deformed radius ``r_o(rho)`` of one pre-stretched membrane.

    Build it with :func:`solve_prestretch`.  ``coef`` holds the variant's representation
    in scaled variables (``rho/Re``, ``r_o/Re``): the Eq. (21) constants for ``analytic``,
    Chebyshev series of ``r`` and ``r'`` on ``[delta_o, 1]`` for ``numeric``, the Eq. (18)
    coefficients ``A1..A5`` for ``fit``.
    """

    kind: str
    membrane: Membrane
    coef: tuple

    def _scaled(self, s):
        if self.kind == "analytic":
            a, b = self.coef
            return a * s + b / s, a - b / s**2
        if self.kind == "numeric":
            cr, cy, dom = self.coef
            t = (2 * s - dom[0] - dom[1]) / (dom[1] - dom[0])
            return C.chebval(t, cr), C.chebval(t, cy)
        a1, a2, a3, a4, a5 = self.coef
        ls = np.log(s)
        return (a1 * ls + a2 * s**2 * ls + a3 * s**2 + a4 * s + a5,
                a1 / s + a2 * (2 * s * ls + s) + 2 * a3 * s + a4)

    def radius(self, rho):
        """Deformed radius ``r_o`` (m) at undeformed radius ``rho`` (m)."""
        s = np.asarray(rho, dtype=float) / self.membrane.Re
        return self.membrane.Re * self._scaled(s)[0]

    def slope(self, rho):
        """Radial stretch ``lambda_1 = d r_o / d rho`` (1) at ``rho`` (m), Eq. (12)."""
        s = np.asarray(rho, dtype=float) / self.membrane.Re
        return self._scaled(s)[1]


def _analytic_coef(delta, delta_o):
    """Constants ``(a, b)`` of Eq. (21): ``r/Re = a rho/Re + b Re/rho``."""
    d2 = delta_o**2
    return ((delta - d2) / (1 - d2), d2 * (1 - delta) / (1 - d2))


def _shoot(law, slope0, delta_o, dense=False):
    # stops where the state reaches the law's limit of extensibility (Gent: W infinite);
    # None when the inner edge is beyond it
    def limit(s, y):
        l1, l2 = y[1], y[0] / s
        return extensibility(law, invariants(l1, l2)[0])
    limit.terminal = True
    if has_limit(law) and limit(delta_o, (delta_o, slope0)) <= 0.0:
        return None  # beyond the limit at the inner edge already
    return solve_ivp(lambda s, y: _equilibrium_rhs(law, s, y), (delta_o, 1.0), [delta_o, slope0], method="DOP853",
                     rtol=_SHOOT_TOL, atol=_SHOOT_TOL, dense_output=dense, events=limit if has_limit(law) else None)


def _cheb_lobatto(n, dom):
    """Chebyshev-Lobatto points on ``dom`` and the differentiation matrix (Trefethen 2000)."""
    t = np.cos(np.pi * np.arange(n + 1) / n)
    c = np.ones(n + 1)
    c[0] = c[-1] = 2.0
    c *= (-1.0) ** np.arange(n + 1)
    dt = t[:, None] - t[None, :]
    d = np.outer(c, 1.0 / c) / (dt + np.eye(n + 1))
    d -= np.diag(d.sum(axis=1))
    half = 0.5 * (dom[1] - dom[0])
    return 0.5 * (dom[0] + dom[1]) + half * t, d / half


def _polish(law, s, r, d):
    """Newton on the first-order Chebyshev collocation of the equilibrium
    (:func:`equilibrium_residual`), ends held fixed;
    ``(r, r')`` at the points once a step falls below 1e-12 (relative; Newton converges
    quadratically, so the iterate is then at round-off), after at most 30 steps, or None
    when the last step is still above 1e-10 or ``r'`` left ``(0, inf)``.

    Unknowns are ``r`` and ``y = r'`` at the Lobatto points; the equations are
    ``D r = y`` everywhere and the equilibrium with ``r'' = D y`` at the interior points.
    The first-order form keeps the round-off amplification of the second derivative at
    ``O(n^2)`` instead of ``O(n^4)``.  The residual at a point depends on ``(r, y, r'')``
    there only; its three partial derivatives are complex-step derivatives (exact to
    rounding, for any law).
    """
    n1 = s.size
    y = d @ r
    eye = np.eye(n1)
    ih = 1j * _COMPLEX_STEP
    for _ in range(30):
        z = d @ y
        f = equilibrium_residual(law, s, r, y, z)
        f_r = equilibrium_residual(law, s, r + ih, y, z).imag / _COMPLEX_STEP
        f_y = equilibrium_residual(law, s, r, y + ih, z).imag / _COMPLEX_STEP
        f_z = equilibrium_residual(law, s, r, y, z + ih).imag / _COMPLEX_STEP
        jac = np.block([[d, -eye], [np.diag(f_r), np.diag(f_y) + f_z[:, None] * d]])
        res = np.concatenate([d @ r - y, f])
        for row in (n1, 2 * n1 - 1):  # boundary rows: the end values stay fixed
            jac[row] = 0.0
            jac[row, row - n1] = 1.0
            res[row] = 0.0
        step = np.linalg.solve(jac, -res)
        r, y = r + step[:n1], y + step[n1:]
        if not (np.all(np.isfinite(y)) and np.all(y > 0)):
            return None
        if np.abs(step).max() < 1e-12 * (1 + np.abs(y).max()):
            break  # quadratic convergence: the next step would be round-off (~1e-14)
    # Newton stalls at round-off (~1e-14); a last step far above it means no convergence
    return (r, y) if np.abs(step).max() < 1e-10 * (1 + np.abs(y).max()) else None


def _numeric_coef(law, delta, delta_o):
    """Solve the equilibrium of ``law`` (Eq. 15 for the neo-Hookean law) with
    ``r(delta_o) = delta_o``, ``r(1) = delta`` (scaled variables).

    Newton on the Chebyshev collocation of the equilibrium itself (:func:`_collocate`), seeded by
    the Eq. (21) approximation; where that seed does not converge, by shooting (the
    paper's method: the slope at the inner edge bracketed around the Eq. (21) value and
    found by Brent's method so that the DOP853 integration of the first-order form hits
    ``r(1) = delta``).  The collocation yields a spectrally accurate series (degree doubled
    from 32 until its tail is below 1e-14); both seeds give the same series.
    """
    dom = (delta_o, 1.0)
    a, b = _analytic_coef(delta, delta_o)
    seeded = _collocate(law, lambda s: a * s + b / s, delta, delta_o, dom)
    if seeded is not None:
        return seeded
    guess = a - b / delta_o**2

    def miss(s):
        sol = _shoot(law, s, delta_o)
        if sol is None or sol.status != 0 or not np.all(np.isfinite(sol.y)):
            return np.inf  # stopped short (an event at the limit of extensibility, or a failure): too steep
        return sol.y[0, -1] - delta

    lo, hi = guess, guess
    for _ in range(60):
        lo = 1.0 + (lo - 1.0) * 0.7 if lo > 1.0 else lo * 0.9
        if miss(lo) < 0:
            break
    for _ in range(60):
        hi = 1.0 + (hi - 1.0) * 1.5
        if miss(hi) > 0:
            break
    if not miss(lo) < 0 < miss(hi):
        raise ArithmeticError(f"pre-stretch equilibrium not found at delta = {delta}, delta_o = {delta_o}: no "
                              "slope at the inner edge reaches r(Re) = Rf"
                              + (" within the law's limit of extensibility" if has_limit(law) else ""))
    s0 = brentq(miss, lo, hi, xtol=1e-15, rtol=1e-15, maxiter=200)
    if not abs(miss(s0)) < 1e-8:  # brentq closed on the jump of a shot that stopped at the limit
        raise ArithmeticError(f"pre-stretch equilibrium not found at delta = {delta}, delta_o = {delta_o}: the "
                              "shots that reach r(Re) stop at the law's limit of extensibility")
    sol = _shoot(law, s0, delta_o, dense=True)
    coef = _collocate(law, lambda s: sol.sol(s)[0], delta, delta_o, dom)
    if coef is None:
        raise ArithmeticError(f"pre-stretch collocation did not converge at delta = {delta}, delta_o = {delta_o}")
    return coef


def _collocate(law, guess, delta, delta_o, dom):
    """Chebyshev series of the solution of the equilibrium by Newton on the collocation
    (:func:`_polish`) from the radius ``guess(rho)``; the degree is doubled from 32 until the
    series' tail is below 1e-14.  None when Newton does not converge or ``r'`` leaves
    ``(0, inf)``."""
    n = 32
    while True:
        s, d = _cheb_lobatto(n, dom)
        r = guess(s)
        r[0], r[-1] = delta, delta_o  # Lobatto points run from rho = Re down to Ro
        polished = _polish(law, s, r, d)
        if polished is None:
            return None
        r, y = polished
        t = (2 * s - dom[0] - dom[1]) / (dom[1] - dom[0])
        cr, cy = C.chebfit(t, r, n), C.chebfit(t, y, n)
        if np.abs(cr[-4:]).max() < 1e-14 * delta or n >= 256:
            return (C.chebtrim(cr, 1e-17), C.chebtrim(cy, 1e-17), dom)
        guess = lambda x, cr=cr: C.chebval((2 * x - dom[0] - dom[1]) / (dom[1] - dom[0]), cr)  # noqa: E731
        n *= 2


def _fit_coef(delta, delta_o, numeric_coef):
    """Least-squares coefficients ``A1..A5`` of Eq. (18) on 401 equispaced radii."""
    ref = Prestretch("numeric", Membrane(delta=delta, delta_o=delta_o), numeric_coef)  # radius(): geometry only
    s = np.linspace(delta_o, 1.0, 401)
    ls = np.log(s)
    basis = np.column_stack([ls, s**2 * ls, s**2, s, np.ones_like(s)])
    coef, *_ = np.linalg.lstsq(basis, ref.radius(s), rcond=None)
    return tuple(float(c) for c in coef)


def check_extensibility(membrane: Membrane) -> None:
    """Refuse a membrane whose outer edge alone is beyond the law's limit of extensibility.

    Raises
    ------
    ValueError
        When ``delta^2 + 2/delta - 3``, the least ``I1 - 3`` of the hoop stretch ``delta`` at
        the outer edge, is not below Gent's ``Jm``.
    """
    d = membrane.delta
    if extensibility(membrane.material, d * d + 2.0 / d) <= 0.0:  # the least I1 of the outer edge
        raise ValueError(f"Jm = {membrane.Jm!r} is invalid at delta = {d!r}: must exceed delta^2 + 2/delta - 3 = "
                         f"{d * d + 2.0 / d - 3.0:.6g}, the least I1 - 3 at the outer edge (no state within the "
                         "Gent law's limit of extensibility)")


def solve_prestretch(membrane: Membrane, kind: str = "numeric") -> Prestretch:
    """Solve the static pre-stretch of ``membrane`` with the chosen variant.

    Parameters
    ----------
    membrane : Membrane
        Geometry and material; only ``delta``, ``delta_o``, ``Re`` and the law with its
        constants (and ``C1``, ``h`` for stresses and traction) matter.
    kind : {"analytic", "numeric", "fit"}
        Eq. (21), Chebyshev collocation of the equilibrium (Eq. 15), or the Eq. (18) fit of the collocation
        solution.

    Returns
    -------
    Prestretch
    """
    if kind not in KINDS:
        raise ValueError(f"prestretch = {kind!r} is invalid: must be one of {', '.join(KINDS)}")
    check_extensibility(membrane)
    d, do = membrane.delta, membrane.delta_o
    if kind == "analytic":
        coef = _analytic_coef(d, do)
    elif kind == "numeric":
        coef = _numeric_coef(membrane.material, d, do)
    else:
        coef = _fit_coef(d, do, _numeric_coef(membrane.material, d, do))
    return Prestretch(kind, membrane, coef)
