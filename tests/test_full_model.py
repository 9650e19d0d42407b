"""The full model's kinematics, pre-stretch and natural frequencies (model/full/), each against
an independent computation: complex-step derivatives of its own energy, the ROM's Chebyshev
collocation of Eq. (15), the ROM's Bessel-basis Galerkin solution of Eq. (25), and the closed-form
in-plane modes of a linear elastic incompressible annulus in plane stress."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import jv, jvp, yv, yvp

from model.full import surface
from model.full.linear import frequencies, inplane_frequencies, stiffness_mass, transverse_frequencies
from model.full.static import solve_full_prestretch
from model.linear import galerkin_frequencies
from model.materials import Gent, MooneyRivlin, NeoHookean
from model.params import Membrane
from model.prestretch import solve_prestretch

LAWS = [dict(), dict(law="mooney-rivlin", C2=0.25 * 0.17e6), dict(law="gent", Jm=20.0)]
#: The paper's Tables 1-2 membranes.
TABLES = [(d, do) for d in (1.1, 1.5, 2.0) for do in (0.2, 0.3)]


@pytest.mark.parametrize("law", [NeoHookean(), MooneyRivlin(0.3), Gent(1.0 / 20.0)])
def test_surface_derivatives_are_those_of_the_energy(law):
    # complex-step derivatives (exact to rounding) of the energy and of the gradient at
    # general deformed states: out of plane, sheared, stretched
    rng = np.random.default_rng(1)
    for _ in range(5):
        a1 = np.array([1.2, 0.0, 0.0]) + 0.3 * rng.normal(size=3)
        a2 = np.array([0.0, 1.1, 0.0]) + 0.3 * rng.normal(size=3)
        g1, g2 = surface.gradient(law, a1, a2)
        H = surface.hessian(law, a1, a2)
        step = 1e-30
        for i in range(6):
            e = np.zeros(6, complex)
            e[i] = 1j * step
            b1, b2 = a1 + e[:3], a2 + e[3:]
            assert surface.energy(law, b1, b2).imag / step == pytest.approx(np.concatenate([g1, g2])[i], abs=1e-13)
            np.testing.assert_allclose(np.concatenate(surface.gradient(law, b1, b2)).imag / step, H[i], atol=1e-12)


@pytest.mark.parametrize("fields", LAWS)
@pytest.mark.parametrize("delta, delta_o", [(1.1, 0.2), (2.0, 0.2), (1.5, 0.3)])
def test_prestretch_equals_the_rom_collocation(delta, delta_o, fields):
    # the same energy (Eq. 14) discretised two ways: Galerkin minimisation on Legendre
    # functions here, Chebyshev collocation of its Euler-Lagrange equation (Eq. 15) in the ROM
    m = Membrane(delta=delta, delta_o=delta_o, **fields)
    full, rom = solve_full_prestretch(m), solve_prestretch(m, "numeric")
    rho = np.linspace(m.Ro, m.Re, 301)
    assert np.abs(full.radius(rho) - rom.radius(rho)).max() < 1e-10 * m.Re
    assert np.abs(full.slope(rho) - rom.slope(rho)).max() < 1e-9
    assert full.traction() == pytest.approx(rom.traction(), rel=1e-9)
    np.testing.assert_allclose(full.stresses(rho), rom.stresses(rho), rtol=1e-8)


def test_prestretch_converges_exponentially_with_the_order():
    # e_N ~ C q^N: equal steps in the order divide the error by equal factors; an algebraic
    # rate N^-p would divide it by (16/8)^p, then by the smaller (24/16)^p
    m = Membrane(delta=1.5, delta_o=0.2)
    rho = np.linspace(m.Ro, m.Re, 301)
    ref = solve_prestretch(m, "numeric").radius(rho)
    e8, e16, e24 = (np.abs(solve_full_prestretch(m, order).radius(rho) - ref).max() for order in (8, 16, 24))
    assert e16 / e8 < 1e-2 and e24 / e16 < 1e-2
    assert e24 / e16 < 3 * (e16 / e8)  # no slowdown: exponential, not algebraic


def test_prestretch_beyond_the_limit_of_extensibility_is_refused():
    with pytest.raises(ValueError, match="Jm = 1.0 is invalid"):
        solve_full_prestretch(Membrane(delta=2.0, law="gent", Jm=1.0))
    with pytest.raises(ArithmeticError, match="limit of extensibility"):
        solve_full_prestretch(Membrane(delta=2.0, law="gent", Jm=3.0))


@pytest.mark.parametrize("delta, delta_o", TABLES)
def test_transverse_frequencies_equal_the_converged_galerkin_ones(delta, delta_o):
    # at linear order about the planar state w decouples from (u, v) and obeys Eq. (25): the
    # ROM's Bessel-basis Galerkin solution converges to the full model's frequencies (at an
    # algebraic rate, about basis^-3), within 1e-8 at 128 functions
    m = Membrane(delta=delta, delta_o=delta_o)
    full, rom = solve_full_prestretch(m), solve_prestretch(m, "numeric")
    for n in range(4):
        omega = transverse_frequencies(full, n, 3)
        errors = [np.abs(galerkin_frequencies(rom, n, 3, basis=b)[0] / omega - 1).max() for b in (32, 128)]
        assert errors[1] < 1e-8
        assert errors[1] < errors[0]


def test_frequencies_converge_with_the_order():
    m = Membrane(delta=1.1, delta_o=0.2)
    coarse, fine = solve_full_prestretch(m, 24), solve_full_prestretch(m, 48)
    for n in range(4):
        np.testing.assert_allclose(transverse_frequencies(coarse, n, 3), transverse_frequencies(fine, n, 3), rtol=1e-10)
        np.testing.assert_allclose(inplane_frequencies(coarse, n, 3), inplane_frequencies(fine, n, 3), rtol=1e-10)



@pytest.mark.parametrize("delta, delta_o", [(1.1, 0.2), (2.0, 0.3)])
def test_axisymmetric_transverse_frequencies_tend_to_a_harmonic_series(delta, delta_o):
    # At high m the transverse axisymmetric modes are radial waves of speed c = sqrt(sigma_1 /
    # Gamma) in the pre-stretched membrane (tension sigma_1 h_c per unit length over mass
    # Gamma h_c per unit area), so omega_m0 -> m pi / int dr / c over the deformed radius (WKB,
    # fixed edges), with a correction O(1 / m^2) to omega_m0 / m. The limit is computed from the
    # ROM's collocated pre-stretch, independently of the full model's Galerkin matrices.
    m = Membrane(delta=delta, delta_o=delta_o)
    rom = solve_prestretch(m, "numeric")
    travel, _ = quad(lambda rho: float(rom.slope(rho)) * np.sqrt(m.Gamma / rom.stresses(rho)[0]),
                     m.delta_o * m.Re, m.Re, epsabs=0.0, epsrel=1e-13)
    limit = np.pi / travel
    omega = transverse_frequencies(solve_full_prestretch(m, 64), 0, 24)
    errors = np.array([abs(omega[k - 1] / (k * limit) - 1) for k in (6, 12, 24)])
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all((orders > 1.8) & (orders < 2.2))
    assert errors[-1] < 1e-4

def test_transverse_and_inplane_motion_decouple_about_the_planar_state():
    # the tangent moduli of a planar state have no entry between w and (u, v): the coupled
    # stiffness has no block between them, for any law
    for fields in LAWS:
        full = solve_full_prestretch(Membrane(delta=1.5, delta_o=0.2, **fields), 16)
        for n in (0, 1, 2):
            K, _ = stiffness_mass(full, n, "UVW")
            o = full.basis.order
            assert np.abs(K[:2 * o, 2 * o:]).max() == 0.0 and np.abs(K[2 * o:, 2 * o:]).max() > 0.0


def _elastic_annulus_frequencies(m: Membrane, n: int, count: int, top: float, family: str = "both") -> np.ndarray:
    """In-plane natural frequencies of the unstretched annulus, both edges fixed: linear
    elasticity of an incompressible membrane in plane stress (shear modulus ``mu = 2 C1``,
    plane-stress P-wave modulus ``4 mu``), ``u = grad phi + curl(psi e_z)`` with Bessel
    potentials of the two wave numbers and the 4x4 determinant of the edge conditions.  For
    ``n = 0`` it factorises: ``family`` ``"radial"`` keeps the ``phi`` block, ``"torsional"``
    the ``psi`` block."""
    c_l, c_t = np.sqrt(8 * m.C1 / m.Gamma), np.sqrt(2 * m.C1 / m.Gamma)
    keep = {"both": slice(0, 4), "radial": slice(0, 2), "torsional": slice(2, 4)}[family]

    def det(w):
        w = np.atleast_1d(w)
        kl, kt = w / c_l, w / c_t
        rows = []
        for r in (m.Ro, m.Re):  # u_r = f' + n g / r, u_theta = -(n f / r + g')
            rows.append([kl * jvp(n, kl * r), kl * yvp(n, kl * r), n * jv(n, kt * r) / r, n * yv(n, kt * r) / r])
            rows.append([-n * jv(n, kl * r) / r, -n * yv(n, kl * r) / r, -kt * jvp(n, kt * r), -kt * yvp(n, kt * r)])
        matrix = np.moveaxis(np.array(rows), -1, 0)
        if family != "both":  # n = 0: u_r rows with the phi columns, u_theta rows with the psi ones
            rows_kept = [0, 2] if family == "radial" else [1, 3]
            matrix = matrix[:, rows_kept][:, :, keep]
        d = np.linalg.det(matrix)
        return d if d.size > 1 else float(d[0])

    grid = np.linspace(1.0, top, 20000)
    values = det(grid)
    at = np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]
    return np.array([brentq(det, grid[i], grid[i + 1], xtol=1e-13) for i in at])[:count]


@pytest.mark.parametrize("n", range(4))
def test_inplane_frequencies_of_the_unstretched_limit_are_those_of_plane_elasticity(n):
    # delta -> 1: the pre-strain is 1e-9, so the frequencies differ from those of the
    # unstretched annulus by O(1e-9) relative; for n = 0 the radial and the torsional modes apart
    m = Membrane(delta=1.0 + 1e-9, delta_o=0.2)
    state = solve_full_prestretch(m)
    omega = inplane_frequencies(state, n, 5)
    exact = _elastic_annulus_frequencies(m, n, 5, 1.2 * omega[-1], "radial" if n == 0 else "both")
    assert exact.size == 5
    np.testing.assert_allclose(omega, exact, rtol=1e-7)
    if n == 0:
        torsional = frequencies(state, 0, 5, "V")
        exact = _elastic_annulus_frequencies(m, 0, 5, 1.2 * torsional[-1], "torsional")
        np.testing.assert_allclose(torsional, exact, rtol=1e-7)
