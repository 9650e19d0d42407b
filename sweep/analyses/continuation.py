"""Analysis ``continuation``: bifurcation diagrams of the stroboscopic map (Figs. 14-17).

Per grid point, the branch of periodic responses of the forced ROM is continued by
pseudo-arclength (:func:`model.continuation.continue_orbits`) in one parameter, ``Omega`` or
``P0``, from ``start`` to ``stop``; the other forcing parameters (``P0`` or ``Omega``, and
``c``) come from the grid, and the continued one must not be a grid key.

Options: :attr:`ContinuationAnalysis.OPTIONS` (``docs/options.md``); the branch starts at
``start`` from rest (a unique small response there: ``P0 = 0``, or ``Omega`` away from
resonance).

Outputs (a task's branches differ in length: every ``point`` array is padded with NaN,
``stable`` and ``point_type`` with -1):

* ``<parameter>`` (``point``): the continued parameter's value, a coordinate named after
  it (``Omega`` in rad/s or ``P0`` in Pa; the dataset attribute ``continued_parameter``
  names it too);
* ``modal_coordinate``, ``modal_velocity`` (``point``, ``mode``): the state on the
  stroboscopic section ``t = 0 mod 2 pi / Omega`` (the paper's ``A_mn`` axes);
* ``amplitude`` (``point``): max over one period of ``|w(0.5 Re, 0, t)|`` (m);
* ``stable`` (``point``, int8): 1 stable, 0 unstable (and at located bifurcation points);
  with ``families``, stable means stable to the families' perturbations too;
* ``point_type`` (``point``, int8): 0 regular, 1 fold (saddle-node), 2 period doubling,
  3 Neimark-Sacker, 4 branch point (a family's multiplier crosses +1: symmetry breaking);
  bifurcation points are located to ~1e-10 in arclength and inserted;
* ``multiplier_real``, ``multiplier_imag`` (``point``, ``multiplier``): Floquet
  multipliers by decreasing modulus, and ``multiplier_modulus`` (``point``) the largest;
* ``fold_value``, ``fold_amplitude`` (``fold``, :data:`MAX_FOLDS` long, NaN padded): the
  saddle-node points in branch order, and ``n_points``, ``n_folds``.

Mixed mode sets (``modes`` with ``n != 0`` and at least one ``n = 0`` mode, no ``families``):
the branch starts from rest, which the uniform pressure keeps axisymmetric, so it is continued
in the ROM of the axisymmetric modes with one family block per wave number and companion
(:func:`model.families.symmetry_blocks`); the outputs keep the mixed set's layout (the
asymmetric coordinates are zero, the multipliers are those of all blocks).  This gives the
2-D mixed ROM's branch and multipliers (to ~1e-8, tests) at the cost of the axisymmetric one,
and locates the branch points where an asymmetric block's multiplier crosses +1.

Asymmetric families (``families = {n = [1, 3], radial = 4}``, axisymmetric ``modes`` only):
the Floquet multipliers of each family's block (:mod:`model.families`) along the branch,
``family_multiplier_modulus`` (``point``, ``family``) and ``family_multiplier_real``/``_imag``
(``point``, ``family``, ``family_multiplier``), and ``point_family`` (``point``): the wave
number of the block of a located point (0 for the axisymmetric block).

Branch switching (``branch_switching = {max_points = N, n = 1}``, with ``families``): at the
first branch point of family n (of any family without ``n``) the asymmetric branch is followed (:mod:`model.switching`) for at
most N points; outputs over ``switched_point``: ``switched_<parameter>``,
``switched_amplitude``, ``switched_asymmetric_amplitude`` (the family's part of
``w(0.5 Re, 0)``), ``switched_stable``, ``switched_point_type``,
``switched_multiplier_modulus``, and ``switched_modal_coordinate`` with the modes
``switched_mode_m``/``switched_mode_n``.  Reaching N points is not a failure: the branch
is followed as far as asked.

Brute-force check (``family_check = {values = [40, 44], periods = 100, saturate = 0}``, with
``families``): at the resonant responses (the stretch from ``start`` to the first
saddle-node) nearest each value, each family's mixed ROM (axisymmetric modes plus the
family's, 2-D quadrature) is integrated from the orbit plus 1e-9 m in the family's
coordinates (:func:`model.families.perturbation_growth`): ``check_growth`` (``check``,
``family``), the growth per period, against ``check_floquet_modulus``; with ``saturate``
the asymmetric amplitude reached, ``check_asymmetric_amplitude``, and the width of the range
of its stroboscopic samples, ``check_asymmetric_spread`` (zero for a period-one state).

Curves of bifurcation points (``bifurcation_curves = {parameter = "P0", start = 0.2, stop =
2.0}``): every located point of the branch (up to :data:`MAX_CURVES`) is followed in the
second parameter (``c``, ``delta`` or the forcing parameter not continued) from the task's
value towards ``start`` and towards ``stop`` (:func:`model.codim2.continue_curve`; in
``delta`` the pre-stretch, ROM and family are rebuilt at every value met); outputs ``curve_<second>``, ``curve_<parameter>``,
``curve_amplitude`` (``curve``, ``curve_point``, NaN padded), ``curve_kind`` and
``curve_family`` (``curve``).  A curve that does not reach both ends makes the task
``not_converged`` with the reason.

Fold loci by two-parameter continuation (Fig. 17): ``fold_curve = {parameter = "c",
start = 0.05, stop = 3.0}`` follows the first saddle-node of the branch as the second
parameter (``c``, or the forcing parameter not continued) goes from ``start`` towards
``stop``, through the cusps where two saddle-nodes merge (:mod:`model.codim2`).  Outputs
``fold_curve_<second>``, ``fold_curve_<parameter>``, ``fold_curve_amplitude``
(``curve_point``, ``max_points`` long, NaN padded) and ``cusp_<second>``,
``cusp_<parameter>`` (``cusp``, :data:`MAX_CUSPS` long, NaN padded).

Fold loci versus damping by extrapolation (without ``fold_curve``): put ``c`` in the grid
(a dense list).  When ``c`` has three or more values and ``parameter = "P0"``, :meth:`ContinuationAnalysis.derived` adds,
per combination of the other grid keys, the cusp where the two folds merge
(:func:`model.continuation.cusp_from_folds`): ``cusp_c`` (N s/m^3) and ``cusp_value``
(Pa).  The status is ``ok`` when the branch reached ``stop``, ``not_converged`` otherwise
(``message`` says why), ``failed`` when a state on the branch is not finite.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from model.codim2 import continue_curve, continue_folds
from model.continuation import BRANCH_POINT, FOLD, KIND_NAMES, continue_orbits, cusp_from_folds, resonant_end
from model.families import build_family, perturbation_growth, symmetry_blocks
from model.forced import DEFAULT_STEPS, ForcedMap
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom
from model.shooting import shoot
from model.switching import follow_bifurcated_branch, mixed_rom

from . import options as opt
from .base import (DEFAULT_CONTEXT, GRID_KEYS, STATUS_FAILED, STATUS_NOT_CONVERGED, STATUS_OK, Analysis, JobError, Variable,
                   check_keys)

#: Length of the ``fold`` dimension.
MAX_FOLDS = 6


@dataclass(frozen=True)
class ContinuationOptions:
    parameter: str
    start: float
    stop: float
    modes: tuple[tuple[int, int], ...]
    prestretch: str
    max_points: int
    ds_max: float
    steps: int | None
    fold_curve: tuple[str, float, float] | None = None
    families: tuple[tuple[int, ...], int] | None = None
    bifurcation_curves: tuple[str, float, float] | None = None
    switch_points: int = 0
    switch_family: int = 0
    check: tuple[tuple[float, ...], int, int] | None = None
    #: the job's material law (``[membrane] law``): the warmups compile its kernels
    material: str = "neo-hookean"


#: Length of the ``cusp`` dimension (cusps of the fold curve, NaN padded).
MAX_CUSPS = 4
#: Arclength (scaled unknowns: the parameter range is 1, 0.05 m of displacement is 1) that
#: the default ``max_points`` covers at steps of ``ds_max``.  The Fig. 14 branches (delta =
#: 1.1, 1.5, 2.0; P0 = 1 Pa, c = 0.05 N s/m^3, Omega 25..55 rad/s) are about 96, 170 and 290
#: long (885, 1614 and 2873 points at ds_max = 0.1; 319, 563 and 980 at 0.3).
BRANCH_ARCLENGTH = 400
#: Largest arclength step of the bifurcation curves (scaled unknowns): along them the
#: orbit's phase turns while its amplitude barely changes, so steps are larger than on a
#: branch; the turning test (model.continuation.MAX_TURN) still bounds them.
CURVE_DS_MAX = 0.5
#: Length of the ``curve`` dimension (bifurcation curves, NaN padded).
MAX_CURVES = 16


#: Largest number of values of ``family_check``.
MAX_CHECKS = 16


def _family_check(table, section):
    """The ``family_check = {values, periods, saturate}`` option: ``(values, periods,
    saturate)`` or None."""
    value = table.get("family_check")
    if value is None:
        return None
    key = f"{section}.family_check"
    if not isinstance(value, dict) or not {"values"} <= set(value) <= {"values", "periods", "saturate"}:
        raise JobError(key, value, "must be a table {values = [..], periods = N, saturate = N}")
    if table.get("families") is None:
        raise JobError(key, value, "needs continuation.families")
    values = value["values"]
    if (not isinstance(values, list) or not 0 < len(values) <= MAX_CHECKS
            or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in values)):
        raise JobError(f"{key}.values", values, f"must be a list of 1 to {MAX_CHECKS} finite numbers")
    return (tuple(float(v) for v in values), opt.number(value, key, "periods", 100, integer=True, low=10, high=100_000),
            opt.number(value, key, "saturate", 0, integer=True, low=0, high=1_000_000))


def _curves_option(table, section, parameter, grid, damping):
    """The ``bifurcation_curves`` option; the grid values of its parameter must lie in its
    range (the curves run from each task's value to both ends)."""
    value = _second_parameter(table, section, parameter, damping, "bifurcation_curves")
    if value is not None and value[0] in grid:
        lo, hi = min(value[1:]), max(value[1:])
        outside = [float(v) for v in np.atleast_1d(grid[value[0]]) if not lo <= v <= hi]
        if outside:
            raise JobError(f"{section}.bifurcation_curves", table["bifurcation_curves"],
                           f"the [grid] values of {value[0]} must lie in [start, stop]; {outside} do not")
    return value


def _switching(table, section, families) -> tuple[int, int]:
    """The ``branch_switching = {max_points = N, n = wave number}`` option: ``(N, n)`` (n = 0:
    the first branch point of any family), or ``(0, 0)`` without it."""
    value = table.get("branch_switching")
    if value is None:
        return 0, 0
    key = f"{section}.branch_switching"
    if not isinstance(value, dict) or not {"max_points"} <= set(value) <= {"max_points", "n"}:
        raise JobError(key, value, "must be a table {max_points = N} or {max_points = N, n = wave number}")
    if families is None:
        raise JobError(key, value, "needs continuation.families (branch points are found in the families)")
    n = opt.number(value, key, "n", 0, integer=True, low=0)
    if n and n not in families[0]:
        raise JobError(f"{key}.n", n, f"must be one of the families' wave numbers {list(families[0])}")
    return opt.number(value, key, "max_points", integer=True, low=2, high=10_000), n


def _second_parameter(table, section, parameter, damping, name="fold_curve"):
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


class ContinuationAnalysis(Analysis):
    """Pseudo-arclength continuation of periodic responses in Omega or P0 (Figs. 14-17)."""

    name = "continuation"
    #: The option table ``[continuation]``: key -> description (docs/options.md).
    OPTIONS = {
        "parameter": "Omega | P0 (required): the continued forcing parameter, not a grid key; the "
                     "other forcing keys must be grid keys",
        "start": "start of the range (required; rad/s or Pa): the branch starts there from rest",
        "stop": "end of the range (required)",
        "modes": opt.MODES_HELP,
        "prestretch": "analytic (Eq. 21) | numeric (Eq. 15, default) | fit (Eq. 18)",
        "max_points": "length of the point dimension: most points on a branch (default "
                      f"ceil({BRANCH_ARCLENGTH} / ds_max), {math.ceil(BRANCH_ARCLENGTH / 0.1)} at ds_max = 0.1: "
                      "enough for the paper's Fig. 14 branches; shorter branches are NaN padded)",
        "ds_max": "largest arclength step in scaled unknowns: the whole parameter range is 1, 0.05 m "
                  "of displacement is 1 (default 0.1)",
        "steps": opt.steps_help(DEFAULT_STEPS, "the modes of `modes`, not those of `families`"),
        "fold_curve": "{parameter, start, stop}: follow the first saddle-node in a second parameter "
                      "(a constant of the damping law: c, alpha, beta or zeta; or the forcing parameter not "
                      "continued) through its cusps (default none)",
        "bifurcation_curves": "{parameter, start, stop}: follow every located point of the branch (folds, branch "
                              "points, period doublings, Neimark-Sacker points) in a second parameter (a damping "
                              "constant, delta, or the forcing parameter not continued) from its grid value to "
                              "start and to stop (default none)",
        "branch_switching": "{max_points = N, n = wave number}: at the first branch point of family n (of any "
                            "family without n) on the branch, switch onto the bifurcating asymmetric branch and "
                            "follow it for at most N points in the ROM of the axisymmetric modes plus the "
                            "family's (needs families; default none)",
        "family_check": "{values = [..], periods = 100, saturate = 0}: brute-force check of the families' "
                        "stability at the resonant responses nearest these parameter values: growth per period of "
                        "a small asymmetric perturbation in the nonlinear mixed ROM (axisymmetric + family modes, "
                        "2-D quadrature) against the Floquet multiplier; with saturate = N, N periods more and the "
                        "asymmetric amplitude reached (needs families; default none)",
        "families": "{n = [wave numbers], radial = M}: Floquet multipliers of the asymmetric mode families "
                    "(radial modes 1..M of each n) along the axisymmetric branch; branch points, period "
                    "doublings and Neimark-Sacker points of each family are located (default none; needs "
                    "axisymmetric modes)",
    }

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        s = self.name
        check_keys(table, s, tuple(self.OPTIONS))
        parameter = opt.forcing_parameter(table, s, grid, "is continued", context.damping)
        low = 0.0
        start = opt.number(table, s, "start", low=low, low_open=parameter == "Omega")
        stop = opt.number(table, s, "stop", low=low, low_open=parameter == "Omega")
        if start == stop:
            raise JobError(f"{s}.stop", stop, "must differ from continuation.start")
        modes = opt.modes(table, s)
        families = opt.families(table, s, modes)
        opt.rom_only(table, s, context.model, ("families", "branch_switching", "check"))
        opt.damping_modes(context.damping, s, modes, families or any(n for _, n in modes))
        ds_max = opt.number(table, s, "ds_max", 0.1, low=0.0, low_open=True, high=1.0)
        return ContinuationOptions(
            parameter, start, stop, modes, opt.prestretch(table, s),
            opt.number(table, s, "max_points", math.ceil(BRANCH_ARCLENGTH / ds_max), low=2, high=100_000,
                       integer=True),
            ds_max,
            opt.steps(table, s, DEFAULT_STEPS, low=16),
            _second_parameter(table, s, parameter, context.damping), families,
            _curves_option(table, s, parameter, grid, context.damping), *_switching(table, s, families),
            _family_check(table, s), membrane.law)

    def variables(self, options):
        n, k, p = options.max_points, 2 * len(options.modes), options.parameter
        K = len(options.modes)
        units, what = GRID_KEYS[p]
        pt = ("point",)
        return (self._fold_curve_variables(options) + self._family_variables(options)
                + self._bifurcation_curve_variables(options) + self._switched_variables(options)
                + self._check_variables(options)) + [
            Variable(p, pt, (n,), "f8", units, f"continued parameter: {what}"),
            Variable("amplitude", pt, (n,), "f8", "m", "max over one period of |w(0.5 Re, 0, t)|"),
            Variable("modal_coordinate", ("point", "mode"), (n, K), "f8", "m",
                     "modal coordinate q_mn on the stroboscopic section t = 0 mod 2 pi / Omega (A_mn axis)"),
            Variable("modal_velocity", ("point", "mode"), (n, K), "f8", "m s-1",
                     "modal velocity dq_mn/dt on the stroboscopic section t = 0 mod 2 pi / Omega"),
            Variable("stable", pt, (n,), "i1", "1", "stability of the periodic response", -1,
                     {"flag_values": np.array([-1, 0, 1], np.int8), "flag_meanings": "padding unstable stable"}),
            Variable("point_type", pt, (n,), "i1", "1", "kind of point on the branch", -1,
                     {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
                      "flag_meanings": "padding " + " ".join(KIND_NAMES)}),
            Variable("multiplier_real", ("point", "multiplier"), (n, k), "f8", "1",
                     "real part of the Floquet multipliers, by decreasing modulus"),
            Variable("multiplier_imag", ("point", "multiplier"), (n, k), "f8", "1",
                     "imaginary part of the Floquet multipliers, by decreasing modulus"),
            Variable("multiplier_modulus", pt, (n,), "f8", "1", "largest Floquet multiplier modulus"),
            Variable("fold_value", ("fold",), (MAX_FOLDS,), "f8", units, f"{p} at the saddle-node points"),
            Variable("fold_amplitude", ("fold",), (MAX_FOLDS,), "f8", "m", "amplitude at the saddle-node points"),
            Variable("n_points", (), (), "i4", "1", "points on the branch", -1),
            Variable("n_folds", (), (), "i4", "1", "saddle-node points on the branch", -1),
            Variable("rk4_steps", (), (), "i4", "1", "RK4 steps per forcing period", 0),
        ]

    @staticmethod
    def _family_variables(options):
        n = options.max_points
        point_family = [Variable("point_family", ("point",), (n,), "i2", "1",
                                 "wave number n of the block a located point belongs to (0: axisymmetric block "
                                 "and regular points)", -1)]
        if options.families is None:
            return point_family if _by_symmetry(options) else []
        F, w = len(options.families[0]), 2 * options.families[1]
        pf, pfm = ("point", "family"), ("point", "family", "family_multiplier")
        return [
            Variable("family_multiplier_modulus", pf, (n, F), "f8", "1",
                     "largest Floquet multiplier modulus of the family's block"),
            Variable("family_multiplier_real", pfm, (n, F, w), "f8", "1",
                     "real part of the family's Floquet multipliers, by decreasing modulus"),
            Variable("family_multiplier_imag", pfm, (n, F, w), "f8", "1",
                     "imaginary part of the family's Floquet multipliers, by decreasing modulus"),
        ] + point_family

    @staticmethod
    def _check_variables(options):
        if options.check is None:
            return []
        C, F, p = len(options.check[0]), len(options.families[0]), options.parameter
        cf = ("check", "family")
        return [
            Variable(f"check_{p}", ("check",), (C,), "f8", GRID_KEYS[p][0],
                     f"{p} of the resonant response checked (the point of the resonant stretch nearest each family_check value)"),
            Variable("check_floquet_modulus", cf, (C, F), "f8", "1", "largest multiplier modulus of the family's block"),
            Variable("check_growth", cf, (C, F), "f8", "1",
                     "growth per period of a small asymmetric perturbation in the nonlinear mixed ROM"),
            Variable("check_asymmetric_amplitude", cf, (C, F), "f8", "m",
                     "largest asymmetric |w(0.5 Re, 0)| after the family_check saturate periods (NaN without)"),
            Variable("check_asymmetric_spread", cf, (C, F), "f8", "m",
                     "max - min of the asymmetric w(0.5 Re, 0) over the stroboscopic samples of the last tenth "
                     "of the saturate periods: 0 for a period-one state (NaN without saturate)"),
        ]

    @staticmethod
    def _switched_variables(options):
        if not options.switch_points:
            return []
        n, p, sp = options.switch_points, options.parameter, ("switched_point",)
        K = len(options.modes) + options.families[1]
        return [
            Variable(f"switched_{p}", sp, (n,), "f8", GRID_KEYS[p][0],
                     f"{p} along the asymmetric branch bifurcating at the first branch point"),
            Variable("switched_amplitude", sp, (n,), "f8", "m", "max over one period of |w(0.5 Re, 0, t)|"),
            Variable("switched_asymmetric_amplitude", sp, (n,), "f8", "m",
                     "max over one period of the asymmetric part of w(0.5 Re, 0, t)"),
            Variable("switched_stable", sp, (n,), "i1", "1", "stability within the ROM of the axisymmetric and "
                     "the family's cosine modes", -1,
                     {"flag_values": np.array([-1, 0, 1], np.int8), "flag_meanings": "padding unstable stable"}),
            Variable("switched_point_type", sp, (n,), "i1", "1", "kind of point on the asymmetric branch", -1,
                     {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
                      "flag_meanings": "padding " + " ".join(KIND_NAMES)}),
            Variable("switched_multiplier_modulus", sp, (n,), "f8", "1", "largest Floquet multiplier modulus"),
            Variable("switched_modal_coordinate", ("switched_point", "switched_mode"), (n, K), "f8", "m",
                     "modal coordinates on the stroboscopic section (modes: switched_mode_m, switched_mode_n)"),
            Variable("switched_mode_m", ("switched_mode",), (K,), "i4", "1", "radial index m of the switched ROM's modes",
                     -1),
            Variable("switched_mode_n", ("switched_mode",), (K,), "i4", "1", "wave number n of the switched ROM's modes",
                     -1),
        ]

    @staticmethod
    def _bifurcation_curve_variables(options):
        if options.bifurcation_curves is None:
            return []
        p, q, n = options.parameter, options.bifurcation_curves[0], options.max_points
        cp = ("curve", "curve_point")
        return [
            Variable(f"curve_{q}", cp, (MAX_CURVES, n), "f8", GRID_KEYS[q][0],
                     f"{q} along the curve of bifurcation points (two-parameter continuation)"),
            Variable(f"curve_{p}", cp, (MAX_CURVES, n), "f8", GRID_KEYS[p][0], f"{p} along the curve"),
            Variable("curve_amplitude", cp, (MAX_CURVES, n), "f8", "m", "amplitude along the curve"),
            Variable("curve_kind", ("curve",), (MAX_CURVES,), "i1", "1", "kind of the bifurcation points of the curve",
                     -1, {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
                          "flag_meanings": "padding " + " ".join(KIND_NAMES)}),
            Variable("curve_family", ("curve",), (MAX_CURVES,), "i2", "1",
                     "wave number n of the block of the curve (0: axisymmetric)", -1),
        ]

    @staticmethod
    def _fold_curve_variables(options):
        if options.fold_curve is None:
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
        families = {} if options.families is None else {
            "family": (("family",), np.array(options.families[0], dtype=np.int32),
                       {"long_name": "circumferential wave number n of the asymmetric mode family", "units": "1"}),
            "family_multiplier": (("family_multiplier",), np.arange(2 * options.families[1], dtype=np.int32),
                                  {"long_name": "Floquet multiplier index within the family's block", "units": "1"})}
        curve = {} if options.fold_curve is None else {
            "cusp": (("cusp",), np.arange(MAX_CUSPS, dtype=np.int32), {"long_name": "cusp index", "units": "1"})}
        if options.check is not None:
            curve["check"] = (("check",), np.arange(len(options.check[0]), dtype=np.int32),
                              {"long_name": "index of the family_check value", "units": "1"})
        if options.switch_points:
            curve["switched_point"] = (("switched_point",), np.arange(options.switch_points, dtype=np.int32),
                                       {"long_name": "index along the switched (asymmetric) branch", "units": "1"})
        if options.bifurcation_curves is not None:
            curve["curve"] = (("curve",), np.arange(MAX_CURVES, dtype=np.int32),
                              {"long_name": "index of the bifurcation curve (located points in branch order)",
                               "units": "1"})
        if options.fold_curve is not None or options.bifurcation_curves is not None:
            curve["curve_point"] = (("curve_point",), np.arange(options.max_points, dtype=np.int32),
                                    {"long_name": "index along a two-parameter curve", "units": "1"})
        return {
            **families,
            **curve,
            **opt.mode_coords(options.modes),
            "point": (("point",), np.arange(options.max_points, dtype=np.int32),
                      {"long_name": "index along the branch", "units": "1"}),
            "multiplier": (("multiplier",), np.arange(2 * len(options.modes), dtype=np.int32),
                           {"long_name": "Floquet multiplier index", "units": "1"}),
            "fold": (("fold",), np.arange(MAX_FOLDS, dtype=np.int32),
                     {"long_name": "saddle-node index along the branch", "units": "1"}),
        }

    def compute(self, point, options, subtask):
        axisymmetric, blocks = symmetry_blocks(options.modes)
        by_symmetry = _by_symmetry(options)
        modes = tuple(options.modes[i] for i in axisymmetric) if by_symmetry else options.modes
        fmap = point.model.forced_map(point, options, modes, DEFAULT_STEPS).varied(options.parameter, options.start)
        steps = getattr(fmap, "steps", 0)
        if by_symmetry:
            # a sine block with the radial indices of a cosine block has its multipliers:
            # one family each, so that every point is located once
            unique = list(dict.fromkeys((n, radial) for n, radial, _ in blocks))
            families = opt.families_for(point.membrane, options.prestretch, modes, tuple(unique))
        elif options.families is not None:
            ns, M = options.families
            families = opt.families_for(point.membrane, options.prestretch, modes,
                                        tuple((n, tuple(range(1, M + 1))) for n in ns))
        else:
            families = ()
        br = continue_orbits(fmap, options.parameter, options.start, options.stop, ds_max=options.ds_max,
                             max_points=options.max_points, families=families)
        branch = br  # in the ROM's own coordinates, for the curves and branch switching
        if by_symmetry:
            br = _full_layout(br, len(options.modes), axisymmetric,
                              [(radial, unique.index((n, radial))) for n, radial, _ in blocks])
        n, k = options.max_points, 2 * len(options.modes)
        m = br.value.size
        K = len(options.modes)
        out = {options.parameter: np.full(n, np.nan), "amplitude": np.full(n, np.nan),
               "modal_coordinate": np.full((n, K), np.nan), "modal_velocity": np.full((n, K), np.nan),
               "stable": np.full(n, -1, np.int8), "point_type": np.full(n, -1, np.int8),
               "multiplier_real": np.full((n, k), np.nan), "multiplier_imag": np.full((n, k), np.nan),
               "multiplier_modulus": np.full(n, np.nan),
               "fold_value": np.full(MAX_FOLDS, np.nan), "fold_amplitude": np.full(MAX_FOLDS, np.nan),
               "rk4_steps": steps}
        out[options.parameter][:m] = br.value
        out["amplitude"][:m] = br.amplitude
        out["modal_coordinate"][:m], out["modal_velocity"][:m] = br.state[:, :K], br.state[:, K:]
        out["stable"][:m] = br.stable
        out["point_type"][:m] = br.kind
        out["multiplier_real"][:m] = br.multipliers.real
        out["multiplier_imag"][:m] = br.multipliers.imag
        out["multiplier_modulus"][:m] = np.abs(br.multipliers).max(axis=1)
        folds = br.special(FOLD)[:MAX_FOLDS]
        out["fold_value"][:folds.size] = br.value[folds]
        out["fold_amplitude"][:folds.size] = br.amplitude[folds]
        if options.families is not None:
            F, w = len(families), 2 * options.families[1]
            mu = br.family_multipliers
            out["family_multiplier_modulus"] = np.full((n, F), np.nan)
            out["family_multiplier_modulus"][:m] = np.abs(mu).max(axis=2)
            out["family_multiplier_real"] = np.full((n, F, w), np.nan)
            out["family_multiplier_imag"] = np.full((n, F, w), np.nan)
            out["family_multiplier_real"][:m], out["family_multiplier_imag"][:m] = mu.real, mu.imag

        if options.families is not None or by_symmetry:
            out["point_family"] = np.full(n, -1, np.int16)
            out["point_family"][:m] = br.family
        out["n_points"] = np.int32(m)
        out["n_folds"] = np.int32(br.special(FOLD).size)
        out["status"] = STATUS_OK if br.complete else STATUS_NOT_CONVERGED
        if not br.complete:
            out["message"] = (f"reached max_points = {options.max_points} (raise max_points)"
                              if m >= options.max_points else br.message)
        if not (np.all(np.isfinite(br.state)) and np.all(np.isfinite(br.amplitude))):
            out["status"], out["message"] = STATUS_FAILED, "non-finite periodic response on the branch"
        problems = []
        if options.fold_curve is not None:
            curve, problem = self._compute_fold_curve(fmap, options)
            out.update(curve)
            problems.append(problem)
        if options.bifurcation_curves is not None:
            q = options.bifurcation_curves[0]
            curves, problem = self._compute_bifurcation_curves(
                fmap, branch, families, options,
                point.value(q), point)
            out.update(curves)
            problems.append(problem)
        if options.check is not None:
            checks, problem = self._compute_check(point, fmap, branch, families, options)
            out.update(checks)
            problems.append(problem)
        if options.switch_points:
            switched, problem = self._compute_switched(point, fmap, branch, families, options)
            out.update(switched)
            problems.append(problem)
        problem = "; ".join(p for p in problems if p)
        if problem and out["status"] == STATUS_OK:
            out["status"], out["message"] = STATUS_NOT_CONVERGED, problem
        return out

    @staticmethod
    def _compute_check(point, fmap, br, families, options):
        """The family_check outputs (brute force against Floquet), and what went wrong."""
        values, periods, saturate = options.check
        C, F, p = len(values), len(families), options.parameter
        out = {f"check_{p}": np.full(C, np.nan), "check_floquet_modulus": np.full((C, F), np.nan),
               "check_growth": np.full((C, F), np.nan), "check_asymmetric_amplitude": np.full((C, F), np.nan),
               "check_asymmetric_spread": np.full((C, F), np.nan)}
        end = resonant_end(br.kind)
        ps = opt.prestretch_for(point.membrane, options.prestretch)
        Ka = fmap.rom.dof
        problems = []
        for j, fam in enumerate(families):
            mixed = fmap.with_rom(mixed_rom(ps, fmap.rom, fam))
            asymmetric = tuple(range(Ka, Ka + len(fam.radial)))
            for c, v in enumerate(values):
                i = int(np.argmin(np.abs(br.value[:end] - v)))
                out[f"check_{p}"][c] = br.value[i]
                out["check_floquet_modulus"][c, j] = np.nanmax(np.abs(br.family_multipliers[i, j]))
                try:
                    out["check_growth"][c, j], (low, high) = perturbation_growth(
                        mixed.varied(p, br.value[i]), br.state[i], asymmetric, periods=periods, saturate=saturate)
                    out["check_asymmetric_amplitude"][c, j] = max(abs(low), abs(high))
                    out["check_asymmetric_spread"][c, j] = high - low
                except ValueError as exc:
                    problems.append(f"family_check n = {fam.n} at {p} = {br.value[i]:.6g}: {exc}")
        return out, "; ".join(problems)

    @staticmethod
    def _compute_switched(point, fmap, br, families, options):
        """The switched-branch outputs, and what went wrong ("" when nothing did, or when
        the branch has no branch point of a family)."""
        n, p, K = options.switch_points, options.parameter, len(options.modes) + options.families[1]
        out = {f"switched_{p}": np.full(n, np.nan), "switched_amplitude": np.full(n, np.nan),
               "switched_asymmetric_amplitude": np.full(n, np.nan), "switched_stable": np.full(n, -1, np.int8),
               "switched_point_type": np.full(n, -1, np.int8), "switched_multiplier_modulus": np.full(n, np.nan),
               "switched_modal_coordinate": np.full((n, K), np.nan), "switched_mode_m": np.full(K, -1, np.int32),
               "switched_mode_n": np.full(K, -1, np.int32)}
        bps = [i for i in np.flatnonzero(br.kind == BRANCH_POINT)
               if br.family[i] > 0 and options.switch_family in (0, br.family[i])]
        if not bps:
            return out, ""
        i = bps[0]
        family = next(f for f in families if f.n == br.family[i])
        ps = opt.prestretch_for(point.membrane, options.prestretch)
        try:
            sw, fmap_mixed, asym = follow_bifurcated_branch(ps, fmap, family, p, options.start, options.stop,
                                                            br.state[i], br.value[i], ds_max=options.ds_max,
                                                            max_points=n)
        except (RuntimeError, ArithmeticError, np.linalg.LinAlgError) as exc:
            return out, f"branch switching at {p} = {br.value[i]:.9g}: {type(exc).__name__}: {exc}"
        m = sw.value.size
        out[f"switched_{p}"][:m], out["switched_amplitude"][:m] = sw.value, sw.amplitude
        out["switched_asymmetric_amplitude"][:m], out["switched_stable"][:m] = asym, sw.stable
        out["switched_point_type"][:m] = sw.kind
        out["switched_multiplier_modulus"][:m] = np.abs(sw.multipliers).max(axis=1)
        out["switched_modal_coordinate"][:m] = sw.state[:, :K]
        modes = np.array(fmap_mixed.rom.modes, dtype=np.int32)
        out["switched_mode_m"], out["switched_mode_n"] = modes[:, 0], modes[:, 1]
        return out, "" if sw.complete or m >= n else f"switched branch: {sw.message}"

    @staticmethod
    def _compute_bifurcation_curves(fmap, br, families, options, q_here, point):
        """The bifurcation-curve outputs, and what went wrong ("" when nothing did); the
        curves start at the task's value ``q_here`` of the second parameter.  In ``delta``
        the pre-stretch, the ROM and the family are rebuilt at every value met, without the
        one-mode tables (quadrature kernels: a rebuild costs milliseconds)."""
        p, (q, q_start, q_stop), n = options.parameter, options.bifurcation_curves, options.max_points
        out = {f"curve_{q}": np.full((MAX_CURVES, n), np.nan), f"curve_{p}": np.full((MAX_CURVES, n), np.nan),
               "curve_amplitude": np.full((MAX_CURVES, n), np.nan), "curve_kind": np.full(MAX_CURVES, -1, np.int8),
               "curve_family": np.full(MAX_CURVES, -1, np.int16)}
        located = np.flatnonzero(br.kind > 0)
        problems = [f"{located.size - MAX_CURVES} located points not followed (MAX_CURVES = {MAX_CURVES})"] \
            if located.size > MAX_CURVES else []
        by_n = {f.n: f for f in families}
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
                                                 rebuild=_rebuild(point, options, fmap, family) if q == "delta"
                                                 else None))
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

    @staticmethod
    def _compute_fold_curve(fmap, options):
        """The fold-curve outputs, and why the curve is incomplete ("" when it is not)."""
        p, (q, q_start, q_stop), n = options.parameter, options.fold_curve, options.max_points
        out = {f"fold_curve_{q}": np.full(n, np.nan), f"fold_curve_{p}": np.full(n, np.nan),
               "fold_curve_amplitude": np.full(n, np.nan), f"cusp_{q}": np.full(MAX_CUSPS, np.nan),
               f"cusp_{p}": np.full(MAX_CUSPS, np.nan)}
        try:
            curve = continue_folds(fmap, p, q, q_start, q_stop, (options.start, options.stop), max_points=n)
        except (RuntimeError, ArithmeticError, np.linalg.LinAlgError) as exc:
            return out, f"fold curve: {type(exc).__name__}: {exc}"
        m, c = min(curve.p.size, n), min(len(curve.cusp), MAX_CUSPS)
        out[f"fold_curve_{q}"][:m], out[f"fold_curve_{p}"][:m], out["fold_curve_amplitude"][:m] = \
            curve.q[:m], curve.p[:m], curve.amplitude[:m]
        out[f"cusp_{q}"][:c], out[f"cusp_{p}"][:c] = curve.cusp[:c, 0], curve.cusp[:c, 1]
        no_fold = curve.p.size == 0
        return out, "" if curve.complete or no_fold else f"fold curve: {curve.message}"

    def warmups(self, options):
        axisymmetric, _ = symmetry_blocks(options.modes)
        modes = tuple(options.modes[i] for i in axisymmetric) if _by_symmetry(options) else options.modes
        return [partial(_compile_shooting, modes, options.material)]

    def attributes(self, options):
        return {"continued_parameter": options.parameter}

    def coordinate_variables(self, options):
        return (options.parameter,)

    def derived(self, ds, options):
        if options.fold_curve is not None or not (options.parameter == "P0" and ds.sizes.get("c", 0) >= 3):
            return {}
        cusp_c, cusp_v = _cusp(ds)
        return {"cusp_c": cusp_c.assign_attrs(units=GRID_KEYS["c"][0],
                                              long_name="damping at which the two saddle-nodes merge (cusp)"),
                "cusp_value": cusp_v.assign_attrs(units=GRID_KEYS["P0"][0], long_name="P0 at the cusp")}


def _cusp(ds):
    import xarray as xr

    order = np.argsort(ds.c.values)
    sub = ds.isel(c=order)
    return xr.apply_ufunc(
        lambda v, a: cusp_from_folds(sub.c.values, v, a), sub.fold_value, sub.fold_amplitude,
        input_core_dims=[["c", "fold"], ["c", "fold"]], output_core_dims=[[], []], vectorize=True)


def _rebuild(point, options, fmap, family):
    """``delta -> (map, family)`` for curves in ``delta``: the task's membrane with that delta,
    the same modes (the ROM's), forcing and steps; quadrature kernels (no tables)."""
    def at(delta):
        ps = solve_prestretch(replace(point.membrane, delta=delta), options.prestretch)
        rom = build_rom(ps, fmap.rom.modes, force_table=False)
        fam = None if family is None else build_family(ps, rom, family.n, family.radial, jacobian_table=False)
        return fmap.with_rom(rom), fam
    return at


def _by_symmetry(options) -> bool:
    """A mixed mode set (axisymmetric and other modes) without ``families``: continued on the
    axisymmetric subspace with family blocks."""
    axisymmetric, blocks = symmetry_blocks(options.modes)
    return options.families is None and bool(blocks) and bool(axisymmetric)


def _full_layout(br, K, axisymmetric, blocks):
    """A branch of the axisymmetric modes with the family blocks of a mixed mode set, in the
    mixed set's layout: the asymmetric coordinates zero, the multipliers of the axisymmetric
    block and of every block of the set (``blocks``: its radial indices and the index of its
    family in the continuation; cosine and sine companions share one) together, by
    decreasing modulus."""
    N, Ka = br.value.size, len(axisymmetric)
    state = np.zeros((N, 2 * K))
    state[:, axisymmetric] = br.state[:, :Ka]
    state[:, [K + i for i in axisymmetric]] = br.state[:, Ka:]
    mu = [br.multipliers] + [br.family_multipliers[:, j, :2 * len(radial)] for radial, j in blocks]
    mu = np.concatenate(mu, axis=1)
    order = np.lexsort((-mu.imag, -np.abs(mu)), axis=-1)
    return replace(br, state=state, multipliers=np.take_along_axis(mu, order, axis=1),
                   family_multipliers=np.zeros((N, 0, 0)))


CONTINUATION = ContinuationAnalysis()


def _compile_shooting(modes, material: str) -> None:
    # Continuation.warmups: the shooting Newton iteration of a ROM of these modes and this law
    rom = opt.rom_for(Membrane(law=material), "analytic", modes)
    shoot(ForcedMap.from_loading(rom, Loading(30.0, 0.1, 0.05), steps=16), np.zeros(2 * rom.dof))
