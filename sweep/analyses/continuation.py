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
  stroboscopic section ``t = 0 mod 2 pi / Omega`` (the paper's ``A_mn`` axes; for the full
  model the fit of ``w`` by the mode shapes, :func:`model.protocol.modal_section`);
* ``section_state`` (``point``, ``state``), for a model whose state is not its modal section
  (the full model: :meth:`sweep.models.base.Model.state_size`): the map's state on the
  section, from which shooting at that point restarts;
* ``amplitude`` (``point``): max over one period of ``|w(0.5 Re, 0, t)|`` (m);
* ``stable`` (``point``, int8): 1 stable, 0 unstable (and at located bifurcation points);
  with ``families``, stable means stable to the families' perturbations too;
* ``point_type`` (``point``, int8): 0 regular, 1 fold (saddle-node), 2 period doubling,
  3 Neimark-Sacker, 4 branch point (a family's multiplier crosses +1: symmetry breaking);
  bifurcation points are located to ~1e-10 in arclength and inserted;
* ``multiplier_real``, ``multiplier_imag`` (``point``, ``multiplier``): Floquet
  multipliers by decreasing modulus (the ``2K`` of largest modulus of a model with more
  coordinates than modes: the full model), and ``multiplier_modulus`` (``point``) the largest;
* ``fold_value``, ``fold_amplitude`` (``fold``, :data:`MAX_FOLDS` = 16 long, NaN padded):
  the first saddle-node points in branch order, and ``n_points``, ``n_folds`` (all of them);
* ``n_unlocated``: the bifurcations detected between two points but not located (a corrector
  failed, or a complex pair crossed the unit circle with no NS point located), not
  inserted and so not counted in ``point_type``, ``n_folds`` or ``fold_value``; ``message``
  names each, with the parameter at its two points.

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

Branch switching (``branch_switching = {max_points = N, n = 1, periods = P}``, with
``families``): at the first branch point of family n (of any family without ``n``) the
asymmetric branch, of standing waves, is followed (:mod:`model.switching`) for at most N points;
outputs over ``switched_point``: ``switched_<parameter>``, ``switched_amplitude``,
``switched_asymmetric_amplitude`` (the family's part of ``w(0.5 Re, 0)``), ``switched_stable``
(within the cosine modes), ``switched_point_type``, ``switched_multiplier_modulus``, the
stability with the family's sine companions added (:mod:`model.waves`):
``switched_odd_multiplier_modulus``, ``switched_neutral_multiplier`` (the group orbit's, 1)
and ``switched_stable_o2``, and ``switched_modal_coordinate`` with the modes
``switched_mode_m``/``switched_mode_n``.  With ``periods``, a time integration from the last
standing wave with a small perturbation in the sine companions: ``switched_check_<parameter>``,
``switched_check_drift`` (rad per period), ``switched_check_drift_spread``,
``switched_check_wave_amplitude`` (m) and ``switched_check_wave_spread``
(:func:`model.waves.wave_motion`).  Reaching N points is not a failure: the branch is
followed as far as asked.  On the full model (families in ``U, V, W`` on all its radial
functions) the branch is followed on the circumferential harmonics 0, n, 2n
(:mod:`model.full.harmonic`), ``switched_stable`` within them, ``switched_stable_o2`` and the
time integration with their sine companions (the same harmonics turned by a quarter period); the
modal coordinates are the ROM's alone.

Rotating waves (``rotating_waves = {max_points = N, n = 3, periods = P}``, with ``families``):
at the first Neimark-Sacker point of family n the rotating waves (:func:`model.waves.continue_rotating_waves`)
for at most N points, over ``rotating_point``: ``rotating_<parameter>``, ``rotating_amplitude``,
``rotating_wave_amplitude`` (m), ``rotating_drift`` (rad per period), ``rotating_stable``,
``rotating_multiplier_modulus``, ``rotating_neutral_multiplier`` and
``rotating_modal_coordinate`` with ``rotating_mode_m``/``rotating_mode_n`` (the sine companions
with negative n).  With ``periods``, a time integration from the axisymmetric response at the
rotating wave nearest the middle of the family's unstable interval (where the axisymmetric
response is unstable), perturbed towards a standing wave: ``rotating_check_*`` as for
branch switching.  On the full model (families in ``U, V, W`` on all its radial functions) the
rotating waves live on its harmonics 0, n, 2n with their sine companions, and the modal
coordinates are not reported.

Time-symmetry breaking (``symmetry_breaking = {max_points = N}``): at the first branch point of
the axisymmetric block, the responses without the half-period symmetry for at most N points,
with the families' multipliers: ``broken_*`` over ``broken_point``
(:mod:`sweep.analyses.time_symmetry`).

Brute-force check (``family_check = {values = [40, 44], periods = 100, saturate = 0,
classify = 0}``, with ``families``): at the resonant responses (the stretch from ``start`` to the first
saddle-node) nearest each value, each family's mixed model is integrated from the orbit plus
1e-9 m in the family's coordinates (:func:`model.families.perturbation_growth`): the ROM's
axisymmetric modes plus the family's (2-D quadrature), or the full model on the
circumferential harmonics 0, n and 2n (:mod:`model.full.harmonic`; families in ``U, V, W``
on all the model's radial functions), or on 0, n, ..., K n with ``harmonics = K`` (2 to 6;
``check_highest_harmonic``, ``family``, says which): ``check_growth`` (``check``,
``family``), the growth per period, against ``check_floquet_modulus``; with ``saturate``
the asymmetric amplitude reached, ``check_asymmetric_amplitude``, and the width of the range
of its stroboscopic samples, ``check_asymmetric_spread`` (zero for a period-one state); with
``classify = L`` (needs ``saturate``) the state reached is iterated L periods more with the
Lyapunov spectrum of the mixed model's map and classified as a bifurcation diagram's points are
(:func:`model.lyapunov.classify`, periods up to 16): ``check_lyapunov_exponent`` and
``check_lyapunov_error`` (the largest exponent, s-1), ``check_lyapunov_sum`` (the sum of all:
the flow's ``-2 alpha dof`` under a mass-proportional damping, lower on the full model, whose
RK4 step damps the in-plane modes it does not resolve), ``check_kind`` (flags: periodic,
quasi-periodic, chaotic, ...), ``check_kind_period`` and ``check_rotation_number``.

Parametric thresholds (``tongues = true``, with ``families``; the ROM): at every point and
for every family, ``tongue_threshold`` (``point``, ``family``): the smallest scale ``s`` of the
orbit's stiffness modulation (``mean + s (S(t) - mean)``) at which the family's block reaches
the unit circle (below 1 at the points where the family is unstable), and
``tongue_threshold_averaged``, the same by first-order averaging (:mod:`model.tongues`), with
the resonance ``p Omega ~ omega_i + omega_j`` the averaging finds lowest: ``tongue_harmonic``,
``tongue_modes``, ``tongue_frequencies``, ``tongue_rates`` (``tongue_pair``: i, j),
``tongue_depth`` and ``tongue_detuning``.

Curves of bifurcation points (``bifurcation_curves = {parameter = "P0", start = 0.2, stop =
2.0}``): every located point of the branch (up to
:data:`sweep.analyses.branch_features.MAX_CURVES`) is followed in the
second parameter (``c``, ``delta`` or the forcing parameter not continued) from the task's
value towards ``start`` and towards ``stop`` (:func:`model.codim2.continue_curve`; in
``delta`` the model rebuilds its pre-stretch, map and family at every value met, the ROM's or
the full model's); outputs ``curve_<second>``, ``curve_<parameter>``,
``curve_amplitude`` (``curve``, ``curve_point``, NaN padded), ``curve_kind`` and
``curve_family`` (``curve``).  A curve that does not reach both ends makes the task
``not_converged`` with the reason.

Fold loci by two-parameter continuation (Fig. 17): ``fold_curve = {parameter = "c",
start = 0.05, stop = 3.0}`` follows the first saddle-node of the branch as the second
parameter (``c``, or the forcing parameter not continued) goes from ``start`` towards
``stop``, through the cusps where two saddle-nodes merge (:mod:`model.codim2`).  Outputs
``fold_curve_<second>``, ``fold_curve_<parameter>``, ``fold_curve_amplitude``
(``curve_point``, ``max_points`` long, NaN padded) and ``cusp_<second>``,
``cusp_<parameter>`` (``cusp``, :data:`sweep.analyses.branch_features.MAX_CUSPS` long, NaN padded).

Fold loci versus damping by extrapolation (without ``fold_curve``): put ``c`` in the grid
(a dense list).  When ``c`` has three or more values and ``parameter = "P0"``, :meth:`ContinuationAnalysis.derived` adds,
per combination of the other grid keys, the cusp where the two folds merge
(:func:`model.continuation.cusp_from_folds`): ``cusp_c`` (N s/m^3) and ``cusp_value``
(Pa).  The status is ``ok`` when the branch reached ``stop``, ``not_converged`` otherwise
(``message`` says why), ``failed`` when a state on the branch is not finite.  A bifurcation
detected between two points but not located (:attr:`model.continuation.Branch.unlocated`) is
not inserted: ``n_unlocated`` counts them and ``message`` names each, with the two values of
the parameter between which it lies, whatever the status.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from model.continuation import FOLD, KIND_LABELS, KIND_NAMES, NEIMARK_SACKER, continue_orbits, cusp_from_folds
from model.families import symmetry_blocks
from model.forced import DEFAULT_STEPS, ForcedMap
from model.params import Loading, Membrane
from model.protocol import modal_section
from model.shooting import shoot

from sweep.models.rom import rom_for

from . import options as opt
from .base import (DEFAULT_CONTEXT, GRID_KEYS, STATUS_FAILED, STATUS_NOT_CONVERGED, STATUS_OK, Analysis, JobError, Variable,
                   add_message, blank_outputs, check_keys)
from .branch_features import (BRANCH_FEATURES, BranchContext, FamilyCheckOption, by_symmetry, curves_option,
                              family_check_option, family_radials, second_parameter, tongues_option)
from .time_symmetry import TIME_SYMMETRY_FEATURES, symmetry_breaking_option
from .wave_features import WAVE_FEATURES, rotating_option, switching_option

#: The optional features, in the order of their outputs and of their computation.
FEATURES = BRANCH_FEATURES + WAVE_FEATURES + TIME_SYMMETRY_FEATURES

#: Length of the ``fold`` dimension: the first saddle-nodes of a branch (``n_folds`` counts
#: them all; ``point_type`` marks every one). The full model's Fig. 15a branch has 8.
MAX_FOLDS = 16


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
    #: the asymmetric families (wave numbers, radial functions per family: a count or the
    #: counts of a study, in-plane fields or not)
    families: opt.FamiliesOption | None = None
    bifurcation_curves: tuple[str, float, float] | None = None
    switch_points: int = 0
    switch_family: int = 0
    #: periods of the time integration from a perturbed standing wave (0: none)
    switch_periods: int = 0
    check: FamilyCheckOption | None = None
    #: the families' parametric thresholds at every point (``tongues = true``)
    tongues: bool = False
    #: the job's material law (``[membrane] law``): the warmups compile its kernels
    material: str = "neo-hookean"
    #: ``rotating_waves``: (max_points, wave number, periods of the check); (0, 0, 0) without
    rotating: tuple[int, int, int] = (0, 0, 0)
    #: ``symmetry_breaking``: points of the branch without the half-period symmetry (0: none)
    broken_points: int = 0
    #: whether the job's model is the ROM (:attr:`sweep.models.base.Model.rom_features`): the
    #: switched and rotating waves' modal coordinates
    rom_features: bool = False
    #: the size of the map's state when it is not its modal section (the full model), stored
    #: as ``section_state``; 0: not stored (:meth:`sweep.models.base.Model.state_size`)
    state_size: int = 0


#: Arclength (scaled unknowns: the parameter range is 1, 0.05 m of displacement is 1) that
#: the default ``max_points`` covers at steps of ``ds_max``.  The Fig. 14 branches (delta =
#: 1.1, 1.5, 2.0; P0 = 1 Pa, c = 0.05 N s/m^3, Omega 25..55 rad/s) are about 96, 170 and 290
#: long (885, 1614 and 2873 points at ds_max = 0.1; 319, 563 and 980 at 0.3).
BRANCH_ARCLENGTH = 400


class ContinuationAnalysis(Analysis):
    """Pseudo-arclength continuation of periodic responses in Omega or P0 (Figs. 14-17)."""

    name = "continuation"
    model_needs = ("forced_map",)
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
        "branch_switching": "{max_points = N, n = wave number, periods = P}: at the first branch point of family n "
                            "(of any family without n) on the branch, switch onto the bifurcating asymmetric branch "
                            "(standing waves) and follow it for at most N points in the ROM of the axisymmetric "
                            "modes plus the family's cosine modes (the full model: its harmonics 0, n, 2n, families "
                            "in U, V, W on all its radial functions); its stability also with the sine companions "
                            "(O(2)); with P >= 20, P periods of time integration from the last standing wave with a "
                            "small perturbation in the sine companions (needs families; default none)",
        "rotating_waves": "{max_points = N, n = wave number, periods = P}: at the first Neimark-Sacker point of "
                          "family n on the branch, follow the rotating waves (periodic in a turning frame) for at "
                          "most N points in the ROM of the axisymmetric modes plus the family's cosine and sine "
                          "modes (the full model: its harmonics 0, n, 2n with their sine companions, families in "
                          "U, V, W on all its radial functions), with their drift per period and stability; with P >= 20, P periods of time "
                          "integration from the axisymmetric response at the one nearest the middle of the "
                          "family's unstable interval, perturbed towards a standing wave (needs families; default none)",
        "family_check": "{values = [..], periods = 100, saturate = 0, classify = 0, harmonics = 2}: brute-force check of the families' "
                        "stability at the resonant responses nearest these parameter values: growth per period of "
                        "a small asymmetric perturbation in the nonlinear mixed model (the ROM: axisymmetric + family "
                        "modes, 2-D quadrature; the full model: circumferential harmonics 0, n, 2n, or 0, n, ..., K n "
                        "with harmonics = K (2 to 6; RK4's step must stay stable on the harmonic K n at continuation.start), "
                        "families in U, V, W on all its radial functions) against the Floquet multiplier; with saturate = N, N periods "
                        "more and the asymmetric amplitude reached; with classify = L (a multiple of 10, at least 40, "
                        "needs saturate), L periods more with the Lyapunov spectrum and the kind of the state reached "
                        "(periodic, quasi-periodic, chaotic, ...) (needs families; default none)",
        "families": "{n = [wave numbers], radial = M}: Floquet multipliers of the asymmetric mode families "
                    "(radial modes 1..M of each n) along the axisymmetric branch; branch points, period "
                    "doublings and Neimark-Sacker points of each family are located (default none; needs "
                    "axisymmetric modes); radial = [M1, M2, ..] is a convergence study: every family at every "
                    "count, along a dimension family_radial; the full model ([model] kind = \"full\"): the first M "
                    "functions of its basis per field (M <= order), the perturbations in (U, V, W), or W alone "
                    "with inplane = false (the ROM's families are W alone)",
        "symmetry_breaking": "{max_points = N}: at the first branch point of the axisymmetric block (a response "
                             "symmetric in time, w(t + T/2) = -w(t), giving way to responses without that "
                             "symmetry), switch onto the new branch and follow it for at most N points, with the "
                             "families' multipliers along it; past the point where it meets the symmetric branch "
                             "again it goes on along its image under the symmetry (default none)",
        "tongues": "true: at every point and for every family, the smallest scale of the orbit's stiffness "
                   "modulation that destabilises the family (Floquet multipliers of the scaled block) and the "
                   "same by first-order averaging, with the resonance p Omega ~ omega_i + omega_j it finds "
                   "lowest (needs families; ROM only; default false)",
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
        opt.rom_only(table, s, context.model, ("tongues",))
        if "families" in table and not context.model.model().provides("families"):
            raise JobError(f"{s}.families", table["families"], f"needs a model with asymmetric families; this "
                           f"job's model is {context.model.kind!r} ([model] kind)")
        families = opt.families(table, s, modes, context.model)
        rom = context.model.model().rom_features
        for key in ("family_check", "branch_switching", "rotating_waves"):
            if key in table and families is not None and not isinstance(families.radial, tuple) and not rom:
                order, _ = context.model.model().family_limits(context.model.options)
                if not families.inplane or families.radial != order:
                    raise JobError(f"{s}.{key}", table[key], "needs on this model the families in U, V, W on all "
                                   f"its radial functions (continuation.families: radial = {order}, inplane = "
                                   "true): the harmonics' blocks of the nonlinear model")
        opt.model_modes(s, context.model, modes)
        if families is not None and isinstance(families[1], tuple):  # a study in the radial modes
            for key in ("branch_switching", "rotating_waves", "family_check", "bifurcation_curves",
                        "symmetry_breaking"):
                if key in table:
                    raise JobError(f"{s}.{key}", table[key], "needs one radial count in continuation.families "
                                   "(radial = M), not a list")
        opt.damping_modes(context.damping, s, modes, families or any(n for _, n in modes))
        if "symmetry_breaking" in table and families is None and any(n for _, n in modes):
            raise JobError(f"{s}.modes", table.get("modes"), "must be axisymmetric (every n = 0) with "
                           "continuation.symmetry_breaking (the asymmetric modes go in continuation.families)")
        curves = curves_option(table, s, parameter, grid, context.damping)
        if curves is not None and curves[0] == "delta" and not context.model.model().provides("rebuilt"):
            raise JobError(f"{s}.bifurcation_curves", table["bifurcation_curves"],
                           f"curves in delta rebuild the model at each delta, which model {context.model.kind!r} "
                           "([model] kind) cannot")
        ds_max = opt.number(table, s, "ds_max", 0.1, low=0.0, low_open=True, high=1.0)
        return ContinuationOptions(
            parameter, start, stop, modes, opt.prestretch(table, s, context),
            opt.number(table, s, "max_points", math.ceil(BRANCH_ARCLENGTH / ds_max), low=2, high=100_000,
                       integer=True),
            ds_max,
            opt.steps(table, s, DEFAULT_STEPS, low=16),
            second_parameter(table, s, parameter, context.damping), families,
            curves, *switching_option(table, s, families),
            family_check_option(table, s, context.model), tongues_option(table, s), membrane.law,
            rotating_option(table, s, families), symmetry_breaking_option(table, s), rom,
            context.model.model().state_size(context.model.options))

    def variables(self, options):
        return [v for feature in FEATURES for v in feature.variables(options)] + self._branch_variables(options)

    @staticmethod
    def _branch_variables(options):
        n, k, p = options.max_points, 2 * len(options.modes), options.parameter
        K = len(options.modes)
        units, what = GRID_KEYS[p]
        pt = ("point",)
        return [
            Variable(p, pt, (n,), "f8", units, f"continued parameter: {what}"),
            Variable("amplitude", pt, (n,), "f8", "m", "max over one period of |w(0.5 Re, 0, t)|"),
            Variable("modal_coordinate", ("point", "mode"), (n, K), "f8", "m",
                     "modal coordinate q_mn on the stroboscopic section t = 0 mod 2 pi / Omega (A_mn axis)"),
            Variable("modal_velocity", ("point", "mode"), (n, K), "f8", "m s-1",
                     "modal velocity dq_mn/dt on the stroboscopic section t = 0 mod 2 pi / Omega"),
            *([Variable("section_state", ("point", "state"), (n, options.state_size), "f8", "m, m s-1",
                         "the map's state on the stroboscopic section (the full model: the Legendre-Galerkin "
                         "coefficients of u then w, or of w alone with u held, times Re, then their rates), "
                         "from which shooting restarts")]
              if options.state_size else []),
            Variable("stable", pt, (n,), "i1", "1", "stability of the periodic response", -1,
                     {"flag_values": np.array([-1, 0, 1], np.int8), "flag_meanings": "padding unstable stable"}),
            Variable("point_type", pt, (n,), "i1", "1", "kind of point on the branch", -1,
                     {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
                      "flag_meanings": "padding " + " ".join(KIND_NAMES)}),
            Variable("multiplier_real", ("point", "multiplier"), (n, k), "f8", "1",
                     "real part of the Floquet multipliers of largest modulus, by decreasing modulus"),
            Variable("multiplier_imag", ("point", "multiplier"), (n, k), "f8", "1",
                     "imaginary part of the Floquet multipliers of largest modulus, by decreasing modulus"),
            Variable("multiplier_modulus", pt, (n,), "f8", "1", "largest Floquet multiplier modulus"),
            Variable("fold_value", ("fold",), (MAX_FOLDS,), "f8", units, f"{p} at the saddle-node points"),
            Variable("fold_amplitude", ("fold",), (MAX_FOLDS,), "f8", "m", "amplitude at the saddle-node points"),
            Variable("n_points", (), (), "i4", "1", "points on the branch", -1),
            Variable("n_folds", (), (), "i4", "1", "saddle-node points on the branch (located ones)", -1),
            Variable("n_unlocated", (), (), "i4", "1", "bifurcations detected between two points but not "
                     "located (not in point_type, n_folds, fold_value; the message names them)", -1),
            Variable("rk4_steps", (), (), "i4", "1", "RK4 steps per forcing period", 0),
        ]

    def coords(self, options):
        features = {}
        for feature in FEATURES:
            features.update(feature.coords(options))
        return {
            **features,
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
        reduced = by_symmetry(options)
        modes = tuple(options.modes[i] for i in axisymmetric) if reduced else options.modes
        fmap = point.model.forced_map(point, options, modes, DEFAULT_STEPS).varied(options.parameter, options.start)
        steps = getattr(fmap, "steps", 0)
        if reduced:
            # a sine block with the radial indices of a cosine block has its multipliers:
            # one family each, so that every point is located once
            unique = list(dict.fromkeys((n, radial) for n, radial, _ in blocks))
            families = point.model.families(point, options, modes, tuple(unique))
        elif options.families is not None:
            families = point.model.families(point, options, modes, tuple(
                (n, tuple(range(1, M + 1))) for M in family_radials(options) for n in options.families.n))
        else:
            families = ()
        br = continue_orbits(fmap, options.parameter, options.start, options.stop, ds_max=options.ds_max,
                             max_points=options.max_points, families=families)
        branch = br  # in the ROM's own coordinates, for the curves and branch switching
        if reduced:
            br = _full_layout(br, len(options.modes), axisymmetric,
                              [(radial, unique.index((n, radial))) for n, radial, _ in blocks])
        m = br.value.size
        K = len(options.modes)
        out = blank_outputs(self._branch_variables(options))
        out["rk4_steps"] = np.int32(steps)
        out[options.parameter][:m] = br.value
        out["amplitude"][:m] = br.amplitude
        section = modal_section(fmap, br.state)
        out["modal_coordinate"][:m], out["modal_velocity"][:m] = section[:, :K], section[:, K:]
        if options.state_size:
            out["section_state"][:m] = br.state
        out["stable"][:m] = br.stable
        out["point_type"][:m] = br.kind
        out["multiplier_real"][:m] = br.multipliers.real[:, :2 * K]
        out["multiplier_imag"][:m] = br.multipliers.imag[:, :2 * K]
        out["multiplier_modulus"][:m] = np.abs(br.multipliers).max(axis=1)
        folds = br.special(FOLD)[:MAX_FOLDS]
        out["fold_value"][:folds.size] = br.value[folds]
        out["fold_amplitude"][:folds.size] = br.amplitude[folds]
        out["n_points"] = np.int32(m)
        out["n_folds"] = np.int32(br.special(FOLD).size)
        out["n_unlocated"] = np.int32(len(br.unlocated))
        out["status"] = STATUS_OK if br.complete else STATUS_NOT_CONVERGED
        if not br.complete:
            out["message"] = (f"reached max_points = {options.max_points} (raise max_points)"
                              if m >= options.max_points else br.message)
        if not (np.all(np.isfinite(br.state)) and np.all(np.isfinite(br.amplitude))):
            out["status"], out["message"] = STATUS_FAILED, "non-finite periodic response on the branch"
        ctx = BranchContext(point, fmap, branch, br, families, options)
        problems = []
        for feature in FEATURES:
            if feature.enabled(options):
                outputs, problem = feature.compute(ctx)
                out.update(outputs)
                problems.append(problem)
        problem = "; ".join(p for p in problems if p)
        if problem and out["status"] == STATUS_OK:
            out["status"], out["message"] = STATUS_NOT_CONVERGED, problem
        if br.unlocated:
            add_message(out, _unlocated_message(br))
        return out

    def warmups(self, options):
        axisymmetric, _ = symmetry_blocks(options.modes)
        modes = tuple(options.modes[i] for i in axisymmetric) if by_symmetry(options) else options.modes
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


def _unlocated_message(br) -> str:
    """The bifurcations of ``br`` (a :class:`model.continuation.Branch`) detected but not
    located, for the task's message: the points' stability stands, an interval bounded there
    is known to the branch's spacing."""
    where = [f"{'complex pair crossing' if kind == NEIMARK_SACKER else KIND_LABELS[kind]}{f' of n = {n}' if n else ''} "
             f"between {br.parameter} = {a:.6g} and {b:.6g}" for kind, n, a, b in br.unlocated]
    return "not located (bounded by the neighbouring points): " + ", ".join(where)


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
    rom = rom_for(Membrane(law=material), "analytic", modes)
    shoot(ForcedMap.from_loading(rom, Loading(30.0, 0.1, 0.05), steps=16), np.zeros(2 * rom.dof))
