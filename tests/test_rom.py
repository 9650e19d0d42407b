"""The nonlinear Galerkin ROM (Eq. 31) and its integrators: RK4 and DOP853.

Reference values come from closed forms (derivatives, energy conservation, the observed
order of RK4), the independent linear Galerkin solver of :mod:`model.linear`, and
``scipy.integrate.solve_ivp``.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from plain_rom import plain_rhs

from model import dopri
from model.damping import Rayleigh, Viscous
from model.damping_kernels import matrix_or_none
from model.forced import ForcedMap
from model.integrate import monodromy, rk4_quadrature_lockstep, rk4_steps
from model.linear import galerkin_frequencies
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import (LEAN_RADIAL_POINTS, Forcing, build_rom, elastic_force, force_jacobian, force_work,
                       lean_radial_points, total_energy)

AXI = [(1, 0), (2, 0), (3, 0)]
MIXED = [(1, 0), (2, 0), (1, 1), (1, 2)]


@pytest.fixture(scope="module")
def prestretch():
    return solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")


@pytest.fixture(scope="module")
def roms(prestretch):
    return {"1": build_rom(prestretch, [(1, 0)]), "axi": build_rom(prestretch, AXI),
            "mixed": build_rom(prestretch, MIXED)}


def _force(rom, q):
    g = np.empty(rom.dof)
    elastic_force(np.asarray(q, dtype=float), rom.tables, g, force_work(rom.tables))
    return g


@pytest.mark.parametrize("kind", ["axi", "mixed"])
def test_jacobian_matches_central_differences(roms, kind):
    rom = roms[kind]
    rng = np.random.default_rng(4)
    jac = np.empty((rom.dof, rom.dof))
    for _ in range(3):
        q = rng.uniform(-0.4, 0.4, rom.dof)
        force_jacobian(q, rom.tables, jac)
        h = 1e-5
        fd = np.column_stack([(_force(rom, q + h * e) - _force(rom, q - h * e)) / (2 * h)
                              for e in np.eye(rom.dof)])
        assert np.abs(jac - fd).max() <= 1e-7 * np.abs(fd).max()


def _backbone_states(dof):
    """States met along the paper's backbones: |w(0.5, 0)| up to 0.4 m on the first mode,
    the other modes at the percent level (Fig. 9)."""
    q = np.random.default_rng(5).uniform(-0.01, 0.01, (3, dof))
    q[:, 0] = [0.75, -0.4, 0.1]
    return q


@pytest.mark.parametrize("kind", ["axi", "mixed"])
def test_doubling_the_default_quadrature_changes_nothing(roms, kind):
    # The closed-form pre-stretch: the Chebyshev series of the numeric one is exact only to
    # ~1e-12, which would show up as a quadrature-independent floor at this tolerance.
    analytic = solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "analytic")
    rom = build_rom(analytic, roms[kind].modes)
    fine = build_rom(analytic, rom.modes, radial_points=2 * rom.radial_points,
                     theta_points=2 * rom.theta_points)
    for q in _backbone_states(rom.dof):
        g, g_fine = _force(rom, q), _force(fine, q)
        assert np.abs(g - g_fine).max() <= 1e-12 * _force_scale(fine, q)


def _force_scale(rom, q):
    """Round-off scale of the force: the quadrature sum of the integrands' magnitudes.

    A higher mode's force under a large first mode is a small difference of large
    contributions (|g_3| is ~1e-4 of this sum at |w| = 0.4 m), so its digits below
    ~1e-16 of this sum are noise whatever the rule."""
    t = rom.tables
    a, b = q @ t.b_rho, q @ t.b_theta
    delta = t.hoop2 * (t.radial2 + a * a) + t.radial2 * b * b * t.inv_rho2
    ia = np.abs(2 * a * (1 - t.hoop2 / delta**2)) * t.weight
    ib = np.abs(2 * b * t.inv_rho2 * (1 - t.radial2 / delta**2)) * t.weight
    return float((np.abs(t.b_rho) @ ia + np.abs(t.b_theta) @ ib).max())


def test_small_amplitude_frequencies_equal_linear_galerkin(prestretch, roms):
    """The linearised ROM is the linear Galerkin problem on the same basis (n decouple)."""
    rom = roms["mixed"]
    jac = np.empty((rom.dof, rom.dof))
    force_jacobian(np.zeros(rom.dof), rom.tables, jac)
    d = np.sqrt(rom.tables.k_force)
    omega = np.sort(np.sqrt(np.linalg.eigvalsh(d[:, None] * jac * d[None, :])))
    ref = np.sort(np.concatenate([galerkin_frequencies(prestretch, n, len(ms), basis=len(ms))[0]
                                  for n, ms in ((0, [1, 2]), (1, [1]), (2, [1]))]))
    np.testing.assert_allclose(omega, ref, rtol=1e-10)


@pytest.mark.parametrize("kind,periods", [("1", 1000), ("axi", 300)])
def test_energy_conserved_by_dop853(roms, kind, periods):
    rom = roms[kind]
    y0 = np.zeros(2 * rom.dof)
    y0[0], y0[rom.dof] = 0.2, 3.0
    T = 2 * np.pi / 38.0
    states, _ = dopri.solve(rom, y0, np.arange(periods + 1) * T, rtol=1e-12, atol=1e-15)
    energy = np.array([total_energy(rom, y) for y in states[0]])
    assert np.abs(energy / energy[0] - 1).max() <= 1e-9


def test_dop853_agrees_with_solve_ivp(roms):
    rom = roms["axi"]
    y0 = np.array([0.3, -0.01, 0.002, 0.0, 1.0, 0.0])
    te = np.linspace(0, 0.3, 4)
    ours, _ = dopri.solve(rom, y0, te, c=0.05, P0=1.0, Omega=33.5, rtol=1e-12, atol=1e-14)
    ref = solve_ivp(lambda t, y: plain_rhs(rom)(t, y) + np.concatenate(
        [np.zeros(3), -0.05 / 2.2 * y[3:] + np.cos(33.5 * t) * rom.tables.load]),
        (0, 0.3), y0, method="DOP853", t_eval=te, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(ours[0], ref.y.T, atol=1e-8 * np.abs(ref.y).max())


def test_rk4_shows_fourth_order(roms):
    rom = roms["axi"]
    y0 = np.array([0.25, -0.01, 0.001, 0.0, 0.0, 0.0])
    omega = 33.5
    period = 2 * np.pi / omega
    ref, _ = dopri.solve(rom, y0, [period], c=0.05, P0=1.0, Omega=omega, rtol=1e-13, atol=1e-15)
    errors = []
    for steps in (96, 192, 384):
        y = y0.copy()
        rk4_steps(y, 0.0, period / steps, steps, rom.tables, Forcing(0.05 / 2.2, 1.0, omega), np.empty((6, 6)))
        errors.append(np.abs(y - ref[0, 0]).max())
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 4.0) < 0.15), orders


def test_batches_equal_one_by_one(roms):
    rom = roms["axi"]
    rng = np.random.default_rng(7)
    y0 = rng.uniform(-0.1, 0.1, (4, 6))
    c, p0, om = np.array([0.0, 0.05, 0.5, 1.0]), np.array([0.0, 1.0, 2.0, 0.5]), np.array([30.0, 33.5, 35.0, 40.0])
    batch, nfev = dopri.solve(rom, y0, [0.1, 0.3], c=c, P0=p0, Omega=om)
    ext = dopri.extrema(rom, y0, 0.5, 6, c=c, P0=p0, Omega=om)
    for i in range(4):
        one, nf = dopri.solve(rom, y0[i], [0.1, 0.3], c=c[i], P0=p0[i], Omega=om[i])
        assert np.array_equal(one[0], batch[i]) and nf[0] == nfev[i]
        e1 = dopri.extrema(rom, y0[i], 0.5, 6, c=c[i], P0=p0[i], Omega=om[i])
        assert np.array_equal(e1.times[0], ext.times[i], equal_nan=True)
    fmap = ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05), steps=50)
    out = fmap.advance_batch(y0, periods=2)
    for i in range(4):
        assert np.array_equal(fmap.advance(y0[i], periods=2), out[i])


@pytest.mark.parametrize("law", [Viscous(0.05), Rayleigh(0.3, 4e-4)], ids=["viscous", "rayleigh"])
@pytest.mark.parametrize("kind", ["1", "axi2", "axi", "axi4", "axi5", "mixed"])
def test_lockstep_quadrature_is_the_scalar_loop(prestretch, roms, kind, law):
    """RK4 with the quadrature force in lock-step (one trajectory per column) = the scalar
    loop, trajectory by trajectory, from t0 != 0, up to rounding (fastmath reassociates
    the quadrature sums; one mode: the scalar loop reads the force table, 1e-13 from the
    quadrature: 1e-12 relative over 64 steps); columns beyond ``count``, NaN here, are
    left untouched and touch nothing.  Three and four axisymmetric modes take the
    unrolled loop, the others the general one; a Rayleigh law brings a damping matrix."""
    if kind.startswith("axi") and kind != "axi":
        rom = build_rom(prestretch, [(m, 0) for m in range(1, int(kind[3:]) + 1)])
    else:
        rom = roms[kind]
    t, K = rom.tables, rom.dof
    forcing = ForcedMap.build(rom, 1.0, 33.5, law).forcing
    assert forcing.damping_matrix.shape == ((0, 0) if K == 1 or law.name == "viscous" else (K, K))
    h = 2 * np.pi / 33.5 / 64
    rng = np.random.default_rng(3)
    y0 = np.zeros((19, 2 * K))
    y0[:, :K] = rng.uniform(-0.05, 0.05, (19, K))
    y0[:, 0] = rng.uniform(-0.3, 0.3, 19)
    y0[:, K] = rng.uniform(-10.0, 10.0, 19)
    y0[17:] = np.nan
    columns = np.ascontiguousarray(y0.T)
    t0 = 0.37
    rk4_quadrature_lockstep(columns, 17, t0, h, 64, t.weight, t.inv_rho2, t.hoop2, t.radial2, t.b_rho, t.b_theta,
                            t.axisymmetric, t.law, t.k_force, t.load, forcing.damping_rate, forcing.P0, forcing.Omega,
                            matrix_or_none(forcing.damping_matrix))
    work = np.empty((6, 2 * K))
    for b in range(17):
        y = y0[b].copy()
        rk4_steps(y, t0, h, 64, t, forcing, work)
        np.testing.assert_allclose(columns[:, b], y, rtol=1e-12, atol=1e-12 * np.abs(y).max())
    assert np.all(np.isnan(columns[:, 17:]))


def test_extrema_are_zeros_of_the_probe_velocity(roms):
    rom = roms["axi"]
    y0 = np.array([0.2, 0.0, 0.0, 0.0, 0.0, 0.0])
    ext = dopri.extrema(rom, y0, 1.0, 8, rtol=1e-11)
    n = int(ext.count[0])
    assert n == 8
    probe = rom.tables.probe
    v = ext.states[0, :n, 3:] @ probe
    assert np.abs(v).max() <= 1e-9 * np.abs(ext.states[0, :n, 3:]).max()
    w = ext.states[0, :n, :3] @ probe
    assert np.all(np.sign(w[1:]) == -np.sign(w[:-1]))


def test_monodromy_matches_finite_differences(roms):
    rom = roms["axi"]
    y0 = np.array([0.2, -0.01, 0.001, 0.0, 0.5, 0.0])
    args = (0.0, 0.05, 40, rom.tables, Forcing(0.0, 0.0, 1.0))
    _, phi = monodromy(y0, *args)
    h = 1e-6
    fd = np.column_stack([(monodromy(y0 + h * e, *args)[0] - monodromy(y0 - h * e, *args)[0]) / (2 * h)
                          for e in np.eye(6)])
    assert np.abs(phi - fd).max() <= 1e-7 * np.abs(fd).max()


@pytest.mark.parametrize("call,message", [
    (lambda r: dopri.solve(r, np.zeros(3), [1.0]), r"y0 shape \(1, 3\) is invalid: need \(N, 2\)"),
    (lambda r: dopri.solve(r, [np.nan, 0.0], [1.0]), r"y0 is invalid: the initial states must be finite"),
    (lambda r: dopri.solve(r, np.zeros(2), [1.0], c=-1.0), r"c = -1.0 is invalid: must be finite and >= 0"),
    (lambda r: dopri.solve(r, np.zeros(2), [1.0], Omega=0.0), r"Omega = 0.0 is invalid: must be finite and > 0"),
    (lambda r: dopri.solve(r, np.zeros(2), [1.0], rtol=0.0), r"rtol = 0.0, atol = 1e-12 is invalid"),
    (lambda r: dopri.solve(r, np.zeros(2), [2.0, 1.0]), r"t_eval = .* is invalid: need a non-empty increasing"),
    (lambda r: dopri.extrema(r, np.zeros(2), 1.0, 0), r"max_count = 0, t_end = 1.0 is invalid"),
])
def test_integrator_errors_name_the_value(roms, call, message):
    with pytest.raises(ValueError, match=message):
        call(roms["1"])


def test_sine_companions_are_the_cosine_modes_rotated(prestretch):
    # (1,0) + (1,1) + (1,-1): the sine companion of (1,1) is (1,1) turned by pi/2, so a motion
    # started in (1,-1) is the one started in (1,1) with the two coordinates exchanged; the
    # companions share mass, stiffness and a zero load.
    rom = build_rom(prestretch, [(1, 0), (1, 1), (1, -1)])
    assert rom.mass[1] == pytest.approx(rom.mass[2], rel=1e-12)
    assert abs(rom.forcing[2]) <= 1e-12 * abs(rom.forcing[0]) and rom.tables.probe[2] == 0.0
    fmap = ForcedMap.from_loading(rom, Loading(Omega=44.0, P0=1.0, c=0.05))
    a = fmap.advance(np.array([0.3, 0.05, 0.0, 0.0, 0.0, 0.0]), 3)
    b = fmap.advance(np.array([0.3, 0.0, 0.05, 0.0, 0.0, 0.0]), 3)
    assert np.abs(a[[0, 1, 3, 4]] - b[[0, 2, 3, 5]]).max() <= 1e-10 * np.abs(a).max()
    assert np.abs(a[[2, 5]]).max() <= 1e-12 and np.abs(b[[1, 4]]).max() <= 1e-12
    # a travelling wave q_11 = A cos(w t), q_1-1 = A sin(w t) keeps |w| rotationally invariant:
    # the elastic force of a rotated state is the rotated force
    g1, g2 = np.empty(3), np.empty(3)
    elastic_force(np.array([0.2, 0.04, 0.03]), rom.tables, g1, force_work(rom.tables))
    elastic_force(np.array([0.2, -0.03, 0.04]), rom.tables, g2, force_work(rom.tables))   # turned by pi/2
    assert np.abs(g2[[0, 1, 2]] - np.array([g1[0], -g1[2], g1[1]])).max() <= 1e-10 * np.abs(g1).max()


@pytest.mark.parametrize("theta_points", [None, 35])
def test_folded_angular_rule_is_the_full_rule(prestretch, theta_points):
    # Without sine companions the angular rule is folded onto [0, pi] (nt // 2 + 1 points;
    # the default nt = 96 is even: 0 and pi are points; 35 is odd: pi is not);
    # adding the companion (1, -1) at zero amplitude keeps the full rule on [0, 2 pi), whose
    # sums the folded one must give to rounding: mass, load, force and Jacobian.
    folded = build_rom(prestretch, MIXED, theta_points=theta_points)
    full = build_rom(prestretch, MIXED + [(1, -1)], theta_points=theta_points)
    nr, nt = folded.radial_points, folded.theta_points
    assert full.theta_points == nt and full.radial_points == nr
    assert folded.tables.weight.size == nr * (nt // 2 + 1) and full.tables.weight.size == nr * nt
    K = folded.dof
    assert np.abs(folded.mass - full.mass[:K]).max() <= 1e-13 * folded.mass.max()
    assert np.abs(folded.forcing - full.forcing[:K]).max() <= 1e-13 * np.abs(folded.forcing).max()
    jac, jac_full = np.empty((K, K)), np.empty((K + 1, K + 1))
    for q in np.random.default_rng(11).uniform(-0.2, 0.2, (4, K)):
        g, g_full = _force(folded, q), _force(full, np.append(q, 0.0))
        assert np.abs(g - g_full[:K]).max() <= 1e-13 * np.abs(g_full).max()
        force_jacobian(q, folded.tables, jac)
        force_jacobian(np.append(q, 0.0), full.tables, jac_full)
        assert np.abs(jac - jac_full[:K, :K]).max() <= 1e-13 * np.abs(jac_full).max()


@pytest.mark.parametrize("kind", ["1", "axi", "mixed"])
@pytest.mark.parametrize("parameter", ["Omega", "P0"])
def test_parameter_derivative_of_the_map_matches_central_differences(roms, kind, parameter):
    # dP/dOmega and dP/dP0 from the RK4 variational equations (model.integrate.monodromy_parameter)
    # against central differences of the map (h = 1e-6 relative in Omega, 1e-3 in P0, where the
    # map is nearly linear: truncation and rounding both below ~1e-10), and the monodromy
    # matrix against model.integrate.monodromy.
    rom = roms[kind]
    fmap = ForcedMap.from_loading(rom, Loading(Omega=40.0, P0=1.0, c=0.05))
    y = np.zeros(2 * rom.dof)
    y[0], y[rom.dof] = 0.3, 2.0
    yT, phi, d = fmap.monodromy_parameter(y, parameter)
    lam = getattr(fmap.forcing, parameter)
    h = (1e-6 if parameter == "Omega" else 1e-3) * lam
    fd = (fmap.varied(parameter, lam + h).advance(y) - fmap.varied(parameter, lam - h).advance(y)) / (2 * h)
    assert np.abs(d - fd).max() <= 1e-9 * np.abs(fd).max()
    y_ref, phi_ref = fmap.monodromy(y)
    assert np.array_equal(yT, y_ref) and np.array_equal(phi, phi_ref)


@pytest.mark.parametrize("amplitude", [0.02, 0.4])
def test_lean_radial_rule_keeps_the_accelerations(amplitude):
    """model.rom.lean_radial_points: on states of the given amplitude, the ROM of the rule
    it picks gives the modal accelerations of a 384-point reference rule to about the
    tolerance (the default rule's own error is far below it); at small amplitude the
    fewest candidate rule suffices, and at |w| = 0.4 m with large higher-mode content
    that rule fails the tolerance, so a larger one is picked."""
    analytic = solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "analytic")
    rom = build_rom(analytic, AXI)
    rng = np.random.default_rng(5)
    q = amplitude * rng.uniform(-1.0, 1.0, size=(40, 3)) * [1.0, 0.3, 0.1]
    states = np.concatenate([q, np.zeros_like(q)], axis=1)
    rtol = 1e-10
    points = lean_radial_points(rom, states, rtol)
    reference = build_rom(analytic, AXI, radial_points=384)

    def accelerations(r):
        return np.array([r.tables.load - r.tables.k_force * _force(r, y) for y in q])

    exact = accelerations(reference)
    error = np.abs(accelerations(build_rom(analytic, AXI, radial_points=points)) - exact).max()
    assert error <= 2 * rtol * np.abs(exact).max()
    if amplitude < 0.1:
        assert points == LEAN_RADIAL_POINTS[0]
    else:
        assert points > LEAN_RADIAL_POINTS[0]
        fewest = build_rom(analytic, AXI, radial_points=LEAN_RADIAL_POINTS[0])
        assert np.abs(accelerations(fewest) - exact).max() > rtol * np.abs(exact).max()


@pytest.mark.parametrize("modes, kwargs, message", [
    ([(0, 0)], {}, r"mode = \(0, 0\) is invalid: need m >= 1"),
    ([(1, 0), (1, 0)], {}, r"modes = \[\(1, 0\), \(1, 0\)\] is invalid: a mode is repeated"),
    ([(1, 0), (1, 1)], {"theta_points": 0}, r"theta_points = 0 is invalid: must be >= 1"),
    ([(1, 0), (1, 1)], {"theta_points": -4}, r"theta_points = -4 is invalid: must be >= 1"),
])
def test_build_rom_errors_name_the_value(prestretch, modes, kwargs, message):
    with pytest.raises(ValueError, match=message):
        build_rom(prestretch, modes, **kwargs)
