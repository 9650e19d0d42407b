"""The stroboscopic map object (model/forced.py) and the parameter records it is built from.

References: composition of the map with itself, finite differences of the map for the
monodromy matrix, the closed form of the damping rate and of a small free vibration, and
the parameter records' own metadata.
"""

import numpy as np
import pytest

from model.forced import ForcedMap, sorted_multipliers, state_scale, steps_per_period
from model.linear import galerkin_frequencies
from model.params import Loading, Membrane, ParameterError, parameter_info
from model.prestretch import solve_prestretch
from model.rom import build_rom, force_jacobian

PAPER = Loading(Omega=33.5, P0=1.0, c=0.05)


@pytest.fixture(scope="module", params=[[(1, 0)], [(1, 0), (2, 0)]], ids=["1 mode", "2 modes"])
def fmap(request):
    rom = build_rom(solve_prestretch(Membrane(), "analytic"), request.param)
    return ForcedMap.from_loading(rom, PAPER, steps=64)


def test_damping_rate_is_c_over_gamma_h():
    m = Membrane(h=2e-3, Gamma=1000.0)
    assert m.damping_rate(0.5) == 0.5 / 2.0
    rom = build_rom(solve_prestretch(Membrane(), "analytic"), [(1, 0)])
    f = ForcedMap.from_loading(rom, PAPER)
    assert f.forcing[:3] == (0.05 / 2.2, 1.0, 33.5) and f.forcing.damping_matrix.size == 0
    assert f.period == 2 * np.pi / 33.5


def test_k_periods_are_the_map_composed_k_times(fmap):
    y = np.zeros(2 * fmap.dof)
    y[0] = -0.05
    once = fmap.advance(y)
    assert np.array_equal(fmap.advance(y, periods=3), fmap.advance(fmap.advance(once), 1))
    assert np.array_equal(fmap.advance_batch(np.stack([y, once]), 2)[1], fmap.advance(once, 2))


def test_monodromy_is_the_derivative_of_the_map(fmap):
    y = np.zeros(2 * fmap.dof)
    y[0], y[fmap.dof] = -0.05, 0.3
    yT, phi = fmap.monodromy(y)
    # the one-mode monodromy is its own fused kernel: equal to the map up to round-off
    np.testing.assert_allclose(yT, fmap.advance(y), rtol=1e-13, atol=1e-15)
    h = 1e-6 * np.abs(y).max()
    fd = np.column_stack([(fmap.advance(y + h * e) - fmap.advance(y - h * e)) / (2 * h)
                          for e in np.eye(y.size)])
    assert np.abs(phi - fd).max() <= 1e-6 * np.abs(fd).max()
    mu = fmap.multipliers(y)
    assert np.all(np.diff(np.abs(mu)) <= 0) and np.prod(mu).real == pytest.approx(np.linalg.det(phi), rel=1e-10)


def test_varied_changes_one_forcing_parameter(fmap):
    g = fmap.varied("Omega", 30.0)
    assert g.forcing[:3] == (fmap.forcing.damping_rate, fmap.forcing.P0, 30.0) and g.steps == fmap.steps
    assert fmap.varied("P0", 0.5).forcing.P0 == 0.5
    assert fmap.varied("c", 0.5).forcing.damping_rate == 0.5 / 2.2
    with pytest.raises(ValueError, match="parameter = 'h' is invalid: must be one of Omega, P0, c"):
        fmap.varied("h", 1.0)


def test_amplitude_over_several_periods_of_a_periodic_orbit_is_its_one_period_value():
    # Free small vibration q = a cos(w0 t) with the map's period 2 pi / w0: periodic over
    # any number of periods, so the estimate over 3 periods is the one-period estimate.
    rom = build_rom(solve_prestretch(Membrane(), "analytic"), [(1, 0)])
    jac = np.empty((1, 1))
    force_jacobian(np.zeros(1), rom.tables, jac)
    w0 = np.sqrt(rom.tables.k_force[0] * jac[0, 0])
    f = ForcedMap.from_loading(rom, Loading(Omega=float(w0)), steps=128)
    y = np.array([1e-5, 0.0])
    assert f.amplitude(y, periods=3) == pytest.approx(f.amplitude(y), rel=1e-9)
    assert f.amplitude(y) == pytest.approx(abs(rom.tables.probe[0]) * 1e-5, rel=1e-6)


def test_two_by_two_multipliers_in_closed_form_are_lapacks():
    # The closed form of the one-mode case against LAPACK's eigenvalues (numpy), sorted
    # alike: real and complex pairs, a near double root, a singular and a zero matrix, a
    # tie in modulus, entries whose formula overflows (LAPACK then); not finite: NaN.
    rng = np.random.default_rng(3)
    cases = [m for m in rng.normal(size=(200, 2, 2))]
    cases += [np.array([[1.0, 1e-9], [0.0, 1.0 + 1e-12]]), np.array([[2.0, 4.0], [1.0, 2.0]]), np.zeros((2, 2)),
              np.array([[0.0, -1.0], [1.0, 0.0]]), np.diag([-1.0, 1.0]), np.diag([1.0, -1.0])]
    for phi in cases:
        mu = sorted_multipliers(phi)
        ref = np.linalg.eigvals(phi).astype(complex)
        ref = ref[np.lexsort((-ref.real, -ref.imag, -np.abs(ref)))]
        scale = np.abs(phi).max() or 1.0
        assert np.allclose(mu, ref, rtol=0, atol=1e-12 * scale), (phi, mu, ref)
        assert mu.dtype == complex and mu.shape == (2,)
    huge = np.array([[1e200, 1.0], [1.0, -1e200]])
    assert np.allclose(sorted_multipliers(huge), [1e200, -1e200], rtol=1e-12)
    for bad in (np.array([[np.inf, 0.0], [0.0, 1.0]]), np.array([[np.nan, 0.0], [0.0, 1.0]]), np.full((4, 4), np.nan)):
        mu = sorted_multipliers(bad)
        assert mu.shape == (bad.shape[0],) and np.all(np.isnan(mu))


def test_a_diverging_guess_is_not_converged_rather_than_an_error():
    # shoot() reports failure (its docstring: it never raises for that) and the branch
    # reports that it found no response, for one mode (the closed-form multipliers) too.
    from model.continuation import continue_orbits
    from model.shooting import shoot

    rom = build_rom(solve_prestretch(Membrane(), "analytic"), [(1, 0)])
    fmap = ForcedMap.from_loading(rom, PAPER, steps=64)
    with np.errstate(over="ignore", invalid="ignore"):  # the guess overflows on purpose
        res = shoot(fmap, np.array([1e300, 1e300]))
        branch = continue_orbits(fmap, "P0", 1.0, 2.0, guess=np.array([1e300, 1e300]))
    assert not res.converged
    assert not branch.complete and "no periodic response found" in branch.message


def test_bad_arguments_are_named():
    rom = build_rom(solve_prestretch(Membrane(), "analytic"), [(1, 0)])
    with pytest.raises(ValueError, match="steps = 0 is invalid: must be an integer >= 1"):
        ForcedMap.from_loading(rom, PAPER, steps=0)
    with pytest.raises(ValueError, match=r"state shape \(3,\) is invalid: expected \(2,\)"):
        ForcedMap.from_loading(rom, PAPER).advance(np.zeros(3))
    with pytest.raises(ValueError, match="periods = 0 is invalid: must be >= 1"):
        ForcedMap.from_loading(rom, PAPER).amplitude(np.zeros(2), 0)
    assert np.array_equal(state_scale(2, 4.0), [1.0, 1.0, 0.25, 0.25])


def test_parameter_records_carry_their_units_and_rules():
    assert parameter_info("Omega") == (Loading, "rad s-1", "forcing frequency")
    assert parameter_info("delta")[0] is Membrane
    with pytest.raises(KeyError):
        parameter_info("E")
    with pytest.raises(ParameterError) as err:
        Loading(P0=-1)
    assert (err.value.name, err.value.value, err.value.allowed) == ("P0", -1.0, "a finite number >= 0 (Pa)")


def test_auto_steps_integrate_the_fastest_mode_as_the_base_integrates_one_mode():
    # steps_per_period scales the one-mode default by (omega_max / omega_min)^(5/4), with
    # the frequencies of model.linear here (an independent computation): RK4's error per
    # period grows as omega^5 / steps^4, so at the scaled steps the three-mode map is as
    # accurate as the one-mode map at the base (ratio 0.94 with the rounding up), at the
    # base itself 3.07^5 = 270 times less.
    ps = solve_prestretch(Membrane(), "numeric")
    one, three = build_rom(ps, [(1, 0)]), build_rom(ps, [(1, 0), (2, 0), (3, 0)])
    omega = galerkin_frequencies(ps, 0, 3)[0]
    base = 64
    steps = steps_per_period(three, base)
    assert steps_per_period(one, base) == base
    assert steps == 8 * np.ceil(base * (omega[2] / omega[0]) ** 1.25 / 8)

    def error(rom, n):   # one period from a small state (linear regime), against 8x the steps
        y = np.r_[np.full(rom.dof, 1e-3), np.zeros(rom.dof)]
        fine = ForcedMap.from_loading(rom, PAPER, 8 * n).advance(y)
        return np.abs(ForcedMap.from_loading(rom, PAPER, n).advance(y) - fine).max() / np.abs(fine).max()

    e1 = error(one, base)
    assert error(three, steps) < 1.5 * e1 and error(three, base) > 50 * e1
