"""Roots of Eq. (27) and mode shapes of Eq. (26)."""

import numpy as np
import pytest
from scipy.special import jn_zeros, jv, yv

from model.modes import bessel_jy, bessel_roots, cross_product, mode_shape


def bessel_eigenvalues(n, delta_o, count, points=100):
    """Independent check: Chebyshev collocation of -(rho phi')'/rho + n^2 phi/rho^2 = a^2 phi."""
    t = np.cos(np.pi * np.arange(points + 1) / points)
    c = np.r_[2.0, np.ones(points - 1), 2.0] * (-1.0) ** np.arange(points + 1)
    d = np.outer(c, 1 / c) / (t[:, None] - t[None, :] + np.eye(points + 1))
    d -= np.diag(d.sum(axis=1))
    d *= 2 / (1 - delta_o)
    rho = 0.5 * (1 + delta_o) + 0.5 * (1 - delta_o) * t
    op = -(d @ d) - (1 / rho)[:, None] * d + np.diag(n**2 / rho**2)
    lam = np.linalg.eigvals(op[1:-1, 1:-1])
    return np.sqrt(np.sort(lam.real)[:count])


@pytest.mark.parametrize("n", range(0, 11))
@pytest.mark.parametrize("delta_o", [0.05, 0.2, 0.5, 0.9])
def test_roots_are_complete_and_simple(n, delta_o):
    alpha = bessel_roots(n, delta_o, 6)
    assert np.all(np.diff(alpha) > 0)
    scale = np.abs(cross_product(alpha[:, None] * (1 + np.array([-1e-6, 1e-6])), n, delta_o)).max(axis=1)
    assert np.all(np.abs(cross_product(alpha, n, delta_o)) < 1e-9 * scale)
    # The roots are the square roots of the Dirichlet eigenvalues of Bessel's operator on
    # the annulus: none missed, none duplicated.
    np.testing.assert_allclose(alpha, bessel_eigenvalues(n, delta_o, 6), rtol=1e-8)


def test_thin_annulus_spacing():
    # For delta_o -> 1 the roots tend to m pi / (1 - delta_o).
    alpha = bessel_roots(0, 0.9, 3)
    np.testing.assert_allclose(alpha, np.pi * np.arange(1, 4) / 0.1, rtol=2e-3)


def test_small_hole_tends_to_disk():
    # For delta_o -> 0 and n >= 1 the roots tend to the zeros of J_n.
    np.testing.assert_allclose(bessel_roots(2, 1e-3, 3), jn_zeros(2, 3), rtol=1e-8)


def test_mode_shape_boundary_values_and_derivative():
    a = bessel_roots(1, 0.3, 2)[1]
    phi, dphi = mode_shape(np.array([0.6, 2.0]), a, 1, Re=2.0)
    np.testing.assert_allclose(phi, 0.0, atol=1e-12)
    rho = np.linspace(0.7, 1.9, 5)
    fd = (mode_shape(rho + 1e-6, a, 1, 2.0)[0] - mode_shape(rho - 1e-6, a, 1, 2.0)[0]) / 2e-6
    np.testing.assert_allclose(mode_shape(rho, a, 1, 2.0)[1], fd, rtol=1e-7)


@pytest.mark.parametrize("args,pattern", [
    ((-1, 0.2, 3), r"n = -1 is invalid: must be an integer >= 0"),
    ((0, 1.2, 3), r"delta_o = 1\.2 is invalid: must be in the open interval \(0, 1\)"),
    ((0, 0.2, 0), r"count = 0 is invalid: must be an integer >= 1"),
])
def test_bad_arguments(args, pattern):
    with pytest.raises(ValueError, match=pattern):
        bessel_roots(*args)


@pytest.mark.parametrize("n", [0, 1, 2, 5])
def test_bessel_jy_equals_the_general_functions(n):
    # orders 0 and 1 come from scipy's dedicated j0/y0/j1/y1 (fast), the others from jv/yv
    x = np.linspace(0.05, 300.0, 2001)
    j, y = bessel_jy(n, x)
    np.testing.assert_allclose(j, jv(n, x), rtol=0, atol=1e-14)
    np.testing.assert_allclose(y, yv(n, x), rtol=1e-13, atol=1e-14)
