"""Stability of the full model's axisymmetric motion to asymmetric perturbations, one
circumferential harmonic at a time (docs/model.md, "The full model", "Asymmetric families").

About an axisymmetric state ``(u0(s, t), w0(s, t))`` of :class:`model.full.axisymmetric.AxisymmetricFull`
a perturbation of harmonic ``n >= 1``,

    u = U(s) cos(n theta),   v = V(s) sin(n theta),   w = W(s) cos(n theta),

couples to no other harmonic and not to the axisymmetric motion at linear order (the
reflection ``theta -> -theta`` leaves the state alone, and the angular integrals of products
of different harmonics vanish); the sine companion (``cos`` and ``sin`` exchanged) has the
same equations.  Its stiffness is the second variation of the energy,
``K_n(q) = int dF^T A(q) dF s ds`` with ``A`` the tangent moduli at the axisymmetric state
(:mod:`model.full.family_kernels`): at the flat pre-stretch it is the matrix of
:func:`model.full.linear.stiffness_mass` (whose frequencies it has), on a deflected state it
couples ``W`` with ``U`` and ``V``.  The perturbation obeys
``X'' = -omega_0^2 M^-1 K_n(q(t)) X - D X'`` with ``D`` the damping law on the family's own
linear problem (the viscous pressure: the map's rate on all three components).

The family's unknowns are ``radial`` Legendre-Galerkin functions per field (the first
functions of the model's basis: the basis is hierarchical), for the fields ``U, V, W`` or, to
measure what the in-plane freedom changes, ``W`` alone (``u = v = 0`` held in the
perturbation, as in the ROM's families).  ``n = 0`` with the fields ``U, W`` is the
axisymmetric block itself (the tests check it against the map's own monodromy).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.linalg import eigh

from .axisymmetric import AxisymmetricFull
from .family_kernels import FIELD_U, FIELD_V, FIELD_W, family_stiffness, variation_vectors

#: The fields of a family, by their letters.
FIELD_CODES = {"U": FIELD_U, "V": FIELD_V, "W": FIELD_W}


@dataclass(frozen=True, eq=False)
class FullFamily:
    """The perturbations of harmonic ``n`` of the full model with ``radial`` basis functions
    per field of ``fields``.  Build with :meth:`build`.

    Attributes
    ----------
    n : int
    radial : int
        Basis functions per field (at most the model's order).
    fields : str
        ``"UVW"``, ``"W"`` (in-plane perturbations held at zero), or any subset of ``"UVW"``.
    model : AxisymmetricFull
        The axisymmetric model whose orbits carry the family.
    phi, dphi : (points, radial) arrays
        The family's basis functions and their ``s``-derivatives at the model's quadrature points.
    variations : (F, 2, 6) array
        What a coefficient of each field moves in ``F`` per ``phi'`` and per ``phi / s``.
    inverse_mass : (radial, radial) array
        ``M^-1`` of one field.
    omega_max : float
        The family's highest frequency about the pre-stretch (rad s-1): it grows with ``n``
        (at order 12, 1.004 times the axisymmetric model's at ``n = 6``, 1.24 at ``n = 20``), and
        RK4 integrates the block only for ``omega_max dt < 2.8``.
    """

    n: int
    radial: int
    fields: str
    model: AxisymmetricFull
    phi: np.ndarray
    dphi: np.ndarray
    variations: np.ndarray
    inverse_mass: np.ndarray
    omega_max: float = 0.0

    @classmethod
    def build(cls, model: AxisymmetricFull, n: int, radial: int | None = None, fields: str = "UVW") -> FullFamily:
        """The family of harmonic ``n`` on ``radial`` functions per field (default: the
        model's order) for ``fields``."""
        if isinstance(n, bool) or int(n) != n or n < 0:
            raise ValueError(f"n = {n!r} is invalid: a family needs a wave number n >= 0")
        radial = model.order if radial is None else radial
        if isinstance(radial, bool) or int(radial) != radial or not 1 <= radial <= model.order:
            raise ValueError(f"radial = {radial!r} is invalid: must be an integer from 1 to the model's order "
                             f"{model.order}")
        if not fields or any(f not in FIELD_CODES for f in fields) or len(set(fields)) != len(fields):
            raise ValueError(f"fields = {fields!r} is invalid: must be distinct letters of 'UVW'")
        fields = "".join(f for f in "UVW" if f in fields)
        b = model.state.basis
        radial = int(radial)
        phi = np.ascontiguousarray(b.phi[:radial].T)
        dphi = np.ascontiguousarray(b.dphi[:radial].T)
        codes = np.array([FIELD_CODES[f] for f in fields], dtype=np.int64)
        inverse_mass = np.linalg.inv(model.mass_block[:radial, :radial])
        family = cls(int(n), radial, fields, model, phi, dphi, variation_vectors(float(n), codes), inverse_mass)
        highest = eigh(*family.linear_system()[::-1], eigvals_only=True)[-1]
        return replace(family, omega_max=float(np.sqrt(max(highest, 0.0))))

    @property
    def size(self) -> int:
        """Dimension ``2 F radial`` of the family's block of the monodromy matrix."""
        return 2 * len(self.fields) * self.radial

    def stiffness(self, q) -> np.ndarray:
        """``K_n(q)`` ``(F radial, F radial)``: the second variation of ``int W/C1 s ds`` (the
        energy over ``pi h C1 Re^2``) at the axisymmetric coordinates ``q = (U, W)`` (over
        ``Re``), fields in the order of :attr:`fields`."""
        law, phi, dphi, s, sw, _, r0, dr0 = self.model.kernel_tables
        m = len(self.fields) * self.radial
        out = np.empty((m, m))
        family_stiffness(law, phi, dphi, s, sw, r0, dr0, np.ascontiguousarray(q, dtype=float), self.phi, self.dphi,
                         self.variations, np.empty((6, 6)), np.empty((len(self.fields),) * 2 + (2, 2)), out)
        return out

    def mass(self) -> np.ndarray:
        """The mass matrix ``(F radial, F radial)`` of the family (block diagonal, one
        ``int phi_k phi_l s ds`` block per field)."""
        return np.kron(np.eye(len(self.fields)), self.model.mass_block[:self.radial, :self.radial])

    def linear_system(self, membrane=None) -> tuple[np.ndarray, np.ndarray]:
        """``(M, K0)``: mass and stiffness about the pre-stretch in the scale of
        ``X'' = -M^-1 K0 X`` (s-2), what a damping law is built on
        (:meth:`model.damping.DampingLaw.terms`).  ``membrane`` is not used (the model has it)."""
        return self.mass(), self.model.omega0_2 * self.stiffness(np.zeros(self.model.dof))
