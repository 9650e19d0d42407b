"""Linear transverse vibration of the pre-stretched membrane (paper, section 4.1).

Three estimates of ``omega_mn`` (rad/s):

* :func:`galerkin_frequencies`: the variable-coefficient problem Eq. (25) by Galerkin on
  the Bessel basis of Eq. (26) (the paper's App.1 with the ``fit`` pre-stretch, App.2
  with ``analytic``; ``numeric`` is the converged reference);
* :func:`approximate_frequency`: Eq. (28);
* :func:`frequency_bound`: Eq. (29), the limit ``delta -> inf``.

Linearising the exact transverse energy (docs/model.md, "Transverse energy") gives
the coefficients ``1 + L1`` and ``1/rho^2 + L3`` of the membrane's law at its pre-stretch
(:func:`model.transverse.slope_factors` at zero slope; for the neo-Hookean law
``1 + L1 = 1 - rho^2 / (r_o'^4 r_o^2)`` and ``1/rho^2 + L3 = 1/rho^2 - rho^2/(r_o'^2 r_o^4)``),
so that ``omega^2 = (2 C1 / Gamma) lambda`` with ``lambda`` the generalised eigenvalues of
``K_kl = int rho [(1+L1) phi_k' phi_l' + n^2 (1/rho^2+L3) phi_k phi_l] drho`` and
``M_kl = int rho phi_k phi_l drho``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.linalg import eigh
from scipy.special import roots_legendre

from .materials import is_neo_hookean
from .modes import bessel_roots, mode_shape
from .params import Membrane
from .prestretch import Prestretch
from .transverse import slope_factors

#: Smallest basis of the adaptive Galerkin solve, and its cap.
DEFAULT_BASIS = 32
MAX_BASIS = 256
#: Adaptive stopping rule: relative change of the frequencies when the basis doubles.  The
#: error falls like basis**-2.5 or faster, so the finer result is ~5 times more accurate.
CHANGE_TOL = 2e-6


@lru_cache(maxsize=64)
def _legendre(points: int):
    return roots_legendre(points)


def gauss_radial(membrane: Membrane, points: int):
    """Gauss-Legendre nodes (m) and weights (m) on ``[Ro, Re]``."""
    x, w = _legendre(points)
    a, b = membrane.Ro, membrane.Re
    return 0.5 * (a + b) + 0.5 * (b - a) * x, 0.5 * (b - a) * w


def stiffness_coefficients(prestretch: Prestretch, rho):
    """``(1 + L1, 1/rho^2 + L3)`` of Eq. (25) at undeformed radii ``rho`` (m), for the
    membrane's law: half the :func:`model.transverse.slope_factors` at zero slope.

    Returns the dimensionless radial coefficient and the circumferential one (m-2).
    """
    r, dr = prestretch.radius(rho), prestretch.slope(rho)
    ca, cb = slope_factors(prestretch.membrane.material, 0.0, 0.0, 1.0 / rho**2, (r / rho)**2, dr**2)
    return 0.5 * ca, 0.5 * cb


def galerkin_frequencies(prestretch: Prestretch, n: int, count: int,
                         basis: int | None = None, quad_points: int | None = None,
                         full_output: bool = False):
    """Lowest ``count`` frequencies of Eq. (25) for wave number ``n`` by Galerkin.

    Parameters
    ----------
    prestretch : Prestretch
        The static solution entering ``L1``, ``L3``.
    n : int
        Circumferential wave number, ``n >= 0``.
    count : int
        Number of frequencies (``m = 1..count``), ``count <= basis``.
    basis : int, optional
        Number of Bessel functions ``phi_1n .. phi_{basis,n}`` in the trial space.  By
        default the basis starts at :data:`DEFAULT_BASIS` functions and doubles until
        the frequencies change by less than :data:`CHANGE_TOL` (relative), which
        converges them to better than 1e-6 (tests; at most :data:`MAX_BASIS`).
    quad_points : int, optional
        Gauss-Legendre points on ``[Ro, Re]``; default ``4*basis + 40``, enough to
        integrate the products of the most oscillatory basis functions.
    full_output : bool
        Also return the last relative change of the adaptive basis.

    Returns
    -------
    omega : numpy.ndarray
        ``omega_mn`` (rad/s), ascending.
    vectors : numpy.ndarray
        ``(basis, count)`` coefficients of the eigenfunctions on the Bessel basis in the
        paper's normalisation, ``M``-orthonormal.
    change : float
        Only with ``full_output``: the largest relative change of the frequencies at the
        last doubling of the basis (below :data:`CHANGE_TOL` when converged; NaN for a
        given ``basis``).
    """
    if basis is not None:
        omega, vec = _galerkin(prestretch, n, count, basis, quad_points)
        return (omega, vec, np.nan) if full_output else (omega, vec)
    size = max(DEFAULT_BASIS, count)
    omega, vec = _galerkin(prestretch, n, count, size, quad_points)
    change = np.inf
    while size < MAX_BASIS:
        size *= 2
        finer, vec = _galerkin(prestretch, n, count, size, quad_points)
        change = np.max(np.abs(finer - omega) / finer)
        omega = finer
        if change < CHANGE_TOL:
            break
    return (omega, vec, float(change)) if full_output else (omega, vec)


def _galerkin(prestretch, n, count, basis, quad_points):
    if count > basis:
        raise ValueError(f"count = {count} is invalid: must be <= basis = {basis}")
    m = prestretch.membrane
    rho, wq = gauss_radial(m, quad_points or 4 * basis + 40)
    alpha = bessel_roots(n, m.delta_o, basis)
    phi, dphi = mode_shape(rho, alpha, n, m.Re, m.delta_o)  # (basis, points), all roots at once
    # Scale the basis to unit norm for conditioning; undone on the eigenvectors.
    scale = 1.0 / np.sqrt((phi**2 * rho * wq).sum(axis=1))
    phi *= scale[:, None]
    dphi *= scale[:, None]
    a1, a3 = stiffness_coefficients(prestretch, rho)
    wr = rho * wq
    K = (dphi * (a1 * wr)) @ dphi.T + n**2 * (phi * (a3 * wr)) @ phi.T
    M = (phi * wr) @ phi.T
    lam, vec = eigh(K, M, subset_by_index=(0, count - 1))
    return np.sqrt(m.wave_speed2 * lam), vec * scale[:, None]


def approximate_frequency(prestretch: Prestretch, alpha: float):
    """Eq. (28): ``sqrt(2 alpha^2 C1 / (Re^2 Gamma) (1 + L1)(Re))`` (rad/s), the radial
    coefficient of Eq. (25) taken at the outer edge; for the neo-Hookean law ``1 + L1 = 1 -
    1/(delta^2 r_o'(Re)^4)`` there, Eq. (28) as printed."""
    m = prestretch.membrane
    # the outer edge's stretches: delta exactly (the boundary condition) and r_o'(Re)
    ca, _ = slope_factors(m.material, 0.0, 0.0, 1.0 / m.Re**2, m.delta**2, float(prestretch.slope(m.Re)) ** 2)
    return np.sqrt(m.wave_speed2 * alpha**2 / m.Re**2 * 0.5 * ca)


def frequency_bound(membrane: Membrane, alpha: float):
    """Eq. (29): the upper bound ``sqrt(2 alpha^2 C1 / (Re^2 Gamma))`` (rad/s) that the
    neo-Hookean frequencies approach as ``delta -> inf``; NaN for the other laws, whose
    frequencies have no such bound (Mooney-Rivlin's ``C2`` term grows with the stretch,
    Gent's stretch is limited)."""
    if not is_neo_hookean(membrane.material):
        return np.nan
    return np.sqrt(membrane.wave_speed2) * alpha / membrane.Re
