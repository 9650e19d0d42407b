"""Axisymmetric motion of the full model (model/full/axisymmetric.py): its force is the gradient
of its energy, its compiled loops are the numpy ones, its free motion conserves energy and has
the linear frequency and the second-order in-plane displacement of a small vibration."""

import numpy as np
import pytest
from scipy.linalg import eigh

from model.full.axisymmetric import AxisymmetricFull
from model.full.linear import stiffness_mass
from model.full.static import solve_full_prestretch
from model.params import Membrane


@pytest.fixture(scope="module")
def model():
    return AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), 16))


def test_force_is_the_gradient_of_the_energy(model):
    rng = np.random.default_rng(3)
    q = 0.02 * rng.normal(size=model.dof)
    g, H = model.gradient(q), model.hessian(q)
    np.testing.assert_allclose(model.compiled_gradient(q), g, rtol=1e-11, atol=1e-13)
    assert np.abs(model.gradient(np.zeros(model.dof))).max() < 1e-13  # the pre-stretch is an equilibrium
    step = 1e-30
    for k in (0, model.order - 1, model.order, model.dof - 1):  # complex step: exact to rounding
        e = np.zeros(model.dof, complex)
        e[k] = 1j * step
        assert model.energy(q + e).imag / step == pytest.approx(g[k], rel=1e-10, abs=1e-14)
        np.testing.assert_allclose(model.gradient(q + e).imag / step, H[k], rtol=1e-9, atol=1e-12)


def test_hessian_at_rest_is_that_of_the_linear_problem(model):
    K_w, _ = stiffness_mass(model.state, 0, "W")
    K_u, _ = stiffness_mass(model.state, 0, "U")
    H = model.hessian(np.zeros(model.dof))
    o = model.order
    np.testing.assert_allclose(H[o:, o:], K_w, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(H[:o, :o], K_u, rtol=1e-12, atol=1e-12)
    assert np.abs(H[:o, o:]).max() == 0.0


def _first_mode(model):
    K, M = stiffness_mass(model.state, 0, "W")
    lam, vec = eigh(K, M)
    v = vec[:, 0] / model.state.basis.evaluate(vec[:, 0], np.array([0.5]))[0][0]  # w(0.5 Re) = 1 m
    return np.sqrt(model.omega0_2 * lam[0]), v


def test_small_free_vibration(model):
    # 1 and 2 mm at the probe: the frequency is the linear one but for the hardening, which is
    # of relative order (A / Re)^2 and so grows four times from 1 to 2 mm (the leading
    # nonlinearity is cubic); the energy is conserved by RK4 to its O(dt^4) error; and the
    # radial displacement, driven by w'^2, is of second order in the amplitude
    omega, v = _first_mode(model)
    period = 2 * np.pi / omega
    probe = model.state.basis.evaluate(np.eye(model.order), np.array([0.5]))[0][:, 0]
    s = np.linspace(model.membrane.delta_o, 1.0, 81)
    shifts, radial = [], []
    for amplitude in (1e-3, 2e-3):
        q = model.relaxed(-amplitude * v / model.membrane.Re)
        steps = int(np.ceil(3 * period * model.highest_frequency()))  # omega_max dt = 1
        states = model.free_motion(np.concatenate([q, np.zeros(model.dof)]), 3 * period, steps)
        energy = [model.energy(y[:model.dof]) + model.kinetic(y[model.dof:]) for y in states[::50]]
        assert np.ptp(energy) < 1e-8 * (energy[0] - model.energy(np.zeros(model.dof)))
        w = states[:, model.order:model.dof] @ probe
        t = np.linspace(0.0, 3 * period, states.shape[0])
        up = np.nonzero((w[:-1] < 0) & (w[1:] >= 0))[0]
        crossings = t[up] - w[up] * (t[up + 1] - t[up]) / (w[up + 1] - w[up])
        shifts.append(2 * np.pi / np.diff(crossings).mean() / omega - 1)
        radial.append(max(np.abs(model.displacements(y[:model.dof], s)[0]).max() for y in states[::20]))
    assert 0 < shifts[0] < 1e-4
    assert shifts[1] / shifts[0] == pytest.approx(4.0, rel=0.05)
    assert radial[1] / radial[0] == pytest.approx(4.0, rel=0.02)


def test_free_flow_derivative_is_that_of_the_rk4_steps(model):
    # the variational equations give the exact derivative of the discrete map: central
    # differences of the same RK4 steps converge to it as h^2 (the in-plane waves make the
    # map strongly nonlinear at the steps that resolve them: the differences' error is then
    # O(h^2) with a large constant, 1e-2 relative at h = 1e-6 of a 2 cm state, and falls 100
    # times per decade of h until rounding, ~1e-14 / h, takes over)
    from model.full.free import FreeFull

    free = FreeFull(model)
    omega = free.linear_frequencies()[0][0]
    rng = np.random.default_rng(5)
    y0 = np.concatenate([0.02 * rng.normal(size=free.dof) / np.sqrt(free.dof), np.zeros(free.dof)])
    duration = 0.3 * 2 * np.pi / omega
    y, phi = free.flow(y0, duration, 16)
    steps = free.steps_for(y0[:free.dof], duration, 16)
    assert steps > 16  # the in-plane waves raise the steps to RK4's stability limit
    # plain RK4, the same steps in other code: their roundings differ by ~eps and the flow
    # amplifies a difference in a state by at most |phi| (~1e7: the in-plane waves)
    eps = np.finfo(float).eps * np.abs(phi).max()
    np.testing.assert_allclose(y, model.free_motion(y0, duration, steps)[-1], rtol=eps, atol=eps * np.abs(y0).max())
    for k in (0, free.dof - 1, free.dof + model.order):
        errors = []
        for h in (1e-6, 1e-7, 1e-8):
            e = np.zeros_like(y0)
            e[k] = h
            fd = (model.free_motion(y0 + e, duration, steps)[-1] - model.free_motion(y0 - e, duration, steps)[-1]) / (2 * h)
            errors.append(np.abs(phi[:, k] - fd).max() / np.abs(fd).max())
        # h^2 where the truncation shows (a wrong derivative leaves a floor instead) down to
        # 5 times the rounding of the smallest step
        for coarse, finer in zip(errors, errors[1:]):
            assert finer < max(coarse / 50, 1e-5)


def test_a_flow_asking_for_too_many_steps_is_refused_as_a_failed_solve(model, monkeypatch):
    # A Newton iterate gone astray (a wild state whose fastest mode asks for millions of steps)
    # must fail like a singular solve, so that the backbone continuation halves its step,
    # instead of running for hours
    from model.full import free as free_module

    free = free_module.FreeFull(model)
    y0 = np.zeros(2 * free.dof)
    duration = 0.25 * 2 * np.pi / free.linear_frequencies()[0][0]
    steps = free.steps_for(y0[:free.dof], duration, 16)
    monkeypatch.setattr(free_module, "MAX_FLOW_STEPS", steps - 1)
    with pytest.raises(np.linalg.LinAlgError, match=f"asks for {steps} RK4 steps"):
        free.flow(y0, duration, 16)
    monkeypatch.setattr(free_module, "MAX_FLOW_STEPS", steps)
    assert np.all(np.isfinite(free.flow(y0, duration, 16)[0]))
