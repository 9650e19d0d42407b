"""The continuation's asymmetric waves: standing waves by branch switching and rotating waves.

Two features of :mod:`sweep.analyses.branch_features`' kind, on the O(2) symmetry of a model
with a family's sine companions (:mod:`model.waves`; the maps' ``companions`` capability: the
ROM's sine modes, the full model's harmonics with their companions):

* :data:`BRANCH_SWITCHING` (``branch_switching``) -- the asymmetric branch born at the first
  branch point of a family (:func:`model.switching.follow_bifurcated_branch`), a branch of
  standing waves, with its stability within the cosine modes and with the companions (the group
  orbit's multiplier removed), and optionally a time integration from a perturbed standing wave;
* :data:`ROTATING_WAVES` (``rotating_waves``) -- the rotating waves born at the first
  Neimark-Sacker point of a family (:func:`model.waves.continue_rotating_waves`), with their
  drift and stability, and optionally a time integration from the unstable axisymmetric
  response perturbed towards a standing wave.

The time integrations (:func:`model.waves.wave_motion`) say what the motion settles to
without the continuation: a stable rotating wave is reached with its drift and size, a stable
standing wave with no drift.
"""

from __future__ import annotations

import numpy as np

from model.continuation import BRANCH_POINT, NEIMARK_SACKER
from model.families import embedded
from model.shooting import shoot
from model.switching import follow_bifurcated_branch
from model.waves import continue_rotating_waves, neimark_sacker_direction, standing_wave_stability, wave_motion

from . import options as opt
from .base import GRID_KEYS, JobError, Variable, blank_outputs
from .branch_features import BranchFeature, kind_attrs

#: Size (m, the norm of the family's cosine coordinates) of the standing pattern that starts a
#: check from an axisymmetric response, shaped as the family's critical Floquet mode, and the
#: fraction of it given to the sine coordinates (a standing wave, slightly turned out of the
#: reflection-symmetric subspace so that a rotating wave can take over).
CHECK_SIZE, CHECK_ODD = 1e-4, 1e-3
#: Relative size of the odd perturbation of a standing wave that starts its check: across the
#: group orbit (a radial profile that the rotation of the wave does not produce).
STANDING_KICK = 1e-2

_FLAGS = {"flag_values": np.array([-1, 0, 1], np.int8), "flag_meanings": "padding unstable stable"}


def _wave_option(table, section, key, families, n_optional) -> tuple[int, int, int]:
    """``{max_points = N, n = wave number, periods = P}`` -> ``(N, n, P)``, ``(0, 0, 0)``
    without the option; ``n_optional``: whether ``n`` may be left out."""
    value = table.get(key)
    if value is None:
        return 0, 0, 0
    name = f"{section}.{key}"
    if not isinstance(value, dict) or not {"max_points"} <= set(value) <= {"max_points", "n", "periods"}:
        optional = "n and periods" if n_optional else "periods"
        raise JobError(name, value, f"must be a table {{max_points = N, n = wave number, periods = P}} ({optional} "
                                    "optional)")
    if families is None:
        raise JobError(name, value, "needs continuation.families (the points are found in the families)")
    if not n_optional and "n" not in value:
        raise JobError(name, value, "needs n, the wave number of the family whose Neimark-Sacker point starts it")
    n = opt.number(value, name, "n", 0, integer=True, low=0 if n_optional else 1)
    if n and n not in families[0]:
        raise JobError(f"{name}.n", n, f"must be one of the families' wave numbers {list(families[0])}")
    points = opt.number(value, name, "max_points", integer=True, low=2, high=10_000)
    periods = opt.number(value, name, "periods", 0, integer=True, low=0, high=1_000_000)
    if 0 < periods < 20:
        raise JobError(f"{name}.periods", periods, "must be 0 (no time integration) or at least 20")
    return points, n, periods


def switching_option(table, section, families) -> tuple[int, int, int]:
    """The ``branch_switching = {max_points = N, n = wave number, periods = P}`` option:
    ``(N, n, P)`` (n = 0: the first branch point of any family; P = 0: no time integration),
    or ``(0, 0, 0)`` without it."""
    return _wave_option(table, section, "branch_switching", families, True)


def rotating_option(table, section, families) -> tuple[int, int, int]:
    """The ``rotating_waves = {max_points = N, n = wave number, periods = P}`` option:
    ``(N, n, P)``, or ``(0, 0, 0)`` without it."""
    return _wave_option(table, section, "rotating_waves", families, False)


def _check_variables(prefix: str, parameter: str, what: str) -> list[Variable]:
    """The outputs of one time-integration check (:class:`model.waves.WaveMotion`)."""
    return [
        Variable(f"{prefix}_check_{parameter}", (), (), "f8", GRID_KEYS[parameter][0],
                 f"{parameter} of the time integration {what}"),
        Variable(f"{prefix}_check_drift", (), (), "f8", "rad", "mean angle the pattern turns per forcing period "
                 "over the last tenth of the time integration"),
        Variable(f"{prefix}_check_drift_spread", (), (), "f8", "rad", "range of that angle over the samples"),
        Variable(f"{prefix}_check_wave_amplitude", (), (), "f8", "m", "mean size of the family's pattern, "
                 "sqrt(sum of squared cosine and sine coordinates), over the last tenth"),
        Variable(f"{prefix}_check_wave_spread", (), (), "f8", "1", "range of that size over the samples, "
                 "relative to its mean (0 for a rotating wave or a periodic standing wave)"),
    ]


def _run_check(out, prefix, parameter, value, o2, y0, n, periods) -> None:
    motion = wave_motion(o2, y0, n, periods)
    out[f"{prefix}_check_{parameter}"] = np.float64(value)
    out[f"{prefix}_check_drift"], out[f"{prefix}_check_drift_spread"] = motion.drift, motion.drift_spread
    out[f"{prefix}_check_wave_amplitude"], out[f"{prefix}_check_wave_spread"] = (motion.wave_amplitude,
                                                                               motion.wave_spread)


def _mode_variables(prefix: str, K: int) -> list[Variable]:
    return [
        Variable(f"{prefix}_mode_m", (f"{prefix}_mode",), (K,), "i4", "1", f"radial index m of the {prefix} ROM's "
                 "modes", -1),
        Variable(f"{prefix}_mode_n", (f"{prefix}_mode",), (K,), "i4", "1", f"wave number n of the {prefix} ROM's "
                 "modes (n < 0: the sine companion of |n|)", -1),
    ]


class BranchSwitching(BranchFeature):
    """``branch_switching``: the standing waves born at the first branch point of a family."""

    def enabled(self, options):
        return bool(options.switch_points)

    def variables(self, options):
        if not self.enabled(options):
            return []
        n, p, sp = options.switch_points, options.parameter, ("switched_point",)
        K = len(options.modes) + options.families[1]
        out = [
            Variable(f"switched_{p}", sp, (n,), "f8", GRID_KEYS[p][0],
                     f"{p} along the asymmetric branch bifurcating at the first branch point"),
            Variable("switched_amplitude", sp, (n,), "f8", "m", "max over one period of |w(0.5 Re, 0, t)|"),
            Variable("switched_asymmetric_amplitude", sp, (n,), "f8", "m",
                     "max over one period of the asymmetric part of w(0.5 Re, 0, t)"),
            Variable("switched_stable", sp, (n,), "i1", "1", "stability within the mixed model: the ROM of the "
                     "axisymmetric and the family's cosine modes, or the full model's harmonics 0, n, 2n", -1, _FLAGS),
            Variable("switched_point_type", sp, (n,), "i1", "1", "kind of point on the asymmetric branch", -1,
                     kind_attrs()),
            Variable("switched_multiplier_modulus", sp, (n,), "f8", "1", "largest Floquet multiplier modulus"),
        ]
        out += [
            Variable("switched_odd_multiplier_modulus", sp, (n,), "f8", "1", "largest multiplier modulus of the "
                     "perturbations in the family's sine companions, the group orbit's multiplier 1 removed"),
            Variable("switched_neutral_multiplier", sp, (n,), "f8", "1", "the group orbit's multiplier as computed "
                     "(1 up to the symmetry error of the model's discretisation)"),
            Variable("switched_stable_o2", sp, (n,), "i1", "1", "stability with the family's sine companions "
                     "(O(2)): the ROM's sine modes or the full model's harmonics' companions, the group orbit's "
                     "multiplier removed", -1, _FLAGS),
        ]
        if options.switch_periods:
            out += _check_variables("switched", p, "from the last standing wave with a small perturbation in the "
                                    "sine companions")
        if options.rom_features:
            out += [
                Variable("switched_modal_coordinate", ("switched_point", "switched_mode"), (n, K), "f8", "m",
                         "modal coordinates on the stroboscopic section (modes: switched_mode_m, switched_mode_n)"),
                *_mode_variables("switched", K),
            ]
        return out

    def coords(self, options):
        if not self.enabled(options):
            return {}
        return {"switched_point": (("switched_point",), np.arange(options.switch_points, dtype=np.int32),
                                   {"long_name": "index along the switched (asymmetric) branch", "units": "1"})}

    def compute(self, ctx):
        """The outputs, and "" as the problem also when the branch has no branch point of a family."""
        options, br, fmap = ctx.options, ctx.branch, ctx.fmap
        out = blank_outputs(self.variables(options))
        n, p, K = options.switch_points, options.parameter, len(options.modes) + options.families[1]
        bps = [i for i in np.flatnonzero(br.kind == BRANCH_POINT)
               if br.family[i] > 0 and options.switch_family in (0, br.family[i])]
        if not bps:
            return out, ""
        i = bps[0]
        family = next(f for f in ctx.families if f.n == br.family[i])
        try:
            sw, fmap_mixed, asym = follow_bifurcated_branch(fmap, family, p, options.start, options.stop,
                                                            br.state[i], br.value[i], ds_max=options.ds_max,
                                                            max_points=n)
        except (RuntimeError, ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            return out, f"branch switching at {p} = {br.value[i]:.9g}: {type(exc).__name__}: {exc}"
        m = sw.value.size
        out[f"switched_{p}"][:m], out["switched_amplitude"][:m] = sw.value, sw.amplitude
        out["switched_asymmetric_amplitude"][:m], out["switched_stable"][:m] = asym, sw.stable
        out["switched_point_type"][:m] = sw.kind
        out["switched_multiplier_modulus"][:m] = np.abs(sw.multipliers).max(axis=1)
        problems = [] if sw.complete or m >= n else [f"switched branch: {sw.message}"]
        if getattr(fmap, "companions", None) is None:  # the O(2) outputs stay padding
            problems.append("standing waves in O(2): this model's maps have no sine companions (the companions "
                            "capability)")
        else:
            try:
                self._o2(out, options, fmap.varied(p, sw.value[0]), family, sw)
            except (RuntimeError, ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
                problems.append(f"standing waves in O(2): {type(exc).__name__}: {exc}")
        if options.rom_features:
            out["switched_modal_coordinate"][:m] = sw.state[:, :K]
            modes = np.array(fmap_mixed.rom.modes, dtype=np.int32)
            out["switched_mode_m"], out["switched_mode_n"] = modes[:, 0], modes[:, 1]
        return out, "; ".join(problems)

    @staticmethod
    def _o2(out, options, fmap, family, sw) -> None:
        """The standing waves' stability with the sine companions (of ``fmap`` at the branch
        point: its RK4 step is checked against the companions' damped motion there), and the
        check."""
        p, m = options.parameter, sw.value.size
        o2 = fmap.companions(family)
        out["switched_stable_o2"][:m] = 0  # as switched_stable: a located point is not stable
        for k in range(m):
            y = embedded(sw.state[k], o2.fmap.dof)
            if not np.any(o2.generator @ y):
                continue  # the branch point itself: axisymmetric, its group orbit a point
            st = standing_wave_stability(o2._replace(fmap=o2.fmap.varied(p, sw.value[k])), y)
            out["switched_odd_multiplier_modulus"][k] = np.abs(st.odd).max()
            out["switched_neutral_multiplier"][k] = st.neutral
            out["switched_stable_o2"][k] = st.stable and sw.kind[k] == 0
        if options.switch_periods and m > 1:
            y = embedded(sw.state[m - 1], o2.fmap.dof)
            # companions with alternating signs over the family's coordinates: not along the
            # group orbit (the standing wave turned), whose companions are n times its cosines
            y[o2.sine] = STANDING_KICK * np.abs(y[o2.cosine]).max() * (-1.0) ** np.arange(o2.sine.size)
            _run_check(out, "switched", p, sw.value[m - 1], o2._replace(fmap=o2.fmap.varied(p, sw.value[m - 1])), y,
                       family.n, options.switch_periods)


class RotatingWaves(BranchFeature):
    """``rotating_waves``: the rotating waves born at the first Neimark-Sacker point of a family."""

    def enabled(self, options):
        return bool(options.rotating[0])

    def variables(self, options):
        if not self.enabled(options):
            return []
        (n, family, periods), p, rp = options.rotating, options.parameter, ("rotating_point",)
        K = len(options.modes) + 2 * options.families[1]
        out = [
            Variable(f"rotating_{p}", rp, (n,), "f8", GRID_KEYS[p][0],
                     f"{p} along the rotating waves bifurcating at the first Neimark-Sacker point of the family"),
            Variable("rotating_amplitude", rp, (n,), "f8", "m", "max over one period of |w(0.5 Re, 0, t)| (depends "
                     "on the wave's orientation, which the continuation fixes arbitrarily; rotating_wave_amplitude "
                     "does not)"),
            Variable("rotating_wave_amplitude", rp, (n,), "f8", "m", "size of the family's pattern, sqrt(sum of "
                     "squared cosine and sine coordinates), constant along a rotating wave"),
            Variable("rotating_drift", rp, (n,), "f8", "rad", "angle the pattern turns per forcing period"),
            Variable("rotating_stable", rp, (n,), "i1", "1", "stability with the family's sine companions (O(2)): "
                     "the ROM's sine modes or the full model's harmonics' companions, the group orbit's multiplier "
                     "removed", -1, _FLAGS),
            Variable("rotating_multiplier_modulus", rp, (n,), "f8", "1", "largest Floquet multiplier modulus in "
                     "the rotating frame, the group orbit's multiplier 1 removed"),
            Variable("rotating_neutral_multiplier", rp, (n,), "f8", "1", "the group orbit's multiplier as "
                     "computed (1 up to the symmetry error of the model's discretisation)"),
        ]
        if options.rom_features:
            out += [
                Variable("rotating_modal_coordinate", ("rotating_point", "rotating_mode"), (n, K), "f8", "m",
                         "modal coordinates on the stroboscopic section (modes: rotating_mode_m, rotating_mode_n)"),
                *_mode_variables("rotating", K),
            ]
        if periods:
            out += _check_variables("rotating", p, f"from the axisymmetric response perturbed towards a standing "
                                    f"wave of family {family}")
        return out

    def coords(self, options):
        if not self.enabled(options):
            return {}
        return {"rotating_point": (("rotating_point",), np.arange(options.rotating[0], dtype=np.int32),
                                   {"long_name": "index along the rotating waves", "units": "1"})}

    def compute(self, ctx):
        options, br, fmap = ctx.options, ctx.branch, ctx.fmap
        (n, wave_number, periods), p = options.rotating, options.parameter
        out = blank_outputs(self.variables(options))
        ns = [i for i in np.flatnonzero(br.kind == NEIMARK_SACKER) if br.family[i] == wave_number]
        if not ns:
            return out, ""
        if getattr(fmap, "companions", None) is None:
            return out, "rotating waves: this model's maps have no sine companions (the companions capability)"
        i = ns[0]
        family = next(f for f in ctx.families if f.n == wave_number)
        try:
            rw, o2 = continue_rotating_waves(fmap, family, p, options.start, options.stop, br.state[i], br.value[i],
                                             ds_max=options.ds_max, max_points=n)
        except (RuntimeError, ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            return out, f"rotating waves at {p} = {br.value[i]:.9g}: {type(exc).__name__}: {exc}"
        m = rw.value.size
        out[f"rotating_{p}"][:m], out["rotating_amplitude"][:m] = rw.value, rw.amplitude
        out["rotating_wave_amplitude"][:m], out["rotating_drift"][:m] = rw.wave_amplitude, rw.drift
        out["rotating_stable"][:m] = rw.stable
        out["rotating_multiplier_modulus"][:m] = np.abs(rw.multipliers).max(axis=1)
        out["rotating_neutral_multiplier"][:m] = rw.neutral
        if options.rom_features:
            out["rotating_modal_coordinate"][:m] = rw.state[:, :o2.fmap.dof]
            modes = np.array(o2.fmap.rom.modes, dtype=np.int32)
            out["rotating_mode_m"], out["rotating_mode_n"] = modes[:, 0], modes[:, 1]
        problems = [] if rw.complete or m >= n else [f"rotating waves: {rw.message}"]
        if periods and m > 1:
            k = _check_point(br, ctx.families.index(family), i, rw.value)
            if k is None:
                problems.append(f"rotating-wave check: no rotating wave where the axisymmetric response is unstable "
                                f"to n = {wave_number}")
            else:
                try:
                    problems += self._check(out, fmap, o2, family, p, rw.value[k], rw.state[k], periods)
                except (RuntimeError, ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
                    problems.append(f"rotating-wave check: {type(exc).__name__}: {exc}")
        return out, "; ".join(problems)

    @staticmethod
    def _check(out, fmap, o2, family, p, value, state, periods) -> list[str]:
        """From the axisymmetric response at ``value``, a standing perturbation with a trace of
        sine: which wave the motion settles to."""
        Ka, K = fmap.dof, o2.fmap.dof
        at = fmap.varied(p, value)
        axi = shoot(at, np.concatenate([state[:Ka], state[K:K + Ka]]))
        if not axi.converged:
            return [f"rotating-wave check: no axisymmetric response found at {p} = {value:.9g}"]
        if np.abs(np.linalg.eigvals(at.family_monodromy(axi.state, family))).max() <= 1.0:
            return [f"rotating-wave check: the axisymmetric response found at {p} = {value:.9g} is stable to "
                    f"n = {family.n} (another of the coexisting responses)"]
        # the pattern of the family's complex Floquet mode nearest the unit circle (its real
        # part: a standing pattern in the family's own shape, not spread over every coefficient)
        shape = neimark_sacker_direction(at, axi.state, family)[0][:o2.cosine.size].real
        y = embedded(axi.state, K)
        y[o2.cosine] = CHECK_SIZE * shape / np.linalg.norm(shape)
        y[o2.sine] = CHECK_ODD * y[o2.cosine]
        _run_check(out, "rotating", p, value, o2._replace(fmap=o2.fmap.varied(p, value)), y, family.n, periods)
        return []


def _check_point(br, family_index: int, ns: int, values) -> int | None:
    """The rotating wave nearest the middle of the family's unstable interval of the
    axisymmetric branch that ends at the Neimark-Sacker point ``ns``: where the axisymmetric
    response is unstable, so that a time integration from it must settle elsewhere; None when
    no rotating wave lies in that interval (they bifurcate towards the stable side)."""
    intervals = br.unstable_intervals(family_index)
    if not intervals:
        return None
    ends = min(intervals, key=lambda ab: min(abs(ab[0] - br.value[ns]), abs(ab[1] - br.value[ns])))
    lo, hi = min(ends), max(ends)  # a branch may run backwards in the parameter
    inside = np.flatnonzero((values > lo) & (values < hi))
    if inside.size == 0:
        return None
    return int(inside[np.argmin(np.abs(values[inside] - 0.5 * (lo + hi)))])


BRANCH_SWITCHING = BranchSwitching()
ROTATING_WAVES = RotatingWaves()
#: These features in the order of their outputs and of their computation.
WAVE_FEATURES = (BRANCH_SWITCHING, ROTATING_WAVES)
