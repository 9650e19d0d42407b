"""Linear frequencies against the paper's Tables 1-2, limits and an independent solver."""

import numpy as np
import pytest
from scipy.linalg import eig

from model.linear import approximate_frequency, frequency_bound, galerkin_frequencies
from model.modes import bessel_roots
from model.params import Membrane
from model.prestretch import solve_prestretch
from sweep.reference import TABLE1, TABLE2, TOL_AN, TOL_APP, TOL_FEM


def lowest(delta, delta_o, kind, n=0):
    return galerkin_frequencies(solve_prestretch(Membrane(delta=delta, delta_o=delta_o), kind), n, 1)[0][0]


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_app2_analytic_prestretch(key):
    # App.2 is the Galerkin solution with the Appendix B coefficients, i.e. Eq. (21).
    assert lowest(*key, "analytic") == pytest.approx(TABLE1[key][3], rel=TOL_APP)


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_app1_fit_prestretch(key):
    # App.1 uses the Eq. (18) fit.  The paper's entry at (1.5, 0.2), 45.768, lies above both
    # its App.2 (45.686) and FEM (45.716) values; every variant here gives 45.68-45.69, so
    # that entry is held to 0.2 % (see docs/validation.md), the others to 0.1 %.
    rel = 2e-3 if key == (1.5, 0.2) else TOL_APP
    assert lowest(*key, "fit") == pytest.approx(TABLE1[key][2], rel=rel)


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_fem(key):
    assert lowest(*key, "numeric") == pytest.approx(TABLE1[key][0], rel=TOL_FEM)


@pytest.mark.parametrize("key", sorted(TABLE1))
def test_table1_eq28_against_an(key):
    m = Membrane(delta=key[0], delta_o=key[1])
    w = approximate_frequency(solve_prestretch(m, "analytic"), bessel_roots(0, key[1], 1)[0])
    assert w == pytest.approx(TABLE1[key][1], rel=TOL_AN)


@pytest.mark.parametrize("key", sorted(TABLE2))
def test_table2(key):
    delta_o, n, delta = key
    an, fem = TABLE2[key]
    assert lowest(delta, delta_o, "numeric", n) == pytest.approx(fem, rel=TOL_FEM)
    m = Membrane(delta=delta, delta_o=delta_o)
    w = approximate_frequency(solve_prestretch(m, "analytic"), bessel_roots(n, delta_o, 1)[0])
    assert w == pytest.approx(an, rel=TOL_AN)


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
