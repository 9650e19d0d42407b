"""Shooting on the stroboscopic map: linear limits in closed form, Liouville, stability."""

import numpy as np
import pytest

from model.forced import ForcedMap
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom, force_jacobian
from model.shooting import shoot


@pytest.fixture(scope="module")
def rom():
    return build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0)])


def _linear(rom, loading):
    tab = rom.tables
    jac = np.zeros((1, 1))
    force_jacobian(np.zeros(1), tab, jac)
    w0sq = tab.k_force[0] * jac[0, 0]
    cd = loading.c / (rom.membrane.Gamma * rom.membrane.h)  # Eq. 31 divided by Gamma h M
    return w0sq, cd


def test_small_forcing_gives_the_linear_frequency_response(rom):
    ld = Loading(Omega=31.0, P0=1e-4, c=0.5)
    w0sq, cd = _linear(rom, ld)
    amp_q = abs(rom.tables.load[0]) * ld.P0 / np.hypot(w0sq - ld.Omega**2, cd * ld.Omega)
    orbit = shoot(ForcedMap.from_loading(rom, ld), np.zeros(2))
    assert orbit.converged and orbit.iterations <= 3
    # tolerance: RK4 truncation at 128 steps per period near resonance (~1e-5)
    assert orbit.amplitude == pytest.approx(abs(rom.tables.probe[0]) * amp_q, rel=1e-4)


def test_linear_multipliers_are_exp_of_the_damped_eigenvalues(rom):
    ld = Loading(Omega=31.0, P0=1e-6, c=0.5)
    w0sq, cd = _linear(rom, ld)
    orbit = shoot(ForcedMap.from_loading(rom, ld), np.zeros(2))
    lam = -cd / 2 + 1j * np.sqrt(w0sq - cd**2 / 4)
    T = 2 * np.pi / ld.Omega
    expected = np.exp(lam * T)
    mu = orbit.multipliers
    assert np.abs(mu) == pytest.approx(np.full(2, abs(expected)), rel=1e-7)
    assert sorted(np.abs(np.angle(mu))) == pytest.approx([abs(np.angle(expected))] * 2, rel=1e-5)
    assert orbit.stable


def test_monodromy_determinant_obeys_liouville_on_a_large_orbit(rom):
    # trace of the variational matrix is -K c/(Gamma h): det Phi = exp(-K c T/(Gamma h))
    ld = Loading(Omega=33.5, P0=1.0, c=0.05)
    orbit = shoot(ForcedMap.from_loading(rom, ld), np.array([-0.1, 0.0]))
    assert orbit.converged and orbit.amplitude > 0.05
    _, phi = ForcedMap.from_loading(rom, ld).monodromy(orbit.state)
    cd = ld.c / (rom.membrane.Gamma * rom.membrane.h)
    # RK4 keeps it to its truncation error (~3e-8 at 128 steps per period)
    assert np.linalg.det(phi) == pytest.approx(np.exp(-cd * 2 * np.pi / ld.Omega), rel=1e-6)
    assert np.prod(orbit.multipliers).real == pytest.approx(np.linalg.det(phi), rel=1e-10)


def test_three_coexisting_responses_at_the_paper_point(rom):
    # Fig. 15a / 19a: delta = 1.1, Omega = 33.5, P0 = 1, c = 0.05 lies in the range of
    # three periodic responses, two stable (small and resonant) and one saddle.
    ld = Loading(Omega=33.5, P0=1.0, c=0.05)
    orbits = [shoot(ForcedMap.from_loading(rom, ld), np.array([g, 0.0])) for g in (0.0, -0.1, 0.1)]
    assert all(o.converged for o in orbits)
    amps = [o.amplitude for o in orbits]
    assert len({round(a, 6) for a in amps}) == 3
    assert [o.stable for o in orbits] == [True, True, False]
    saddle = orbits[2].multipliers
    assert saddle[0].real > 1 > abs(saddle[1]) and abs(saddle[0].imag) == 0


def test_stable_orbit_is_a_fixed_point_of_long_time_integration(rom):
    ld = Loading(Omega=33.5, P0=1.0, c=0.05)
    orbit = shoot(ForcedMap.from_loading(rom, ld), np.array([-0.1, 0.0]))
    y = ForcedMap.from_loading(rom, ld).advance(orbit.state, periods=200)
    s = np.array([1.0, 1.0 / ld.Omega])
    assert np.linalg.norm(s * (y - orbit.state)) < 1e-8 * np.linalg.norm(s * orbit.state)
    assert ForcedMap.from_loading(rom, ld).amplitude(y) == pytest.approx(orbit.amplitude, rel=1e-8)


def test_amplitude_of_a_sinusoid_is_refined_between_samples(rom):
    # A free linear orbit sampled with 16 steps: the parabolic refinement recovers the
    # maximum of |w| to (2 pi/16)^4-ish accuracy, far better than the raw samples.
    ld = Loading(Omega=30.0, P0=0.0, c=0.0)
    w0 = np.sqrt(_linear(rom, ld)[0])
    q0 = 1e-4
    amp = ForcedMap.from_loading(rom, ld, steps=16).amplitude(np.array([q0 * 0.6, q0 * 0.8 * w0]))
    assert amp == pytest.approx(abs(rom.tables.probe[0]) * q0, rel=3e-3)


def test_bad_guess_shape_is_rejected(rom):
    with pytest.raises(ValueError, match=r"guess.shape = \(3,\) is invalid: expected \(2,\)"):
        shoot(ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05)), np.zeros(3))


def test_non_convergence_is_reported_not_raised(rom):
    orbit = shoot(ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05)), np.array([0.05, 0.0]), max_iter=1)
    assert not orbit.converged and orbit.iterations == 1
