"""Brute-force stepped sweeps: linear limit, jumps at the continuation's folds, errors."""

import numpy as np
import pytest

from model.continuation import FOLD, continue_orbits
from model.forced import ForcedMap
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.response import refine_jumps, stepped_sweep
from model.rom import build_rom, force_jacobian
from sweep.analyses.base import JobError
from sweep.analyses.response import RESPONSE
from sweep.jobspec import grid_point
from sweep.models.rom import rom_for


@pytest.fixture(scope="module")
def rom():
    return build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0)])


def test_linear_limit_matches_the_closed_form_in_both_directions(rom):
    ld = Loading(Omega=30.0, P0=1e-5, c=2.0)
    values = np.linspace(30.0, 35.0, 6)
    res = stepped_sweep(ForcedMap.from_loading(rom, ld), "Omega", values)
    jac = np.zeros((1, 1))
    force_jacobian(np.zeros(1), rom.tables, jac)
    w0sq = rom.tables.k_force[0] * jac[0, 0]
    cd = ld.c / (rom.membrane.Gamma * rom.membrane.h)
    frf = abs(rom.tables.load[0] * rom.tables.probe[0]) * 1e-5 / np.hypot(w0sq - values**2, cd * values)
    assert res.converged.all()
    # criterion tol 1e-6 with |mu| ~ 0.91 per period: ~1e-5 relative left, plus RK4 error
    for d in range(2):
        assert res.amplitude[d] == pytest.approx(frf, rel=1e-4)


def test_jumps_land_at_the_folds_of_the_continuation(rom):
    # c = 1 (transients of ~200 periods): hysteresis between the two saddle-nodes.
    ld = Loading(Omega=33.5, P0=1.0, c=1.0)
    br = continue_orbits(ForcedMap.from_loading(rom, ld), "P0", 0.0, 3.0, ds_max=0.3)
    lo, hi = sorted(br.value[br.special(FOLD)])
    values = np.linspace(1.0, 2.6, 81)
    res = stepped_sweep(ForcedMap.from_loading(rom, ld), "P0", values)
    assert res.converged.all()
    up = np.argmax(np.diff(res.amplitude[0]))
    down = np.argmax(np.diff(res.amplitude[1]))
    assert values[up] <= hi <= values[up + 1] and values[down] <= lo <= values[down + 1]
    assert abs(0.5 * (values[up] + values[up + 1]) - hi) < 0.02 * hi
    assert abs(0.5 * (values[down] + values[down + 1]) - lo) < 0.02 * lo
    # off the hysteresis loop both directions agree
    outside = (values < lo) | (values > hi)
    assert res.amplitude[0, outside] == pytest.approx(res.amplitude[1, outside], rel=1e-3)


def _folds(rom, ld):
    br = continue_orbits(ForcedMap.from_loading(rom, ld), "P0", 0.0, 4.0, ds_max=0.3)
    return sorted(br.value[br.special(FOLD)])


def test_refined_jumps_land_at_the_folds_from_a_coarse_sweep(rom):
    ld = Loading(Omega=33.5, P0=1.0, c=1.0)
    lo, hi = _folds(rom, ld)
    res = stepped_sweep(ForcedMap.from_loading(rom, ld), "P0", np.linspace(0.0, 4.0, 9))
    jumps = refine_jumps(ForcedMap.from_loading(rom, ld), "P0", res)
    # the march's resolution: refine_jumps' rtol = 1e-3 relative
    assert jumps[0, 0] == pytest.approx(hi, rel=1e-3) and jumps[1, 0] == pytest.approx(lo, rel=1e-3)
    assert np.isnan(jumps[:, 1]).all()


@pytest.mark.slow
def test_refined_jumps_at_the_papers_damping(rom):
    # Fig. 15a: c = 0.05 (transients of thousands of periods); the coarse up-sweep jumps
    # early (a 0.5 Pa step leaves the shrinking basin), the adaptive march does not.
    ld = Loading(Omega=33.5, P0=1.0, c=0.05)
    lo, hi = _folds(rom, ld)
    res = stepped_sweep(ForcedMap.from_loading(rom, ld), "P0", np.linspace(0.0, 4.0, 9))
    jumps = refine_jumps(ForcedMap.from_loading(rom, ld), "P0", res)
    # the march's resolution: refine_jumps' rtol = 1e-3 relative
    assert jumps[0, 0] == pytest.approx(hi, rel=1e-3) and jumps[1, 0] == pytest.approx(lo, rel=1e-3)


def test_max_periods_gives_not_converged(rom):
    res = stepped_sweep(ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05)), "P0", [0.5], max_periods=50)
    assert not res.converged.any() and res.periods[0, 0] == 50


@pytest.mark.parametrize("kwargs, message", [
    ({"parameter": "c", "values": [1.0]}, "parameter = 'c' is invalid: must be one of Omega, P0"),
    ({"parameter": "P0", "values": []}, "values = [] is invalid: need a non-empty list of finite numbers"),
    ({"parameter": "Omega", "values": [0.0, 1.0]}, "Omega must be > 0"),
    ({"parameter": "P0", "values": [1.0], "tol": 0.0}, "need tol > 0, consecutive >= 1"),
    ({"parameter": "P0", "values": [1.0], "initial": np.zeros(3)}, r"initial.shape = (3,) is invalid: expected (2,)"),
])
def test_bad_arguments_are_rejected(rom, kwargs, message):
    with pytest.raises(ValueError) as err:
        stepped_sweep(ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05)), **kwargs)
    assert message in str(err.value)


GRID = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1e-5]), "c": np.array([2.0])}
MEMBRANE = Membrane()


@pytest.mark.parametrize("table, grid, message", [
    ({"values": {"start": 1.0, "stop": 2.0, "num": 3}}, GRID,
     "response.parameter = <missing> is invalid: must be one of Omega, P0"),
    ({"parameter": "P0", "values": {"start": 0.0, "stop": 2.0, "num": 3}}, GRID,
     "response.parameter = 'P0' is invalid: P0 is swept by the analysis"),
    ({"parameter": "Omega", "values": {"start": 30.0, "stop": 35.0, "num": 3}},
     {k: v for k, v in GRID.items() if k != "P0"}, "grid.P0 = <missing> is invalid: response in Omega needs P0"),
    ({"parameter": "Omega", "values": {"start": 0.0, "stop": 35.0, "num": 3}}, GRID,
     "response.values.start = 0.0 is invalid: must be > 0.0"),
    ({"parameter": "Omega", "values": {"start": 30.0, "stop": 35.0, "num": 3}, "tol": -1.0}, GRID,
     "response.tol = -1.0 is invalid: must be > 0.0"),
    ({"parameter": "Omega", "values": {"start": 30.0, "stop": 35.0, "num": 3}, "x": 1}, GRID,
     "response.x = 1 is invalid: unknown key"),
    ({"parameter": "Omega", "values": {"start": 30.0, "stop": 35.0, "num": 3}, "poincare_points": 15}, GRID,
     "response.poincare_points = 15 is invalid: 0 or a multiple of 10 of at least 2 max_period = 32"),
])
def test_option_errors_name_key_value_and_rule(table, grid, message):
    with pytest.raises(JobError) as err:
        RESPONSE.parse_options(table, grid, MEMBRANE)
    assert message in str(err.value)


def test_compute_returns_declared_shapes():
    options = RESPONSE.parse_options({"parameter": "Omega", "values": {"start": 30.0, "stop": 34.0, "num": 3}},
                                     GRID, MEMBRANE)
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "P0": 1e-5, "c": 2.0})
    out = RESPONSE.compute(point, options, 0)
    for v in RESPONSE.variables(options):
        assert np.shape(out[v.name]) == v.shape
    assert out["status"] == 0 and (out["converged"] == 1).all()
    assert list(RESPONSE.coords(options)["direction"][1]) == ["up", "down"]
    # the stroboscopic state lies on the orbit: |w| there is at most the orbit's amplitude
    rom = rom_for(point.membrane, options.prestretch, options.modes)
    w = np.abs(out["modal_coordinate"] @ rom.tables.probe)
    assert np.all(w <= out["amplitude"] * (1 + 1e-9)) and np.all(w > 0)


def test_a_bifurcation_diagram_of_a_linear_response_is_periodic_with_the_damping_exponents():
    # P0 = 1e-5 Pa: a linear, strongly damped (c = 2) response.  Every value is period one,
    # its Poincare points are the stroboscopic state, and the exponents of the linear map
    # sum to -rate per mode (Liouville) with the mean -rate / 2 (tests/test_lyapunov.py).
    options = RESPONSE.parse_options({"parameter": "Omega", "values": {"start": 30.0, "stop": 34.0, "num": 3},
                                      "poincare_points": 40}, GRID, MEMBRANE)
    point = grid_point(MEMBRANE, {"delta": 1.1, "delta_o": 0.2, "P0": 1e-5, "c": 2.0})
    out = RESPONSE.compute(point, options, 0)
    for v in RESPONSE.variables(options):
        assert np.shape(out[v.name]) == v.shape
    assert out["status"] == 0
    assert (out["response_kind"] == 1).all() and (out["response_period"] == 1).all()
    assert np.isnan(out["rotation_number"]).all()
    last = out["poincare_coordinate"][:, :, -1]
    assert last == pytest.approx(out["modal_coordinate"], rel=1e-12)
    assert np.all(np.ptp(out["poincare_coordinate"], axis=2) <= 1e-5 * np.abs(last))
    rate = point.membrane.damping_rate(2.0)
    assert out["lyapunov_exponent"].sum(axis=-1) == pytest.approx(np.full((3, 2), -rate), rel=1e-6)
