"""Lyapunov exponents, rotation numbers and the kind of a response (model/lyapunov.py).

Against closed forms and published values: a linear damped system (the ROM about rest, the
discrete map's exponents in closed form), Liouville's sum rule of the viscous law on a forced
nonlinear orbit, Ueda's chaotic oscillator, the rotation of an undamped linear oscillator,
and the period doubling of the escape oscillator located independently by continuation.
"""

import numpy as np
import pytest

from escape_oscillator import EscapeMap, Forcing, ueda_map
from model.continuation import PERIOD_DOUBLING, continue_orbits
from model.forced import ForcedMap
from model.attractors import Attractor
from model.lyapunov import (CHAOTIC, DIVERGED, PERIODIC, QUASI_PERIODIC, classify, lyapunov_spectrum,
                            rotation_number)
from model.params import Loading, Membrane
from sweep.models.rom import rom_for


def _rom_map(P0, Omega=34.0, modes=((1, 0), (2, 0)), steps=128):
    rom = rom_for(Membrane(delta=1.1, delta_o=0.2), "numeric", modes)
    return ForcedMap.from_loading(rom, Loading(Omega, P0, 0.05), steps=steps)


def test_linear_damped_exponents_are_those_of_the_discrete_map_and_minus_alpha():
    # About rest the ROM is q'' + rate q' + omega_j^2 q = 0: every exponent of the flow is
    # -rate/2 (mass-proportional damping).  The RK4 map's exponents are log|R(h s)| / h with
    # s = -rate/2 +- i omega_d and R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24; the eigenvalues of
    # the map's matrix give s.  The finite run's estimates differ from the limits by at most
    # log(cond V) / (N T) (V the eigenvectors in the frame's norm).
    fmap = _rom_map(0.0)
    N, T, h = 2000, fmap.period, fmap.period / fmap.steps
    rec = lyapunov_spectrum(fmap, np.full(4, 1e-12), N, 10)
    phi = fmap.monodromy(np.zeros(4))[1]
    scale = fmap.state_scale()
    mu, V = np.linalg.eig(scale[:, None] * phi / scale[None, :])
    s = np.log(mu.astype(complex)) / T  # one period of steps: s per second of the discrete map
    omega_d = np.abs(s.imag)
    z = h * (-0.5 * fmap.forcing.damping_rate + 1j * omega_d)
    discrete = np.log(np.abs(1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24)) / h
    bound = np.log(np.linalg.cond(V)) / (N * T)
    assert np.sort(rec.exponents) == pytest.approx(np.sort(discrete), abs=bound + 1e-12)
    # and the discrete map's exponents are the flow's, -rate/2, to RK4's error (h omega)^5/120
    alpha = 0.5 * fmap.forcing.damping_rate
    assert np.max(np.abs(discrete + alpha)) <= np.max((h * omega_d) ** 5) / 120 / h


def test_the_sum_is_log_det_and_liouvilles_contraction_on_a_forced_nonlinear_orbit():
    # The spectrum's sum equals the mean log|det dP/dy| exactly (orthogonal frames); for
    # the viscous law the flow's divergence is -rate per mode whatever the nonlinearity,
    # so the sum is -K rate, to the RK4 error of the determinant (halved by 2^4 per halved step).
    gaps = []
    for steps in (128, 256):
        fmap = _rom_map(1.0, steps=steps)
        y = fmap.advance(np.zeros(4), 50)
        rec = lyapunov_spectrum(fmap, y, 20, 10)
        assert rec.exponents.sum() == pytest.approx(rec.log_det / rec.period, rel=1e-12)
        gaps.append(abs(rec.exponents.sum() + 2 * fmap.forcing.damping_rate))
    assert gaps[1] <= 1e-3 * 2 * fmap.forcing.damping_rate
    assert gaps[1] <= gaps[0] / 8  # fourth order: 16 in theory


def test_ueda_oscillator_is_chaotic_with_its_published_exponent():
    # x'' + 0.05 x' + x^3 = 7.5 cos t: lambda = (0.0999, 0, -0.1499) per unit time
    # (Sprott's, RK4 step 1e-3, of the flow with the time as a state; the stroboscopic map
    # drops the zero).  5 %: 40000 periods give 0.1029 +- 0.0007 here, 3 % above it.
    fmap = ueda_map(128)
    y = fmap.advance(np.array([0.1, 0.0]), 100)
    rec = lyapunov_spectrum(fmap, y, 4000, 20)
    assert rec.exponents[0] == pytest.approx(0.0999, rel=0.05)
    assert rec.exponents.sum() == pytest.approx(-0.05, rel=1e-3)
    assert classify(fmap, rec).kind == CHAOTIC


def test_an_undamped_linear_oscillator_is_quasi_periodic_with_its_rotation_number():
    # x'' + x = F sin(Omega t): the free part turns by 2 pi / Omega per forcing period on an
    # ellipse about the forced response, rotation number frac(1 / Omega) folded into [0, 1/2].
    # The mean angle step on an ellipse is off by less than the angle's distortion (< pi/2)
    # twice over N steps: 1 / (2 N).
    ratio = 1.3819660112501051
    fmap = EscapeMap(0.0, Forcing(0.0, 0.1, 1.0 / ratio), 256, (1.0, 0.0, 0.0))
    N = 400
    rec = lyapunov_spectrum(fmap, np.array([0.3, 0.0]), N, 10)
    kind = classify(fmap, rec)
    assert kind.kind == QUASI_PERIODIC
    assert kind.rotation_number == pytest.approx(min(ratio % 1, 1 - ratio % 1), abs=1 / (2 * N))


def test_rotation_number_refuses_points_not_on_a_circle():
    rng = np.random.default_rng(1)
    assert np.isnan(rotation_number(rng.normal(size=(50, 2)), np.ones(2)))


@pytest.fixture(scope="module")
def period_doubling():
    # The escape equation's period doubling in F at beta = 0.1, Omega = 1, located by continuation
    fmap = EscapeMap(0.1, Forcing(0.1, 0.0, 1.0), 128)
    br = continue_orbits(fmap, "P0", 0.0, 0.3, ds_max=0.1, max_points=400)
    i = int(br.special(PERIOD_DOUBLING)[0])
    return fmap, br.value[i], br.state[i]


@pytest.mark.parametrize("side, period", [(-1, 1), (1, 2)])
def test_classification_finds_period_one_below_and_two_above_the_located_doubling(period_doubling, side, period):
    fmap, F, y = period_doubling
    at = fmap.varied("P0", F * (1 + 0.02 * side))
    y = at.advance(y + 1e-3, 400)
    kind = classify(at, lyapunov_spectrum(at, y, 40, 10))
    assert (kind.kind, kind.period) == (PERIODIC, period)


def test_an_escape_is_diverged():
    fmap = EscapeMap(0.1, Forcing(0.0, 0.3, 0.85), 128)
    rec = lyapunov_spectrum(fmap, np.zeros(2), 100, 10)
    assert not rec.finite and np.all(np.isnan(rec.exponents))
    assert classify(fmap, rec).kind == DIVERGED


def test_bad_run_lengths_are_refused():
    with pytest.raises(ValueError, match="periods, blocks"):
        lyapunov_spectrum(ueda_map(), np.zeros(2), 15, 10)


def test_a_lightly_damped_periodic_response_is_periodic_when_the_run_cannot_resolve_its_exponent():
    """The paper's damping with a short run: the exponent of the forced periodic response,
    -alpha = -c / (2 Gamma h), lies within the run's resolution 0.1 / (N T) of zero, and the
    run starts off the orbit (a slow transient).  Newton on P finds the orbit the run tends to,
    so the response is periodic, not quasi-periodic: the periodic search must not wait for
    the exponent.  The run spirals in, turning about once in 23 periods (the rotation number
    0.044 the classification finds otherwise), on an ellipse: its plain distance to the orbit
    swings with the phase (it said "no" at 3 of these 12 starts), so whether the run
    approaches is judged in the Lyapunov norm of the orbit's map, at every phase of the turn."""
    fmap = _rom_map(1.0, modes=((1, 0),))
    N = 20
    alpha = 0.5 * fmap.forcing.damping_rate
    assert alpha < 0.1 / (N * fmap.period)  # the premise: the exponent is not resolved
    y = fmap.advance(np.array([0.01, 0.0]), 50)  # still on its way to the orbit
    for shift in range(0, 24, 2):
        kind = classify(fmap, lyapunov_spectrum(fmap, fmap.advance(y, shift), N, 10))
        assert kind.kind == PERIODIC and kind.period == 1, shift


class _Linear:
    """The linear map ``y -> A y`` of period 1 s (its fixed point: the origin)."""

    period = 1.0

    def __init__(self, A):
        self.A, self.dof = np.asarray(A, float), len(A) // 2

    def monodromy(self, y):
        return self.A @ y, self.A

    def state_scale(self):
        return np.ones(len(self.A))


def test_a_run_approaches_a_stable_node_that_first_carries_it_away():
    # A = 0.998 [[1, 0.2], [0, 1]]: both multipliers 0.998 (a Jordan node, no eigenvector
    # basis), and from (0, 1) the run first moves away, |A^j y0| = 0.998^j |(0.2 j, 1)|, five
    # times farther after 50 periods than at the first: a plain distance says it does not
    # approach.  In the Lyapunov norm x^T X x (A^T X A - X = -I) every period lowers it by
    # |x|^2, so the run approaches at every length.
    from model.lyapunov import _approaches

    fmap = _Linear(0.998 * np.array([[1.0, 0.2], [0.0, 1.0]]))
    points = np.array([np.linalg.matrix_power(fmap.A, j) @ [0.0, 1.0] for j in range(1, 51)])
    assert np.linalg.norm(points[-1]) > 5 * np.linalg.norm(points[0])
    orbit = Attractor(np.zeros((1, 2)), np.linalg.eigvals(fmap.A), 0, fmap.A)
    assert all(_approaches(points[:n], orbit, np.ones(2)) for n in range(2, 51))
    # and a run that leaves the orbit's neighbourhood the other way (time reversed) does not
    assert not _approaches(points[::-1].copy(), orbit, np.ones(2))


class _TwoPhase:
    """A map with a stable period-two orbit whose two phases have different linear parts:
    the state ``(x1, x2, s, t)``; ``s`` alternates between +-1e-3 (``s' = -sign(s) (1e-3 +
    (|s| - 1e-3) / 2)``), ``t' = t / 2``, and ``x' = b + L1 (x - a)`` where ``s > 0``, ``a + L2
    (x - b)`` elsewhere: the orbit ``(a, 1e-3, 0) -> (b, -1e-3, 0)``, ``P^2`` linear in ``x``
    about each point (``L2 L1`` at the first, ``L1 L2`` at the second)."""

    dof, period = 2, 1.0
    a, b = np.array([0.005, 0.0]), np.array([-0.005, 0.0])
    L1 = 0.99 * np.array([[np.cos(0.4), -3 * np.sin(0.4)], [np.sin(0.4) / 3, np.cos(0.4)]])
    L2 = 0.99 * np.array([[np.cos(0.3), -np.sin(0.3) / 2], [2 * np.sin(0.3), np.cos(0.3)]])

    def monodromy(self, y):
        x, s, t = y[:2], y[2], y[3]
        L, image = (self.L1, self.b + self.L1 @ (x - self.a)) if s > 0 else (self.L2, self.a + self.L2 @ (x - self.b))
        jac = np.zeros((4, 4))
        jac[:2, :2], jac[2, 2], jac[3, 3] = L, -0.5, 0.5
        return np.concatenate([image, [-np.sign(s) * (1e-3 + 0.5 * (abs(s) - 1e-3)), 0.5 * t]]), jac

    def state_scale(self):
        return np.ones(4)


def test_a_run_far_from_a_period_two_orbit_is_judged_at_its_own_phase():
    # A run 5 cm from the orbit, whose points are 1 cm apart: the orbit point nearest its last
    # point is, at some lengths, of the other phase; the test takes the phase Newton converged
    # to (Attractor.found_at: the last point's), and the run, linear about the orbit in each
    # phase, approaches at every length.
    from model.lyapunov import _approaches

    fmap = _TwoPhase()
    y, points = np.array([0.05, 0.03, 1e-3, 0.0]), []
    for _ in range(60):
        y = fmap.monodromy(y)[0]
        points.append(y)
    points = np.array(points)
    orbit_points = np.array([[*fmap.a, 1e-3, 0.0], [*fmap.b, -1e-3, 0.0]])
    jacobians = []  # of P^2 at each orbit point: the chain rule along the orbit
    for start in orbit_points:
        first_image, first_jacobian = fmap.monodromy(start)
        jacobians.append(fmap.monodromy(first_image)[1] @ first_jacobian)
    other_phase = 0
    for n in range(4, 61):
        phase = 0 if points[n - 1, 2] > 0 else 1
        nearest = int(np.argmin(np.linalg.norm(orbit_points - points[n - 1], axis=1)))
        other_phase += nearest != phase
        assert _approaches(points[:n], Attractor(orbit_points, np.ones(4) * 0.98, phase, jacobians[phase]), np.ones(4)), n
    assert other_phase > 0  # the case the phase bookkeeping is for


def test_a_found_orbit_carries_the_derivative_of_p_k_at_the_point_newton_converged_to():
    # Newton on P^2 of the two-phase map from near each orbit point: the Attractor's points
    # start at the smaller first coordinate (b), found_at names the converged point, and
    # jacobian is the chain rule along the orbit from there (L2 L1 at a, L1 L2 at b)
    from model.attractors import find_periodic_orbit

    fmap = _TwoPhase()
    for start, phase, chain in ((fmap.a, 1, fmap.L2 @ fmap.L1), (fmap.b, 0, fmap.L1 @ fmap.L2)):
        y0 = np.array([*(start + [2e-4, -1e-4]), 1e-3 if phase == 1 else -1e-3, 1e-4])
        orbit = find_periodic_orbit(y0, 2, fmap, np.ones(4), 1e-12)
        assert orbit is not None and orbit.found_at == phase
        np.testing.assert_allclose(orbit.points[0, :2], fmap.b, atol=1e-12)
        np.testing.assert_allclose(orbit.jacobian[:2, :2], chain, rtol=1e-14)
        np.testing.assert_allclose(orbit.jacobian[2:, 2:], np.diag([0.25, 0.25]), rtol=1e-14)


def test_the_approach_test_holds_where_the_lyapunov_equation_cannot_be_solved():
    # P = V R V^-1, R three rotations of modulus 0.9999, cond V = 1e4: the direct solve of the
    # Stein equation returns a matrix that is not positive definite (the equation's solution
    # is); the test then sums the norm's series sum_j |J^j x|^2, and a linear run approaches
    # (and the same run reversed does not), without warnings
    import warnings

    from scipy.linalg import solve_discrete_lyapunov

    from model.lyapunov import _approaches

    rng = np.random.default_rng(1)  # (one of the draws where it fails)
    R = np.zeros((6, 6))
    for i, angle in enumerate((0.3, 1.1, 2.0)):
        R[2 * i:2 * i + 2, 2 * i:2 * i + 2] = 0.9999 * np.array([[np.cos(angle), -np.sin(angle)],
                                                                  [np.sin(angle), np.cos(angle)]])
    U, W = (np.linalg.qr(rng.standard_normal((6, 6)))[0] for _ in range(2))
    V = U @ np.diag(np.logspace(0, 4, 6)) @ W
    fmap = _Linear(V @ R @ np.linalg.inv(V))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        direct = solve_discrete_lyapunov(fmap.A.T, np.eye(6))
    assert np.linalg.eigvalsh(0.5 * (direct + direct.T)).min() < 0  # the case
    points = np.array([np.linalg.matrix_power(fmap.A, j) @ np.ones(6) for j in range(1, 201)])
    orbit = Attractor(np.zeros((1, 6)), np.linalg.eigvals(fmap.A), 0, fmap.A)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _approaches(points, orbit, np.ones(6))
        assert not _approaches(points[::-1].copy(), orbit, np.ones(6))
