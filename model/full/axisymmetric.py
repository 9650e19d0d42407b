"""Axisymmetric motion of the full model: the radial and transverse displacements ``u(s, t)``,
``w(s, t)`` on the Legendre-Galerkin basis, exact energy (docs/model.md, "The full model",
"Axisymmetric motion").

About the pre-stretch ``r_o`` of :class:`model.full.static.FullPrestretch`, a material point
moves to ``(r_o + u) e_r + w e_z``; the columns of the deformation gradient are
``a1 = (r_o' + u', 0, w')`` and ``a2 = (0, (r_o + u)/s, 0)`` and the energy is
``2 pi h C1 Re^2 int W s ds``.  The coordinates ``q = (U_0 .. U_{N-1}, W_0 .. W_{N-1})`` are the
coefficients of ``u / Re`` and ``w / Re`` on the basis; Lagrange's equations are

    q'' = -omega_0^2 M^{-1} g(q) - (c / (Gamma h)) q',     omega_0^2 = C1 / (Gamma Re^2),

with ``g`` the gradient of ``int W / C1 s ds`` (:meth:`AxisymmetricFull.gradient`), ``M`` the
block-diagonal mass matrix ``int phi_k phi_l s ds`` and the viscous damping ``-c`` times the
whole velocity per unit undeformed area (mass-proportional on both components).

``AxisymmetricFull(state, inplane=False)`` holds ``u`` at zero: the ROM's hypothesis
``u = v = 0`` on the full model's radial discretisation (the exact energy of ``w`` alone,
its ``U`` equations dropped).  Its coordinates stay ``(U, W)`` for the compiled loops, whose
``U`` rows then have no inverse mass and no bias; :attr:`AxisymmetricFull.moving` names the
coordinates that move.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from . import surface
from .axisymmetric_kernels import axisymmetric_gradient, axisymmetric_hessian, rk4_motion
from .static import FullPrestretch


class AxisymmetricFull:
    """The axisymmetric full model about ``state`` (its basis and quadrature); with
    ``inplane=False`` the radial displacement held at zero."""

    def __init__(self, state: FullPrestretch, inplane: bool = True):
        self.state = state
        #: whether ``u`` moves (False: held at zero, the ROM's hypothesis)
        self.inplane = bool(inplane)
        b = state.basis
        self.order = b.order
        self.dof = 2 * b.order
        self.r0, self.dr0 = state.scaled(b.s)
        self._sw = b.s * b.weights
        mass = (b.phi * self._sw) @ b.phi.T
        self.mass_block = mass
        self._mass_factor = cho_factor(mass)
        m = state.membrane
        self.omega0_2 = m.C1 / (m.Gamma * m.Re**2)
        self.membrane = m
        #: ``M^-1`` of one field (``(order, order)``)
        self.inverse_mass = np.linalg.inv(mass)
        #: the indices in ``q = (U, W)`` of the coordinates that move: all, or ``W`` alone
        self.moving = np.arange(0 if self.inplane else self.order, self.dof)
        #: the indices in ``(q, q')`` of the moving coordinates and their velocities
        self.state_indices = np.concatenate([self.moving, self.dof + self.moving])
        #: the mass matrix of the moving coordinates (block diagonal, one ``mass`` per field)
        self.moving_mass = self.restricted(np.kron(np.eye(2), mass))
        #: ``M^-1`` per field, ``(2, order, order)`` (``U`` then ``W``), as the compiled motion
        #: takes it: the ``U`` block zero when ``u`` is held
        self.inverse_masses = np.stack([self.inverse_mass * self.inplane, self.inverse_mass])
        #: what the compiled loops take before the state: the law, the basis and its derivative
        #: at the quadrature points (``(points, order)``), ``s``, ``s`` times the weights, the
        #: weights and the pre-stretch ``r_o``, ``r_o'``
        self.kernel_tables = (m.material, np.ascontiguousarray(b.phi.T), np.ascontiguousarray(b.dphi.T), b.s,
                              self._sw, b.weights, self.r0, self.dr0)
        #: ``W''`` per Pa of the uniform pressure on the projected pre-stretched area (``(order,)``,
        #: s-2 Pa-1): ``M^-1 f / (Gamma h Re)`` with ``f_k = int phi_k r_o r_o' ds`` (over ``Re^2``)
        self.load = self.inverse_mass @ (b.phi @ (self.r0 * self.dr0 * b.weights)) / (m.Gamma * m.h * m.Re)
        g0 = self.compiled_gradient(np.zeros(self.dof))
        #: ``omega_0^2 M^-1 g(0)`` (s-2), the constant accelerations the compiled motion adds:
        #: the pre-stretch solves ``g(0) = 0`` to rounding (``|g(0)|`` about 1e-15), and this
        #: makes it an exact equilibrium of the discrete motion, so that a periodic response
        #: near rest converges to a relative tolerance (at ``P0 = 0`` the rest state itself)
        self.bias = self.omega0_2 * np.concatenate([self.inverse_masses[0] @ g0[:self.order],
                                                    self.inverse_masses[1] @ g0[self.order:]])

    @functools.cached_property
    def state_tangents(self) -> np.ndarray:
        """The unit vectors of the moving components of ``(q, q')`` (columns, ``(2 dof,
        moving components)``): the tangents along which the compiled variational flow is
        integrated."""
        return np.ascontiguousarray(np.eye(2 * self.dof)[:, self.state_indices])

    def restricted(self, matrix) -> np.ndarray:
        """The rows and columns of the moving coordinates of a ``(dof, dof)`` matrix."""
        return matrix[np.ix_(self.moving, self.moving)]

    def compiled_gradient(self, q) -> np.ndarray:
        """:meth:`gradient` by the compiled loop (:func:`axisymmetric_gradient`)."""
        out = np.empty(self.dof)
        axisymmetric_gradient(*self.kernel_tables, np.ascontiguousarray(q, dtype=float), out)
        return out

    def compiled_hessian(self, q) -> np.ndarray:
        """:meth:`hessian` by the compiled loop (:func:`axisymmetric_hessian`)."""
        out = np.empty((self.dof, self.dof))
        axisymmetric_hessian(*self.kernel_tables, np.ascontiguousarray(q, dtype=float), out)
        return out

    def free_motion(self, y0, duration: float, steps: int, c: float = 0.0, every: int = 1):
        """The free motion from ``y0 = (q, q')`` over ``duration`` (s) by ``steps`` RK4 steps
        (compiled, :func:`rk4_motion`): the states every ``every`` steps, ``(steps // every + 1,
        2 dof)``.  With ``u`` held, a ``U`` in ``y0`` keeps its value (give it zero).  RK4 is
        stable for ``omega_max dt < 2.8`` with ``omega_max`` the highest frequency of the
        discretisation (:meth:`highest_frequency`)."""
        record = np.empty((steps // every + 1, 2 * self.dof))
        rk4_motion(*self.kernel_tables, self.inverse_masses, self.omega0_2, self.bias, self.membrane.damping_rate(c),
                   None, self.load, 0.0, 0.0, np.asarray(y0, float), duration / steps, steps, every, record)
        return record

    def highest_frequency(self) -> float:
        """The highest natural frequency (rad s-1) of the discretised axisymmetric model about
        the pre-stretch (it bounds the explicit time step)."""
        from scipy.linalg import eigh

        o = self.order
        K = self.hessian(np.zeros(self.dof))
        lam_u = eigh(K[:o, :o], self.mass_block, eigvals_only=True)[-1] if self.inplane else 0.0
        lam_w = eigh(K[o:, o:], self.mass_block, eigvals_only=True)[-1]
        return float(np.sqrt(self.omega0_2 * max(lam_u, lam_w)))

    def fields(self, q):
        """``(u', u, w')`` over ``Re`` at the quadrature points for the coordinates ``q``."""
        b = self.state.basis
        U, W = q[:self.order], q[self.order:]
        return U @ b.dphi, U @ b.phi, W @ b.dphi

    def _columns(self, q):
        du, u, dw = self.fields(q)
        zero = np.zeros_like(du)
        s = self.state.basis.s
        return (np.stack([self.dr0 + du, zero, dw], axis=-1),
                np.stack([zero, (self.r0 + u) / s, zero], axis=-1))

    def energy(self, q):
        """``int W / C1 s ds`` (the energy over ``2 pi h C1 Re^2``; complex for complex ``q``,
        the complex-step derivatives of the tests)."""
        return surface.energy(self.membrane.material, *self._columns(q)) @ self._sw

    def gradient(self, q) -> np.ndarray:
        """``d energy / d q`` (``(dof,)``)."""
        b = self.state.basis
        p1, p2 = surface.gradient(self.membrane.material, *self._columns(q))
        g_u = b.dphi @ (p1[:, 0] * self._sw) + b.phi @ (p2[:, 1] * b.weights)
        g_w = b.dphi @ (p1[:, 2] * self._sw)
        return np.concatenate([g_u, g_w])

    def hessian(self, q) -> np.ndarray:
        """``d^2 energy / dq^2`` (``(dof, dof)``)."""
        b = self.state.basis
        A = surface.hessian(self.membrane.material, *self._columns(q))
        s, w = b.s, b.weights
        # the variations: U moves a1_r by phi' and a2_theta by phi/s, W moves a1_z by phi'
        du = [(surface.A1_R, b.dphi), (surface.A2_THETA, b.phi / s)]
        dw = [(surface.A1_Z, b.dphi)]
        H = np.empty((self.dof, self.dof))
        o = self.order
        for rows, left in ((slice(0, o), du), (slice(o, None), dw)):
            for cols, right in ((slice(0, o), du), (slice(o, None), dw)):
                H[rows, cols] = sum((fi * (A[:, i, j] * s * w)) @ fj.T for i, fi in left for j, fj in right)
        return 0.5 * (H + H.T)

    def acceleration(self, q, v, c: float = 0.0) -> np.ndarray:
        """``q''`` (s-2) of the free motion under the viscous damping ``c`` (N s m-3)."""
        g = self.gradient(q)
        o = self.order
        a = np.concatenate([cho_solve(self._mass_factor, g[:o]) * self.inplane, cho_solve(self._mass_factor, g[o:])])
        return self.bias - self.omega0_2 * a - (c / (self.membrane.Gamma * self.membrane.h)) * v

    def kinetic(self, v) -> float:
        """``(1/2) v^T M v`` over ``omega_0^2``: the kinetic energy in the units of :meth:`energy`."""
        o = self.order
        return 0.5 * float(v[:o] @ self.mass_block @ v[:o] + v[o:] @ self.mass_block @ v[o:]) / self.omega0_2

    def relaxed(self, W) -> np.ndarray:
        """The coordinates ``(U, W)`` whose ``U`` makes the energy stationary at the given ``W``:
        the in-plane displacement that a quasi-static transverse deflection carries (Newton)."""
        o = self.order
        q = np.concatenate([np.zeros(o), np.asarray(W, float)])
        for _ in range(50):
            step = -np.linalg.solve(self.hessian(q)[:o, :o], self.gradient(q)[:o])
            q[:o] += step
            if np.abs(step).max() < 1e-14 * (1.0 + np.abs(q).max()):
                return q
        raise ArithmeticError("the in-plane displacement at the given deflection did not converge")

    def displacements(self, q, s):
        """``(u, w)`` (m) at scaled radii ``s``."""
        b = self.state.basis
        re = self.membrane.Re
        return re * b.evaluate(q[:self.order], s)[0], re * b.evaluate(q[self.order:], s)[0]
