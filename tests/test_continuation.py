"""Pseudo-arclength continuation: linear limit, folds where a multiplier crosses +1,
agreement with independent shooting, the continuation analysis' options and output."""

import numpy as np
import pytest

from model.backbone import linear_mode
from model.free import FreeRom
from model.continuation import (BRANCH_POINT, FOLD, NEIMARK_SACKER, PERIOD_DOUBLING, REGULAR, continue_orbits,
                                cusp_from_folds, resonant_end, stable_amplitudes_at, unstable_intervals)
from model.forced import DEFAULT_STEPS, ForcedMap
from model.families import GROWTH_LIMIT
from model.lyapunov import PERIODIC, UNSETTLED
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom, force_jacobian
from model.shooting import shoot
from sweep.analyses.base import JobError
from sweep.analyses.continuation import CONTINUATION
from sweep.jobspec import grid_point

PAPER = Loading(Omega=33.5, P0=1.0, c=0.05)


@pytest.fixture(scope="module")
def rom():
    return build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0)])


@pytest.fixture(scope="module")
def p0_branch(rom):
    return continue_orbits(ForcedMap.from_loading(rom, PAPER), "P0", 0.0, 3.0, ds_max=0.3)


def test_linear_resonance_curve_in_omega(rom):
    # P0 = 1e-5 Pa: the response is linear; every point matches the closed-form FRF.
    ld = Loading(Omega=30.0, P0=1e-5, c=1.0)
    br = continue_orbits(ForcedMap.from_loading(rom, ld), "Omega", 30.0, 35.0, ds_max=0.1)
    jac = np.zeros((1, 1))
    force_jacobian(np.zeros(1), rom.tables, jac)
    w0sq = rom.tables.k_force[0] * jac[0, 0]
    cd = ld.c / (rom.membrane.Gamma * rom.membrane.h)
    frf = abs(rom.tables.load[0] * rom.tables.probe[0]) * 1e-5 / np.hypot(w0sq - br.value**2, cd * br.value)
    assert br.complete and br.value[0] == 30.0 and br.value[-1] == pytest.approx(35.0, abs=1e-12)
    assert np.all(np.diff(br.value) > 0) and br.stable.all() and not br.special(FOLD).size
    assert br.amplitude == pytest.approx(frf, rel=1e-4)


def test_p0_branch_has_two_folds_around_p0_1(p0_branch):
    # Fig. 15a: at delta = 1.1, Omega = 33.5, c = 0.05 the folds bracket P0 = 1.
    folds = p0_branch.special(FOLD)
    assert p0_branch.complete and folds.size == 2
    lo, hi = sorted(p0_branch.value[folds])
    assert lo < 1.0 < hi


def test_folds_are_where_a_multiplier_is_plus_one_and_stability_changes(p0_branch):
    br = p0_branch
    for i in br.special(FOLD):
        mu = br.multipliers[i]
        assert abs(mu[0] - 1.0) < 1e-8
        assert br.stable[i - 1] != br.stable[i + 1]
    regular = br.kind == REGULAR
    assert np.array_equal(br.stable[regular], np.abs(br.multipliers[regular]).max(axis=1) < 1)


def test_fold_value_is_the_extremum_of_the_branch(p0_branch):
    # Independent check of the location: no regular point passes the folds.
    br = p0_branch
    f1, f2 = br.special(FOLD)
    assert br.value[f1] >= br.value[: f2].max() - 1e-14
    assert br.value[f2] <= br.value[f1:].min() + 1e-14


def test_points_agree_with_shooting_and_stable_ones_with_time_integration(rom, p0_branch):
    br = p0_branch
    idx = np.flatnonzero(br.kind == REGULAR)[5::25]
    for i in idx:
        ld = Loading(Omega=33.5, P0=float(br.value[i]), c=0.05)
        orbit = shoot(ForcedMap.from_loading(rom, ld), br.state[i])
        assert orbit.iterations <= 1 and orbit.amplitude == pytest.approx(br.amplitude[i], rel=1e-9)
        if br.stable[i]:
            y = ForcedMap.from_loading(rom, ld).advance(br.state[i], periods=100)
            assert np.abs(y - br.state[i]).max() < 1e-8


def test_bad_arguments_are_rejected(rom):
    with pytest.raises(ValueError, match="parameter = 'c' is invalid: must be one of Omega, P0"):
        continue_orbits(ForcedMap.from_loading(rom, PAPER), "c", 0.0, 1.0)
    with pytest.raises(ValueError, match=r"\(start, stop\) = \(1.0, 1.0\) is invalid"):
        continue_orbits(ForcedMap.from_loading(rom, PAPER), "P0", 1.0, 1.0)
    with pytest.raises(ValueError, match="Omega must stay > 0"):
        continue_orbits(ForcedMap.from_loading(rom, PAPER), "Omega", 0.0, 1.0)
    with pytest.raises(ValueError, match="need 0 < ds_min <= ds <= ds_max"):
        continue_orbits(ForcedMap.from_loading(rom, PAPER), "P0", 0.0, 1.0, ds=1.0, ds_max=0.1)
    with pytest.raises(ValueError, match="max_points = 1 is invalid: must be >= 2"):
        continue_orbits(ForcedMap.from_loading(rom, PAPER), "P0", 0.0, 1.0, max_points=1)


def test_a_bifurcation_in_the_last_step_max_points_allows_is_recorded_unlocated(rom, p0_branch):
    # max_points ending the branch at the regular point just past the first fold: that step
    # has no room for the located fold, which is recorded between its two points instead
    fold = p0_branch.special(FOLD)[0]
    br = continue_orbits(ForcedMap.from_loading(rom, PAPER), "P0", 0.0, 3.0, ds_max=0.3, max_points=int(fold) + 1)
    assert not br.complete and br.value.size == fold + 1 and not br.special(FOLD).size
    assert br.unlocated == ((FOLD, 0, p0_branch.value[fold - 1], p0_branch.value[fold + 1]),)


def test_max_points_stops_and_says_so(rom):
    br = continue_orbits(ForcedMap.from_loading(rom, PAPER), "P0", 0.0, 3.0, max_points=5)
    assert br.value.size == 5 and not br.complete and "max_points = 5 reached" in br.message


GRID = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "Omega": np.array([33.5]),
        "c": np.array([0.05])}
MEMBRANE = Membrane()


@pytest.mark.parametrize("table, grid, message", [
    ({"start": 0.0, "stop": 1.0}, GRID, "continuation.parameter = <missing> is invalid: must be one of Omega, P0"),
    ({"parameter": "Omega", "start": 30.0, "stop": 40.0}, GRID,
     "continuation.parameter = 'Omega' is invalid: Omega is continued, so it must not also be a [grid] key"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0}, {k: v for k, v in GRID.items() if k != "c"},
     "grid.c = <missing> is invalid: continuation in P0 needs c (N s m-3) in [grid]"),
    ({"parameter": "P0", "start": -1.0, "stop": 1.0}, GRID, "continuation.start = -1.0 is invalid: must be >= 0.0"),
    ({"parameter": "P0", "start": 1.0, "stop": 1.0}, GRID,
     "continuation.stop = 1.0 is invalid: must differ from continuation.start"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "max_points": 1}, GRID,
     "continuation.max_points = 1 is invalid: must be >= 2"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "bogus": 1}, GRID,
     "continuation.bogus = 1 is invalid: unknown key"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": [1, 2]}, GRID,
     "continuation.families = [1, 2] is invalid: must be a table {n = [wave numbers >= 1], radial = "),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [0, 1], "radial": 2}}, GRID,
     "continuation.families.n = [0, 1] is invalid: must be a non-empty list of distinct integers >= 1"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 0}}, GRID,
     "continuation.families.radial = 0 is invalid: must be >= 1"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "modes": [[1, 0], [1, 1]]}, GRID,
     "continuation.modes = [[1, 0], [1, 1]] is invalid: must be axisymmetric (every n = 0) when families are given"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "branch_switching": {"max_points": 10}}, GRID,
     "continuation.branch_switching = {'max_points': 10} is invalid: needs continuation.families"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "branch_switching": {"max_points": 10, "n": 2}}, GRID,
     "continuation.branch_switching.n = 2 is invalid: must be one of the families' wave numbers [1]"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "bifurcation_curves": {"parameter": "P0", "start": 0, "stop": 1}},
     GRID, "continuation.bifurcation_curves.parameter = 'P0' is invalid: must be one of c, Omega"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "bifurcation_curves": {"parameter": "c", "start": 0.1, "stop": 1}},
     GRID, "the [grid] values of c must lie in [start, stop]; [0.05] do not"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "family_check": {"values": [float("nan")]}}, GRID,
     "continuation.family_check.values = [nan] is invalid: must be a list of 1 to 16 finite numbers"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "family_check": {"values": [0.5], "saturate": 100, "classify": 45}}, GRID,
     "continuation.family_check.classify = 45 is invalid: must be 0 or a multiple of 10 from 40 (twice the longest "
     "period looked for, 16)"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "family_check": {"values": [0.5], "classfy": 40}}, GRID,
     "continuation.family_check.classfy = 40 is invalid: unknown key; the keys of [continuation.family_check] are "
     "values, periods, saturate, classify, harmonics"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "family_check": {"values": [0.5], "harmonics": 3}}, GRID,
     "continuation.family_check.harmonics = 3 is invalid: needs a model with circumferential harmonics ([model] "
     "kind = \"full\"); this job's model is 'rom', whose mixed model is its axisymmetric and family modes"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "family_check": {"values": [0.5], "classify": 40}}, GRID,
     "continuation.family_check.classify = 40 is invalid: needs saturate > 0 (the transient before the "
     "classification)"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": [4, 2]}}, GRID,
     "continuation.families.radial = [4, 2] is invalid: an integer from 1 to 32, or a list of distinct increasing"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": [2, 40]}}, GRID,
     "continuation.families.radial = [2, 40] is invalid: an integer from 1 to 32, or a list of distinct"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": [2, 4]},
      "branch_switching": {"max_points": 10}}, GRID,
     "continuation.branch_switching = {'max_points': 10} is invalid: needs one radial count in continuation.families"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "rotating_waves": {"max_points": 10, "n": 1}}, GRID,
     "continuation.rotating_waves = {'max_points': 10, 'n': 1} is invalid: needs continuation.families"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "rotating_waves": {"max_points": 10}}, GRID,
     "continuation.rotating_waves = {'max_points': 10} is invalid: needs n, the wave number of the family"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "rotating_waves": {"max_points": 10, "n": 3}}, GRID,
     "continuation.rotating_waves.n = 3 is invalid: must be one of the families' wave numbers [1]"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "branch_switching": {"max_points": 10, "periods": 5}}, GRID,
     "continuation.branch_switching.periods = 5 is invalid: must be 0 (no time integration) or at least 20"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "rotating_waves": {"max_points": 10, "n": 1, "speed": 2}}, GRID,
     "is invalid: must be a table {max_points = N, n = wave number, periods = P} (periods optional)"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": 2},
      "branch_switching": {"points": 10}}, GRID,
     "is invalid: must be a table {max_points = N, n = wave number, periods = P} (n and periods optional)"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": [2, 4]},
      "rotating_waves": {"max_points": 10, "n": 1}}, GRID,
     "continuation.rotating_waves = {'max_points': 10, 'n': 1} is invalid: needs one radial count in "
     "continuation.families"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "symmetry_breaking": {"points": 10}}, GRID,
     "continuation.symmetry_breaking.points = 10 is invalid: unknown key (the table is {max_points = N})"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "symmetry_breaking": 10}, GRID,
     "continuation.symmetry_breaking = 10 is invalid: must be a table {max_points = N}"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "symmetry_breaking": {"max_points": 1}}, GRID,
     "continuation.symmetry_breaking.max_points = 1 is invalid: must be >= 2"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "modes": [[1, 0], [1, 1]], "symmetry_breaking": {"max_points": 9}},
     GRID, "continuation.modes = [[1, 0], [1, 1]] is invalid: must be axisymmetric (every n = 0) with "
     "continuation.symmetry_breaking"),
    ({"parameter": "P0", "start": 0.0, "stop": 1.0, "families": {"n": [1], "radial": [2, 4]},
      "symmetry_breaking": {"max_points": 10}}, GRID,
     "continuation.symmetry_breaking = {'max_points': 10} is invalid: needs one radial count in "
     "continuation.families"),
])
def test_option_errors_name_key_value_and_rule(table, grid, message):
    with pytest.raises(JobError) as err:
        CONTINUATION.parse_options(table, grid, MEMBRANE)
    assert message in str(err.value)


def test_compute_pads_outputs_to_max_points():
    options = CONTINUATION.parse_options({"parameter": "P0", "start": 0.0, "stop": 3.0, "max_points": 200,
                                          "ds_max": 0.3}, GRID, MEMBRANE)
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "Omega": 33.5, "c": 0.05})
    out = CONTINUATION.compute(point, options, 0)
    shapes = {v.name: v.shape for v in CONTINUATION.variables(options)}
    assert all(np.shape(out[k]) == s for k, s in shapes.items())
    n = int(out["n_points"])
    assert out["status"] == 0 and out["n_folds"] == 2
    assert np.isnan(out["P0"][n:]).all() and (out["stable"][n:] == -1).all()
    assert np.isfinite(out["fold_value"][:2]).all() and np.isnan(out["fold_value"][2:]).all()
    assert set(np.unique(out["point_type"][:n])) == {0, 1}


def test_a_bifurcation_that_cannot_be_located_is_reported_between_its_neighbours(monkeypatch, p0_branch):
    # With every corrector of the locator failing (model.continuation.locate returns None, as it
    # does when a corrector fails), the two folds of the P0 branch are not inserted but named
    # in Branch.unlocated, each with the parameter at the two points where the fold test changed
    # sign: the regular points on either side of the fold the working locator inserts (the
    # locator does not alter the steps, so the regular points are the same); the analysis says
    # so in the task's message and keeps the status (every point's stability stands)
    import model.continuation as continuation

    monkeypatch.setattr(continuation, "locate", lambda *args, **kwargs: None)
    rom = build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0)])
    br = continue_orbits(ForcedMap.from_loading(rom, PAPER), "P0", 0.0, 3.0, ds_max=0.3)
    assert br.complete and not br.special(FOLD).size and len(br.unlocated) == 2
    np.testing.assert_array_equal(br.value, p0_branch.value[p0_branch.kind == REGULAR])
    for (kind, n, a, b), fold in zip(br.unlocated, p0_branch.special(FOLD)):
        assert kind == FOLD and n == 0 and (a, b) == (p0_branch.value[fold - 1], p0_branch.value[fold + 1])
    options = CONTINUATION.parse_options({"parameter": "P0", "start": 0.0, "stop": 3.0, "ds_max": 0.3}, GRID,
                                         MEMBRANE)
    out = CONTINUATION.compute(grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "Omega": 33.5, "c": 0.05}),
                               options, 0)
    a, b = br.unlocated[0][2:]
    assert out["status"] == 0 and out["n_folds"] == 0 and out["n_unlocated"] == 2
    assert f"saddle-node between P0 = {a:.6g} and {b:.6g}" in out["message"]


@pytest.mark.parametrize("pair, crossing", [((1.2, 1 / 1.2), False), ((np.exp(0.7j), np.exp(-0.7j)), True)],
                         ids=["neutral saddle", "complex pair"])
def test_only_a_complex_pair_on_the_circle_makes_a_neimark_sacker_point(pair, crossing):
    # The NS test changes sign also where a complex pair meets on the real axis and drops out
    # of its product: a located zero is kept only with a complex pair on the unit circle, not
    # with a real pair mu, 1/mu there (a neutral saddle)
    from model.continuation import _complex_pair_on_circle

    phi = np.diag(np.array([*pair, 0.3], dtype=complex))
    assert _complex_pair_on_circle(None, None, None, phi) is crossing


def test_compute_with_families_reports_each_family():
    # Fig. 14a resonance in Omega with the n = 1 and n = 2 families: n = 1 has branch points
    # on the resonant stretch (tests/test_families.py checks them independently), n = 2 none.
    grid = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1.0]), "c": np.array([0.05])}
    options = CONTINUATION.parse_options({"parameter": "Omega", "start": 25.0, "stop": 55.0, "max_points": 600,
                                          "ds_max": 0.3, "families": {"n": [1, 2], "radial": 2}}, grid, MEMBRANE)
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "P0": 1.0, "c": 0.05})
    out = CONTINUATION.compute(point, options, 0)
    shapes = {v.name: v.shape for v in CONTINUATION.variables(options)}
    assert all(np.shape(out[k]) == s for k, s in shapes.items())
    n = int(out["n_points"])
    bp = out["point_type"][:n] == 4
    assert out["status"] == 0 and bp.sum() == 2 and (out["point_family"][:n][bp] == 1).all()
    modulus = out["family_multiplier_modulus"][:n]
    assert modulus[:, 0].max() > 1.2 and modulus[:, 1].max() < 1.0
    assert not (out["stable"][:n][modulus[:, 0] > 1.0]).any()
    assert (out["point_family"][n:] == -1).all() and np.isnan(modulus).sum() == 0


def test_a_radial_study_gives_each_count_as_its_own_run_does():
    # families = {n = [1], radial = [2, 3]}: one branch, the n = 1 family at 2 and at 3
    # radial modes along family_radial.  Each count's instability intervals are those of a
    # run with that count alone (their ends are located points, to ~1e-10 in arclength;
    # the study's branch also holds the other count's located points).
    grid = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1.0]), "c": np.array([0.05])}
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "P0": 1.0, "c": 0.05})

    def run(radial):
        options = CONTINUATION.parse_options({"parameter": "Omega", "start": 25.0, "stop": 55.0, "max_points": 600,
                                              "ds_max": 0.3, "families": {"n": [1], "radial": radial}}, grid, MEMBRANE)
        out = CONTINUATION.compute(point, options, 0)
        assert out["status"] == 0 and all(np.shape(out[v.name]) == v.shape for v in CONTINUATION.variables(options))
        n = int(out["n_points"])
        return options, out, n

    options, study, n = run([2, 3])
    assert [v.dims for v in CONTINUATION.variables(options) if v.name == "family_multiplier_modulus"] == \
        [("point", "family_radial", "family")]
    assert list(CONTINUATION.coords(options)["family_radial"][1]) == [2, 3]
    assert np.isnan(study["family_multiplier_real"][:n, 0, 0, 4:]).all()  # 2 x 2 radial modes, padded to 6
    end = resonant_end(study["point_type"][:n])
    for r, radial in enumerate((2, 3)):
        _, alone, m = run(radial)
        a = unstable_intervals(alone["Omega"][:m][:resonant_end(alone["point_type"][:m])],
                               alone["family_multiplier_modulus"][:m, 0][:resonant_end(alone["point_type"][:m])])
        b = unstable_intervals(study["Omega"][:n][:end], study["family_multiplier_modulus"][:n, r, 0][:end])
        assert len(a) == len(b) >= 1 and np.allclose(a, b, atol=1e-6), (radial, a, b)


def test_cusp_extrapolation_of_a_square_root_merger():
    # Fold amplitudes a_cusp +- sqrt(c* - c) and values P* +- (c* - c)^1.5: cusp at c* = 2.
    c = np.array([1.0, 1.5, 1.9, 2.5])
    d = np.sqrt(np.clip(2.0 - c, 0, None))
    value = np.stack([1 + d**3, 1 - d**3], axis=1)
    amp = np.stack([0.05 + d, 0.05 - d], axis=1)
    value[-1] = amp[-1] = np.nan
    cc, cv = cusp_from_folds(c, value, amp)
    assert cc == pytest.approx(2.0, rel=1e-12) and cv == pytest.approx(1.0, rel=1e-12)


@pytest.mark.slow
def test_omega_branch_bends_right_with_two_folds(rom):
    # Fig. 14a: P0 = 1, c = 0.05; the resonant branch leans past the ROM's linear frequency
    # (hardening) and a multiplier crosses +1 exactly at each fold.
    br = continue_orbits(ForcedMap.from_loading(rom, PAPER), "Omega", 28.0, 50.0, ds_max=0.3, max_points=1000)
    folds = br.special(FOLD)
    assert br.complete and folds.size == 2
    assert br.value[folds[0]] > br.value[folds[1]] > linear_mode(FreeRom(rom))[0]
    for i in folds:
        assert abs(br.multipliers[i, 0] - 1) < 1e-8 and br.stable[i - 1] != br.stable[i + 1]
    regular = br.kind == REGULAR
    between = regular & (np.arange(br.value.size) > folds[0]) & (np.arange(br.value.size) < folds[1])
    assert not br.stable[between].any() and br.stable[regular & ~between].all()


def test_stable_amplitudes_on_an_s_curve():
    # x = a^3 - a: stable where dx/da > 0 (|a| > 1/sqrt(3)); at x = 0 the stable roots are +-1.
    a = np.linspace(-1.5, 1.5, 3000)
    x = a**3 - a
    stable = (3 * a**2 - 1 > 0).astype(np.int8)
    found = np.sort(stable_amplitudes_at(np.append(x, np.nan), np.append(a, np.nan), np.append(stable, -1),
                                         0.0))
    assert np.allclose(found, [-1.0, 1.0], atol=1e-6)


def test_compute_bifurcation_curves_through_the_located_points():
    grid = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1.0]), "c": np.array([0.05])}
    options = CONTINUATION.parse_options(
        {"parameter": "Omega", "start": 25.0, "stop": 55.0, "max_points": 600, "ds_max": 0.3,
         "families": {"n": [1], "radial": 2}, "bifurcation_curves": {"parameter": "P0", "start": 0.9, "stop": 1.1}},
        grid, MEMBRANE)
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "P0": 1.0, "c": 0.05})
    out = CONTINUATION.compute(point, options, 0)
    shapes = {v.name: v.shape for v in CONTINUATION.variables(options)}
    assert all(np.shape(out[k]) == s for k, s in shapes.items())
    n = int(out["n_points"])
    located = np.flatnonzero(out["point_type"][:n] > 0)
    assert out["status"] == 0 and located.size == 4   # two saddle-nodes, two n = 1 branch points
    assert list(out["curve_kind"][:4]) == list(out["point_type"][located]) and (out["curve_kind"][4:] == -1).all()
    for j, i in enumerate(located):
        q, p = out["curve_P0"][j], out["curve_Omega"][j]
        at = np.flatnonzero(q == 1.0)   # the curve passes through the task's own point
        assert at.size == 1 and p[at[0]] == pytest.approx(out["Omega"][i], rel=1e-9)
        assert np.nanmin(q) < 0.9 and np.nanmax(q) > 1.1


@pytest.mark.parametrize("modes", [[[1, 0], [1, 1], [1, 2]], [[1, 0], [1, 1], [1, -1]]])
def test_mixed_mode_set_by_symmetry_blocks_equals_the_2d_rom(rom, modes):
    # A mixed set is continued on the axisymmetric subspace with one family block per wave
    # number and companion (model.families); the reference is the 2-D mixed ROM continued as
    # it is (model.rom quadrature in theta, its own monodromy).
    opts = CONTINUATION.parse_options({"parameter": "P0", "start": 0.0, "stop": 3.0, "max_points": 300,
                                       "ds_max": 0.3, "modes": modes, "steps": DEFAULT_STEPS}, GRID, MEMBRANE)
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "Omega": 33.5, "c": 0.05})
    out = CONTINUATION.compute(point, opts, 0)
    mixed = build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [tuple(m) for m in modes])
    ref = continue_orbits(ForcedMap.from_loading(mixed, PAPER), "P0", 0.0, 3.0, ds_max=0.3, max_points=300)
    n = int(out["n_points"])
    assert out["status"] == 0 and n == ref.value.size and out["n_folds"] == 2
    assert np.abs(out["P0"][:n] - ref.value).max() <= 1e-9
    assert np.abs(out["fold_value"][:2] / ref.value[ref.special(FOLD)] - 1).max() <= 1e-9
    mu = out["multiplier_real"][:n] + 1j * out["multiplier_imag"][:n]
    # as multisets: double multipliers (sine companions) tie, so sort by (real to 1e-8, imag)
    def canonical(m):
        return np.take_along_axis(m, np.lexsort((m.imag, np.round(m.real, 8)), axis=-1), axis=1)

    assert np.abs(canonical(mu) - canonical(ref.multipliers)).max() <= 1e-8
    assert np.array_equal(out["stable"][:n], ref.stable) and np.array_equal(out["point_type"][:n], ref.kind)
    assert (out["modal_coordinate"][:n, 1:] == 0).all()


def test_family_check_compares_time_integration_with_floquet():
    # Fig. 14a, n = 1: inside its interval (Omega ~ 44) the perturbation grows at the Floquet
    # rate; outside (~ 36) it decays.  Beats between equal-modulus multipliers limit the
    # agreement where the family is stable (docs/validation.md: 8e-4 for n = 1 at 36 rad/s over
    # 100 periods); the bound 1.5e-3 stays inside the 2e-3 between them and the stability limit.
    out = _fig14a_check({"values": [36.0, 44.0], "periods": 100})
    assert out["status"] == 0 and out["check_Omega"] == pytest.approx([36.0, 44.0], abs=0.2)
    floquet, growth = out["check_floquet_modulus"][:, 0], out["check_growth"][:, 0]
    assert floquet[0] < 1.0 and growth[0] < 1.0 and growth[0] == pytest.approx(floquet[0], rel=1.5e-3)
    assert floquet[1] > 1.3 and growth[1] == pytest.approx(floquet[1], rel=1e-4)
    assert np.isnan(out["check_asymmetric_amplitude"]).all()


def _fig14a_check(check, n: int = 1) -> dict:
    """The continuation of Fig. 14a (delta = 1.1, the family n on 2 radial modes) with
    ``family_check = check``: the task's outputs."""
    grid = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1.0]), "c": np.array([0.05])}
    options = CONTINUATION.parse_options(
        {"parameter": "Omega", "start": 25.0, "stop": 55.0, "max_points": 600, "ds_max": 0.3,
         "families": {"n": [n], "radial": 2}, "family_check": check}, grid, MEMBRANE)
    return CONTINUATION.compute(grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "P0": 1.0, "c": 0.05}), options, 0)


def test_family_check_classifies_the_state_reached():
    # Fig. 14a, n = 1 at 44 rad/s, inside the family's interval: the perturbation grows and
    # saturates on the asymmetric orbits born at the interval's branch point (a supercritical
    # pitchfork: tests/test_switching.py), so after the transient the state reached is periodic
    # of period one, with an asymmetric part far above the 1e-9 m start.  The light damping
    # (alpha T = 2e-3 per period) leaves a transient of a few hundred periods: 600 saturate
    # periods.  The sum of the exponents is Liouville's -2 K alpha of the viscous law for K = 3
    # coordinates, to RK4's error of the determinant (the bound of tests/test_lyapunov.py).
    out = _fig14a_check({"values": [44.0], "periods": 100, "saturate": 600, "classify": 40})
    assert out["status"] == 0 and out["check_floquet_modulus"][0, 0] > 1.3
    assert out["check_kind"][0, 0] == PERIODIC and out["check_kind_period"][0, 0] == 1
    assert np.isnan(out["check_rotation_number"][0, 0]) and out["check_asymmetric_amplitude"][0, 0] > 1e-3
    alpha = 0.05 / (2 * MEMBRANE.Gamma * MEMBRANE.h)
    assert out["check_lyapunov_sum"][0, 0] == pytest.approx(-2 * 3 * alpha, rel=1e-3)
    assert out["check_lyapunov_error"][0, 0] > 0


def test_a_perturbation_still_leaving_an_unstable_orbit_is_unsettled():
    # Just inside the n = 3 family's upper interval (43.86 rad/s, multiplier 1.0067) the
    # perturbation of 1e-9 m grows to about 2e-9 m over the fit's 120 periods and one saturate
    # period, far below GROWTH_LIMIT: the run still leaves the unstable orbit, with a positive
    # exponent, and is reported unsettled, neither chaotic nor periodic.
    out = _fig14a_check({"values": [43.86], "periods": 100, "saturate": 1, "classify": 40}, n=3)
    assert 1.0 < out["check_floquet_modulus"][0, 0] < 1.01
    assert out["check_asymmetric_amplitude"][0, 0] < GROWTH_LIMIT
    assert out["check_kind"][0, 0] == UNSETTLED and out["check_lyapunov_exponent"][0, 0] > 0


def test_sine_companions_do_not_duplicate_located_points():
    # {n = 1, radial = 2, sine = true}: the sine block has the cosine block's multipliers (each
    # twice in the output) but its branch points are located once, as with the cosine modes.
    grid = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1.0]), "c": np.array([0.05])}
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "P0": 1.0, "c": 0.05})
    outs = []
    for modes in ([[1, 0], [1, 1], [2, 1]], [[1, 0], {"n": 1, "radial": 2, "sine": True}]):
        options = CONTINUATION.parse_options({"parameter": "Omega", "start": 25.0, "stop": 55.0, "max_points": 600,
                                              "ds_max": 0.3, "modes": modes}, grid, MEMBRANE)
        outs.append(CONTINUATION.compute(point, options, 0))
    cos, both = outs
    n = int(cos["n_points"])
    assert int(both["n_points"]) == n and (cos["point_type"][:n] == 4).sum() == 2
    assert np.array_equal(cos["point_type"][:n], both["point_type"][:n])
    assert (both["point_family"][:n][both["point_type"][:n] == 4] == 1).all()
    mu_cos = np.abs(cos["multiplier_real"][:n] + 1j * cos["multiplier_imag"][:n])
    mu_both = np.abs(both["multiplier_real"][:n] + 1j * both["multiplier_imag"][:n])
    assert mu_both.shape == (n, 10)
    # every multiplier of the set with companions is one of the cosine set's
    assert np.abs(mu_both[:, :, None] - mu_cos[:, None, :]).min(axis=2).max() <= 1e-12


def test_the_ns_test_changes_sign_where_a_pair_meets_on_the_real_axis_but_no_pair_crosses_the_circle():
    # a complex pair inside the circle that becomes two real multipliers drops out of the
    # product of the NS test, whose sign flips; the count of complex multipliers outside the
    # circle does not change, so the continuation locates nothing there.  A pair crossing the
    # circle changes the count by two.
    from model.continuation import _ns_test, _outside

    before = np.array([0.5 + 0.1j, 0.5 - 0.1j, 0.9])
    after = np.array([0.55, 0.45, 0.9])
    assert _ns_test(before) * _ns_test(after) < 0
    assert _outside(before) == _outside(after) == (0, 0)
    crossed = np.array([1.01 * np.exp(0.3j), 1.01 * np.exp(-0.3j), 0.9])
    inside = np.array([0.99 * np.exp(0.3j), 0.99 * np.exp(-0.3j), 0.9])
    assert _ns_test(crossed) * _ns_test(inside) < 0
    assert _outside(crossed)[0] - _outside(inside)[0] == 2
    # both in one step: the test keeps its sign, no bracket (the continuation tells the
    # crossing from the count of multipliers outside: the next test)
    assert _ns_test(np.concatenate([inside, before[:2]])) * _ns_test(np.concatenate([crossed, after[:2]])) > 0


def _block_tests(multipliers, n=0, block=None):
    """The continuation's BP, PD and NS test tuples of a block with these multipliers (a real
    matrix: a rotation-scaling block per complex pair, given by its upper member)."""
    from model.continuation import _bp_test, _ns_test, _outside, _pd_test
    from model.protocol import sorted_multipliers
    from scipy.linalg import block_diag

    parts = [np.array([[m.real, -m.imag], [m.imag, m.real]]) if m.imag > 0 else np.array([[m.real]])
             for m in np.asarray(multipliers, complex)]
    phi = block_diag(*parts)
    mu = sorted_multipliers(phi)
    return [(BRANCH_POINT, n, block, _bp_test(phi), (0, 0)), (PERIOD_DOUBLING, n, block, _pd_test(phi), (0, 0)),
            (NEIMARK_SACKER, n, block, _ns_test(mu), _outside(mu))]


@pytest.mark.parametrize("before, after, crossed", [
    ([0.99 * np.exp(0.3j), 0.9], [1.01 * np.exp(0.3j), 0.9], True),  # a pair crosses out
    ([1.01 * np.exp(0.3j), 0.9], [0.99 * np.exp(0.3j), 0.9], True),  # ... and in
    ([0.99 * np.exp(0.05j)], [1.03, 1.01], True),  # crosses out, meets on the real axis outside
    ([0.99 * np.exp(0.3j), 0.5 + 0.1j], [1.01 * np.exp(0.3j), 0.55, 0.45], True),  # while another meets inside
    ([1.01 * np.exp(0.3j), 0.55, 0.45], [0.99 * np.exp(0.3j), 0.5 + 0.1j], True),  # ... the mirror
    ([0.99 * np.exp(0.3j), 0.98 * np.exp(1.0j)], [1.01 * np.exp(0.3j), 1.02 * np.exp(1.0j)], True),  # two pairs
    ([0.5 + 0.1j, 0.9], [0.55, 0.45, 0.9], False),  # a pair meets on the real axis inside
    ([1.2 + 0.1j, 0.99], [1.25, 1.15, 1.01], False),  # ... outside, while a real one crosses +1
    ([1.2 + 0.1j, 0.99, -0.99], [1.25, 1.15, 1.01, -1.01], False),  # ... while one crosses +1, one -1
    ([0.99 * np.exp(0.3j), 0.9], [0.995 * np.exp(0.31j), 0.9], False),  # nothing crosses
], ids=["out", "in", "out-then-real", "out-and-merge", "in-and-split", "two-pairs", "merge-inside",
        "merge-outside-and-bp", "merge-outside-bp-pd", "none"])
def test_a_pair_crossing_the_circle_is_told_by_the_count_outside_the_real_crossings_leave(before, after, crossed):
    # _unbracketed_crossings: the multipliers outside the circle change by one per real
    # crossing (which the branch-point and period-doubling tests show) and by two per pair; a
    # change beyond the real crossings, in a block whose NS test the step did not locate, is a
    # pair crossing recorded in Branch.unlocated -- where the NS test itself may keep its sign
    from model.continuation import _unbracketed_crossings

    a, b = _block_tests(before, 3, 0), _block_tests(after, 3, 0)
    assert _unbracketed_crossings(a, b, set()) == ([(3, 0)] if crossed else [])
    assert _unbracketed_crossings(a, b, {0}) == []  # the step located (or tried) its NS point
