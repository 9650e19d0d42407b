"""Two-parameter continuation of bifurcation points of periodic responses, and cusps.

A bifurcation point of the branch of periodic responses in a parameter ``p`` (``P0`` or
``Omega``) is a fixed point of the stroboscopic map ``P(y; p, q)``
(:class:`model.protocol.StroboscopicMap`) where one scalar condition on the monodromy matrix
holds.
As a second parameter ``q`` (``c``, ``P0`` or ``Omega``) varies, such points form a curve in
the ``(q, p)`` plane: the solutions of the extended system (AUTO-07p's continuation of
folds, period doublings and tori, ISW = 2, here in the standard rather than the minimally
augmented form)::

    P(y; p, q) - y = 0                 (2K equations)
    condition(y; p, q) = 0             (1 equation)

in the unknowns ``(y, p, q)``, with the condition

* fold (saddle-node): ``det(Phi - I)`` (``Phi = dP/dy``);
* branch point of an asymmetric family (:mod:`model.families`): ``det(Phi_n - I)``;
* period doubling: ``det(B + I)`` for ``B = Phi`` or a family's block ``Phi_n``;
* Neimark-Sacker: ``Re prod_{i<j} (mu_i mu_j - 1)`` over the complex multipliers of ``B``
  (``|mu|^2 - 1`` for a single pair),

followed by pseudo-arclength continuation in the scaled unknowns
``(S y / L, p / span_p, q / span_q)``.  Its Jacobian is formed by central differences
(2 (2K + 2) evaluations of the map and its monodromy per Newton step: cheap for the few
modes of a ROM).  Where the curve turns back in ``q`` it is located as the zero of the
``q``-component of the unit tangent by the secant (Illinois) method on the arclength, as
:mod:`model.continuation` locates folds; on a fold curve such a turn is a **cusp** (two
folds of a hysteresis loop merge), on a branch-point curve the end of an instability
interval.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .continuation import (BRANCH_POINT, FOLD, KIND_NAMES, LENGTH, NEIMARK_SACKER, PERIOD_DOUBLING, _ns_test,
                           bordered_newton, continue_orbits, locate, step, unit_tangent)
from .families import Family
from .protocol import StroboscopicMap, sorted_multipliers


@dataclass
class BifurcationCurve:
    """Bifurcation points of the periodic responses followed in two parameters.

    Attributes
    ----------
    kind : int
        :data:`model.continuation.FOLD`, ``BRANCH_POINT``, ``PERIOD_DOUBLING`` or
        ``NEIMARK_SACKER``.
    family : int
        Wave number of the block the condition is on (0: the axisymmetric block).
    parameters : tuple of str
        ``(p, q)``: the point's own parameter and the second one.
    p, q : (N,) arrays
        Parameter values along the curve (SI units of each).
    state : (N, 2K) array
        ``y(0)`` of the orbit.
    amplitude : (N,) array
        ``max_t |w(0.5 Re, 0, t)|`` (m).
    turns : (C, 2) array
        ``(q, p)`` of each point where the curve turns back in ``q``, in curve order.
    complete : bool
        The curve reached the end of the ``q`` range (or came back to its start value).
    message : str
        Why the continuation stopped.
    """

    kind: int
    family: int
    parameters: tuple[str, str]
    p: np.ndarray
    q: np.ndarray
    state: np.ndarray
    amplitude: np.ndarray
    turns: np.ndarray
    complete: bool
    message: str

    @property
    def cusp(self) -> np.ndarray:
        """The turns of a fold curve: its cusps ``(q, p)`` (empty for other kinds)."""
        return self.turns if self.kind == FOLD else np.zeros((0, 2))


class _CurveSystem:
    """The scaled extended system of a curve of bifurcation points."""

    def __init__(self, fmap: StroboscopicMap, p: str, q: str, p_span: float, q_range: tuple[float, float],
                 kind: int = FOLD, family: Family | None = None, rebuild=None):
        if kind not in (FOLD, BRANCH_POINT, PERIOD_DOUBLING, NEIMARK_SACKER):
            raise ValueError(f"kind = {kind!r} is invalid: must be FOLD, BRANCH_POINT, PERIOD_DOUBLING or NEIMARK_SACKER")
        if kind == FOLD and family is not None:
            raise ValueError(f"family = {family!r} is invalid for a fold curve: folds are of the axisymmetric block")
        self.fmap, self.p, self.q = fmap, p, q
        self.kind, self.family = kind, family
        self.rebuild = None if rebuild is None else functools.lru_cache(maxsize=16)(rebuild)
        self.p_span = p_span
        self.q_lo, self.q_hi = min(q_range), max(q_range)
        self.q_span = self.q_hi - self.q_lo
        self.s = fmap.state_scale() / LENGTH
        self.n = 2 * fmap.dof

    def pack(self, y, p, q):
        return np.concatenate([self.s * y, [p / self.p_span, q / self.q_span]])

    def unpack(self, x):
        return x[:self.n] / self.s, x[self.n] * self.p_span, x[self.n + 1] * self.q_span

    def at(self, p, q) -> StroboscopicMap:
        return self.at_family(p, q)[0]

    def at_family(self, p, q) -> tuple[StroboscopicMap, Family | None]:
        """The map at ``(p, q)`` and the family block there (rebuilt when ``q`` is a membrane
        parameter)."""
        if self.rebuild is None:
            return self.fmap.varied(self.p, p).varied(self.q, q), self.family
        fmap, family = self.rebuild(float(q))
        return fmap.varied(self.p, p), (None if self.family is None else family)

    def condition(self, fmap, y, phi, family=None) -> float:
        """The scalar condition of the curve's kind at the orbit ``y`` of ``fmap``."""
        if family is None:
            block = phi
        else:
            block = fmap.family_monodromy(y, family)
        eye = np.eye(block.shape[0])
        if self.kind in (FOLD, BRANCH_POINT):
            return float(np.linalg.det(block - eye))
        if self.kind == PERIOD_DOUBLING:
            return float(np.linalg.det(block + eye))
        return _ns_test(sorted_multipliers(block))

    def residual(self, x):
        y, p, q = self.unpack(x)
        fmap, family = self.at_family(p, q)
        yT, phi = fmap.monodromy(y)
        return np.append(self.s * (yT - y), self.condition(fmap, y, phi, family))

    def jacobian(self, x, h=1e-7):
        cols = []
        for i in range(x.size):
            e = np.zeros(x.size)
            e[i] = h
            cols.append((self.residual(x + e) - self.residual(x - e)) / (2 * h))
        return np.column_stack(cols)

    def evaluate(self, x):
        """The residual and its Jacobian (for :func:`model.continuation.bordered_newton`)."""
        return self.residual(x), self.jacobian(x)

    def tangent(self, jac, previous):
        return unit_tangent(jac, previous)

    def correct(self, x0, normal, anchor, sigma, tol, max_iter=10):
        """Newton on the system plus ``normal . (x - anchor) = sigma``; ``(x, jac)`` or None."""
        res = bordered_newton(self.evaluate, x0, normal, anchor, sigma, tol, max_iter)
        return None if res is None else (res[0], res[1][1])


def fold_at(fmap: StroboscopicMap, parameter: str, second: str, value: float, guess, p_guess: float,
            tol: float = 1e-11, kind: int = FOLD, family: Family | None = None) -> tuple[np.ndarray, float] | None:
    """The bifurcation point of ``kind`` (default: fold) near ``(guess, p_guess)`` at
    ``second = value``, by Newton on the extended system with ``second`` fixed.  Returns
    ``(y, p)`` or None."""
    sys_ = _CurveSystem(fmap, parameter, second, max(abs(p_guess), 1e-3), (value, value + 1.0), kind, family)
    x0 = sys_.pack(np.asarray(guess, float), p_guess, value)
    e = np.zeros(x0.size)
    e[-1] = 1.0
    res = sys_.correct(x0, e, x0, 0.0, tol)
    if res is None:
        return None
    y, p, _ = sys_.unpack(res[0])
    return y, p


def continue_folds(fmap: StroboscopicMap, parameter: str, second: str, start: float, stop: float,
                   p_range: tuple[float, float], max_points: int = 400, **steps) -> BifurcationCurve:
    """Follow the folds of the responses in ``parameter`` as ``second`` goes from ``start``.

    The curve starts at the first fold of the one-parameter branch in ``parameter`` over
    ``p_range`` at ``second = start`` (:func:`model.continuation.continue_orbits`) and is
    followed by :func:`continue_curve` (``steps``: its step and tolerance arguments).

    Parameters
    ----------
    fmap : StroboscopicMap
        The map with the fixed parameters and the RK4 steps per period.
    parameter : {"P0", "Omega"}
        The fold's own parameter.
    second : str
        The second parameter (different from ``parameter``): ``"P0"``, ``"Omega"`` or a
        constant of the map's damping law (:attr:`model.protocol.StroboscopicMap.parameters`).
    start, stop : float
        Range of ``second``.
    p_range : (float, float)
        Range of ``parameter`` for the starting one-parameter branch.
    max_points : int
        Largest number of points (cusps included).

    Returns
    -------
    BifurcationCurve
        With no point when the starting branch has no fold.
    """
    if parameter == second:
        raise ValueError(f"second = {second!r} is invalid: it must differ from parameter")
    branch = continue_orbits(fmap.varied(second, start), parameter, *p_range, ds_max=0.3, max_points=max_points)
    folds = branch.special(FOLD)
    if folds.size == 0:
        return BifurcationCurve(FOLD, 0, (parameter, second), np.zeros(0), np.zeros(0), np.zeros((0, 2 * fmap.dof)),
                                np.zeros(0), np.zeros((0, 2)), False,
                                f"no fold on the {parameter} branch at {second} = {start}")
    return continue_curve(fmap, parameter, second, start, stop, branch.state[folds[0]], branch.value[folds[0]],
                          abs(p_range[1] - p_range[0]), max_points=max_points, **steps)


def continue_curve(fmap: StroboscopicMap, parameter: str, second: str, start: float, stop: float, state, value: float,
                   p_span: float, kind: int = FOLD, family: Family | None = None, ds: float = 0.02,
                   ds_min: float = 1e-7, ds_max: float = 0.05, max_points: int = 400,
                   tol: float = 1e-10, rebuild=None) -> BifurcationCurve:
    """Follow a curve of bifurcation points of ``kind`` from ``(state, value)`` at ``second = start``.

    The curve is followed towards ``stop``; it ends at the first point past either end of
    ``[start, stop]`` (the far end, or back past ``start`` after a turn), after
    ``max_points`` points, or when the step falls below ``ds_min``.

    Parameters
    ----------
    fmap : StroboscopicMap
        The map with the fixed parameters and the RK4 steps per period.
    parameter : {"P0", "Omega"}
        The point's own parameter (the one of the branch it was located on).
    second : str
        ``"P0"``, ``"Omega"``, a constant of the map's damping law (``"c"``, ``"zeta"``, ...:
        :attr:`model.protocol.StroboscopicMap.parameters`) or a membrane parameter (e.g. ``"delta"``,
        with ``rebuild``)
        The second parameter (different from ``parameter``).
    start, stop : float
        Range of ``second``.
    state : (2K,) array
        Orbit ``y(0)`` at the starting point (refined by Newton first).
    value : float
        ``parameter`` at the starting point.
    p_span : float
        Scale of ``parameter`` in the arclength (e.g. the length of the branch's range).
    kind : int
        :data:`model.continuation.FOLD` (default), ``BRANCH_POINT``, ``PERIOD_DOUBLING`` or
        ``NEIMARK_SACKER``.
    family : Family, optional
        The asymmetric family the condition is on (None: the axisymmetric block, whose
        branch points, det(Phi - I) = 0 without a fold, break the time symmetry).
    ds, ds_min, ds_max : float
        Arclength steps in the scaled unknowns.
    max_points : int
        Largest number of points (turns included).
    tol : float
        Newton tolerance on the scaled unknowns.
    rebuild : callable, optional
        For a membrane parameter ``second``: ``value -> (StroboscopicMap, Family or None)``, the map
        (with ``fmap``'s forcing and steps) and the family block rebuilt at that value; called
        once per value met (cached).

    Returns
    -------
    BifurcationCurve
    """
    if parameter == second:
        raise ValueError(f"second = {second!r} is invalid: it must differ from parameter")
    if not 0 < ds_min <= ds <= ds_max:
        raise ValueError(f"(ds_min, ds, ds_max) = ({ds_min}, {ds}, {ds_max}) is invalid: need 0 < ds_min <= ds <= ds_max")
    if not (np.isfinite(start) and np.isfinite(stop)) or start == stop:
        raise ValueError(f"(start, stop) = ({start!r}, {stop!r}) is invalid: need two different finite values")
    if (second in fmap.parameters) == (rebuild is not None):
        raise ValueError(f"second = {second!r} is invalid here: a forcing or damping parameter "
                         f"({', '.join(fmap.parameters)}) takes no rebuild, a membrane parameter needs one")
    sys_ = _CurveSystem(fmap, parameter, second, p_span, (start, stop), kind, family, rebuild)
    x = sys_.pack(np.asarray(state, dtype=float), value, start)
    direction = np.sign(stop - start)
    e = np.zeros(x.size)
    e[-1] = direction
    res = sys_.correct(x, e, x, 0.0, tol)
    if res is None:
        raise RuntimeError(f"the {KIND_NAMES[kind]} point at {second} = {start} could not be refined")
    x, jac = res
    t = sys_.tangent(jac, e)
    pts, turns = [x], []

    def finish(complete, message):
        ys, ps, qs = zip(*(sys_.unpack(v) for v in pts))
        amp = [sys_.at(p, q).amplitude(y) for y, p, q in zip(ys, ps, qs)]
        return BifurcationCurve(kind, 0 if family is None else family.n, (parameter, second), np.array(ps),
                                np.array(qs), np.array(ys), np.array(amp), np.array(turns).reshape(-1, 2),
                                complete, message)

    while len(pts) < max_points:
        try:
            res, t_new, ds = step(sys_.correct, sys_.tangent, x, t, ds, ds_min, tol)
        except ArithmeticError as exc:  # a rebuild the model refuses there (e.g. its RK4 step)
            return finish(False, str(exc))
        if res is None:
            return finish(False, f"step size fell below ds_min = {ds_min}")
        x_new, jac = res
        q_new = sys_.unpack(x_new)[2]
        if t[-1] * t_new[-1] < 0 and len(pts) < max_points - 1:
            turn = _locate_turn(sys_, x, t, ds, t[-1], t_new[-1], tol)
            if turn is not None:
                _, p_c, q_c = sys_.unpack(turn)
                turns.append((q_c, p_c))
                pts.append(turn)
        pts.append(x_new)
        if not sys_.q_lo <= q_new <= sys_.q_hi:
            return finish(True, f"{second} left [{sys_.q_lo}, {sys_.q_hi}] at {q_new:.9g}")
        x, t = x_new, t_new
        ds = min(ds_max, ds * 1.5)
    return finish(False, f"max_points = {max_points} reached")


def _locate_turn(sys_, x, t, ds, fa, fb, tol):
    """The point between ``x`` and the next one where the second parameter's tangent
    component vanishes (the curve turns back in it), or None."""
    found = locate(sys_.correct, lambda res: sys_.tangent(res[1], t)[-1], x, t, ds, fa, fb, tol)
    return None if found is None else found[1][0]
