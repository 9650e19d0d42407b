"""Two-parameter continuation of folds and the cusp (model/codim2.py), Fig. 17 case, and of
the n = 1 branch point of the Fig. 14a resonance.

Independent checks: the one-parameter continuation's folds (located by the secant on the
tangent's parameter component, model/continuation.py) at fixed damping, the number of
folds of the one-parameter branch on both sides of the cusp, and the cusp extrapolated
from one-parameter folds (model.continuation.cusp_from_folds).
"""

import numpy as np
import pytest

from model.codim2 import continue_curve, continue_folds, fold_at
from model.continuation import BRANCH_POINT, FOLD, continue_orbits, cusp_from_folds
from model.families import build_family
from model.forced import ForcedMap
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom


@pytest.fixture(scope="module")
def fmap():
    rom = build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0)])
    return ForcedMap.from_loading(rom, Loading(Omega=33.5, P0=1.0, c=0.05))


@pytest.fixture(scope="module")
def curve(fmap):
    return continue_folds(fmap, "P0", "c", 0.05, 3.0, (0.0, 4.0))


def _one_parameter_folds(fmap, c, ds_max=0.3):
    branch = continue_orbits(fmap.varied("c", c), "P0", 0.0, 4.0, ds_max=ds_max, max_points=2000)
    folds = branch.special(FOLD)
    return branch.value[folds], branch.amplitude[folds]


@pytest.mark.slow
def test_fold_curve_agrees_with_one_parameter_folds(fmap, curve):
    assert curve.complete and curve.cusp.shape == (1, 2)
    for c in (0.05, 0.5, 1.5, 2.2):
        folds = np.sort(_one_parameter_folds(fmap, c)[0])
        assert folds.size == 2
        for p in folds:
            i = np.argmin(np.abs(curve.p - p) + 10 * np.abs(curve.q - c))
            y, p_curve = fold_at(fmap, "P0", "c", c, curve.state[i], curve.p[i])
            assert p_curve == pytest.approx(p, rel=1e-6)


@pytest.mark.slow
def test_the_cusp_is_where_the_two_folds_merge(fmap, curve):
    c_cusp, p_cusp = curve.cusp[0]
    # the one-parameter branch (fine steps: near a cusp its loop is small) has two folds
    # 1 % below the cusp and none 1 % above
    offsets = np.array([0.04, 0.02, 0.01])
    rows = [_one_parameter_folds(fmap, c_cusp * (1 - d), ds_max=0.02) for d in offsets]
    assert all(v.size == 2 for v, _ in rows)
    assert _one_parameter_folds(fmap, c_cusp * 1.01, ds_max=0.02)[0].size == 0
    # the one-parameter extrapolation (fold amplitudes separate like sqrt(c_cusp - c)) from
    # those three c: its error is of the order of the neglected curvature over 1-4 % of c
    cusp_c, cusp_p = cusp_from_folds(c_cusp * (1 - np.append(offsets, -0.01)),
                                     np.array([np.append(v, np.nan) for v, _ in rows] + [[np.nan] * 3]),
                                     np.array([np.append(a, np.nan) for _, a in rows] + [[np.nan] * 3]))
    assert cusp_c == pytest.approx(c_cusp, rel=1e-3) and cusp_p == pytest.approx(p_cusp, rel=1e-3)
    # the curve turns back in c there: every point of the curve has c <= c_cusp
    assert curve.q.max() <= c_cusp * (1 + 1e-9)


def test_no_fold_no_curve(fmap):
    curve = continue_folds(fmap, "P0", "c", 3.0, 4.0, (0.0, 4.0))
    assert not curve.complete and curve.p.size == 0 and "no fold" in curve.message
    with pytest.raises(ValueError, match="second = 'P0' is invalid"):
        continue_folds(fmap, "P0", "P0", 0.0, 1.0, (0.0, 1.0))


def test_branch_point_curve_agrees_with_one_parameter_branch_points(fig14a_n1):
    # The n = 1 branch point of the Fig. 14a resonance (delta = 1.1, c = 0.05) followed in P0
    # from 1 Pa: at curve points, the one-parameter branch in Omega at that P0 locates its
    # branch point (Illinois on det(Phi_1 - I) along the branch) at the curve's Omega.
    fmap, fam, branch = fig14a_n1.fmap, fig14a_n1.family, fig14a_n1.branch
    first = branch.special(BRANCH_POINT)[0]
    curve = continue_curve(fmap, "Omega", "P0", 1.0, 2.0, branch.state[first], branch.value[first], 30.0,
                           kind=BRANCH_POINT, family=fam, ds_max=0.5)
    assert curve.complete and curve.family == 1 and curve.turns.size == 0
    for i in (curve.p.size // 3, 2 * curve.p.size // 3):
        one = continue_orbits(fmap.varied("P0", curve.q[i]), "Omega", 25.0, 55.0, ds_max=0.3, max_points=1000,
                              families=[fam])
        located = one.value[one.special(BRANCH_POINT)]
        assert np.min(np.abs(located / curve.p[i] - 1)) <= 1e-6
    # going down in P0 the two branch points of the resonance merge where the curve turns
    down = continue_curve(fmap, "Omega", "P0", 1.0, 0.2, branch.state[first], branch.value[first], 30.0,
                          kind=BRANCH_POINT, family=fam, ds_max=0.5)
    assert down.turns.shape == (1, 2) and 0.2 < down.turns[0, 0] < 1.0
    near = continue_orbits(fmap.varied("P0", down.turns[0, 0] * 1.01), "Omega", 25.0, 55.0, ds_max=0.3,
                           max_points=1000, families=[fam])
    below = continue_orbits(fmap.varied("P0", down.turns[0, 0] * 0.99), "Omega", 25.0, 55.0, ds_max=0.3,
                            max_points=1000, families=[fam])
    assert near.special(BRANCH_POINT).size == 2 and below.special(BRANCH_POINT).size == 0


def test_curves_in_delta_agree_with_one_parameter_branches():
    # The saddle-node and the n = 1 branch point of the Fig. 14a resonance followed in delta
    # (the analysis rebuilds pre-stretch, ROM and family at each delta): at a curve point, the
    # one-parameter branch at that delta has the same point (independent: the ROM with its
    # tables, the secant location on the branch).
    from sweep.analyses.continuation import CONTINUATION
    from sweep.jobspec import grid_point

    membrane = Membrane()
    grid = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1.0]), "c": np.array([0.05])}
    options = CONTINUATION.parse_options(
        {"parameter": "Omega", "start": 25.0, "stop": 55.0, "max_points": 400, "ds_max": 0.3, "prestretch": "analytic",
         "families": {"n": [1], "radial": 2}, "bifurcation_curves": {"parameter": "delta", "start": 1.1, "stop": 1.13}},
        grid, membrane)
    out = CONTINUATION.compute(grid_point(membrane, {"delta": 1.1, "delta_o": 0.2, "P0": 1.0, "c": 0.05}), options, 0)
    assert out["status"] == 0
    for kind in (FOLD, BRANCH_POINT):
        j = int(np.flatnonzero(out["curve_kind"] == kind)[0])
        q, p = out["curve_delta"][j], out["curve_Omega"][j]
        i = int(np.flatnonzero(np.isfinite(q))[-1]) // 2
        ps = solve_prestretch(Membrane(delta=q[i], delta_o=0.2), "analytic")
        rom = build_rom(ps, [(1, 0)])
        one = continue_orbits(ForcedMap.from_loading(rom, Loading(Omega=25.0, P0=1.0, c=0.05)), "Omega", 25.0, 55.0,
                              ds_max=0.3, max_points=1000, families=[build_family(ps, rom, 1, 2)])
        assert np.min(np.abs(one.value[one.special(kind)] / p[i] - 1)) <= 1e-6
