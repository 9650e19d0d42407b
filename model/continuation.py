"""Pseudo-arclength continuation of periodic responses in ``Omega`` or ``P0`` (Figs. 14-17).

The branch of fixed points of the stroboscopic map (:class:`model.protocol.StroboscopicMap`,
e.g. the ROM's :class:`model.forced.ForcedMap`) is
followed in the scaled unknowns ``x = (S y / L, lambda / Lambda)`` (``S`` of
:func:`model.forced.state_scale` at the reference frequency, ``L`` = :data:`LENGTH`,
``Lambda`` = the length of the parameter range), so that arclength weighs a change of the
response and a change of the parameter alike.  The steps follow AUTO-07p/BifurcationKit:

* predictor ``x + ds t`` along the unit tangent ``t``;
* corrector: Newton on ``G(x) = S (P(y) - y) / L = 0`` plus the arclength condition
  ``t . (x - x_pred) = 0``, with the bordered Jacobian ``[[S (Phi - I) S^-1, dG/dmu], [t]]``
  (``Phi`` the monodromy matrix and ``dG/dmu`` from one integration of the RK4 variational
  equations, ``monodromy_parameter`` of the map);
* step control: a failed corrector or a tangent turning by more than :data:`MAX_TURN`
  halves ``ds``; a corrector converged in at most 3 iterations grows it by 1.5, up to
  ``ds_max``;
* test functions between consecutive points: the parameter component of the tangent
  (fold, saddle-node: a real multiplier crosses +1), ``det(Phi + I)`` (period doubling: a
  multiplier crosses -1) and ``Re prod_{i<j} (mu_i mu_j - 1)`` restricted to a complex pair
  (Neimark-Sacker: a pair crosses the unit circle).  A sign change is located by the secant
  (Illinois) method on the arclength from the previous point, each evaluation a corrector
  solve on the same hyperplane, until the arclength changes by less than 1e-10 (a fold's
  parameter value is then exact to ~1e-12 relative, the test function being quadratic in it);
  the located point is inserted into the branch.

A fourth test, ``det(Phi - I)``, changes sign at folds and at symmetry-breaking branch
points of the axisymmetric block itself (a symmetric response, ``q(t + T/2) = -q(t)``, giving
way to an asymmetric one); where it changes sign without the fold test, a branch point of
family 0 is located.

With asymmetric mode families (:mod:`model.families`) the multipliers of each family's
block are computed at every point of the axisymmetric branch, and three more test functions
per family are watched: ``det(Phi_n - I)`` (a real multiplier crosses +1: a
symmetry-breaking branch point, the pitchfork of the O(2)-symmetric membrane),
``det(Phi_n + I)`` (period doubling) and the Neimark-Sacker test of the block.  They are
located like the others; the point records the family's wave number ``n``.

A bifurcation detected but not located is recorded in :attr:`Branch.unlocated`: where a
corrector of the locator fails, and where a complex pair crosses the unit circle without a
sign change of the NS test to locate -- its sign is the parity of the complex pairs outside the
circle, which a pair meeting on the real axis in the same step flips back -- told from the
number of multipliers outside the circle (:func:`_unbracketed_crossings`).

The branch ends when the parameter leaves ``[min(start, stop), max(start, stop)]`` (the last
point is placed exactly on the bound), after ``max_points`` points, or when ``ds`` falls
below ``ds_min``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numba as nb
import numpy as np

from .families import Family
from .protocol import PARAMETERS, StroboscopicMap, sorted_multipliers
from .shooting import shoot

#: Length scale ``L`` (m) of the scaled displacements.
LENGTH = 0.05
#: Largest angle (rad) between consecutive tangents before a step is rejected.
MAX_TURN = 0.3
#: Newton iterations of a corrector retried while a bifurcation point is located (near a
#: singular point of the continued problem Newton converges linearly).
SINGULAR_MAX_ITER = 40
#: How far from the unit circle a located point's largest multiplier may lie and still bound
#: an unstable interval (:func:`unstable_intervals`): the accuracy of a located branch point of
#: the axisymmetric block, the least accurate kind (8e-6 in ``tests/test_symmetry_breaking.py``,
#: up to 3e-4 on the Fig. 14a runs with u = v = 0 held), with a margin; a point where another
#: multiplier is already outside lies further from the circle than that.
LOCATED_TOL = 1e-3
#: Labels of the points of a branch.
REGULAR, FOLD, PERIOD_DOUBLING, NEIMARK_SACKER, BRANCH_POINT = 0, 1, 2, 3, 4
KIND_NAMES = ("regular", "fold", "period_doubling", "neimark_sacker", "branch_point")
#: Their names in figures and reports.
KIND_LABELS = ("regular", "saddle-node", "period doubling", "Neimark-Sacker", "branch point")


@dataclass
class Branch:
    """A continued branch of periodic responses.

    Attributes
    ----------
    parameter : str
        ``"Omega"`` or ``"P0"``.
    value : (N,) array
        Parameter along the branch (rad s-1 or Pa).
    state : (N, 2K) array
        ``y(0)`` of each response.
    amplitude : (N,) array
        ``max_t |w(0.5 Re, 0, t)|`` (m).
    multipliers : (N, 2K) complex array
        Floquet multipliers, sorted by decreasing modulus.
    stable : (N,) bool array
        All multipliers, the families' included, inside the unit circle (False at located
        bifurcation points).
    kind : (N,) int array
        :data:`REGULAR`, :data:`FOLD`, :data:`PERIOD_DOUBLING`, :data:`NEIMARK_SACKER` or
        :data:`BRANCH_POINT`.
    family : (N,) int array
        Wave number of the block a located point belongs to: 0 for the axisymmetric block
        (and at regular points), ``n`` for a point of the family ``n``.
    family_multipliers : (N, F, 2 M_max) complex array
        Multipliers of each family's block (the order of ``families``), by decreasing
        modulus, NaN padded to the largest block; ``(N, 0, 0)`` without families.
    complete : bool
        The branch reached the end of the parameter range.
    message : str
        Why the continuation stopped.
    unlocated : tuple of (int, int, float, float)
        The bifurcations detected between two neighbouring points but not located -- a test
        function changed sign and a corrector failed (or the step was the last one
        ``max_points`` leaves room for), or a complex pair crossed the unit circle
        with no NS point located in the step (:func:`_unbracketed_crossings`): ``(kind, n,
        value_a, value_b)``, the kind, the wave number of its block (0: axisymmetric) and the
        parameter at the two points.  The bifurcation lies between them; intervals bounded by
        it are known to that spacing.
    """

    parameter: str
    value: np.ndarray
    state: np.ndarray
    amplitude: np.ndarray
    multipliers: np.ndarray
    stable: np.ndarray
    kind: np.ndarray
    family: np.ndarray
    family_multipliers: np.ndarray
    complete: bool
    message: str
    unlocated: tuple = ()

    def special(self, kind: int) -> np.ndarray:
        """Indices of the points of type ``kind`` (e.g. :data:`FOLD`)."""
        return np.flatnonzero(self.kind == kind)

    def unstable_intervals(self, family: int, end: int | None = None) -> list[tuple[float, float]]:
        """:func:`unstable_intervals` of family number ``family`` (an index into the
        ``families`` of the continuation) over points ``0..end-1`` (default: all)."""
        return unstable_intervals(self.value[:end], np.nanmax(np.abs(self.family_multipliers[:end, family]), axis=1))


def resonant_end(kind) -> int:
    """Number of points of a branch in ``Omega`` from its start up to and including its
    first saddle-node: the resonant stretch of a hardening resonance continued from below.
    ``kind`` is the branch's point types (all points when there is no saddle-node)."""
    folds = np.flatnonzero(np.asarray(kind) == FOLD)
    return int(folds[0]) + 1 if folds.size else len(kind)


def unstable_points(modulus) -> np.ndarray:
    """Points whose largest multiplier ``modulus`` lies outside the unit circle (beyond the
    ~1e-10 to which located points sit on it)."""
    return np.asarray(modulus) > 1.0 + 1e-9


def unstable_intervals(value, modulus, located=None) -> list[tuple[float, float]]:
    """Parameter intervals along a branch where the largest multiplier ``modulus`` exceeds 1.

    An interval runs between the points that bound a run of unstable points: the located
    bifurcation points where the run starts and ends (modulus 1 to ~1e-10), or the ends of
    the branch.  ``value`` and ``modulus`` are per point, in branch order.  ``located``
    (bool per point, optional): the block's own located points; one whose largest modulus
    is within :data:`LOCATED_TOL` of 1 is a bound, not an unstable point (a branch point of
    the axisymmetric block is located only to ~1e-4: :func:`locate`), one with another
    multiplier already outside stays unstable.
    """
    unstable = unstable_points(modulus)
    if located is not None:
        unstable &= ~(np.asarray(located, dtype=bool) & (np.abs(np.asarray(modulus) - 1.0) < LOCATED_TOL))
    out = []
    i = 0
    while i < unstable.size:
        if unstable[i]:
            j = i
            while j + 1 < unstable.size and unstable[j + 1]:
                j += 1
            out.append((float(value[max(i - 1, 0)]), float(value[min(j + 1, unstable.size - 1)])))
            i = j + 1
        else:
            i += 1
    return out


class _Problem:
    """The scaled fixed-point problem ``G(x) = 0`` of one continuation."""

    def __init__(self, fmap, parameter, start, stop, families=()):
        self.fmap, self.parameter, self.families = fmap, parameter, tuple(families)
        self.start, self.stop = start, stop
        self.span = abs(stop - start)
        self.lo, self.hi = min(start, stop), max(start, stop)
        self.s = fmap.state_scale(None if parameter == "P0" else 0.5 * (start + stop)) / LENGTH
        self.n = 2 * fmap.dof
        self._ratio = self.s[:, None] / self.s[None, :]  # dG/dy = (s_i / s_j) (Phi - I)_ij

    def lam(self, x):
        return self.start + x[-1] * self.span

    def unpack(self, x):
        return x[:-1] / self.s, self.lam(x)

    def pack(self, y, lam):
        return np.append(self.s * y, (lam - self.start) / self.span)

    def at(self, lam) -> StroboscopicMap:
        """The stroboscopic map at parameter value ``lam``."""
        return self.fmap.varied(self.parameter, lam)

    def evaluate(self, x):
        """``G(x)``, its Jacobian ``(n, n+1)`` and the monodromy matrix."""
        y, lam = self.unpack(x)
        yT, phi, dparam = self.at(lam).monodromy_parameter(y, self.parameter)
        g, jac = _scaled_residual(self.s, self.span, self._ratio, y, yT, phi, dparam)
        return g, jac, phi

    def family_blocks(self, x, which=None):
        """Monodromy blocks of the families (or of family number ``which`` only) at the
        corrected point ``x``."""
        y, lam = self.unpack(x)
        f = self.at(lam)
        chosen = self.families if which is None else (self.families[which],)
        return [f.family_monodromy(y, fam) for fam in chosen]

    def tangent(self, jac, previous):
        """Unit null vector of ``jac`` with a positive projection on ``previous``."""
        return unit_tangent(jac, previous)

    def correct(self, x0, normal, anchor, sigma, tol, max_iter=8):
        """Newton on ``G(x) = 0``, ``normal . (x - anchor) = sigma``; ``(x, jac, phi, iters)`` or None."""
        res = bordered_newton(self.evaluate, x0, normal, anchor, sigma, tol, max_iter)
        if res is None:
            return None
        x, (_, jac, phi), it = res
        return x, jac, phi, it


def _pd_test(phi):
    return float(np.linalg.det(phi + np.eye(phi.shape[0])))


def _ns_test(mu):
    # Re prod_{i<j} (mu_i mu_j - 1) over the complex multipliers only (a real pair with
    # mu_i mu_j = 1 is a neutral saddle, not a bifurcation); +1 when there is no pair.
    c = mu[np.abs(mu.imag) > 1e-12 * np.maximum(1.0, np.abs(mu))]
    out = 1.0 + 0j
    for i in range(c.size):
        for j in range(i + 1, c.size):
            out *= c[i] * c[j] - 1.0
    return float(out.real)


def _unbracketed_crossings(values, new_values, handled) -> list[tuple[int, object]]:
    """``(n, block)`` of the blocks where a complex pair crossed the unit circle between two
    points without an NS point located there, from the test tuples of the two points
    (``(kind, n, block, value, outside)``, :func:`_outside` for the NS tests) and the set
    ``handled`` of the blocks whose NS test the step located, or tried to.

    The multipliers outside the circle change in number by one per real crossing, which the
    block's branch-point and period-doubling tests show by a sign change each (a fold's
    crossing at +1 by the branch-point test), and by two per pair crossing: a change larger
    than the real crossings is a pair that crossed.  The NS test alone can miss it -- its sign
    is the parity of the complex pairs outside, which a pair meeting on the real axis inside
    the circle, or leaving it, flips back in the same step.  Counts cannot tell every case: two
    pairs crossing opposite ways, or a pair crossing out while a real multiplier crosses in,
    leave the number as it was."""
    real: dict[object, int] = {}
    change: dict[object, tuple[int, int]] = {}
    for (kind, n, block, a, outside_a), (*_, b, outside_b) in zip(values, new_values):
        if kind in (BRANCH_POINT, PERIOD_DOUBLING) and a * b < 0:
            real[block] = real.get(block, 0) + 1
        elif kind == NEIMARK_SACKER:
            change[block] = (n, outside_b[1] - outside_a[1])
    return [(n, block) for block, (n, d) in change.items() if block not in handled and abs(d) > real.get(block, 0)]


def _outside(mu) -> tuple[int, int]:
    """How many complex multipliers (those :func:`_ns_test` takes) lie outside the unit
    circle, and how many multipliers in all: a Neimark-Sacker point changes both by two, a
    complex pair meeting on the real axis outside the circle only the first, a real
    multiplier crossing the circle only the second, by one."""
    c = mu[np.abs(mu.imag) > 1e-12 * np.maximum(1.0, np.abs(mu))]
    return int(np.count_nonzero(np.abs(c) > 1.0)), int(np.count_nonzero(np.abs(mu) > 1.0))


def continue_orbits(fmap: StroboscopicMap, parameter: str, start: float, stop: float, guess=None,
                    ds: float = 0.01, ds_min: float = 1e-6, ds_max: float = 0.05,
                    max_points: int = 400, tol: float = 1e-10,
                    families: Sequence[Family] = (), switch=None) -> Branch:
    """Follow the periodic responses of the forced ROM from ``start`` to ``stop``.

    Parameters
    ----------
    fmap : StroboscopicMap
        The stroboscopic map with the fixed ``Omega`` (rad s-1), ``P0`` (Pa) and damping,
        and the RK4 steps per period; the continued parameter is overridden by the branch.
    parameter : {"Omega", "P0"}
        The continuation parameter.
    start, stop : float
        Parameter range (rad s-1 or Pa); the branch starts at ``start`` from the response
        that :func:`model.shooting.shoot` finds from ``guess``.
    guess : (2K,) array, optional
        Initial guess at ``start`` (default: rest, which converges to the unique small
        response away from resonance and at ``P0 = 0``).
    ds, ds_min, ds_max : float
        Initial, smallest and largest arclength step in the scaled unknowns (a unit
        parameter step is the whole range; a unit state step is :data:`LENGTH`).
    max_points : int
        Largest number of points (located bifurcation points included).
    tol : float
        Corrector tolerance on the scaled unknowns.
    families : sequence of Family
        Asymmetric mode families (:func:`model.families.build_family` for the axisymmetric
        ROM of ``fmap``) whose stability is followed along the branch.
    switch : (state, value, direction), optional
        Branch switching: start at the bifurcation point ``(state, value)`` (inside
        ``[start, stop]``; recorded as the first point, a :data:`BRANCH_POINT`) instead of
        at ``start``, and take the first step along the state ``direction`` (the null vector
        of the bifurcating block) at fixed parameter; the new branch is then followed away
        from the point until the parameter leaves ``[start, stop]``
        (:func:`model.switching.follow_bifurcated_branch`).

    Returns
    -------
    Branch
        Every point computed; ``complete`` is False when the range end was not reached.
    """
    if parameter not in PARAMETERS:
        raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(PARAMETERS)}")
    if not (np.isfinite(start) and np.isfinite(stop)) or start == stop:
        raise ValueError(f"(start, stop) = ({start!r}, {stop!r}) is invalid: need two different finite values")
    if parameter == "Omega" and min(start, stop) <= 0:
        raise ValueError(f"(start, stop) = ({start!r}, {stop!r}) is invalid: Omega must stay > 0")
    if not 0 < ds_min <= ds <= ds_max:
        raise ValueError(f"(ds_min, ds, ds_max) = ({ds_min}, {ds}, {ds_max}) is invalid: need 0 < ds_min <= ds <= ds_max")
    if max_points < 2:
        raise ValueError(f"max_points = {max_points} is invalid: must be >= 2")
    prob = _Problem(fmap, parameter, float(start), float(stop), families)
    width = max((f.size for f in prob.families), default=0)
    pts: list[tuple] = []
    unlocated: list[tuple[int, int, float, float]] = []

    def record(x, phi, kind, family=0, blocks=None):
        y, lam = prob.unpack(x)
        mu = sorted_multipliers(phi)
        fam_mu = np.full((len(prob.families), width), np.nan + 0j)
        for i, block in enumerate(prob.family_blocks(x) if blocks is None else blocks):
            fam_mu[i, :block.shape[0]] = sorted_multipliers(block)
        moduli = np.concatenate([np.abs(mu), np.abs(fam_mu[~np.isnan(fam_mu)])])
        stable = kind == REGULAR and bool(moduli.max() < 1.0)
        amp = prob.at(lam).amplitude(y)
        pts.append((lam, y, amp, mu, stable, kind, family, fam_mu))

    def finish(complete, message):
        lam, y, amp, mu, st, kind, fam, fam_mu = (list(v) for v in zip(*pts))
        return Branch(parameter, np.array(lam), np.array(y), np.array(amp), np.array(mu),
                      np.array(st, dtype=bool), np.array(kind, dtype=np.int8), np.array(fam, dtype=np.int16),
                      np.array(fam_mu).reshape(len(pts), len(prob.families), width), complete, message,
                      tuple(unlocated))

    def tests(t, phi, blocks):
        # (kind, n, block index (None: axisymmetric), value, outside): fold, symmetry-breaking
        # branch point, PD, NS of the axisymmetric block, then BP, PD, NS of each family;
        # `outside` (NS only, (0, 0) otherwise): the complex multipliers and all multipliers
        # outside the unit circle (_outside)
        def ns(block_phi):
            mu = sorted_multipliers(block_phi)
            return _ns_test(mu), _outside(mu)
        none = (0, 0)
        out = [(FOLD, 0, None, t[-1], none), (BRANCH_POINT, 0, None, _bp_test(phi), none),
               (PERIOD_DOUBLING, 0, None, _pd_test(phi), none), (NEIMARK_SACKER, 0, None, *ns(phi))]
        for i, (fam, block) in enumerate(zip(prob.families, blocks)):
            out += [(BRANCH_POINT, fam.n, i, _bp_test(block), none),
                    (PERIOD_DOUBLING, fam.n, i, _pd_test(block), none), (NEIMARK_SACKER, fam.n, i, *ns(block))]
        return out

    e = np.zeros(prob.n + 1)
    e[-1] = 1.0
    if switch is None:
        first = shoot(prob.at(float(start)), np.zeros(prob.n) if guess is None else guess)
        x = prob.pack(first.state, float(start))
        g, jac, phi = prob.evaluate(x)
        blocks = prob.family_blocks(x)
        record(x, phi, REGULAR, blocks=blocks)
        if not first.converged:
            return finish(False, f"no periodic response found at {parameter} = {start}")
        t = prob.tangent(jac, e)
    else:
        state, value, direction = switch
        anchor = prob.pack(np.asarray(state, dtype=float), float(value))
        _, _, phi = prob.evaluate(anchor)
        record(anchor, phi, BRANCH_POINT)
        d = np.append(prob.s * np.asarray(direction, dtype=float), 0.0)
        d /= np.linalg.norm(d)
        res = None
        while res is None and ds >= ds_min:
            res = prob.correct(anchor + ds * d, d, anchor, ds, tol)
            ds = ds if res is not None else 0.5 * ds
        if res is None:
            raise RuntimeError(f"branch switching at {parameter} = {value:.9g}: no bifurcated orbit found along "
                               f"the direction given (step fell below ds_min = {ds_min})")
        x, jac, phi, _ = res
        blocks = prob.family_blocks(x)
        record(x, phi, REGULAR, blocks=blocks)
        t = prob.tangent(jac, d)
    values = tests(t, phi, blocks)
    while len(pts) < max_points:
        res, t_new, ds = step(prob.correct, prob.tangent, x, t, ds, ds_min, tol)
        if res is None:
            return finish(False, f"step size fell below ds_min = {ds_min} at {parameter} = {prob.lam(x):.9g}")
        x_new, jac, phi, iters = res
        lam_new = prob.lam(x_new)
        if not prob.lo <= lam_new <= prob.hi:
            bound = prob.hi if lam_new > prob.hi else prob.lo
            sigma = (bound - prob.lam(x)) / (lam_new - prob.lam(x))
            end = prob.correct(x + sigma * (x_new - x), e, prob.pack(np.zeros(prob.n), bound), 0.0, tol)
            if end is None:
                return finish(False, f"could not place the last point on {parameter} = {bound}")
            record(end[0], end[2], REGULAR)
            return finish(True, f"reached {parameter} = {bound}")
        blocks = prob.family_blocks(x_new)
        new_values = tests(t_new, phi, blocks)
        found = []
        handled = set()  # the blocks whose NS test this step located, or tried to
        fold_here = values[0][3] * new_values[0][3] < 0
        for (kind, n, block, a, outside_a), (*_, b, outside_b) in zip(values, new_values):
            # det(Phi - I) changes sign at a fold too: only without one is it a branch point;
            # the NS test also changes sign where a complex pair meets on the real axis (it
            # drops out of the product): only with a change in the complex multipliers outside
            # the circle is it tried, and only a zero with a pair on the circle is kept
            if kind == NEIMARK_SACKER and outside_a[0] == outside_b[0]:
                continue
            if a * b < 0 and not (kind == BRANCH_POINT and n == 0 and fold_here):
                # the last step before max_points has no room for a located point
                loc = (_locate(prob, kind, block, x, t, ds, a, b, tol, x_new)
                       if len(pts) + len(found) < max_points - 1 else None)
                if loc is None:
                    unlocated.append((kind, n, prob.lam(x), lam_new))
                elif kind != NEIMARK_SACKER or _complex_pair_on_circle(prob, block, *loc[1:3]):
                    found.append(loc + (n,))
                else:
                    continue  # a pair meeting on the real axis: no NS point
                if kind == NEIMARK_SACKER:
                    handled.add(block)
        for n, _ in _unbracketed_crossings(values, new_values, handled):
            unlocated.append((NEIMARK_SACKER, n, prob.lam(x), lam_new))
        for sigma, xs, phis, kind, n in sorted(found, key=lambda f: f[0]):
            record(xs, phis, kind, n)
        record(x_new, phi, REGULAR, blocks=blocks)
        x, t, values = x_new, t_new, new_values
        ds = min(ds_max, ds * 1.5) if iters <= 3 else ds
    return finish(False, f"max_points = {max_points} reached at {parameter} = {prob.lam(x):.9g}")


def _bp_test(phi):
    return float(np.linalg.det(phi - np.eye(phi.shape[0])))


def _test_value(prob, kind, block, jac, phi, x, normal):
    # The test function of ``kind`` on the axisymmetric block (``block`` None) or on the
    # family number ``block``, at a corrected point.
    if kind == FOLD:
        return prob.tangent(jac, normal)[-1]
    b = phi if block is None else prob.family_blocks(x, block)[0]
    if kind == BRANCH_POINT:
        return _bp_test(b)
    if kind == PERIOD_DOUBLING:
        return _pd_test(b)
    return _ns_test(sorted_multipliers(b))


def unit_tangent(jac, previous):
    """Unit null vector of ``jac`` (``(n, n+1)``) with a positive projection on ``previous``:
    the solution of ``[jac; previous] t = (0, ..., 0, 1)``, normalised."""
    rhs = np.zeros(jac.shape[0] + 1)
    rhs[-1] = 1.0
    t = _solve(np.vstack([jac, previous]), rhs)
    return t / np.linalg.norm(t)


@nb.njit(cache=True)
def _scaled_residual(s, span, ratio, y, yT, phi, dparam):
    """``G = s (P(y) - y)`` and its Jacobian ``[ratio (Phi - I) | s dP/dlambda span]`` in the
    scaled unknowns of :class:`_Problem`, in one compiled pass (eight numpy calls cost
    three times as much for the small systems of continuation)."""
    n = y.size
    if yT.size != n or dparam.size != n or phi.shape[0] != n or phi.shape[1] != n:
        raise ValueError("the map returned a state, monodromy matrix or parameter derivative of the wrong shape")
    g = np.empty(n)
    jac = np.empty((n, n + 1))
    for i in range(n):
        g[i] = s[i] * (yT[i] - y[i])
        for j in range(n):
            jac[i, j] = ratio[i, j] * phi[i, j] - (1.0 if i == j else 0.0)
        jac[i, n] = s[i] * dparam[i] * span
    return g, jac


@nb.njit(cache=True)
def _bordered_step(bordered, g, jac, normal, x, anchor, sigma):
    """The Newton step ``dx`` of ``[jac; normal] dx = -(G, normal . (x - anchor) - sigma)``;
    ``bordered`` is the work matrix (its last row holds ``normal``).  Raises
    ``np.linalg.LinAlgError`` like numpy when the matrix is singular."""
    n = g.size
    if bordered.shape[0] != n + 1 or jac.shape[0] != n or jac.shape[1] != n + 1:
        raise ValueError("the residual and its Jacobian do not match the unknowns")
    r = np.empty(n + 1)
    for i in range(n):
        r[i] = -g[i]
        for j in range(n + 1):
            bordered[i, j] = jac[i, j]
    r[n] = sigma - normal @ (x - anchor)
    return np.linalg.solve(bordered, r)


@nb.njit(cache=True)
def _solve(a, b):
    """``np.linalg.solve`` (LAPACK) through numba: a quarter of numpy's cost per call for
    the small bordered systems of continuation; raises ``np.linalg.LinAlgError`` alike."""
    return np.linalg.solve(a, b)


def bordered_newton(evaluate, x0, normal, anchor, sigma, tol, max_iter):
    """Newton on ``G(x) = 0`` together with ``normal . (x - anchor) = sigma``.

    ``evaluate(x)`` returns ``(G, dG/dx, *extra)``.  Converged when the step is below
    ``tol`` and ``|G|`` below ``1e3 tol``.

    Returns
    -------
    (x, evaluate(x), iterations) or None
        The iterate whose Newton step was below ``tol`` (it lies within about ``tol`` of
        the solution) with its evaluation, and the evaluations made; None when a linear
        solve fails, an iterate is not finite, or ``max_iter`` passes.
    """
    x = x0.copy()
    bordered = np.empty((x.size, x.size))
    bordered[-1] = normal
    for it in range(1, max_iter + 1):
        values = evaluate(x)
        g = values[0]
        try:
            dx = _bordered_step(bordered, g, values[1], normal, x, anchor, sigma)
        except np.linalg.LinAlgError:
            return None
        step2 = dx @ dx  # squared norms by dot products: a third of np.linalg.norm's cost here
        if not math.isfinite(step2):
            return None
        if step2 < tol * tol and g @ g < (1e3 * tol) ** 2:
            return x, values, it
        x = x + dx
    return None


def step(correct, tangent, x, t, ds, ds_min, tol):
    """One pseudo-arclength step from ``x`` along the unit tangent ``t``.

    ``correct(x0, normal, anchor, sigma, tol)`` solves the system on the hyperplane
    ``normal . (x - anchor) = sigma`` (a tuple whose second item is the Jacobian, or
    None); ``tangent(jac, previous)`` is the new unit tangent.  A failed corrector or a
    tangent turning by more than :data:`MAX_TURN` halves ``ds``, down to ``ds_min``.

    Returns
    -------
    (result, t_new, ds) : the corrector's result, the new tangent and the step used;
        ``(None, None, ds)`` when the step fell below ``ds_min``.
    """
    while ds >= ds_min:
        res = correct(x + ds * t, t, x, ds, tol)
        if res is not None:
            t_new = tangent(res[1], t)
            if t_new @ t >= np.cos(MAX_TURN):
                return res, t_new, ds
        ds *= 0.5
    return None, None, ds


def locate(correct, test, x, t, ds, fa, fb, tol, x_end=None, singular=False):
    """Zero of a test function between ``x`` (arclength 0) and the next point (``ds``).

    Illinois (modified regula falsi) on the arclength ``sigma`` along the hyperplanes
    ``t . (x' - x) = sigma`` (``correct`` as for :func:`step`, its result's first item the
    corrected point), until ``sigma`` changes by less than 1e-10 ``ds``; ``test(result)`` is
    the test function at a corrected point.  Each corrector starts on the chord between the
    corrected points that bracket the zero (``x`` and ``x_end``, the next point, at first;
    ``x + ds t`` without it): its error is of the order of the bracket squared, where the
    tangent's would stay of the order of ``ds`` squared.

    ``singular``: the zero is a branch point of the continued problem itself (a real
    multiplier of the axisymmetric block through +1 without a fold), where the bordered
    Jacobian is singular and Newton's basin shrinks with the distance to it.  A corrector that
    fails there is retried with :data:`SINGULAR_MAX_ITER` iterations (``correct`` must take
    ``max_iter``), and if it fails again the corrected iterate with the smallest ``|test|``
    is returned: inside the bracket, as close to the point as the correctors reached.

    Returns
    -------
    (sigma, result) or None
        The last corrected point (``singular``: the best one), or None when a corrector
        failed (``singular``: when the first one did).
    """
    a, b = 0.0, ds
    xa, xb = x, (x + ds * t if x_end is None else x_end)
    best, best_f = None, np.inf
    sigma_old = np.inf
    for _ in range(60):
        sigma = (a * fb - b * fa) / (fb - fa)
        guess = xa + (sigma - a) / (b - a) * (xb - xa)
        res = correct(guess, t, x, sigma, tol)
        if res is None and singular:
            res = correct(guess, t, x, sigma, tol, max_iter=SINGULAR_MAX_ITER)
        if res is None:
            return best if singular else None
        f = test(res)
        if not singular or abs(f) <= best_f:
            best, best_f = (sigma, res), abs(f)
        if f == 0.0 or abs(sigma - sigma_old) < 1e-10 * ds:
            break
        sigma_old = sigma
        if f * fb < 0:
            a, fa, xa = b, fb, xb
        else:
            fa *= 0.5
        b, fb, xb = sigma, f, res[0]
    return best


def _locate(prob, kind, block, x, t, ds, fa, fb, tol, x_end=None):
    """The zero of the test function of ``kind`` on ``block`` (see :func:`_test_value`)
    between ``x`` and the next point ``x_end``: ``(sigma, x', phi, kind)``, or None when a
    corrector failed."""
    found = locate(prob.correct, lambda res: _test_value(prob, kind, block, res[1], res[2], res[0], t),
                   x, t, ds, fa, fb, tol, x_end, singular=kind == BRANCH_POINT and block is None)
    if found is None:
        return None
    sigma, (xs, _, phi, _) = found
    return sigma, xs, phi, kind


def _complex_pair_on_circle(prob, block, xs, phi) -> bool:
    """Whether the located zero of an NS test on ``block`` at ``xs`` has a complex pair on the
    unit circle: a Neimark-Sacker point, and not where a complex pair meets on the real axis
    (the test's sign jumps there as the pair drops out of its product), which is discarded."""
    b = phi if block is None else prob.family_blocks(xs, block)[0]
    mu = sorted_multipliers(b)
    on_circle = np.abs(np.abs(mu) - 1.0) < 1e-6
    return bool(np.any(np.abs(mu[on_circle].imag) > 1e-8))


def cusp_from_folds(c, fold_value, fold_amplitude) -> tuple[float, float]:
    """Cusp where the two saddle-nodes of a branch merge, from fold pairs along ``c``.

    Near a cusp the amplitudes of the two folds differ like ``sqrt(c_cusp - c)``, so their
    squared difference is linear in ``c``: the cusp is where the straight line through
    that of the last two ``c`` values with two folds reaches zero, bounded by the first
    ``c`` with fewer folds; the fold value is the mean of the pair, extrapolated linearly
    to it.

    Parameters
    ----------
    c : (nc,) array
        Increasing values of the second parameter (e.g. damping, N s m-3).
    fold_value : (nc, F) array
        Parameter values at the folds of the branch at each ``c`` (NaN padded).
    fold_amplitude : (nc, F) array
        Amplitudes (m) at those folds.

    Returns
    -------
    c_cusp, value_cusp : float
        NaN when the folds do not merge inside the range of ``c`` or do not approach.
    """
    c = np.asarray(c, dtype=float)
    value = np.asarray(fold_value, dtype=float)
    amp = np.asarray(fold_amplitude, dtype=float)
    two = np.isfinite(value[:, 0]) & np.isfinite(value[:, 1])
    idx = np.flatnonzero(two)
    if idx.size < 2 or idx[-1] == c.size - 1:
        return np.nan, np.nan
    i, j = idx[-2], idx[-1]
    d2 = np.abs(amp[[i, j], 0] - amp[[i, j], 1]) ** 2
    mean = value[[i, j], :2].mean(axis=1)
    if d2[1] >= d2[0]:
        return np.nan, np.nan
    cc = c[j] + d2[1] * (c[j] - c[i]) / (d2[0] - d2[1])
    cc = min(cc, c[j + 1])
    return cc, mean[1] + (mean[1] - mean[0]) * (cc - c[j]) / (c[j] - c[i])


def stable_amplitudes_at(value, amplitude, stable, x) -> np.ndarray:
    """Amplitudes of the stable parts of a branch at parameter value ``x``.

    Linear interpolation between consecutive stable points that bracket ``x``.

    Parameters
    ----------
    value, amplitude : (N,) arrays
        Parameter and amplitude along the branch (NaN padding is ignored).
    stable : (N,) array
        1 where the point is stable.
    x : float
        Parameter value.

    Returns
    -------
    (S,) array
        One amplitude per stable segment crossing ``x``, in branch order.
    """
    value, amplitude, stable = (np.asarray(a) for a in (value, amplitude, stable))
    ok = np.isfinite(value)
    bx, ba, st = value[ok], amplitude[ok], stable[ok]
    found = []
    for i in range(bx.size - 1):
        if st[i] == 1 and st[i + 1] == 1 and (bx[i] - x) * (bx[i + 1] - x) <= 0 and bx[i] != bx[i + 1]:
            found.append(ba[i] + (ba[i + 1] - ba[i]) * (x - bx[i]) / (bx[i + 1] - bx[i]))
    return np.array(found)
