"""The forced axisymmetric full model (:mod:`model.full.forced`): its derivatives against finite
differences, its small-amplitude response against the frequency-domain solution of its
linearisation, shooting against time integration, and the forced analyses on it from job files."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from model.damping import Rayleigh, Viscous
from model.full.axisymmetric import AxisymmetricFull
from model.full.forced import ForcedFull, linear_system, modal_projection, steps_per_period
from model.full.static import solve_full_prestretch
from model.modes import bessel_roots, mode_shape
from model.params import Membrane
from model.protocol import StroboscopicMap
from model.rk4 import amplification
from model.shooting import shoot
from sweep import cli
from sweep.analyses.base import JobError
from sweep.jobspec import parse_job

ORDER = 8


@pytest.fixture(scope="module")
def model():
    return AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), ORDER))


@pytest.fixture(scope="module", params=[True, False], ids=["inplane", "held"])
def either(request, model):
    """The model, and the same with u held at zero (``inplane=False``: the state is ``W`` alone)."""
    return model if request.param else AxisymmetricFull(model.state, inplane=False)


def _map(model, P0=0.5, Omega=33.5, damping=Viscous(0.05), factor=1):
    return ForcedFull.build(model, P0, Omega, damping, factor * steps_per_period(model, 128), modes=[(1, 0), (2, 0)])


def _state(fmap, w=0.02):
    # a deflection of about w at the probe with some radial displacement (when u moves) and
    # velocities; W is the last `order` coordinates
    o, dof = fmap.model.order, fmap.dof
    y = np.zeros(2 * dof)
    y[dof - o:dof] = w * np.linspace(1.0, 0.2, o)
    y[:dof - o] = 0.1 * w * np.linspace(0.5, -0.5, dof - o)
    y[dof:] = 3.0 * y[:dof]
    return y


def test_the_map_satisfies_the_protocol(either):
    assert isinstance(_map(either), StroboscopicMap)


@pytest.mark.parametrize("parameter", ["state", "Omega", "P0"])
def test_derivatives_are_those_of_the_discrete_map(either, parameter):
    # central differences at h and 2 h: their error is C h^2 and 4 C h^2, so the exact
    # derivative lies within |fd(h) - fd(2h)| / 3 of fd(h); asserted with a margin of 3
    fmap = _map(either, damping=Rayleigh(alpha=0.1, beta=1e-4))
    y = _state(fmap)
    if parameter == "state":
        k = fmap.dof - fmap.model.order + 1  # the second W coefficient
        exact = fmap.monodromy(y)[1][:, k]
        e = np.zeros_like(y)
        e[k] = 1.0

        def at(h):
            return fmap.advance(y + h * e)
        h = 1e-5
    else:
        exact = fmap.monodromy_parameter(y, parameter)[2]
        value = fmap.value(parameter)

        def at(h):
            return fmap.varied(parameter, value + h).advance(y)
        h = 1e-4 * value
    fd = [(at(k * h) - at(-k * h)) / (2 * k * h) for k in (1, 2)]
    scale = np.abs(exact).max()
    assert np.abs(fd[0] - exact).max() <= np.abs(fd[0] - fd[1]).max() + 1e-9 * scale


def test_small_response_is_the_frequency_domain_solution_of_the_linearisation(either):
    # P0 = 1e-2 Pa: w ~ 5e-5 m, the nonlinear terms ~ 1e-8 relative (the backbone bends by 5 %
    # at 0.1 m: (5e-5 / 0.1)^2 0.05).  The linearisation about the pre-stretch, q'' + D q' +
    # M^-1 K0 q = P0 cos(Omega t) b, solved in the frequency domain with the numpy Hessian (the
    # map integrates the compiled one); RK4's error in the forced amplitude is ~ (Omega dt)^4 /
    # 120 = 1e-9, amplified near the resonance by omega_1 / |omega_1 - Omega| ~ 10.  (Smaller
    # loads meet the map's rounding floor, ~3e-16 m per period: docs/model.md.)
    P0, W = 1e-2, 30.0
    model = either
    fmap = _map(model, P0=P0, Omega=W)
    orbit = shoot(fmap, np.zeros(2 * fmap.dof))
    assert orbit.converged and orbit.stable
    mass, stiffness = linear_system(model)  # of the moving coordinates: (U, W), or W
    A = np.linalg.solve(mass, stiffness)
    o, dof = model.order, fmap.dof
    b = np.zeros(dof)
    b[-o:] = model.load * P0 * model.membrane.Re  # m s-2
    Q = np.linalg.solve(A - W**2 * np.eye(dof) + 1j * W * fmap.rate * np.eye(dof), b)
    np.testing.assert_allclose(orbit.state[dof - o:dof], Q[-o:].real, rtol=0, atol=1e-6 * np.abs(Q).max())
    np.testing.assert_allclose(orbit.state[2 * dof - o:], (1j * W * Q[-o:]).real, rtol=0,
                               atol=1e-6 * W * np.abs(Q).max())
    np.testing.assert_allclose(orbit.amplitude, abs(fmap.probe[-o:] @ Q[-o:]), rtol=1e-6)
    if not model.inplane:
        return
    # the linearisation has no u (transverse and in-plane motion decouple about the flat
    # state); the orbit's u is of second order (the energy is even in w): four times as large
    # at twice the load, to the relative size of the next order, (w / 0.1 m)^2 ~ 1e-7
    assert np.abs(Q[:o]).max() == 0.0
    double = shoot(fmap.varied("P0", 2 * P0), 2 * orbit.state)
    np.testing.assert_allclose(double.state[:o], 4 * orbit.state[:o], rtol=1e-4, atol=0)


def test_shooting_finds_the_state_time_integration_settles_on(either):
    # heavy damping (every coordinate decays at rate / 2, mass-proportional): after N periods a
    # transient of the size of the orbit is down by exp(-rate N T / 2) < 1e-9
    fmap = _map(either, P0=2.0, damping=Viscous(2.0))
    orbit = shoot(fmap, np.zeros(2 * fmap.dof))
    assert orbit.converged and orbit.stable
    periods = int(np.ceil(2.0 * np.log(1e9) / (fmap.rate * fmap.period)))
    settled = fmap.advance(np.zeros(2 * fmap.dof), periods)
    scale = fmap.state_scale()
    assert np.linalg.norm(scale * (settled - orbit.state)) <= 1e-8 * np.linalg.norm(scale * orbit.state)


def test_steps_keep_rk4_stable_and_a_lower_forcing_frequency_is_nan(model):
    fmap = _map(model)
    assert fmap.stable_step and fmap.period / fmap.steps * fmap.omega_max <= 2.0
    slow = fmap.varied("Omega", 0.1)
    assert not slow.stable_step
    assert np.isnan(slow.advance(_state(fmap))).all() and np.isnan(slow.amplitude(_state(fmap)))


def test_an_overdamping_law_raises_the_steps_and_a_step_beyond_its_fastest_decay_is_nan(either):
    # stiffness-proportional damping with beta omega_max = 6 overdamps the fastest mode: its
    # eigenvalue ~ -beta omega_max^2, six times omega_max.  Steps bounded by omega_max alone
    # leave it outside RK4's stability region (the map says so and returns NaN); steps from the
    # law's eigenvalues keep it inside, and the rest multipliers are RK4's amplification of
    # every eigenvalue, R(lambda dt)^N
    law = Rayleigh(alpha=0.0, beta=6.0 / either.highest_frequency())
    blind = ForcedFull.build(either, 0.0, 30.0, law, steps_per_period(either, 128))
    assert blind.period / blind.steps * blind.omega_max <= 2.0 and blind.fastest > 5 * blind.omega_max
    assert not blind.stable_step and np.isnan(blind.advance(_state(blind))).all()
    aware = ForcedFull.build(either, 0.0, 30.0, law, steps_per_period(either, 128, law))
    assert aware.stable_step and aware.period / aware.steps * aware.fastest <= 2.0
    expected = amplification(aware.eigenvalues * aware.period / aware.steps) ** aware.steps
    got = aware.multipliers(np.zeros(2 * aware.dof))
    assert np.all(np.isfinite(got)) and got.size == expected.size
    scale = np.abs(expected).max()
    np.testing.assert_allclose(np.sort_complex(got), np.sort_complex(expected), rtol=0, atol=1e-9 * scale)


def test_modal_section_recovers_the_rom_coordinates_of_a_combination_of_mode_shapes(model):
    # w = 0.01 psi_1 - 0.003 psi_2 (Eq. 26) interpolated on the basis: the fit returns the two
    # coefficients to the basis' interpolation error of the shapes (order 8: ~1e-5 relative)
    m, b = model.membrane, model.state.basis
    alpha = bessel_roots(0, m.delta_o, 2)
    s = b.s
    psi = mode_shape(m.Re * s, alpha, 0, m.Re, m.delta_o)[0]
    target = np.array([0.01, -0.003])
    sw = s * b.weights
    W = np.linalg.solve((b.phi * sw) @ b.phi.T, (b.phi * sw) @ (target @ psi))  # L2 fit on the basis
    P = modal_projection(model, [(1, 0), (2, 0)])
    np.testing.assert_allclose(P @ W, target, rtol=0, atol=1e-4 * 0.01)
    with pytest.raises(ValueError, match="axisymmetric modes"):
        modal_projection(model, [(1, 1)])


def test_modal_lift_is_the_basis_fit_of_the_mode_shapes_and_the_section_inverts_it(either):
    # w = sum q_k psi_k fitted on the basis (L2 in rho), u at rest; section(lift(q)) - q is then
    # exactly -G^-1 R q with R_kl = (r_k, r_l) the Gram matrix of the fit residuals r_k of psi_k
    model = either
    fmap = _map(model)
    m, b = model.membrane, model.state.basis
    o, dof = model.order, fmap.dof
    u = dof - o  # the U coordinates before W: none when u is held
    psi = mode_shape(m.Re * b.s, bessel_roots(0, m.delta_o, 2), 0, m.Re, m.delta_o)[0]
    sw = b.s * b.weights
    q = np.array([0.01, -0.003, 0.2, 0.05])
    y = fmap.modal_lift(q)
    assert y.shape == (2 * dof,) and not y[:u].any() and not y[dof:dof + u].any()
    for part, coefficients in ((y[u:dof], q[:2]), (y[dof + u:], q[2:])):
        residual = part @ b.phi - coefficients @ psi
        np.testing.assert_allclose((b.phi * sw) @ residual, 0.0, atol=1e-13 * np.abs(coefficients).max())
    r = fmap.lift @ b.phi - psi
    gram = (psi * sw) @ psi.T
    predicted = -np.linalg.solve(gram, (r * sw) @ r.T)
    round_trip = fmap.modal_section(fmap.modal_lift(np.eye(4))).T  # column i: section(lift(e_i))
    np.testing.assert_allclose(round_trip[:2, :2] - np.eye(2), predicted, atol=1e-14)
    np.testing.assert_allclose(round_trip[2:, 2:] - np.eye(2), predicted, atol=1e-14)
    assert not round_trip[:2, 2:].any() and not round_trip[2:, :2].any()
    assert np.abs(predicted).max() > 1e-12  # order 8 does not hold the shapes exactly: a real check
    with pytest.raises(ValueError, match="coordinates shape"):
        fmap.modal_lift(np.zeros(3))
    # the basins' norm of lifted states: the lattice mode's unit displacement measures 1 / Lx
    # as in the modal coordinates (the ROM's map lifts nothing: its weights are lattice_scale's)
    from model import lattice as ml

    lattice = ml.Lattice(np.linspace(-0.3, 0.3, 5), np.linspace(-10.0, 10.0, 5), 1, 3)
    weights = ml.state_norm_scale(lattice, fmap, 4)
    assert weights.shape == (2 * dof,)
    plane = ml.lattice_states(lattice, slice(None), 4)  # displacements and velocities of mode 2
    np.testing.assert_allclose(np.linalg.norm(fmap.modal_lift(plane) * weights, axis=1),
                               np.linalg.norm(plane * ml.lattice_scale(lattice, 4), axis=1), rtol=1e-14)
    np.testing.assert_array_equal(ml.state_norm_scale(lattice, object(), 4), ml.lattice_scale(lattice, 4))


JOB = """
[job]
name = "full-forced"
analysis = "continuation"

[model]
kind = "full"
order = 8

[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
c = 0.05

[continuation]
parameter = "P0"
start = 0.0
stop = 0.12
modes = [[1, 0], [2, 0]]
ds_max = 0.3
max_points = 200
"""


def _run_job(tmp_path, text):
    """The result of the job ``text`` on the full model at its one grid point, which succeeded."""
    job = tmp_path / "full.toml"
    job.write_text(text)
    out = tmp_path / "full.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    ds = xr.load_dataset(out).squeeze()
    assert ds.attrs["model"] == "full" and int(ds.status) == 0
    return ds


def test_continuation_job_on_the_full_model_reports_rom_coordinates_and_folds(tmp_path):
    ds = _run_job(tmp_path, JOB)
    n = int(ds.n_points)
    assert ds.multiplier_real.sizes["multiplier"] == 4 and ds.modal_coordinate.sizes["mode"] == 2
    # the branch's responses are the periodic orbits shooting finds at those loads from rest
    # (no saddle-node below 0.12 Pa: the full model's is above 2 Pa, docs/validation.md)
    assert int(ds.n_folds) == 0
    model = AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), 8))
    fmap = ForcedFull.build(model, 0.0, 33.5, Viscous(0.05), int(ds.rk4_steps), modes=[(1, 0), (2, 0)])
    for i in (n // 2, n - 1):
        orbit = shoot(fmap.varied("P0", float(ds.P0[i])), np.zeros(2 * fmap.dof))
        assert orbit.converged
        np.testing.assert_allclose(orbit.amplitude, float(ds.amplitude[i]), rtol=1e-8)
        np.testing.assert_allclose(fmap.modal_section(orbit.state)[:2], ds.modal_coordinate[i], rtol=1e-7)
        # the stored state is that orbit's (the corrector's tolerance, 1e-10 of 0.05 m)
        assert "section_state" in ds.data_vars and ds.section_state.sizes["state"] == 2 * fmap.dof
        np.testing.assert_allclose(ds.section_state[i], orbit.state, atol=1e-9 * np.abs(orbit.state).max(), rtol=0)
    # the reported coordinate of (1, 0) carries the probe's deflection: psi_1(0.5 Re) q_1 ~ w
    m = Membrane(delta=1.1, delta_o=0.2)
    psi = mode_shape(np.array([0.5 * m.Re]), bessel_roots(0, m.delta_o, 1), 0, m.Re, m.delta_o)[0][0, 0]
    ratio = np.abs(psi * ds.modal_coordinate.isel(mode=0)[:n]).max() / ds.amplitude[:n].max()
    assert 0.9 < float(ratio) < 1.1


HEAD = """
[job]
name = "refused"
analysis = "{analysis}"

[model]
kind = "full"

[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
c = 0.05
"""


@pytest.mark.parametrize("analysis, table, key", [
    ("continuation", 'parameter = "P0"\nstart = 0.0\nstop = 1.0\nmodes = [[1, 1]]', "continuation.modes"),
    ("response", 'parameter = "P0"\nvalues = {start = 0.1, stop = 1.0, num = 4}\npoincare_points = 64',
     "response.poincare_points"),
    ("basins", "modes = [[1, 0], [1, 1]]", "basins.modes"),
])
def test_full_model_refuses_what_its_axisymmetric_map_cannot_do(analysis, table, key):
    text = HEAD.format(analysis=analysis) + ("P0 = 1.0\n" if analysis == "basins" else "")
    text += f"\n[{analysis}]\n{table}\n"
    with pytest.raises(JobError, match=key.replace(".", r"\.")):
        parse_job(text)



BASINS_JOB = """
[job]
name = "full-basins"
analysis = "basins"

[model]
kind = "full"
order = 8

[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
P0 = 1.0
c = 0.05

[basins]
modes = [[1, 0], [2, 0]]
ic_x = {start = -0.3, stop = 0.3, num = 2}
ic_y = {start = -10.0, stop = 10.0, num = 2}
tiles = 2
"""


def test_basins_job_on_the_full_model_labels_what_plain_integration_reaches(tmp_path):
    # the four corners of the Fig. 19a window (order 8): each initial condition, lifted to the full
    # state by hand, integrated period by period until its modal section is within 0.01 of the
    # window (scaled) of one of the job's attractors' modal sections, which must be its label
    # (the job: the fast method, cells and Newton, capturing in the full state; period by period
    # as its trajectories advance, since some initial conditions of this window change their
    # attractor under a change of 1e-12, docs/validation.md)
    ds = _run_job(tmp_path, BASINS_JOB)
    assert int(ds.n_attractors) == 2 and set(np.unique(ds.label)) == {0, 1}  # both attractors at the corners
    assert float(ds.attractor_amplitude[0]) > 3 * float(ds.attractor_amplitude[1])  # resonant, non-resonant
    model = AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), 8))
    fmap = ForcedFull.build(model, 1.0, 33.5, Viscous(0.05), int(ds.rk4_steps), modes=[(1, 0), (2, 0)])
    scale = np.array([1 / 0.6, 1 / 0.6, 1 / 20.0, 1 / 20.0])
    attractors = np.concatenate([ds.attractor_coordinate.isel(attractor=slice(0, 2), phase=0).values,
                                 ds.attractor_velocity.isel(attractor=slice(0, 2), phase=0).values], axis=-1)
    assert (ds.attractor_period[:2] == 1).all()
    for i, x in enumerate(ds.ic_x.values):
        for j, v in enumerate(ds.ic_y.values):
            q = np.zeros(4)
            q[0], q[2] = x, v
            o, dof = model.order, fmap.dof
            y = np.zeros(2 * dof)
            y[o:dof] = x * fmap.lift[0]
            y[dof + o:] = v * fmap.lift[0]
            np.testing.assert_array_equal(y, fmap.modal_lift(q))
            for _ in range(20_000):  # period by period, as the classifier advances its states
                y = fmap.advance(y)
                near = np.linalg.norm((fmap.modal_section(y) - attractors) * scale, axis=1) < 0.01
                if near.any():
                    break
            assert near.tolist() == [ds.label[i, j] == 0, ds.label[i, j] == 1]


def test_fold_curves_in_delta_on_the_full_model_meet_the_branches_at_other_deltas():
    # the two saddle-nodes of the Fig. 14a branch at a 1 % modal ratio (jobs/fig14a-full.toml at
    # order 6) followed in delta from 1.1 to 1.11: the model rebuilds pre-stretch and map at each
    # delta; at a curve's point the one-parameter branch of a map built there by hand has its
    # saddle-node
    from model.continuation import FOLD, continue_orbits
    from model.damping import Modal
    from sweep.analyses.continuation import CONTINUATION
    from sweep.jobspec import grid_point

    job = parse_job((Path(__file__).resolve().parents[1] / "jobs" / "fig14a-full.toml").read_text()
                    .replace("order = 16", "order = 6").replace("start = 25.0", "start = 33.0")
                    .replace("stop = 55.0", "stop = 38.0")
                    .replace("families = {n = [1, 2, 3, 4, 5, 6], radial = 16, inplane = true}",
                             'bifurcation_curves = {parameter = "delta", start = 1.1, stop = 1.11}'))
    point = grid_point(job.membrane, {"delta": 1.1, "delta_o": 0.2, "P0": 10.0}, job.damping.law, job.model)
    out = CONTINUATION.compute(point, job.options, 0)
    assert out["status"] == 0, out.get("message")
    folds = np.flatnonzero(out["curve_kind"] == FOLD)
    assert folds.size == 2
    for j in folds:
        q, p = out["curve_delta"][j], out["curve_Omega"][j]
        i = int(np.nanargmax(q))  # the curve's far end (its last step may pass delta = 1.11)
        assert q[i] >= 1.11 and np.nanmin(q) == pytest.approx(1.1, abs=1e-9)
        model = AxisymmetricFull(solve_full_prestretch(Membrane(delta=q[i], delta_o=0.2), 6))
        fmap = ForcedFull.build(model, 10.0, 33.0, Modal(0.01), int(out["rk4_steps"]), modes=[(1, 0)])
        one = continue_orbits(fmap, "Omega", 33.0, 38.0, ds_max=0.3, max_points=1000)
        assert np.min(np.abs(one.value[one.special(FOLD)] / p[i] - 1)) <= 1e-6


def test_the_full_model_rebuilt_at_another_delta_keeps_the_map_and_family_but_not_a_step_beyond_rk4s_bound(model):
    # sweep.models.full.FullModel.rebuilt: the forcing, law, steps, probe and modes of the map and
    # the family's wave number, functions and fields, on the membrane's pre-stretch at that delta;
    # at a delta whose fastest modes the task's steps no longer integrate, an ArithmeticError
    from model.full.families import FullFamily
    from sweep.jobspec import grid_point
    from sweep.models.full import FULL, FullOptions

    # steps that put omega_max dt at 1.9 here: above the bound 2 at delta 1.05 (omega_max 10 % higher
    # at order 8), below it at 1.12
    steps = int(np.ceil(2 * np.pi / 35.0 * ForcedFull.build(model, 10.0, 35.0).omega_max / 1.9))
    fmap = ForcedFull.build(model, 10.0, 35.0, Rayleigh(0.0, 1e-5), steps, probe_rho=0.4, modes=[(1, 0), (2, 0)])
    family = FullFamily.build(model, 2, 5, "W")
    point = grid_point(Membrane(), {"delta": 1.1, "delta_o": 0.2, "P0": 10.0, "Omega": 35.0})
    at = FULL.rebuilt(point, FullOptions(ORDER), None, fmap, family)
    other, fam = at(1.12)
    assert other.model.membrane.delta == 1.12 and fam.model is other.model
    assert (fam.n, fam.radial, fam.fields) == (2, 5, "W")
    assert (other.P0, other.Omega, other.steps, other.probe_rho, other.modes, other.damping) == \
        (10.0, 35.0, fmap.steps, 0.4, ((1, 0), (2, 0)), fmap.damping)
    assert other.omega_max < fmap.omega_max and other.rate == fmap.rate  # stiffer pre-stretch: slower in-plane
    assert not np.allclose(other.matrix, fmap.matrix)  # the law's stiffness part rebuilt
    with pytest.raises(ArithmeticError, match="continuation.steps >= "):
        at(1.05)
