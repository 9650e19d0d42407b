"""Linear mode shapes of the fixed-fixed annulus (paper, Eqs. 26-27 and 31).

``alpha_mn`` is the m-th positive root of Eq. (27) for wave number n (the paper writes
``A_mn`` for both the root and the modal amplitude; here the root is ``alpha``).  The mode
shape keeps the paper's normalisation, ``phi = C J_n(alpha rho/Re) - Y_n(alpha rho/Re)``
with ``C = Y_n(alpha)/J_n(alpha)``, so that modal amplitudes compare with the paper's
``A_10`` axes.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from scipy.special import j0, j1, jv, y0, y1, yv


def bessel_jy(n: int, x):
    """``(J_n(x), Y_n(x))`` for an integer order ``n >= 0``.

    Orders 0 and 1 use scipy's dedicated functions (``j0``, ``y0``, ``j1``, ``y1``), about
    14 times faster than the general ``jv``/``yv`` (same values to 1e-15); other orders the
    general ones.
    """
    if n == 0:
        return j0(x), y0(x)
    if n == 1:
        return j1(x), y1(x)
    return jv(n, x), yv(n, x)


def cross_product(alpha, n: int, delta_o: float):
    """Left-hand side of Eq. (27): ``J_n(delta_o a) Y_n(a) - J_n(a) Y_n(delta_o a)``."""
    a = np.asarray(alpha, dtype=float)
    ji, yi = bessel_jy(n, delta_o * a)
    jo, yo = bessel_jy(n, a)
    return ji * yo - jo * yi


def bessel_roots(n: int, delta_o: float, count: int) -> np.ndarray:
    """The first ``count`` positive roots ``alpha_1n < alpha_2n < ...`` of Eq. (27).

    The roots are simple (Sturm-Liouville eigenvalues) and spaced by about
    ``pi / (1 - delta_o)``; for every n they exceed ``n`` (the annulus' Dirichlet
    eigenvalues lie above the disk's, ``j_n1 > n``).  The scan therefore starts just below
    ``n`` with a step of a twentieth of the asymptotic spacing, so that no root is skipped,
    and each bracketed sign change is refined by Brent's method.

    Parameters
    ----------
    n : int
        Circumferential wave number, ``n >= 0``.
    delta_o : float
        Inner radius ratio ``Ro/Re`` in (0, 1).
    count : int
        Number of roots, ``count >= 1``.

    Returns
    -------
    numpy.ndarray
        ``alpha_mn`` for ``m = 1..count`` (dimensionless; the wave number is ``alpha/Re``).
    """
    if int(n) != n or n < 0:
        raise ValueError(f"n = {n!r} is invalid: must be an integer >= 0")
    if int(count) != count or count < 1:
        raise ValueError(f"count = {count!r} is invalid: must be an integer >= 1")
    if not 0.0 < delta_o < 1.0:
        raise ValueError(f"delta_o = {delta_o!r} is invalid: must be in the open interval (0, 1)")
    step = np.pi / (1.0 - delta_o) / 20.0
    roots: list[float] = []
    a0 = max(0.9 * n, step)
    while len(roots) < count:
        grid = a0 + step * np.arange(20 * (count - len(roots)) + 41)
        f = cross_product(grid, n, delta_o)
        for i in np.nonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0)[0]:
            roots.append(brentq(cross_product, grid[i], grid[i + 1], args=(n, delta_o),
                                xtol=1e-14, rtol=4 * np.finfo(float).eps))
            if len(roots) == count:
                break
        a0 = grid[-1]
    return np.array(roots)


def shape_constant(alpha, n: int, delta_o: float):
    """``C = Y_n(alpha)/J_n(alpha)`` of Eq. (26), evaluated where it is well conditioned.

    At a root of Eq. (27) ``C`` also equals ``Y_n(delta_o alpha)/J_n(delta_o alpha)``.
    For a small hole and large n, ``J_n(alpha)`` is itself close to a zero of ``J_n`` and
    the outer quotient loses all its digits, so the quotient is taken at the edge where
    ``|J_n|`` is largest relative to ``|Y_n|``.  ``alpha`` may be an array (one ``C`` each).
    """
    oj, oy = bessel_jy(n, alpha)
    ij, iy = bessel_jy(n, delta_o * np.asarray(alpha))
    inner = np.abs(ij) / np.hypot(ij, iy) > np.abs(oj) / np.hypot(oj, oy)
    return np.where(inner, iy / ij, oy / oj)[()]


def mode_shape(rho, alpha: float, n: int, Re: float = 1.0, delta_o: float | None = None):
    """Radial mode shape of Eq. (26) and its derivative.

    Parameters
    ----------
    rho : array_like
        Undeformed radius (m).
    alpha : float or (B,) array
        Root(s) of Eq. (27) for this n; with B roots the shapes come as ``(B, *rho.shape)``.
    n : int
        Circumferential wave number.
    Re : float
        Outer radius (m).
    delta_o : float, optional
        Inner radius ratio; when given, ``C`` comes from :func:`shape_constant` (needed for
        accuracy near a small hole at large n), otherwise from the outer edge.

    Returns
    -------
    phi, dphi : numpy.ndarray
        ``phi(rho)`` (1) and ``d phi / d rho`` (m-1).
    """
    rho = np.asarray(rho, dtype=float)
    alpha = np.asarray(alpha, dtype=float)
    a = alpha.reshape(alpha.shape + (1,) * rho.ndim)  # roots along a leading axis
    x = a * rho / Re
    if delta_o is None:
        ja, ya = bessel_jy(n, a)
        c = ya / ja
    else:
        c = np.asarray(shape_constant(alpha, n, delta_o)).reshape(a.shape)
    # derivatives by the recurrence Z_n' = (n/x) Z_n - Z_{n+1}: four Bessel evaluations, not six
    jn, yn = bessel_jy(n, x)
    jn1, yn1 = bessel_jy(n + 1, x)
    return c * jn - yn, (a / Re) * (c * (n / x * jn - jn1) - (n / x * yn - yn1))
