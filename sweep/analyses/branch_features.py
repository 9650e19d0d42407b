"""The optional features of the ``continuation`` analysis, one part each.

A feature reads its option of ``[continuation]`` (:mod:`sweep.analyses.continuation`
parses them with the functions here), declares its variables and coordinates once
(:meth:`BranchFeature.variables`, :meth:`BranchFeature.coords`) and computes them from the
continued branch (:meth:`BranchFeature.compute`), starting from the declared blanks
(:func:`sweep.analyses.base.blank_outputs`) so that what it does not reach stays padding:

* :data:`FAMILIES` -- the Floquet multipliers of the asymmetric families along the branch
  (``families``), and the block of each located point;
* :data:`FOLD_CURVE` -- the first saddle-node followed in a second parameter through its
  cusps (``fold_curve``, :func:`model.codim2.continue_folds`);
* :data:`BIFURCATION_CURVES` -- every located point followed in a second parameter
  (``bifurcation_curves``, :func:`model.codim2.continue_curve`);
* :data:`FAMILY_CHECK` -- time integration of the mixed ROMs against the families'
  multipliers (``family_check``, :func:`model.families.perturbation_growth`);
* :data:`TONGUES` -- the families' parametric thresholds at every point, measured and by
  first-order averaging (``tongues``, :func:`model.tongues.family_tongue`).

The standing waves of branch switching and the rotating waves are in
:mod:`sweep.analyses.wave_features`.

The outputs are described in the docstring of :mod:`sweep.analyses.continuation`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from model.codim2 import continue_curve, continue_folds
from model.continuation import KIND_NAMES, resonant_end
from model.families import GROWTH_LIMIT, floquet_start, perturbation_growth, symmetry_blocks
from model.lyapunov import UNSETTLED, Classification, classify, lyapunov_spectrum
from model.response import LYAPUNOV_BLOCKS
from model.tongues import family_tongue

from . import options as opt
from .base import GRID_KEYS, JobError, Variable, blank_outputs, check_keys
from .response import response_kind_attrs

#: Length of the ``cusp`` dimension (cusps of the fold curve, NaN padded).
MAX_CUSPS = 4
#: Largest arclength step of the bifurcation curves (scaled unknowns): along them the
#: orbit's phase turns while its amplitude barely changes, so steps are larger than on a
#: branch; the turning test (model.continuation.MAX_TURN) still bounds them.
CURVE_DS_MAX = 0.5
#: Length of the ``curve`` dimension (bifurcation curves, NaN padded).
MAX_CURVES = 16
#: Largest ``family_check.harmonics``: the mixed model on 0, n, ..., 6 n (the cost of the
#: classification's variational monodromies grows with about the cube of the harmonics).
MAX_CHECK_HARMONICS = 6
#: Largest number of values of ``family_check``.
MAX_CHECKS = 16
#: Longest period (forcing periods) the classification of ``family_check.classify`` looks
#: for (:func:`model.lyapunov.classify`); ``classify`` is at least twice it.
CHECK_MAX_PERIOD = 16
#: Standard errors by which the largest Lyapunov exponent of ``family_check.classify`` must
#: differ from zero to count as nonzero (:func:`model.lyapunov.classify`).
CHECK_SIGMAS = 3.0


def kind_attrs() -> dict:
    return {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
            "flag_meanings": "padding " + " ".join(KIND_NAMES)}


def _curve_point_coord(options) -> dict:
    return {"curve_point": (("curve_point",), np.arange(options.max_points, dtype=np.int32),
                            {"long_name": "index along a two-parameter curve", "units": "1"})}


@dataclass(frozen=True)
class BranchContext:
    """What the features compute from: the task's grid point, its map at ``start``, the
    branch in the map's coordinates (``branch``) and in the job's mode layout (``layout``,
    the same unless a mixed mode set was reduced by symmetry), the families and the
    analysis' options."""

    point: Any
    fmap: Any
    branch: Any
    layout: Any
    families: tuple
    options: Any


class BranchFeature:
    """One optional feature of the continuation (see the module docstring)."""

    def enabled(self, options) -> bool:
        """Whether the job asks for the feature."""
        raise NotImplementedError

    def variables(self, options) -> list[Variable]:
        """The feature's outputs (none when it is not enabled)."""
        raise NotImplementedError

    def coords(self, options) -> dict:
        """The coordinates of the feature's own dimensions."""
        return {}

    def compute(self, ctx: BranchContext) -> tuple[dict[str, np.ndarray], str]:
        """The outputs, and what went wrong ("" when nothing did)."""
        raise NotImplementedError


def by_symmetry(options) -> bool:
    """A mixed mode set (axisymmetric and other modes) without ``families``: continued on the
    axisymmetric subspace with family blocks."""
    axisymmetric, blocks = symmetry_blocks(options.modes)
    return options.families is None and bool(blocks) and bool(axisymmetric)


def family_radials(options) -> tuple[int, ...]:
    """The radial mode counts of ``families``: one, or those of a convergence study
    (``radial = [M1, M2, ..]``)."""
    M = options.families[1]
    return M if isinstance(M, tuple) else (M,)


def family_width(options) -> int:
    """The largest family block: ``2 M`` per perturbation field (``W``, and ``U``, ``V`` with
    ``families.inplane``)."""
    return 2 * max(family_radials(options)) * (3 if options.families.inplane else 1)


def is_radial_study(options) -> bool:
    """Whether ``families`` lists several radial counts (``family_radial`` dimension)."""
    return options.families is not None and isinstance(options.families[1], tuple)


class Families(BranchFeature):
    """``families``: the families' multipliers along the branch; ``point_family`` also for a
    mixed mode set reduced by symmetry.  A study in the radial counts adds the dimension
    ``family_radial`` after ``point`` (the multipliers padded with NaN to the largest count)."""

    def enabled(self, options):
        return options.families is not None or by_symmetry(options)

    def variables(self, options):
        n = options.max_points
        if not self.enabled(options):
            return []
        point_family = [Variable("point_family", ("point",), (n,), "i2", "1",
                                 "wave number n of the block a located point belongs to (0: axisymmetric block "
                                 "and regular points)", -1)]
        if options.families is None:
            return point_family
        F, w = len(options.families.n), family_width(options)
        study = ("family_radial",) if is_radial_study(options) else ()
        R = (len(family_radials(options)),) if study else ()
        pf, pfm = ("point", *study, "family"), ("point", *study, "family", "family_multiplier")
        return [
            Variable("family_multiplier_modulus", pf, (n, *R, F), "f8", "1",
                     "largest Floquet multiplier modulus of the family's block"),
            Variable("family_multiplier_real", pfm, (n, *R, F, w), "f8", "1",
                     "real part of the family's Floquet multipliers, by decreasing modulus"),
            Variable("family_multiplier_imag", pfm, (n, *R, F, w), "f8", "1",
                     "imaginary part of the family's Floquet multipliers, by decreasing modulus"),
        ] + point_family

    def coords(self, options):
        if options.families is None:
            return {}
        radial = {} if not is_radial_study(options) else {
            "family_radial": (("family_radial",), np.array(family_radials(options), dtype=np.int32),
                              {"long_name": "radial modes per asymmetric family", "units": "1"})}
        return {"family": (("family",), np.array(options.families[0], dtype=np.int32),
                           {"long_name": "circumferential wave number n of the asymmetric mode family", "units": "1"}),
                "family_multiplier": (("family_multiplier",), np.arange(family_width(options),
                                                                        dtype=np.int32),
                                      {"long_name": "Floquet multiplier index within the family's block",
                                       "units": "1"}),
                **radial}

    def compute(self, ctx):
        out = blank_outputs(self.variables(ctx.options))
        br = ctx.layout
        m = br.value.size
        if ctx.options.families is not None:
            shape = out["family_multiplier_real"].shape[1:]  # ([R,] F, w): the families by count, then n
            mu = br.family_multipliers.reshape(m, *shape)
            out["family_multiplier_modulus"][:m] = np.nanmax(np.abs(mu), axis=-1)
            out["family_multiplier_real"][:m], out["family_multiplier_imag"][:m] = mu.real, mu.imag
        out["point_family"][:m] = br.family
        return out, ""


def second_parameter(table, section, parameter, damping, name="fold_curve"):
    """A ``{parameter, start, stop}`` option naming a second parameter: ``(name, start,
    stop)`` or None."""
    key = f"{section}.{name}"
    value = table.get(name)
    if value is None:
        return None
    if not isinstance(value, dict) or set(value) != {"parameter", "start", "stop"}:
        raise JobError(key, value, "must be a table {parameter = , start = , stop = }")
    allowed = opt.second_parameters(parameter, damping) + (("delta",) if name == "bifurcation_curves" else ())
    second = opt.choice(value, key, "parameter", allowed)
    low, low_open = (1.0, True) if second == "delta" else (0.0, second == "Omega")
    start = opt.number(value, key, "start", low=low, low_open=low_open)
    stop = opt.number(value, key, "stop", low=low, low_open=low_open)
    if start == stop:
        raise JobError(f"{key}.stop", stop, f"must differ from {key}.start")
    return second, start, stop


class FoldCurve(BranchFeature):
    """``fold_curve``: the first saddle-node in a second parameter, through its cusps."""

    def enabled(self, options):
        return options.fold_curve is not None

    def variables(self, options):
        if not self.enabled(options):
            return []
        p, q, n = options.parameter, options.fold_curve[0], options.max_points
        cp = ("curve_point",)
        return [
            Variable(f"fold_curve_{q}", cp, (n,), "f8", GRID_KEYS[q][0],
                     f"{q} along the curve of saddle-nodes (two-parameter continuation)"),
            Variable(f"fold_curve_{p}", cp, (n,), "f8", GRID_KEYS[p][0], f"{p} at the saddle-node"),
            Variable("fold_curve_amplitude", cp, (n,), "f8", "m", "amplitude at the saddle-node"),
            Variable(f"cusp_{q}", ("cusp",), (MAX_CUSPS,), "f8", GRID_KEYS[q][0],
                     f"{q} at the cusps where two saddle-nodes merge"),
            Variable(f"cusp_{p}", ("cusp",), (MAX_CUSPS,), "f8", GRID_KEYS[p][0], f"{p} at the cusps"),
        ]

    def coords(self, options):
        if not self.enabled(options):
            return {}
        return {"cusp": (("cusp",), np.arange(MAX_CUSPS, dtype=np.int32), {"long_name": "cusp index", "units": "1"}),
                **_curve_point_coord(options)}

    def compute(self, ctx):
        options = ctx.options
        out = blank_outputs(self.variables(options))
        p, (q, q_start, q_stop), n = options.parameter, options.fold_curve, options.max_points
        try:
            curve = continue_folds(ctx.fmap, p, q, q_start, q_stop, (options.start, options.stop), max_points=n)
        except (RuntimeError, ArithmeticError, np.linalg.LinAlgError) as exc:
            return out, f"fold curve: {type(exc).__name__}: {exc}"
        m, c = min(curve.p.size, n), min(len(curve.cusp), MAX_CUSPS)
        out[f"fold_curve_{q}"][:m], out[f"fold_curve_{p}"][:m], out["fold_curve_amplitude"][:m] = \
            curve.q[:m], curve.p[:m], curve.amplitude[:m]
        out[f"cusp_{q}"][:c], out[f"cusp_{p}"][:c] = curve.cusp[:c, 0], curve.cusp[:c, 1]
        no_fold = curve.p.size == 0
        return out, "" if curve.complete or no_fold else f"fold curve: {curve.message}"


def curves_option(table, section, parameter, grid, damping):
    """The ``bifurcation_curves`` option; the grid values of its parameter must lie in its
    range (the curves run from each task's value to both ends)."""
    value = second_parameter(table, section, parameter, damping, "bifurcation_curves")
    if value is not None and value[0] in grid:
        lo, hi = min(value[1:]), max(value[1:])
        outside = [float(v) for v in np.atleast_1d(grid[value[0]]) if not lo <= v <= hi]
        if outside:
            raise JobError(f"{section}.bifurcation_curves", table["bifurcation_curves"],
                           f"the [grid] values of {value[0]} must lie in [start, stop]; {outside} do not")
    return value


class BifurcationCurves(BranchFeature):
    """``bifurcation_curves``: every located point of the branch in a second parameter."""

    def enabled(self, options):
        return options.bifurcation_curves is not None

    def variables(self, options):
        if not self.enabled(options):
            return []
        p, q, n = options.parameter, options.bifurcation_curves[0], options.max_points
        cp = ("curve", "curve_point")
        return [
            Variable(f"curve_{q}", cp, (MAX_CURVES, n), "f8", GRID_KEYS[q][0],
                     f"{q} along the curve of bifurcation points (two-parameter continuation)"),
            Variable(f"curve_{p}", cp, (MAX_CURVES, n), "f8", GRID_KEYS[p][0], f"{p} along the curve"),
            Variable("curve_amplitude", cp, (MAX_CURVES, n), "f8", "m", "amplitude along the curve"),
            Variable("curve_kind", ("curve",), (MAX_CURVES,), "i1", "1", "kind of the bifurcation points of the curve",
                     -1, kind_attrs()),
            Variable("curve_family", ("curve",), (MAX_CURVES,), "i2", "1",
                     "wave number n of the block of the curve (0: axisymmetric)", -1),
        ]

    def coords(self, options):
        if not self.enabled(options):
            return {}
        return {"curve": (("curve",), np.arange(MAX_CURVES, dtype=np.int32),
                          {"long_name": "index of the bifurcation curve (located points in branch order)",
                           "units": "1"}),
                **_curve_point_coord(options)}

    def compute(self, ctx):
        """The curves start at the task's value of the second parameter.  In ``delta`` the
        model rebuilds its pre-stretch, map and family at every value met
        (:meth:`sweep.models.base.Model.rebuilt`)."""
        options, br, fmap = ctx.options, ctx.branch, ctx.fmap
        out = blank_outputs(self.variables(options))
        p, (q, q_start, q_stop), n = options.parameter, options.bifurcation_curves, options.max_points
        q_here = ctx.point.value(q)
        located = np.flatnonzero(br.kind > 0)
        problems = [f"{located.size - MAX_CURVES} located points not followed (MAX_CURVES = {MAX_CURVES})"] \
            if located.size > MAX_CURVES else []
        by_n = {f.n: f for f in ctx.families}
        span = abs(options.stop - options.start)
        for j, i in enumerate(located[:MAX_CURVES]):
            kind, family = int(br.kind[i]), by_n.get(int(br.family[i]))
            out["curve_kind"][j], out["curve_family"][j] = kind, br.family[i]
            halves = []
            for end in (q_start, q_stop):
                if end == q_here:
                    continue
                try:
                    halves.append(continue_curve(fmap, p, q, q_here, end, br.state[i], br.value[i], span, kind=kind,
                                                 family=family, ds_max=CURVE_DS_MAX, max_points=n // 2,
                                                 rebuild=ctx.point.model.rebuilt(ctx.point, options, fmap, family)
                                                 if q == "delta" else None))
                except (RuntimeError, ArithmeticError, np.linalg.LinAlgError) as exc:
                    problems.append(f"curve {j} ({KIND_NAMES[kind]}) towards {q} = {end}: {type(exc).__name__}: {exc}")
            if not halves:
                continue
            first = halves[0]
            qs, ps, amp = first.q[::-1], first.p[::-1], first.amplitude[::-1]
            for h in halves[1:]:
                qs, ps, amp = (np.concatenate([qs, h.q[1:]]), np.concatenate([ps, h.p[1:]]),
                               np.concatenate([amp, h.amplitude[1:]]))
            m = qs.size
            out[f"curve_{q}"][j, :m], out[f"curve_{p}"][j, :m], out["curve_amplitude"][j, :m] = qs, ps, amp
            problems += [f"curve {j} ({KIND_NAMES[kind]}): {h.message}" for h in halves if not h.complete]
        return out, "; ".join(problems)


class FamilyCheckOption(NamedTuple):
    """The ``family_check`` option."""

    #: the parameter values whose nearest resonant responses are checked
    values: tuple[float, ...]
    #: periods of the growth fit
    periods: int
    #: periods more, to the state the perturbation saturates at (0: none)
    saturate: int
    #: periods more, with the Lyapunov spectrum and the classification (0: none)
    classify: int
    #: the full model's mixed model on the harmonics 0, n, ..., harmonics n (None: the
    #: model's default, :meth:`model.full.forced.ForcedFull.perturbed_family`)
    harmonics: int | None = None


def family_check_option(table, section, model) -> FamilyCheckOption | None:
    """The ``family_check = {values, periods, saturate, classify, harmonics}`` option, or
    None; ``model`` the job's (:class:`sweep.models.base.ModelSpec`): ``harmonics`` needs
    one whose mixed model is made of circumferential harmonics."""
    value = table.get("family_check")
    if value is None:
        return None
    key = f"{section}.family_check"
    if not isinstance(value, dict) or "values" not in value:
        raise JobError(key, value, "must be a table {values = [..], periods = N, saturate = N, classify = N, "
                       "harmonics = K}")
    check_keys(value, key, ("values", "periods", "saturate", "classify", "harmonics"))
    if "harmonics" in value and not model.model().circumferential_harmonics:
        raise JobError(f"{key}.harmonics", value["harmonics"], "needs a model with circumferential harmonics ([model] "
                       f"kind = \"full\"); this job's model is {model.kind!r}, whose mixed model is its axisymmetric "
                       "and family modes")
    harmonics = (opt.number(value, key, "harmonics", 2, integer=True, low=2, high=MAX_CHECK_HARMONICS)
                 if "harmonics" in value else None)
    if table.get("families") is None:
        raise JobError(key, value, "needs continuation.families")
    values = value["values"]
    if (not isinstance(values, list) or not 0 < len(values) <= MAX_CHECKS
            or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in values)):
        raise JobError(f"{key}.values", values, f"must be a list of 1 to {MAX_CHECKS} finite numbers")
    saturate = opt.number(value, key, "saturate", 0, integer=True, low=0, high=1_000_000)
    points = opt.number(value, key, "classify", 0, integer=True, low=0, high=1_000_000)
    least = -(-2 * CHECK_MAX_PERIOD // LYAPUNOV_BLOCKS) * LYAPUNOV_BLOCKS  # twice the longest period, rounded up
    if points and (points % LYAPUNOV_BLOCKS or points < least):
        raise JobError(f"{key}.classify", points, f"must be 0 or a multiple of {LYAPUNOV_BLOCKS} from {least} (twice "
                       f"the longest period looked for, {CHECK_MAX_PERIOD})")
    if points and not saturate:
        raise JobError(f"{key}.classify", points, "needs saturate > 0 (the transient before the classification)")
    return FamilyCheckOption(tuple(float(v) for v in values),
                             opt.number(value, key, "periods", 100, integer=True, low=10, high=100_000),
                             saturate, points, harmonics)


class FamilyCheck(BranchFeature):
    """``family_check``: brute force against Floquet at the resonant responses nearest
    the given values."""

    def enabled(self, options):
        return options.check is not None

    def variables(self, options):
        if not self.enabled(options):
            return []
        C, F, p = len(options.check[0]), len(options.families[0]), options.parameter
        cf = ("check", "family")
        return [
            Variable(f"check_{p}", ("check",), (C,), "f8", GRID_KEYS[p][0],
                     f"{p} of the resonant response checked (the point of the resonant stretch nearest each "
                     "family_check value)"),
            Variable("check_floquet_modulus", cf, (C, F), "f8", "1", "largest multiplier modulus of the family's block"),
            Variable("check_growth", cf, (C, F), "f8", "1",
                     "growth per period of a small asymmetric perturbation in the nonlinear mixed model"),
            Variable("check_asymmetric_amplitude", cf, (C, F), "f8", "m",
                     "largest asymmetric |w(0.5 Re, 0)| after the family_check saturate periods (NaN without)"),
            Variable("check_asymmetric_spread", cf, (C, F), "f8", "m",
                     "max - min of the asymmetric w(0.5 Re, 0) over the stroboscopic samples of the last tenth "
                     "of the saturate periods: 0 for a period-one state (NaN without saturate)"),
            *self._classify_variables(options, cf, (C, F)),
            *([Variable("check_highest_harmonic", ("family",), (F,), "i4", "1",
                        "highest circumferential harmonic of the family's mixed model (its harmonics: 0, n, 2n, ..., "
                        "this; family_check.harmonics)", -1)] if options.check.harmonics is not None else []),
        ]

    @staticmethod
    def _classify_variables(options, dims, shape) -> list[Variable]:
        if not options.check.classify:
            return []
        return [
            Variable("check_state_size", ("family",), shape[1:], "i4", "1",
                     "coordinates of the state of the family's mixed model (2 dof): how many Lyapunov exponents "
                     "check_lyapunov_sum adds", -1),
            Variable("check_lyapunov_exponent", dims, shape, "f8", "s-1",
                     "largest Lyapunov exponent of the mixed model's stroboscopic map over the family_check "
                     "classify periods after the saturate periods"),
            Variable("check_lyapunov_error", dims, shape, "f8", "s-1",
                     f"statistical error of check_lyapunov_exponent ({LYAPUNOV_BLOCKS} block means)"),
            Variable("check_lyapunov_sum", dims, shape, "f8", "s-1",
                     "sum of the Lyapunov exponents: the mean log |det| of the map's Jacobian per period over "
                     "the period; the flow's is -2 alpha dof under a mass-proportional damping, the RK4 map's "
                     "lower where its step damps modes it does not resolve (the full model's in-plane ones)"),
            Variable("check_kind", dims, shape, "i1", "1", "kind of the state reached", -1, response_kind_attrs()),
            Variable("check_kind_period", dims, shape, "i4", "1",
                     "least period of a periodic state reached in forcing periods (0: not periodic)", -1),
            Variable("check_rotation_number", dims, shape, "f8", "1",
                     "rotation number of a quasi-periodic state reached on its invariant circle, in [0, 1/2]"),
        ]

    def coords(self, options):
        if not self.enabled(options):
            return {}
        return {"check": (("check",), np.arange(len(options.check[0]), dtype=np.int32),
                          {"long_name": "index of the family_check value", "units": "1"})}

    def compute(self, ctx):
        options, br, fmap = ctx.options, ctx.branch, ctx.fmap
        out = blank_outputs(self.variables(options))
        values, periods, saturate, points, harmonics = options.check
        p = options.parameter
        end = resonant_end(br.kind)
        problems = []
        for j, fam in enumerate(ctx.families):
            try:
                mixed = (fmap.perturbed_family(fam) if harmonics is None
                         else fmap.perturbed_family(fam, harmonics=harmonics))
            except ValueError as exc:
                problems.append(f"family_check n = {fam.n}: {exc}")
                continue
            if harmonics is not None:
                out["check_highest_harmonic"][j] = harmonics * fam.n
            for c, v in enumerate(values):
                i = int(np.argmin(np.abs(br.value[:end] - v)))
                out[f"check_{p}"][c] = br.value[i]
                out["check_floquet_modulus"][c, j] = np.nanmax(np.abs(br.family_multipliers[i, j]))
                try:
                    start = (mixed.start if mixed.start is not None
                             else floquet_start(fmap.varied(p, br.value[i]).family_monodromy(br.state[i], fam)))
                    at = mixed.fmap.varied(p, br.value[i])
                    if points:
                        out["check_state_size"][j] = 2 * at.dof
                    check = perturbation_growth(at, br.state[i], mixed.asymmetric, periods=periods,
                                                saturate=saturate, probe=mixed.probe, start=start, metric=mixed.metric)
                    low, high = check.saturated
                    out["check_growth"][c, j] = check.growth
                    out["check_asymmetric_amplitude"][c, j] = max(abs(low), abs(high))
                    out["check_asymmetric_spread"][c, j] = high - low
                    if points:
                        # the family unstable and the perturbation still linear: it has not
                        # reached its state yet
                        growing = (out["check_floquet_modulus"][c, j] > 1.0
                                   and np.abs(check.state[list(mixed.asymmetric)]).max() < GROWTH_LIMIT)
                        _classify_reached(out, (c, j), at, check.state, points, growing)
                except ValueError as exc:
                    problems.append(f"family_check n = {fam.n} at {p} = {br.value[i]:.6g}: {exc}")
        return out, "; ".join(problems)


def _classify_reached(out, index, fmap, state, points: int, growing: bool) -> None:
    # The Lyapunov spectrum over `points` periods from the state the check reached, and its
    # kind (model.lyapunov), into the check_* outputs at `index`; a perturbation still
    # linear and growing is `unsettled` whatever its exponent (it is still leaving an
    # unstable orbit, not on a chaotic attractor), without the search for periodic orbits.
    record = lyapunov_spectrum(fmap, state, points, LYAPUNOV_BLOCKS)
    if growing and record.finite:
        kind = Classification(UNSETTLED, 0, np.nan)
    else:
        kind = classify(fmap, record, max_period=CHECK_MAX_PERIOD, sigmas=CHECK_SIGMAS)
    out["check_lyapunov_exponent"][index] = record.exponents[0]
    out["check_lyapunov_error"][index] = record.standard_error[0]
    out["check_lyapunov_sum"][index] = record.log_det / record.period
    out["check_kind"][index], out["check_kind_period"][index], out["check_rotation_number"][index] = kind


def tongues_option(table, section) -> bool:
    """The ``tongues = true`` option (needs ``families``)."""
    tongues = opt.flag(table, section, "tongues", False)
    if tongues and table.get("families") is None:
        raise JobError(f"{section}.tongues", table["tongues"], "needs continuation.families")
    return tongues


class Tongues(BranchFeature):
    """``tongues``: per point and family, the smallest scale of the orbit's stiffness
    modulation that destabilises the family's block (measured by Floquet multipliers and by
    first-order averaging, :mod:`model.tongues`), and the resonance the averaging finds lowest.
    A study in the radial counts adds ``family_radial`` as for the multipliers."""

    def enabled(self, options):
        return options.tongues

    def variables(self, options):
        if not self.enabled(options):
            return []
        n = options.max_points
        study = ("family_radial",) if is_radial_study(options) else ()
        R = (len(family_radials(options)),) if study else ()
        F = len(options.families.n)
        pf, pfp = ("point", *study, "family"), ("point", *study, "family", "tongue_pair")
        return [
            Variable("tongue_threshold", pf, (n, *R, F), "f8", "1",
                     "smallest scale s of the stiffness modulation (mean + s (S(t) - mean)) at which the family's "
                     "largest Floquet multiplier modulus reaches 1 (at most 1 where the family is unstable; NaN: "
                     "none up to s = 8)"),
            Variable("tongue_threshold_averaged", pf, (n, *R, F), "f8", "1",
                     "smallest threshold scale s by first-order averaging over every resonance "
                     "p Omega ~ omega_i + omega_j of the mean stiffness' modes"),
            Variable("tongue_harmonic", pf, (n, *R, F), "i2", "1",
                     "harmonic p of the forcing frequency of the resonance with the smallest averaged threshold", -1),
            Variable("tongue_modes", pfp, (n, *R, F, 2), "i2", "1",
                     "i <= j of that resonance: the modes of the family's mean stiffness by increasing frequency "
                     "(1-based)", -1),
            Variable("tongue_frequencies", pfp, (n, *R, F, 2), "f8", "rad s-1", "omega_i, omega_j of that resonance"),
            Variable("tongue_rates", pfp, (n, *R, F, 2), "f8", "s-1",
                     "decay rates alpha_i, alpha_j of its modes: the damping law's and RK4's at the map's step"),
            Variable("tongue_depth", pf, (n, *R, F), "f8", "1",
                     "modulation depth k_ij / (omega_i omega_j) of the orbit at that resonance"),
            Variable("tongue_detuning", pf, (n, *R, F), "f8", "rad s-1", "p Omega - omega_i - omega_j"),
        ]

    def compute(self, ctx):
        options, br = ctx.options, ctx.branch
        out = blank_outputs(self.variables(options))
        shape = out["tongue_threshold"].shape[1:]  # ([R,] F): the families by count, then n
        names = ("tongue_threshold", "tongue_threshold_averaged", "tongue_harmonic", "tongue_modes",
                 "tongue_frequencies", "tongue_rates", "tongue_depth", "tongue_detuning")
        problems, failed = [], 0
        for i in range(br.value.size):
            fmap = ctx.fmap.varied(options.parameter, br.value[i])
            for j, fam in enumerate(ctx.families):
                at = (i, *np.unravel_index(j, shape))
                try:
                    tg = family_tongue(fmap, br.state[i], fam)
                except (ValueError, np.linalg.LinAlgError) as exc:
                    failed += 1
                    if len(problems) < 3:
                        problems.append(f"tongues n = {fam.n} at {options.parameter} = {br.value[i]:.6g}: {exc}")
                    continue
                for k, v in zip(names, (tg.measured, tg.averaged, tg.harmonic, tg.modes, tg.frequencies, tg.rates,
                                        tg.depth, tg.detuning)):
                    out[k][at] = v
        if failed > len(problems):
            problems.append(f"and {failed - len(problems)} more")
        return out, "; ".join(problems)


FAMILIES = Families()
FOLD_CURVE = FoldCurve()
BIFURCATION_CURVES = BifurcationCurves()
FAMILY_CHECK = FamilyCheck()
TONGUES = Tongues()
#: These features in the order of their outputs and of their computation (the standing and
#: rotating waves are in :mod:`sweep.analyses.wave_features`).
BRANCH_FEATURES = (FAMILIES, FOLD_CURVE, BIFURCATION_CURVES, FAMILY_CHECK, TONGUES)
