"""Natural frequencies of the full model about its pre-stretched state
(docs/model.md, "The full model", "Linear vibrations").

A displacement of one circumferential harmonic ``n``,

    u = U(s) cos(n theta),   v = V(s) sin(n theta),   w = W(s) cos(n theta)

(the sine companion exchanges cos and sin and has the same frequencies), changes the
columns of the surface's deformation gradient by

    da1 = (U', V', W'),   da2 = ((-n U - V) / s, (U + n V) / s, -n W / s)

(the first, third and fifth components times ``cos``, the others times ``sin``).  The
second variation of the energy is ``int da . A da s ds`` over the angle with ``A`` the
tangent moduli of :func:`model.full.surface.hessian` at the planar pre-stretch; the angular
integral couples only components of equal parity (a factor ``pi``, ``2 pi`` for ``n = 0``,
which cancels against the kinetic energy ``(Gamma h / 2) int (U^2 + V^2 + W^2) s ds``).
At the planar state ``A`` couples ``W`` with neither ``U`` nor ``V`` (``A`` has no entry between
a ``z`` component and an in-plane one there), so the problem splits into a transverse one --
the same as Eq. (25), whose converged Galerkin frequencies it reproduces -- and an in-plane
one in ``(U, V)``; for ``n = 0`` the in-plane one splits again into radial (``U``) and
torsional (``V``) motion, and only the radial one is driven by axisymmetric transverse motion
(a torsion ``v`` changes sign under ``theta -> -theta``, which leaves such a motion alone).  With ``K`` and ``M`` the Legendre-Galerkin matrices (scaled radii),
``omega^2 = (C1 / (Gamma Re^2)) lambda`` for their generalised eigenvalues ``lambda``.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh

from . import surface
from .static import FullPrestretch, planar_columns


def _tangent(state: FullPrestretch):
    b = state.basis
    r, dr = state.scaled(b.s)
    a1, a2 = planar_columns(r, dr, b.s)
    return surface.hessian(state.membrane.material, a1, a2)


def _variations(state: FullPrestretch, n: int, fields: str):
    """``(6, unknowns, points)``: the change of each component of ``F`` per basis coefficient
    of the ``fields`` (a subset of ``"UVW"``, in that order)."""
    b = state.basis
    k, p = b.order, b.s.size
    zero = np.zeros((k, p))
    inv_s = 1.0 / b.s
    # rows: a1_r, a1_theta, a1_z, a2_r, a2_theta, a2_z; one block of columns per field
    by_field = {
        "U": [b.dphi, zero, zero, -n * b.phi * inv_s, b.phi * inv_s, zero],
        "V": [zero, b.dphi, zero, -b.phi * inv_s, n * b.phi * inv_s, zero],
        "W": [zero, zero, b.dphi, zero, zero, -n * b.phi * inv_s],
    }
    return np.array([np.concatenate([by_field[f][c] for f in fields]) for c in range(6)])


#: Whether each component of ``F`` varies as ``cos(n theta)`` (True) or ``sin(n theta)``.
_COSINE = np.array([True, False, True, False, True, False])
#: Radii on which :func:`transverse_mode` finds a mode's largest deflection (its relative
#: error, the grid's spacing squared times the shape's curvature, is below 1e-6).
MODE_POINTS = 2001


def stiffness_mass(state: FullPrestretch, n: int, fields: str):
    """The Galerkin stiffness and mass matrices of harmonic ``n`` for the ``fields``
    (scaled radii, divided by ``C1 h`` and ``Gamma h`` and by the angular factor)."""
    b = state.basis
    A = _tangent(state)
    dF = _variations(state, n, fields)
    w = b.s * b.weights
    same = _COSINE[:, None] == _COSINE[None, :]
    if n == 0:
        same[:] = True  # every component is independent of theta
    K = np.zeros((dF.shape[1], dF.shape[1]))
    for i in range(6):
        for j in range(6):
            if same[i, j]:
                K += (dF[i] * (A[:, i, j] * w)) @ dF[j].T
    blocks = [(b.phi * w) @ b.phi.T] * len(fields)
    M = np.zeros_like(K)
    o = b.order
    for f, block in enumerate(blocks):
        M[f * o:(f + 1) * o, f * o:(f + 1) * o] = block
    return 0.5 * (K + K.T), M


def frequencies(state: FullPrestretch, n: int, count: int, fields: str) -> np.ndarray:
    """The ``count`` lowest natural frequencies (rad s-1) of harmonic ``n`` for ``fields``:
    ``"W"`` transverse, ``"UV"`` in-plane (``"U"`` radial or ``"V"`` torsional alone for
    ``n = 0``).

    Raises
    ------
    ValueError
        When ``count`` exceeds the unknowns, or the in-plane fields are split for ``n > 0``
        (they are coupled there).
    """
    if n > 0 and fields in ("U", "V"):
        raise ValueError(f"fields = {fields!r} is invalid for n = {n}: U and V are coupled for n > 0 (use 'UV')")
    K, M = stiffness_mass(state, n, fields)
    if count > K.shape[0]:
        raise ValueError(f"count = {count} is invalid: must be <= {K.shape[0]} unknowns of order "
                         f"{state.basis.order}")
    return _frequency(state, eigh(K, M, eigvals_only=True, subset_by_index=(0, count - 1)))


def _frequency(state: FullPrestretch, lam):
    """``omega = sqrt(C1 / (Gamma Re^2) lambda)`` (rad s-1) of the Galerkin eigenvalues ``lambda``."""
    m = state.membrane
    return np.sqrt(m.C1 / (m.Gamma * m.Re**2) * lam)


def transverse_frequencies(state: FullPrestretch, n: int, count: int) -> np.ndarray:
    """``omega_mn`` (rad s-1), ``m = 1 .. count``: the transverse modes of harmonic ``n``."""
    return frequencies(state, n, count, "W")


def inplane_frequencies(state: FullPrestretch, n: int, count: int) -> np.ndarray:
    """The ``count`` lowest in-plane frequencies (rad s-1) of harmonic ``n``: the coupled
    ``(U, V)`` modes for ``n > 0``, the radial (``U``) ones for ``n = 0`` -- those that an
    axisymmetric transverse motion drives; the torsional ``n = 0`` modes (``V``, decoupled and
    left alone by it, ``frequencies(state, 0, count, "V")``) are not among them."""
    return frequencies(state, n, count, "U" if n == 0 else "UV")


def transverse_mode(state: FullPrestretch, n: int, index: int = 0) -> tuple[float, np.ndarray]:
    """The transverse mode ``index`` (0: the lowest) of harmonic ``n``: its frequency (rad
    s-1) and its ``W`` coefficients ``(order,)``, scaled so that the largest ``|W(s)|`` on
    :data:`MODE_POINTS` equally spaced radii from edge to edge is 1 and positive."""
    K, M = stiffness_mass(state, n, "W")
    lam, vectors = eigh(K, M, subset_by_index=(index, index))
    b, m = state.basis, state.membrane
    values = b.evaluate(vectors[:, 0], np.linspace(m.Ro / m.Re, 1.0, MODE_POINTS))[0]
    W = vectors[:, 0] / values[np.argmax(np.abs(values))]
    return float(_frequency(state, lam[0])), W
