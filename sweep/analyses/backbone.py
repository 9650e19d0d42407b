"""Analysis ``backbone``: frequency-amplitude relation of the free vibration (Figs. 9-12).

Per grid point (``delta``, ``delta_o``) and per target amplitude along ``point``:

* ``omega_nl`` -- frequency (rad/s) of the free periodic orbit whose maximum of
  ``|w(0.5 Re, 0, t)|`` equals ``amplitude``, by continuation (shooting) of the free
  periodic orbits of the undamped ROM (:func:`model.backbone.continue_free_orbits`);
* ``omega_peak`` -- the same by the peak-to-peak method of Nandakumar and Chatterjee on
  lightly damped free decays (:func:`model.backbone.peak_to_peak`), the method the paper
  applies to its finite element model (section 4.2);
* ``modal_amplitude`` (``point``, ``mode``) -- the modal amplitudes ``A_mn`` of the orbit in
  the paper's normalisation (Fig. 9), ``(q_k(trough of w) - q_k(peak of w)) / 2``, so that
  ``A_10 > 0`` (models with modes: the ROM);
* ``max_abs_u``, ``max_abs_v``, ``max_abs_w`` (``point``) -- the largest ``|u|``, ``|v|``,
  ``|w|`` (m) over the orbit and the membrane (the full model; ``max_abs_w`` alone with ``u``
  held);
* ``orbit_u``, ``orbit_w`` (``point``, ``orbit_phase``, ``orbit_radius``) -- with
  ``orbit_samples = N`` (models with in-plane motion): ``u`` and ``w`` (m) at ``N`` instants of
  one period of each orbit (``orbit_phase``: the fraction of the period, the first at rest at
  the largest deflection) and at :data:`ORBIT_RADII` equally spaced undeformed radii
  (``orbit_radius``: ``(rho - Ro) / (Re - Ro)``, 0 at the inner edge, 1 at the outer) (Fig. 8;
  ``v`` vanishes on these axisymmetric orbits);
* ``fe_omega``, ``fe_omega_spread``, ``fe_w_deviation``, ``fe_u_deviation`` (``point``,
  ``fe_radial``) -- with
  ``fe_check = {radial = [...], around, periods}`` (the full model with ``u`` free): the membrane on the
  two-dimensional finite-element meshes of ``radial`` P2 elements across and ``around``
  times as many around (:mod:`model.fe_motion`), integrated for ``periods`` periods from
  rest at each orbit's state; its frequency from the extrema of ``w`` at the probe and the
  range of its half periods' frequencies, and the largest deviations of ``w`` and ``u`` from the orbit along the ray ``theta = 0``
  (:func:`model.fe_motion.check_free_orbit`);
* ``fe_harmonic_w_deviation``, ``fe_harmonic_odd_deviation``, ``fe_harmonic_u_deviation``,
  ``fe_harmonic_v_deviation`` (``point``, ``fe_radial``) -- with ``fe_check.asymmetric = A``
  (m): the same meshes from rest at each orbit's deflection plus ``A`` times the lowest
  transverse mode of wave number ``n = fe_check.wave_number`` (default 1; largest ``|w|`` of
  ``A``), the in-plane fields relaxed to it (:meth:`model.full.harmonic.HarmonicFull.relaxed`),
  against the full model on the circumferential harmonics :data:`FE_HARMONICS` times ``n``
  (:mod:`model.full.harmonic`): the largest deviations of ``w``, of ``w(rho, theta) -
  w(rho, theta + pi / n)`` (twice its part on the odd multiples of ``n``: the asymmetric
  motion), of ``u`` and of ``v`` at the mesh's nodes over the instants
  (:func:`model.fe_motion.check_harmonic_motion`); and ``fe_harmonic_reference_w_error``,
  ``fe_harmonic_reference_odd_error``, ``fe_harmonic_reference_u_error``,
  ``fe_harmonic_reference_v_error`` (``point``): how far the harmonics' motion moves with
  the harmonics :data:`FE_MORE_HARMONICS` times ``n`` added, :data:`FE_MORE_RADIAL` radial
  functions per field added and half its step (:func:`model.fe_motion.reference_error`), to
  be read against the finest mesh's deviations;
* ``turn_amplitude``, ``turn_omega`` -- where the pseudo-arclength branch of free orbits
  (:func:`model.backbone.backbone_branch`) first turns back in amplitude (an internal
  resonance), NaN when it reaches the largest target without turning; targets beyond it
  are NaN;
* ``branch_amplitude``, ``branch_omega`` (``branch_point``) -- that branch as followed, through
  its turns, point by point along its arclength (NaN after its last point): what it does at
  internal resonances;
* ``omega_linear`` -- the small-amplitude limit of the model, and ``omega_bound`` -- the
  upper bound of Eq. (29) for the backbone's mode (the ROM's neo-Hookean law).

Options: :attr:`BackboneAnalysis.OPTIONS` (``docs/options.md``).  The status is
``not_converged`` when some target has no ``omega_nl`` or no ``omega_peak``; those entries
are NaN, and the message says where the branch turned.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np

from model.backbone import (MAX_BRANCH_POINTS, PEAK_CYCLES, backbone_branch, continue_free_orbits, decay_start,
                            linear_mode, peak_to_peak)
from model.free import FreeRom
from model.params import Membrane

from sweep.models.rom import rom_for

from . import options as opt
from .base import (DEFAULT_CONTEXT, STATUS_NOT_CONVERGED, STATUS_OK, Analysis, JobError, Variable, add_message,
                   check_keys)

#: Default amplitude targets: 1 mm to 0.4 m.
DEFAULT_AMPLITUDE = {"start": 1e-3, "stop": 0.4, "num": 40}
#: ``fe_check``'s defaults: elements around per element across, periods integrated.
FE_AROUND, FE_PERIODS = 4, 2
#: Instants per period at which ``fe_check`` compares the mesh with the full model.
FE_SAMPLES = 64
#: The circumferential harmonics of ``fe_check.asymmetric``'s model, in multiples of the wave
#: number n of its start: n and what its square and cube drive; the check refines them with
#: :data:`FE_MORE_HARMONICS` (times n), :data:`FE_MORE_RADIAL` radial functions per field and
#: half the step to measure what the truncations and the step contribute.
FE_HARMONICS = (0, 1, 2, 3)
FE_MORE_HARMONICS = (4, 5)
#: Radial functions per field the check's refined reference adds: an estimate of the radial
#: truncation's error.  From 24 functions, from the relaxed start, the changes of ``w``, its odd
#: part, ``u`` and ``v`` with 8 more are within a factor 1.5 of those with 24 more (delta 1.1
#: and 1.5, orbits of 0.02, 0.06 and 0.1 m plus 1 cm of n = 1).
FE_MORE_RADIAL = 8


def fe_harmonics(n: int, multiples=FE_HARMONICS) -> tuple[int, ...]:
    """``multiples`` (default :data:`FE_HARMONICS`) times the wave number ``n`` of
    ``fe_check.asymmetric``'s start: the circumferential harmonics of its model."""
    return tuple(k * n for k in multiples)


def half_turn(n: int) -> str:
    """``pi / n`` as the report and the variables write it (``pi`` for ``n = 1``): the turn
    by which the odd part ``w(theta) - w(theta + pi / n)`` of wave number ``n`` is taken."""
    return "pi" if n == 1 else f"pi / {n}"
#: Radii of ``orbit_u`` and ``orbit_w``, equally spaced from the inner to the outer edge (81:
#: ``rho = 0.55 Re``, the paper's Fig. 8 point, is one of them at ``delta_o = 0.2``).
ORBIT_RADII = 81


@dataclass(frozen=True)
class BackboneOptions:
    modes: tuple[tuple[int, int], ...]
    prestretch: str
    amplitude: tuple[float, float, int]
    peak_damping: float
    #: the job's material law (``[membrane] law``): the warmups compile its kernels
    material: str = "neo-hookean"
    #: whether the model has modes (``modal_amplitude``; the ROM)
    modal: bool = True
    #: the fields of ``max_abs_<field>`` (:meth:`sweep.models.base.Model.orbit_extents`)
    extents: str = ""
    #: instants per period of ``orbit_u``, ``orbit_w`` (0: none)
    orbit_samples: int = 0
    #: ``fe_check``: the meshes' radial elements, the elements around per radial one, the
    #: periods integrated, the asymmetric part's size (m; 0: none) and its wave number;
    #: ``((), 0, 0, 0.0, 1)``: no check
    fe_check: tuple[tuple[int, ...], int, int, float, int] = ((), 0, 0, 0.0, 1)

    @property
    def targets(self) -> np.ndarray:
        """Target amplitudes (m)."""
        return np.linspace(*self.amplitude)


class BackboneAnalysis(Analysis):
    """Backbone curves by shooting and by the peak-to-peak method."""

    name = "backbone"
    model_needs = ("free_vibration",)
    #: The option table ``[backbone]``: key -> description (docs/options.md).
    OPTIONS = {
        "modes": opt.MODES_HELP,
        "prestretch": "analytic (Eq. 21) | numeric (Eq. 15, default) | fit (Eq. 18)",
        "amplitude": "{start, stop, num}: target amplitudes max |w(0.5 Re, 0, t)| (m; default 1 mm to "
                     "0.4 m, 40 points)",
        "peak_damping": "damping c of the decays of the peak-to-peak method (N s/m^3, > 0; default 0.05)",
        "orbit_samples": f"N: u and w over one period of each free orbit at N instants and {ORBIT_RADII} radii, "
                         "orbit_u and orbit_w (Fig. 8; models with in-plane motion; default 0: none)",
        "fe_check": "{radial = [4, 8, 16], around = 4, periods = 2, asymmetric = 0, wave_number = 1}: each free "
                    "orbit's motion on "
                    "two-dimensional finite-element meshes of radial P2 elements across and around x radial around, "
                    "integrated for periods periods from rest at the orbit's state; fe_omega, fe_omega_spread, "
                    "fe_w_deviation, fe_u_deviation (the full model with u free; docs/validation.md, \"The "
                    "finite-element free vibration\"); with asymmetric = A (m), the same from the orbit's deflection "
                    "plus A times the lowest transverse mode of wave number n = wave_number, the in-plane fields "
                    "relaxed to it, against the full model on "
                    f"the harmonics {', '.join(map(str, FE_HARMONICS))} times n: fe_harmonic_w_deviation, "
                    "fe_harmonic_odd_deviation, fe_harmonic_u_deviation, fe_harmonic_v_deviation, and the harmonics' "
                    "own error, fe_harmonic_reference_<w, odd, u, v>_error (A in m; 0: no asymmetric check; "
                    "wave_number 1 to 8, 2 n dividing the elements around of every mesh)",
    }

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        check_keys(table, self.name, tuple(self.OPTIONS))
        opt.rom_only(table, self.name, context.model, ("modes",))
        model = context.model.model()
        inplane = model.provides("inplane_frequencies", context.model.options)
        samples = opt.number(table, self.name, "orbit_samples", 0, integer=True, low=0, high=4096)
        if samples and not inplane:
            raise JobError(f"{self.name}.orbit_samples", samples, "needs a model with in-plane motion ([model] kind "
                           "= \"full\", inplane = true); this job's model has none")
        fe_check = _fe_check_option(table.get("fe_check"), context) if "fe_check" in table else ((), 0, 0, 0.0, 1)
        return BackboneOptions(
            modes=opt.modes(table, self.name),
            prestretch=opt.prestretch(table, self.name, context),
            amplitude=opt.linspace(table, self.name, "amplitude", DEFAULT_AMPLITUDE, low=0.0,
                                   low_open=True, max_num=10_000),
            peak_damping=opt.number(table, self.name, "peak_damping", 0.05, low=0.0, low_open=True),
            material=membrane.law,
            modal=model.rom_features,
            extents=model.orbit_extents(context.model.options), orbit_samples=samples,
            fe_check=fe_check)

    def variables(self, options):
        P, K = options.amplitude[2], len(options.modes)
        return [
            Variable("amplitude", ("point",), (P,), "f8", "m",
                     "maximum of |w| at (rho, theta) = (0.5 Re, 0) over the free periodic orbit"),
            Variable("omega_nl", ("point",), (P,), "f8", "rad s-1",
                     "nonlinear free-vibration frequency, continuation of free periodic orbits"),
            Variable("omega_peak", ("point",), (P,), "f8", "rad s-1",
                     "nonlinear free-vibration frequency, peak-to-peak method on damped decays"),
            Variable("omega_linear", (), (), "f8", "rad s-1",
                     "small-amplitude limit of the backbone (linearised model)"),
            Variable("omega_bound", (), (), "f8", "rad s-1",
                     "upper bound of the frequency of the backbone's mode, Eq. 29 (the ROM's neo-Hookean law; "
                     "NaN otherwise)"),
            Variable("turn_amplitude", (), (), "f8", "m",
                     "amplitude where the branch of free periodic orbits first turns back (NaN: no turn "
                     "below the largest target)"),
            Variable("turn_omega", (), (), "f8", "rad s-1", "frequency there"),
            Variable("branch_amplitude", ("branch_point",), (MAX_BRANCH_POINTS,), "f8", "m",
                     "amplitude along the pseudo-arclength branch of free periodic orbits, through its turns "
                     "(NaN after its last point)"),
            Variable("branch_omega", ("branch_point",), (MAX_BRANCH_POINTS,), "f8", "rad s-1",
                     "frequency along that branch"),
        ] + ([Variable("modal_amplitude", ("point", "mode"), (P, K), "f8", "m",
                       "modal amplitude A_mn of the free periodic orbit (Eq. 31 normalisation)")]
             if options.modal else []) + (
            [Variable(f"max_abs_{f}", ("point",), (P,), "f8", "m",
                      f"largest |{f}| over the free periodic orbit and the membrane") for f in options.extents]) + (
            [Variable(f"orbit_{f}", ("point", "orbit_phase", "orbit_radius"), (P, options.orbit_samples, ORBIT_RADII),
                      "f8", "m", f"{name} over one period of the free periodic orbit")
             for f, name in (("u", "radial displacement u"), ("w", "transverse displacement w"))]
            if options.orbit_samples else []) + _fe_variables(options)

    def coords(self, options):
        orbit = {} if not options.orbit_samples else {
            "orbit_phase": (("orbit_phase",), np.arange(options.orbit_samples) / options.orbit_samples,
                            {"long_name": "time over the period of the free orbit, from rest at its largest "
                                          "deflection", "units": "1"}),
            "orbit_radius": (("orbit_radius",), np.linspace(0.0, 1.0, ORBIT_RADII),
                             {"long_name": "(rho - Ro) / (Re - Ro): the undeformed radius across the annulus",
                              "units": "1"})}
        if options.fe_check[0]:
            orbit["fe_radial"] = (("fe_radial",), np.array(options.fe_check[0], np.int32),
                                  {"long_name": "P2 elements across the annulus of the finite-element mesh "
                                                f"({options.fe_check[1]} times as many around)", "units": "1"})
        orbit["branch_point"] = (("branch_point",), np.arange(MAX_BRANCH_POINTS, dtype=np.int32),
                                 {"long_name": "index of the point along the branch of free orbits", "units": "1"})
        return {"point": (("point",), np.arange(options.amplitude[2], dtype=np.int32),
                          {"long_name": "index of the target amplitude", "units": "1"}),
                **(opt.mode_coords(options.modes) if options.modal else {}), **orbit}

    def warmups(self, options):
        return [partial(_compile_backbone, options.material)]

    def compute(self, point, options, subtask):
        free = point.model.free_vibration(point, options)
        targets = options.targets
        c = options.peak_damping
        starts = decay_start(free, targets, c, PEAK_CYCLES)  # the peak-to-peak method's orbits (several modes)
        branch = backbone_branch(free, float(starts.max()),
                                 targets=np.concatenate([targets, starts]) if free.dof > 1 else targets)
        orbits, _ = continue_free_orbits(free, targets, branch=branch)
        peaks = peak_to_peak(free, targets, c=c, branch=branch)
        turns = np.flatnonzero(branch.turning)
        turn = (branch.amplitude[turns[0]], branch.omega[turns[0]]) if turns.size else (np.nan, np.nan)
        ok = bool(orbits.converged.all() and peaks.converged.all())
        out = {"amplitude": targets,
               "omega_nl": orbits.omega,
               "omega_peak": peaks.omega,
               "omega_linear": linear_mode(free)[0],
               "omega_bound": getattr(free, "frequency_bound", lambda: np.nan)(),
               "turn_amplitude": turn[0], "turn_omega": turn[1],
               "branch_amplitude": _padded(branch.amplitude), "branch_omega": _padded(branch.omega),
               "status": STATUS_OK if ok else STATUS_NOT_CONVERGED}
        if not ok:
            where = (f"; the branch of free orbits turns back at {turn[0]:.6g} m, {turn[1]:.6g} rad/s"
                     if turns.size else f"; the branch of free orbits ends at {branch.amplitude[-1]:.6g} m")
            out["message"] = (f"{np.count_nonzero(~orbits.converged)} target(s) without a free periodic orbit, "
                              f"{np.count_nonzero(~peaks.converged)} without a peak-to-peak sample{where}")
        if options.modal:
            out["modal_amplitude"] = orbits.modal
        if options.extents:
            extent = np.full((targets.size, 3), np.nan)
            for j in np.flatnonzero(orbits.converged):
                extent[j] = free.extent(orbits.modal[j], 2.0 * np.pi / orbits.omega[j])
            out.update({f"max_abs_{f}": extent[:, "uvw".index(f)] for f in options.extents})
        if options.orbit_samples:
            shape = (targets.size, options.orbit_samples, ORBIT_RADII)
            out["orbit_u"], out["orbit_w"] = np.full(shape, np.nan), np.full(shape, np.nan)
            m = point.membrane
            rho = np.linspace(m.Ro, m.Re, ORBIT_RADII)
            for j in np.flatnonzero(orbits.converged):
                out["orbit_u"][j], out["orbit_w"][j] = free.snapshots(orbits.modal[j], 2.0 * np.pi / orbits.omega[j],
                                                                      options.orbit_samples, rho)
        if options.fe_check[0]:
            fe, problem = _fe_check(point, free, orbits, *options.fe_check)
            out.update(fe)
            if problem:
                out["status"] = STATUS_NOT_CONVERGED
                add_message(out, problem)
        return out


BACKBONE = BackboneAnalysis()


def _padded(values) -> np.ndarray:
    out = np.full(MAX_BRANCH_POINTS, np.nan)
    out[:values.size] = values
    return out


def _fe_check_option(value, context) -> tuple[tuple[int, ...], int, int, float, int]:
    """``fe_check = {radial = [...], around = A, periods = P, asymmetric = S, wave_number = n}``
    as ``(radial, A, P, S, n)``."""
    key = "backbone.fe_check"
    if context.model.kind != "full" or not context.model.options.inplane:
        raise JobError(key, value, "a check of the full model's orbits with in-plane motion ([model] kind = "
                       f"\"full\", inplane = true); this job's model is {context.model.kind!r}"
                       + ("" if context.model.kind != "full" else " with u held"))
    if not isinstance(value, dict):
        raise JobError(key, value, "a table {radial = [4, 8, 16], around = 4, periods = 2, asymmetric = 0, "
                                   "wave_number = 1}")
    check_keys(value, key, ("radial", "around", "periods", "asymmetric", "wave_number"))
    radial = value.get("radial", [4, 8, 16])
    what = "a non-empty list of distinct increasing element counts from 1 to 64"
    sizes = (opt.increasing(radial, f"{key}.radial", what, 1, 64) if isinstance(radial, list) else
             (opt.number(value, key, "radial", low=1, high=64, integer=True),))
    around = opt.number(value, key, "around", FE_AROUND, low=1, high=32, integer=True)
    if around * sizes[0] < 8:
        raise JobError(f"{key}.around", around, f"at least {-(-8 // sizes[0])} (8 elements around or more on "
                       f"the coarsest mesh of {sizes[0]} across)")
    asymmetric = opt.number(value, key, "asymmetric", 0.0, low=0.0, high=1.0)
    n = opt.number(value, key, "wave_number", 1, low=1, high=8, integer=True)
    if n != 1 and not asymmetric:
        raise JobError(f"{key}.wave_number", n, "1 without an asymmetric start: the wave number is that of "
                       "fe_check.asymmetric's start, which needs asymmetric > 0")
    allowed = [k for k in range(1, 9) if not any(around * r % (2 * k) for r in sizes)]
    if asymmetric and n not in allowed:
        raise JobError(f"{key}.wave_number", n, f"one of {', '.join(map(str, allowed))} with these meshes: 2 n must "
                       f"divide the elements around of every mesh ({', '.join(str(around * r) for r in sizes)}), "
                       "the odd part turning the mesh by pi / n")
    return (sizes, around, opt.number(value, key, "periods", FE_PERIODS, low=1, high=100, integer=True),
            asymmetric, n)


def _fe_variables(options) -> list[Variable]:
    if not options.fe_check[0]:
        return []
    dims, shape = ("point", "fe_radial"), (options.amplitude[2], len(options.fe_check[0]))
    n = options.fe_check[4]
    harmonics = ", ".join(map(str, fe_harmonics(n)))
    half_wave = half_turn(n)
    asymmetric = [
        Variable("fe_harmonic_w_deviation", dims, shape, "f8", "1", "from rest at the orbit's deflection plus "
                 f"fe_check.asymmetric times the lowest n = {n} transverse mode, the in-plane fields relaxed to "
                 "it: largest |w_fe - w| over the instants and the mesh's nodes, over the largest |w|, w of the "
                 f"full model on the harmonics {harmonics}"),
        Variable("fe_harmonic_odd_deviation", dims, shape, "f8", "1", "the same for the part on the odd "
                 f"multiples of {n}, w(rho, theta) - w(rho, theta + {half_wave}): the asymmetric motion alone"),
        Variable("fe_harmonic_u_deviation", dims, shape, "f8", "1", "the same for the radial displacement u"),
        Variable("fe_harmonic_v_deviation", dims, shape, "f8", "1", "the same for the circumferential "
                 "displacement v"),
        Variable("fe_harmonic_reference_w_error", ("point",), shape[:1], "f8", "1", "largest change of w over "
                 f"the instants and a polar grid, over the largest |w|, when the harmonics "
                 f"{', '.join(map(str, fe_harmonics(n, FE_MORE_HARMONICS)))} are added, {FE_MORE_RADIAL} more "
                 "radial functions per field taken and the step halved: the full model's own error in the "
                 "fe_harmonic_* comparisons"),
        Variable("fe_harmonic_reference_odd_error", ("point",), shape[:1], "f8", "1", "the same for "
                 f"w(rho, theta) - w(rho, theta + {half_wave})"),
        Variable("fe_harmonic_reference_u_error", ("point",), shape[:1], "f8", "1", "the same for u"),
        Variable("fe_harmonic_reference_v_error", ("point",), shape[:1], "f8", "1", "the same for v"),
    ] if options.fe_check[3] else []
    return [
        Variable("fe_omega", dims, shape, "f8", "rad s-1", "frequency of the motion on the finite-element mesh "
                 "from rest at the free orbit's state, from the instants of the extrema of w at the probe"),
        Variable("fe_omega_spread", dims, shape, "f8", "rad s-1", "range of the frequencies pi / (t_(k+1) - t_k) of "
                 "the half periods between those extrema (t_0 = 0, the start): a difference from omega_nl below it "
                 "is not resolved"),
        Variable("fe_w_deviation", dims, shape, "f8", "1", "largest |w_fe - w| over the instants and the radii "
                 "of the ray theta = 0, over the orbit's largest |w| there"),
        Variable("fe_u_deviation", dims, shape, "f8", "1", "the same for the radial displacement u"),
        *asymmetric,
    ]


def _fe_check(point, free, orbits, radial, around, periods, asymmetric, n) -> tuple[dict[str, np.ndarray], str]:
    """The outputs of ``fe_check`` (:func:`model.fe_motion.check_free_orbit`, and with
    ``asymmetric`` :func:`model.fe_motion.check_harmonic_motion` against the harmonics' motion
    from each orbit's deflection plus ``asymmetric`` (m) of the lowest mode of wave number ``n``,
    the in-plane fields relaxed to it on each discretisation of the harmonics, computed once
    per orbit) for the converged orbits (NaN elsewhere), and what went wrong ("" if nothing):
    the orbits whose relaxation did not converge keep NaN in the ``fe_harmonic_*`` outputs."""
    from model.fe_motion import (REFERENCE_STEP, ReferenceChange, asymmetric_start, check_free_orbit,
                                 check_harmonic_motion, harmonic_reference, reference_error)
    from model.full.harmonic import HarmonicFull
    from sweep.models.fe2d import fe_motion_for
    from sweep.models.full import axisymmetric_for

    names = ("fe_omega", "fe_omega_spread", "fe_w_deviation", "fe_u_deviation")
    harmonic_names = ("fe_harmonic_w_deviation", "fe_harmonic_odd_deviation", "fe_harmonic_u_deviation",
                      "fe_harmonic_v_deviation")
    out = {k: np.full((orbits.omega.size, len(radial)), np.nan)
           for k in names + (harmonic_names if asymmetric else ())}
    m = point.membrane
    rho = np.linspace(m.Ro, m.Re, ORBIT_RADII)
    converged = np.flatnonzero(orbits.converged)
    references = {}
    unrelaxed = []  # amplitudes (m) of the orbits whose asymmetric start did not relax
    if asymmetric:
        errors = tuple(f"fe_harmonic_reference_{field}_error" for field in ReferenceChange._fields)
        out.update({k: np.full(orbits.omega.size, np.nan) for k in errors})
        harmonic = HarmonicFull(free.model, fe_harmonics(n))
        finer = HarmonicFull(axisymmetric_for(m, free.model.order + FE_MORE_RADIAL, free.model.inplane),
                             fe_harmonics(n, FE_HARMONICS + FE_MORE_HARMONICS))
        for j in converged:
            period = 2.0 * np.pi / orbits.omega[j]
            try:
                start, finer_start = (h.relaxed(asymmetric_start(h, orbits.modal[j], asymmetric))
                                      for h in (harmonic, finer))
            except ArithmeticError:
                unrelaxed.append(float(orbits.amplitude[j]))
                continue
            references[j] = harmonic_reference(harmonic, start, period, periods, FE_SAMPLES)
            refined = harmonic_reference(finer, finer_start, period, periods, FE_SAMPLES, step=REFERENCE_STEP / 2)
            for name, value in zip(errors, reference_error(references[j], refined)):
                out[name][j] = value
    for k, r in enumerate(radial if converged.size else ()):
        motion = fe_motion_for(m, r, around * r)
        for j in converged:
            check = check_free_orbit(motion, free, orbits.modal[j], 2.0 * np.pi / orbits.omega[j], periods, rho,
                                     FE_SAMPLES)
            for name, value in zip(names, check):
                out[name][j, k] = value
            if j in references:
                for name, value in zip(harmonic_names, check_harmonic_motion(motion, references[j])):
                    out[name][j, k] = value
    problem = (f"fe_check.asymmetric: the in-plane fields did not relax to the start's deflection at "
               f"{', '.join(f'{a:.6g}' for a in unrelaxed)} m (fe_harmonic_* NaN there)" if unrelaxed else "")
    return out, problem


def _compile_backbone(material: str) -> None:
    # Backbone.warmups: the free-orbit continuation and the peak-to-peak integration
    free = FreeRom(rom_for(Membrane(law=material), "analytic", ((1, 0),)))
    continue_free_orbits(free, [1e-3], steps=8)
    peak_to_peak(free, [1e-3], cycles=2)
