"""Linear frequencies against the paper's Tables 1-2, limits and an independent solver."""

import numpy as np
import pytest
from scipy.linalg import eig

from model.linear import approximate_frequency, frequency_bound, galerkin_frequencies
from model.modes import bessel_roots
from model.params import Membrane
from model.prestretch import solve_prestretch

# Paper Table 1 (m = 1, n = 0): (delta, delta_o) -> FEM, AN, App.1, App.2 (rad/s).
TABLE1 = {
    (1.1, 0.2): (32.512, 32.307, 32.497, 32.499),
    (1.5, 0.2): (45.716, 45.561, 45.768, 45.686),
    (2.0, 0.2): (47.431, 47.113, 47.149, 47.150),
    (1.1, 0.3): (38.827, 38.200, 38.608, 38.591),
    (1.5, 0.3): (53.465, 53.390, 53.132, 53.129),
    (2.0, 0.3): (54.926, 54.423, 54.585, 54.585),
}
# Paper Table 2 (m = 1): (delta_o, n, delta) -> AN, FEM (rad/s).
TABLE2 = {
    (0.2, 1, 1.1): (34.751, 35.725), (0.2, 1, 1.5): (50.293, 50.788), (0.2, 1, 2.0): (52.244, 52.513),
    (0.2, 2, 1.1): (42.840, 43.491), (0.2, 2, 1.5): (62.000, 62.349), (0.2, 2, 2.0): (64.406, 64.615),
    (0.3, 1, 1.1): (40.607, 40.984), (0.3, 1, 1.5): (55.873, 56.795), (0.3, 1, 2.0): (58.042, 58.440),
    (0.3, 2, 1.1): (46.879, 46.796), (0.3, 2, 1.5): (64.950, 65.629), (0.3, 2, 2.0): (67.471, 67.725),
}


def lowest(delta, delta_o, kind, n=0):
    return galerkin_frequencies(solve_prestretch(Membrane(delta=delta, delta_o=delta_o), kind), n, 1)[0][0]


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_app2_analytic_prestretch(key):
    # App.2 is the Galerkin solution with the Appendix B coefficients, i.e. Eq. (21).
    assert lowest(*key, "analytic") == pytest.approx(TABLE1[key][3], rel=1e-3)


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_app1_fit_prestretch(key):
    # App.1 uses the Eq. (18) fit.  The paper's entry at (1.5, 0.2), 45.768, lies above both
    # its App.2 (45.686) and FEM (45.716) values; every variant here gives 45.68-45.69, so
    # that entry is held to 0.2 % (see docs/validation.md), the others to 0.1 %.
    rel = 2e-3 if key == (1.5, 0.2) else 1e-3
    assert lowest(*key, "fit") == pytest.approx(TABLE1[key][2], rel=rel)


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_fem(key):
    assert lowest(*key, "numeric") == pytest.approx(TABLE1[key][0], rel=8e-3)


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_eq28_against_an(key):
    m = Membrane(delta=key[0], delta_o=key[1])
    w = approximate_frequency(solve_prestretch(m, "analytic"), bessel_roots(0, key[1], 1)[0])
    assert w == pytest.approx(TABLE1[key][1], rel=2.5e-2)


@pytest.mark.parametrize("key", sorted(TABLE2))
def test_table2(key):
    delta_o, n, delta = key
    an, fem = TABLE2[key]
    assert lowest(delta, delta_o, "numeric", n) == pytest.approx(fem, rel=8e-3)
    m = Membrane(delta=delta, delta_o=delta_o)
    w = approximate_frequency(solve_prestretch(m, "analytic"), bessel_roots(n, delta_o, 1)[0])
    assert w == pytest.approx(an, rel=2.5e-2)


def collocation_frequencies(membrane, n, count, points=90):
    """Independent solver: Chebyshev collocation of the strong form of Eq. (25).

    ``-(rho a w')' + n^2 rho b w = lambda rho w``, ``w(Ro) = w(Re) = 0`` with the
    closed-form Eq. (21) pre-stretch written out here.
    """
    ro, re, d, do = membrane.Ro, membrane.Re, membrane.delta, membrane.delta_o
    t = np.cos(np.pi * np.arange(points + 1) / points)
    c = np.r_[2.0, np.ones(points - 1), 2.0] * (-1.0) ** np.arange(points + 1)
    dm = np.outer(c, 1 / c) / (t[:, None] - t[None, :] + np.eye(points + 1))
    dm -= np.diag(dm.sum(axis=1))
    rho = 0.5 * (ro + re) + 0.5 * (re - ro) * t
    dm *= 2 / (re - ro)
    s = rho / re
    A, B = (d - do**2) / (1 - do**2), do**2 * (1 - d) / (1 - do**2)
    r, dr = re * (A * s + B / s), A - B / s**2
    a = 1 - rho**2 / (dr**4 * r**2)
    b = 1 / rho**2 - rho**2 / (dr**2 * r**4)
    pa = rho * a
    op = -(pa[:, None] * (dm @ dm)) - (dm @ pa)[:, None] * dm + np.diag(n**2 * rho * b)
    inner = slice(1, points)
    lam = eig(op[inner, inner], np.diag(rho[inner]), right=False)
    lam = np.sort(lam[np.abs(lam.imag) < 1e-8 * np.abs(lam)].real)
    return np.sqrt(membrane.wave_speed2 * lam[:count])


@pytest.mark.parametrize("delta,delta_o", [(1.02, 0.05), (1.1, 0.2), (1.5, 0.5), (2.5, 0.8), (4.0, 0.05), (4.0, 0.8)])
@pytest.mark.parametrize("n", [0, 2, 5])
def test_galerkin_matches_collocation(delta, delta_o, n):
    m = Membrane(delta=delta, delta_o=delta_o)
    ref = collocation_frequencies(m, n, 3)
    got = galerkin_frequencies(solve_prestretch(m, "analytic"), n, 3)[0]
    np.testing.assert_allclose(got, ref, rtol=1e-5)


@pytest.mark.parametrize("delta,delta_o", [(1.1, 0.2), (1.02, 0.05)])
def test_default_basis_converged(delta, delta_o):
    ps = solve_prestretch(Membrane(delta=delta, delta_o=delta_o), "numeric")
    for n in (0, 3):
        w = galerkin_frequencies(ps, n, 3)[0]
        fine = galerkin_frequencies(ps, n, 3, basis=200)[0]
        np.testing.assert_allclose(w, fine, rtol=1e-6)


def test_frequency_tends_to_zero_as_delta_tends_to_one():
    ws = [lowest(d, 0.2, "numeric") for d in (1.01, 1.001, 1.0001)]
    assert ws[0] > ws[1] > ws[2]
    # Tension ~ (delta - 1), so omega ~ sqrt(delta - 1): a tenfold smaller stretch divides by ~sqrt(10).
    assert ws[1] / ws[2] == pytest.approx(np.sqrt(10), rel=0.05)


@pytest.mark.parametrize("n", [0, 1, 2])
def test_frequency_approaches_eq29_bound_from_below(n):
    m0 = Membrane(delta=2.0, delta_o=0.2)
    bound = frequency_bound(m0, bessel_roots(n, 0.2, 1)[0])
    ws = [lowest(d, 0.2, "analytic", n) for d in (1.5, 2.0, 4.0, 10.0, 30.0)]
    assert np.all(np.diff(ws) > 0) and ws[-1] < bound
    assert (bound - ws[-1]) / bound < 2e-3
    assert (bound - ws[-1]) < (bound - ws[-2]) < (bound - ws[-3])


def test_count_larger_than_basis_rejected():
    ps = solve_prestretch(Membrane(), "analytic")
    with pytest.raises(ValueError, match=r"count = 5 is invalid: must be <= basis = 4"):
        galerkin_frequencies(ps, 0, 5, basis=4)
