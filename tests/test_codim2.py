"""Two-parameter continuation of folds and the cusp (model/codim2.py), Fig. 17 case.

Independent checks: the one-parameter continuation's folds (located by the secant on the
tangent's parameter component, model/continuation.py) at fixed damping, the number of
folds of the one-parameter branch on both sides of the cusp, and the cusp extrapolated
from one-parameter folds (model.continuation.cusp_from_folds).
"""

import numpy as np
import pytest

from model.codim2 import continue_folds, fold_at
from model.continuation import FOLD, continue_orbits, cusp_from_folds
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
