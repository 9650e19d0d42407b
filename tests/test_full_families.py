"""The full model's asymmetric families (:mod:`model.full.families`): the tangent stiffness of a
harmonic against the second variation of the energy of a two-dimensional displacement field,
the linear problem at the pre-stretch and the axisymmetric Hessian; the monodromy block against
RK4's amplification at rest, against the map's own axisymmetric block (n = 0) and against an
independent integration of its variational equations; continuation jobs with families."""

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp
from scipy.linalg import eigh, eigvals

from model.damping import Modal, Rayleigh, Viscous
from model.full import linear, surface
from model.full.axisymmetric import AxisymmetricFull
from model.full.families import FullFamily
from model.full.family_kernels import tangent_moduli
from model.full.forced import ForcedFull, steps_per_period
from model.full.static import solve_full_prestretch
from model.params import Membrane
from model.shooting import shoot
from sweep import cli
from sweep.analyses.base import JobError
from sweep.jobspec import parse_job

ORDER = 8
MEMBRANE = Membrane(delta=1.1, delta_o=0.2)


@pytest.fixture(scope="module")
def model():
    return AxisymmetricFull(solve_full_prestretch(MEMBRANE, ORDER))


@pytest.fixture(scope="module")
def orbit(model):
    """A forced periodic orbit near the resonance (|w(0.5 Re)| ~ 3 mm) and its map."""
    fmap = ForcedFull.build(model, 1.0, 36.0, Viscous(0.05), steps_per_period(model, 128))
    res = shoot(fmap, np.zeros(2 * model.dof))
    assert res.converged
    return fmap, res.state


def _deflected(model, seed=3):
    rng = np.random.default_rng(seed)
    o = model.order
    return np.concatenate([2e-3 * rng.standard_normal(o), 0.05 * rng.standard_normal(o) / np.arange(1, o + 1)])


@pytest.mark.parametrize("membrane", [MEMBRANE, Membrane(law="mooney-rivlin", C2=0.03e6), Membrane(law="gent", Jm=30.0)],
                         ids=["neo-hookean", "mooney-rivlin", "gent"])
def test_tangent_moduli_at_an_axisymmetric_state_are_those_of_the_surface(membrane):
    rng = np.random.default_rng(0)
    for x in rng.uniform([0.8, -0.6, 0.8], [1.6, 0.6, 1.6], (5, 3)):
        a1, a2 = np.array([x[0], 0.0, x[1]]), np.array([0.0, x[2], 0.0])
        expected = surface.hessian(membrane.material, a1, a2)
        np.testing.assert_allclose(tangent_moduli(membrane.material, *x), expected, atol=1e-13 * np.abs(expected).max())


@pytest.mark.parametrize("n", [0, 1, 2, 5])
def test_stiffness_at_the_prestretch_is_the_linear_problem(model, n):
    fam = FullFamily.build(model, n, fields="UVW")
    K, M = linear.stiffness_mass(model.state, n, "UVW")
    np.testing.assert_allclose(fam.stiffness(np.zeros(model.dof)), K, atol=1e-13 * np.abs(K).max())
    np.testing.assert_allclose(fam.mass(), M, atol=1e-15)


def test_stiffness_of_the_harmonic_zero_is_the_axisymmetric_hessian(model):
    q = _deflected(model)
    H = model.hessian(q)
    np.testing.assert_allclose(FullFamily.build(model, 0, fields="UW").stiffness(q), H, atol=1e-13 * np.abs(H).max())


def _energy(model, q, X, n, eps):
    """``int int W/C1 s ds dtheta`` of the axisymmetric state ``q`` plus ``eps`` times the
    harmonic ``n`` with coefficients ``X`` (fields U, V, W), from the deformation gradient of
    the two-dimensional field (trapezoidal rule in theta: exact for its trigonometric terms)."""
    st, b = model.state, model.state.basis
    o, M = model.order, X.size // 3
    theta = np.linspace(0.0, 2.0 * np.pi, 4 * n + 16, endpoint=False)[:, None]
    s = b.s[None, :]
    r0, dr0 = st.scaled(b.s)
    P, dP = b.phi[:M], b.dphi[:M]
    c, sn = np.cos(n * theta), np.sin(n * theta)
    Xu, Xv, Xw = X[:M], X[M:2 * M], X[2 * M:]
    u = q[:o] @ b.phi + eps * (Xu @ P) * c
    u_s = q[:o] @ b.dphi + eps * (Xu @ dP) * c
    u_t = -n * eps * (Xu @ P) * sn
    v, v_s, v_t = eps * (Xv @ P) * sn, eps * (Xv @ dP) * sn, n * eps * (Xv @ P) * c
    w_s, w_t = q[o:] @ b.dphi + eps * (Xw @ dP) * c, -n * eps * (Xw @ P) * sn
    a1 = np.stack(np.broadcast_arrays(dr0 + u_s, v_s, w_s), axis=-1)
    a2 = np.stack(np.broadcast_arrays((u_t - v) / s, (r0 + u + v_t) / s, w_t / s), axis=-1)
    return 2.0 * np.pi * (surface.energy(MEMBRANE.material, a1, a2) @ (b.s * b.weights)).mean()


@pytest.mark.parametrize("n", [1, 2, 4])
def test_stiffness_is_the_second_variation_of_the_two_dimensional_energy(model, n):
    # d^2E/deps^2 = pi X' K_n X (the angular integral of cos^2 and sin^2).  Central second
    # differences at eps and 2 eps, Richardson-extrapolated: truncation ~ eps^4 (1e-12
    # relative) and rounding ~ 1e-16 |E| / eps^2 (1e-10): asserted to 1e-8
    q = _deflected(model)
    rng = np.random.default_rng(n)
    X = rng.standard_normal(3 * 6) / np.tile(np.arange(1, 7), 3) ** 2
    fam = FullFamily.build(model, n, 6, "UVW")
    e0 = _energy(model, q, X, n, 0.0)

    def second(eps):
        return (_energy(model, q, X, n, eps) - 2.0 * e0 + _energy(model, q, X, n, -eps)) / eps**2
    d2 = (4.0 * second(1e-3) - second(2e-3)) / 3.0
    assert d2 == pytest.approx(np.pi * X @ fam.stiffness(q) @ X, rel=1e-8)


def _continuous_eigenvalues(fam, damping):
    """The eigenvalues of the family's linear damped problem about rest, from its undamped
    frequencies ``omega_k`` in closed form: ``-a_k +- i sqrt(omega_k^2 - a_k^2)`` with the decay
    rate ``a_k`` of each law (viscous ``c / (2 Gamma h)``; Rayleigh ``(alpha + beta omega_k^2) /
    2``; modal ``zeta omega_k``)."""
    mass, stiffness = fam.linear_system()
    omega = np.sqrt(eigh(stiffness, mass, eigvals_only=True))
    if isinstance(damping, Viscous):
        rate = damping.c / (2.0 * MEMBRANE.Gamma * MEMBRANE.h) * np.ones_like(omega)
    elif isinstance(damping, Rayleigh):
        rate = 0.5 * (damping.alpha + damping.beta * omega**2)
    else:
        rate = damping.zeta * omega
    root = np.sqrt((omega**2 - rate**2).astype(complex))
    return np.concatenate([-rate + 1j * root, -rate - 1j * root])


@pytest.mark.parametrize("n, fields, damping", [(1, "UVW", Viscous(0.05)), (3, "W", Viscous(0.05)),
                                                (2, "UVW", Rayleigh(alpha=0.1, beta=2e-5)), (4, "UVW", Modal(0.01))])
def test_block_at_rest_has_the_multipliers_of_rk4_on_the_linear_problem(model, n, fields, damping):
    # about rest the variational equations are linear with constant coefficients, X' = L X, and
    # N RK4 steps of dt multiply each eigenvalue lambda of L into R(dt lambda)^N with R the
    # scheme's polynomial 1 + z + z^2/2 + z^3/6 + z^4/24: exact, to rounding.  The eigenvalues
    # of L in closed form per law, from the family's frequencies; matched both ways
    steps = steps_per_period(model, 128)
    fmap = ForcedFull.build(model, 0.0, 36.0, damping, steps)
    fam = FullFamily.build(model, n, fields=fields)
    block = fmap.family_monodromy(np.zeros(2 * model.dof), fam)
    z = fmap.period / steps * _continuous_eigenvalues(fam, damping)
    expected = np.sort_complex((1.0 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) ** steps)
    got = np.sort_complex(eigvals(block))
    assert max(np.abs(got - e).min() for e in expected) < 1e-10
    assert max(np.abs(expected - g).min() for g in got) < 1e-10


def test_block_beyond_the_stable_step_of_its_harmonic_is_nan(model):
    # the family's highest frequency grows with n: at steps that keep the orbit's within RK4's
    # limit, a high harmonic's is beyond it, and its block is NaN, not a growth
    fam = FullFamily.build(model, 40)
    fmap = ForcedFull.build(model, 0.0, 36.0, Viscous(0.05), 128)
    steps = int(np.ceil(fmap.period * fmap.omega_max / 2.0))
    assert fmap.period / steps * fam.omega_max > 2.8  # the premise
    fmap = ForcedFull.build(model, 0.0, 36.0, Viscous(0.05), steps)
    assert np.isfinite(fmap.family_monodromy(np.zeros(2 * model.dof), FullFamily.build(model, 1))).all()
    assert np.isnan(fmap.family_monodromy(np.zeros(2 * model.dof), fam)).all()


def test_harmonic_zero_block_is_the_axisymmetric_monodromy(model, orbit):
    fmap, y = orbit
    phi = fmap.monodromy(y)[1]
    block = fmap.family_monodromy(y, FullFamily.build(model, 0, fields="UW"))
    np.testing.assert_allclose(block, phi, atol=1e-12 * np.abs(phi).max())


def test_block_agrees_with_an_independent_integration_of_the_variational_equations(model, orbit):
    # DOP853 (rtol 1e-11) of the axisymmetric motion with the numpy gradient and of the W
    # family's variational equations with the family's stiffness, against the compiled RK4
    # block at 1, 2 and 4 times the map's steps: the RK4 error falls as dt^4 and the block at the
    # finest steps is within twice its step-halving difference of the independent one
    fmap, y = orbit
    fam = FullFamily.build(model, 2, fields="W")
    m, dof, re = fam.radial, model.dof, MEMBRANE.Re
    mass_inv = np.linalg.inv(fam.mass())

    def rhs(t, z):
        q, v = z[:dof], z[dof:2 * dof]
        acc = model.acceleration(q, v, 0.05) + np.concatenate([np.zeros(model.order), fmap.P0 * np.cos(fmap.Omega * t)
                                                               * model.load])
        X = z[2 * dof:].reshape(2 * m, 2 * m)
        dX = np.vstack([X[m:], -model.omega0_2 * mass_inv @ fam.stiffness(q) @ X[:m] - fmap.rate * X[m:]])
        return np.concatenate([v, acc, dX.ravel()])
    z0 = np.concatenate([y / re, np.eye(2 * m).ravel()])
    sol = solve_ivp(rhs, (0.0, fmap.period), z0, method="DOP853", rtol=1e-11, atol=1e-14)
    reference = sol.y[2 * dof:, -1].reshape(2 * m, 2 * m)
    maps = [ForcedFull.build(model, fmap.P0, fmap.Omega, fmap.damping, k * fmap.steps) for k in (1, 2, 4)]
    for independent, rk4 in ((sol.y[:2 * dof, -1] * re, [f.advance(y) for f in maps]),
                             (reference, [f.family_monodromy(y, fam) for f in maps])):
        halving = [np.abs(rk4[i + 1] - rk4[i]).max() for i in range(2)]
        assert halving[1] < halving[0] / 8  # the fourth order
        assert np.abs(rk4[2] - independent).max() < 2.0 * halving[1] + 1e-9 * np.abs(independent).max()


def test_a_family_of_another_model_is_refused(model, orbit):
    other = AxisymmetricFull(solve_full_prestretch(MEMBRANE, ORDER))
    with pytest.raises(ValueError, match="fam is invalid here: a family of another model"):
        orbit[0].family_monodromy(orbit[1], FullFamily.build(other, 1))


@pytest.mark.parametrize("kwargs, message", [
    ({"n": -1}, "n = -1 is invalid"), ({"n": 1, "radial": ORDER + 1}, f"radial = {ORDER + 1} is invalid"),
    ({"n": 1, "fields": "UX"}, "fields = 'UX' is invalid"),
])
def test_bad_families_are_refused(model, kwargs, message):
    with pytest.raises(ValueError, match=message):
        FullFamily.build(model, **kwargs)


JOB = """
[job]
name = "full-families"
analysis = "continuation"

[model]
kind = "full"
order = 6

[grid]
delta = 1.1
delta_o = 0.2
Omega = 36.0
c = 0.05

[continuation]
parameter = "P0"
start = 0.0
stop = 0.5
modes = [[1, 0]]
ds_max = 0.5
max_points = 100
families = {n = [1, 3], radial = 4INPLANE}
"""


@pytest.mark.parametrize("inplane", ["", ", inplane = false"])
def test_continuation_job_reports_the_families_of_the_full_model(tmp_path, inplane):
    job = tmp_path / "full.toml"
    job.write_text(JOB.replace("INPLANE", inplane))
    out = tmp_path / "full.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    ds = xr.load_dataset(out).squeeze()
    assert int(ds.status) == 0
    fields = "UVW" if not inplane else "W"
    assert ds.family_multiplier_real.sizes["family_multiplier"] == 2 * 4 * len(fields)
    # at the last point the block is that of the model's own map and family at the branch's state
    model = AxisymmetricFull(solve_full_prestretch(MEMBRANE, 6))
    n = int(ds.n_points) - 1
    fmap = ForcedFull.build(model, float(ds.P0[n]), 36.0, Viscous(0.05), int(ds.rk4_steps))
    orbit = shoot(fmap, np.zeros(2 * model.dof))
    for j, wave in enumerate((1, 3)):
        mu = eigvals(fmap.family_monodromy(orbit.state, FullFamily.build(model, wave, 4, fields)))
        largest = float(ds.family_multiplier_modulus[n, j])
        assert largest == pytest.approx(np.abs(mu).max(), rel=1e-7)


@pytest.mark.parametrize("model_table, families, message", [
    ("", "{n = [1], radial = 2, inplane = true}", "continuation.families.inplane = True is invalid: needs a model "
                                                  "with in-plane displacements"),
    ('[model]\nkind = "full"\norder = 6\n', "{n = [1], radial = 7}", "continuation.families.radial = 7 is invalid"),
    ('[model]\nkind = "full"\norder = 6\n', "{n = [1], radial = 2, inplane = 1}",
     "continuation.families.inplane = 1 is invalid: must be true or false"),
])
def test_family_options_are_checked_against_the_model(model_table, families, message):
    text = JOB.replace('[model]\nkind = "full"\norder = 6\n', model_table)
    text = text.replace("{n = [1, 3], radial = 4INPLANE}", families)
    with pytest.raises(JobError, match=message.replace("(", r"\(").replace(".", r"\.")):
        parse_job(text)
