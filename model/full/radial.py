"""Legendre-Galerkin radial basis of the full model (docs/model.md, "Radial discretisation").

On the scaled radius ``s = rho / Re`` in ``[delta_o, 1]`` with ``x in [-1, 1]`` the affine
image, the functions ``phi_k(x) = L_k(x) - L_{k+2}(x)`` (``k = 0 .. order - 1``, ``L`` the
Legendre polynomials) vanish at both edges and span the polynomials of degree
``order + 1`` that do (Shen 1994).  Their derivatives are ``dphi_k/dx = -(2k + 3) L_{k+1}``.
A field that is analytic on the closed annulus -- the pre-stretch, a mode shape -- is
approximated with an error that falls exponentially with ``order``.  Integrals are by
Gauss-Legendre quadrature with more points than the basis needs for its own products, so
that the non-polynomial energy densities are integrated to the same accuracy.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.polynomial import legendre as L
from scipy.special import roots_legendre


@lru_cache(maxsize=32)
def _gauss(points: int):
    return roots_legendre(points)


@dataclass(frozen=True, eq=False)
class RadialBasis:
    """The basis of ``order`` functions on ``[s_in, s_out]`` sampled at ``points``
    Gauss-Legendre points.

    Attributes
    ----------
    s : numpy.ndarray
        ``(points,)`` quadrature radii (scaled, ``rho / Re``).
    weights : numpy.ndarray
        ``(points,)`` quadrature weights in ``s`` (their sum is ``s_out - s_in``).
    phi, dphi : numpy.ndarray
        ``(order, points)`` basis values and their ``s``-derivatives at ``s``.
    """

    s_in: float
    s_out: float
    order: int
    s: np.ndarray
    weights: np.ndarray
    phi: np.ndarray
    dphi: np.ndarray

    @classmethod
    def build(cls, s_in: float, s_out: float, order: int, points: int | None = None) -> RadialBasis:
        """The basis of ``order`` functions; ``points`` defaults to ``2 order + 24``."""
        if order < 1:
            raise ValueError(f"order = {order!r} is invalid: must be >= 1")
        x, w = _gauss(points or 2 * order + 24)
        half = 0.5 * (s_out - s_in)
        phi, dphi = _values(x, order)
        return cls(s_in, s_out, order, 0.5 * (s_in + s_out) + half * x, half * w, phi, dphi / half)

    def evaluate(self, coef, s):
        """``sum_k coef_k phi_k(s)`` and its ``s``-derivative at the radii ``s`` (``coef``
        ``(..., order)``: the results ``(..., *s.shape)``)."""
        half = 0.5 * (self.s_out - self.s_in)
        s = np.asarray(s, float)
        phi, dphi = _values((s.ravel() - 0.5 * (self.s_in + self.s_out)) / half, self.order)
        coef = np.asarray(coef)
        shape = coef.shape[:-1] + s.shape
        return (coef @ phi).reshape(shape), (coef @ dphi / half).reshape(shape)


def _values(x, order):
    """``phi_k(x)`` and ``dphi_k/dx`` for ``k < order`` at the points ``x`` (``(order, len(x))``)."""
    v = L.legvander(np.atleast_1d(x), order + 1).T  # (order + 2, points): L_0 .. L_{order+1}
    k = np.arange(order)
    return v[:order] - v[2:], -(2 * k + 3)[:, None] * v[1:order + 1]
