"""A model that is not the ROM, through the seams: Thompson's escape oscillator.

``tests/escape_model.py`` registers ``x'' + c x' + x - x^2 = P0 sin(Omega t)`` from outside
``model/`` (``SWEEP_EXTRA_MODELS``); job files choose it with ``[model] kind = "escape"``
and run continuation (with its saddle-nodes and their curve in ``c``), a stepped response
and basins under ``mpiexec -n 2``.  References independent of the code under test: the
stepped response (brute-force time integration) against the continuation's folds, a
one-parameter continuation at the fold curve's end against the curve, scipy's DOP853
over one period against a continuation orbit, and scipy's DOP853 over hundreds of
periods against the basin labels.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from escape_oscillator import EscapeMap, Forcing, rhs
from jobfiles import data, sweep
from model.continuation import FOLD, continue_orbits
from sweep.analyses.base import JobError
from sweep.jobspec import parse_job

pytestmark = pytest.mark.mpi

ENV = {"SWEEP_EXTRA_MODELS": "escape=escape_model:ESCAPE"}
#: beta = 0.1, F = 0.05: the softening resonance of the well bends left, with saddle-nodes
#: at Omega = 0.887 and 0.813 (two coexisting responses between them).
GRID = "[model]\nkind = \"escape\"\n[grid]\nP0 = 0.05\nc = 0.1\n"
CONTINUATION = f"""[job]
name = "escape-continuation"
analysis = "continuation"
{GRID}[continuation]
parameter = "Omega"
start = 0.5
stop = 1.2
max_points = 600
fold_curve = {{parameter = "c", start = 0.1, stop = 0.3}}
"""
RESPONSE = f"""[job]
name = "escape-response"
analysis = "response"
{GRID}[response]
parameter = "Omega"
values = {{start = 0.75, stop = 0.95, num = 11}}
refine_jumps = true
"""
BASINS = """[job]
name = "escape-basins"
analysis = "basins"
[model]
kind = "escape"
[grid]
Omega = 0.85
P0 = 0.05
c = 0.1
[basins]
ic_x = {start = -0.8, stop = 0.8, num = 24}
ic_y = {start = -0.8, stop = 0.8, num = 24}
"""


def _run(tmp_path, name, text):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    proc = sweep("run", path, "-o", f"{name}.nc", ranks=2, cwd=tmp_path, **ENV)
    assert proc.returncode == 0, proc.stderr
    assert "on 2 rank(s)" in proc.stdout
    return data(tmp_path / f"{name}.nc").squeeze()


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("escape")
    return {name: _run(tmp, name, text) for name, text in
            (("continuation", CONTINUATION), ("response", RESPONSE), ("basins", BASINS))}


def test_folds_of_the_continuation_are_the_jumps_of_the_stepped_response(results):
    folds = np.sort(results["continuation"].fold_value.values[:2])
    jumps = np.sort(results["response"].jump_value.values.ravel())
    jumps = jumps[np.isfinite(jumps)]
    assert folds.size == 2 and jumps.size == 2
    # refine_jumps locates a jump to rtol 1e-3 of the value (model/response.py)
    np.testing.assert_allclose(jumps, folds, rtol=2e-3)


def test_a_continuation_orbit_is_periodic_for_scipy(results):
    ds = results["continuation"]
    i = int(np.nanargmin(np.abs(ds.Omega.values - 0.7)))
    omega = float(ds.Omega.values[i])
    y0 = [float(ds.modal_coordinate.values[i]), float(ds.modal_velocity.values[i])]
    assert "section_state" not in ds  # the state is its modal section (sweep.models.base.Model.state_size)
    sol = solve_ivp(rhs(0.1, 0.05, omega), (0.0, 2 * np.pi / omega), y0, method="DOP853", rtol=1e-12, atol=1e-14)
    # RK4 with 128 steps per period: a global error ~ (2 pi / 128)^4 ~ 6e-6 of the state
    np.testing.assert_allclose(sol.y[:, -1], y0, atol=2e-5 * np.abs(y0).max())


def test_the_fold_curve_ends_where_a_direct_continuation_puts_the_fold(results):
    ds = results["continuation"]
    c = ds.fold_curve_c.values
    om = ds.fold_curve_Omega.values
    ok = np.isfinite(c)
    assert ok.sum() > 20
    assert np.isclose(c[ok][0], 0.1) and np.isclose(om[ok][0], ds.fold_value.values[0], rtol=1e-8)
    # the two saddle-nodes merge at a cusp: c rises to a maximum and comes back
    assert c[ok].max() > c[ok][0] + 0.01 and c[ok][-1] < c[ok].max()
    j = int(np.flatnonzero(ok)[len(np.flatnonzero(ok)) // 3])
    fmap = EscapeMap(float(c[j]), Forcing(0.0, 0.05, 0.5), 128)
    br = continue_orbits(fmap, "Omega", 0.5, 1.2, max_points=600)
    folds = br.value[br.kind == FOLD]
    assert np.min(np.abs(folds - om[j])) < 1e-6 * om[j]


def test_basin_labels_agree_with_scipy_integration(results):
    ds = results["basins"]
    label = ds.label.values
    points = np.concatenate([ds.attractor_coordinate.values.reshape(6, 4, 1),
                             ds.attractor_velocity.values.reshape(6, 4, 1)], axis=2)  # (attractor, phase, state)
    found = [a for a in range(points.shape[0]) if np.isfinite(points[a, 0, 0])]
    assert len(found) == 2  # the small and the large response of the hysteresis band
    x, v = ds.ic_x.values, ds.ic_y.values
    omega, period = 0.85, 2 * np.pi / 0.85
    escape = lambda t, y: abs(y[0]) - 5.0  # noqa: E731  (past the hilltop at x = 1 the state runs away)
    escape.terminal = True
    rng = np.random.default_rng(11)
    picks = rng.choice(label.size, 24, replace=False)
    for flat in picks:
        i, j = np.unravel_index(flat, label.shape)
        # 200 periods: the damping (c = 0.1, rate 0.05 s-1) shrinks a settled transient by exp(-74)
        sol = solve_ivp(rhs(0.1, 0.05, omega), (0.0, 200 * period), [x[i], v[j]], method="DOP853", rtol=1e-10,
                        atol=1e-12, t_eval=period * np.arange(201), events=escape)
        if sol.status == 1:
            expected = -1
        else:
            end = sol.y[:, -1]
            d = [np.min(np.linalg.norm(points[a][np.isfinite(points[a, :, 0])] - end, axis=1)) for a in found]
            assert min(d) < 1e-3, (x[i], v[j], d)
            expected = found[int(np.argmin(d))]
        assert label[i, j] == expected, (x[i], v[j])


def test_rom_only_options_are_refused_for_another_model(monkeypatch):
    monkeypatch.setenv("SWEEP_EXTRA_MODELS", ENV["SWEEP_EXTRA_MODELS"])
    with pytest.raises(JobError, match="continuation.families = .* is invalid: needs a model with asymmetric "
                                       "families; this job's model is 'escape'"):
        parse_job(CONTINUATION.replace("max_points = 600", "max_points = 600\nfamilies = {n = [1], radial = 2}"))
    with pytest.raises(JobError, match="model.kind = 'duffing' is invalid: one of the available models: 'rom', 'full', 'fe2d', "
                                       "'escape'"):
        parse_job(CONTINUATION.replace('kind = "escape"', 'kind = "duffing"'))
    # an analysis the model does not run (it has no free vibration, no static state)
    with pytest.raises(JobError, match=r"job.analysis = 'backbone' is invalid: an analysis that model 'escape' can "
                                       r"run with its \[model\] options \(this one needs its free_vibration, which it does not provide\)"):
        parse_job(CONTINUATION.replace('analysis = "continuation"', 'analysis = "backbone"'))
