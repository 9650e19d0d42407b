"""The full model's motion that is not axisymmetric: circumferential harmonics of the three
displacement fields with the exact energy (docs/model.md, "The full model", "Circumferential
harmonics").

The fields are ``u = sum_k U_k(s) cos k theta``, ``v = sum_k V_k(s) sin k theta`` (``k >= 1``)
and ``w = sum_k W_k(s) cos k theta`` over a set of harmonics ``k`` that holds 0: the subspace
even under the reflection ``theta -> -theta``, where the cosine families
(:mod:`model.full.families`) live and where the nonlinearity keeps them (a product of
harmonics ``k`` and ``l`` feeds ``k + l`` and ``|k - l|``; the harmonics left out are a
truncation in ``theta``, as the ROM's modes are one in both directions).  With
``companions`` every block also has its sine companion (the block turned by a quarter of its
period: ``u, w`` on ``sin k theta``, ``v`` on ``-cos k theta``, the torsion ``v = -V_0``), and the
model holds every state of these harmonics, symmetric under the rotations and the reflection
(O(2)).  Each field of each harmonic has the ``order`` functions of the radial basis; the
energy is
``(1 / 2 pi) int int W s ds dtheta`` (over ``2 pi h C1 Re^2``: the axisymmetric model's
:meth:`model.full.axisymmetric.AxisymmetricFull.energy` on the harmonic 0) and Lagrange's
equations are

    q'' = -omega_0^2 M^-1 g(q) - D q' + P(t) load,

with the mass of a block ``int phi_k phi_l s ds`` times the angular mean of the square of its
angular function (1 for ``k = 0``, 1/2 otherwise) and the pressure on the harmonic 0 of
``w`` alone (the uniform pressure's work on ``cos k theta`` vanishes for ``k >= 1``).  About
an axisymmetric state the block of harmonic ``n`` of the Hessian is half the family's
stiffness ``K_n`` (:meth:`model.full.families.FullFamily.stiffness`): with the half mass the
linearised motion is the family's, which is what makes the nonlinear model an independent
check of the families' Floquet multipliers (:func:`model.families.perturbation_growth`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from dataclasses import field as default_field

import numpy as np
from scipy.linalg import block_diag

from model.damping_kernels import matrix_or_none
from model.forced import periodic_peak
from model.protocol import PARAMETERS, sorted_multipliers, state_scale
from model.rk4 import stable

from . import surface
from .axisymmetric import AxisymmetricFull
from .axisymmetric_kernels import NO_PARAMETER, OMEGA, PRESSURE
from .family_kernels import FIELD_U, FIELD_V, FIELD_W, variation_vectors
from .harmonic_kernels import harmonic_gradient, harmonic_hessian, harmonic_motion, harmonic_variational

_LETTERS = {FIELD_U: "U", FIELD_V: "V", FIELD_W: "W"}


class HarmonicFull:
    """The full model of ``model``'s pre-stretch and basis on the circumferential
    ``harmonics`` (0 among them), its angular integrals on ``theta_points`` points of
    ``[0, pi]`` (default ``4 max(harmonics) + 4``); with ``companions``, the sine companions
    of every block as well (the group O(2)), on twice the points over the whole circle.

    A block's angular functions follow from two factors, ``e(theta)`` and ``o(theta)``: the
    field of a ``U`` or ``W`` block is ``e``, that of a ``V`` block ``o``; the cosine blocks
    (parity ``"even"``) have ``e = cos k theta``, ``o = sin k theta``, their companions
    (``"odd"``) the same turned by a quarter of the harmonic's period, ``e = sin k theta``,
    ``o = -cos k theta`` (``v = -V_k cos k theta``; for ``k = 0`` the torsion ``v = -V_0``).
    A rotation of the pattern by ``phi`` then turns each (cosine, companion) pair of
    coefficients by ``k phi`` (:meth:`rotation`), as the ROM's cosine and sine modes
    (:func:`model.waves.rotation`).

    Attributes
    ----------
    blocks : tuple of (int, str, str)
        The coordinate blocks in order, ``(k, field, parity)``: per harmonic ``U``, ``V``
        (``k >= 1``) and ``W`` of parity ``"even"``, then with ``companions`` per harmonic
        ``U`` (``k >= 1``), ``V`` and ``W`` (``k >= 1``) of parity ``"odd"``; each ``order``
        coefficients (over ``Re``).
    dof : int
        ``len(blocks) order``.
    """

    def __init__(self, model: AxisymmetricFull, harmonics, theta_points: int | None = None,
                 companions: bool = False):
        if not model.inplane:
            raise ValueError("model is invalid here: the circumferential harmonics need the in-plane fields "
                             "(inplane = true)")
        ks = sorted({int(k) for k in harmonics})
        if not ks or ks[0] != 0 or any(k != h for k, h in zip(ks, harmonics)) or len(ks) != len(harmonics):
            raise ValueError(f"harmonics = {list(harmonics)!r} is invalid: distinct increasing integers >= 0 "
                             "starting with 0")
        points = 4 * ks[-1] + 4 if theta_points is None else int(theta_points)
        if points < 2 * ks[-1] + 1:
            raise ValueError(f"theta_points = {theta_points!r} is invalid: at least 2 max(harmonics) + 1 = "
                             f"{2 * ks[-1] + 1}")
        self.model = model
        self._highest = None  # highest_frequency(), when first asked
        self.harmonics = tuple(ks)
        self.order = model.order
        self.companions = bool(companions)
        self.blocks = tuple((k, f, "even") for k in ks for f in (("U", "W") if k == 0 else ("U", "V", "W")))
        if self.companions:
            self.blocks += tuple((k, f, "odd") for k in ks for f in (("V",) if k == 0 else ("U", "V", "W")))
        self.dof = len(self.blocks) * self.order
        codes = {v: c for c, v in _LETTERS.items()}
        self._fields = np.array([codes[f] for _, f, _ in self.blocks], dtype=np.int64)
        self._wave = np.array([float(k) for k, _, _ in self.blocks])
        # the midpoint rule on [0, pi] is that on the circle for the even states' integrands,
        # which are even in theta; the companions' are not
        if self.companions:
            points *= 2
        theta = (2.0 if self.companions else 1.0) * math.pi * (np.arange(points) + 0.5) / points
        self.theta = theta
        kt = np.outer(self._wave, theta)
        odd = np.array([parity == "odd" for _, _, parity in self.blocks])[:, None]
        #: ``e`` and ``o`` of each block at the angular points ``(B, T)``
        self._even_factor = np.ascontiguousarray(np.where(odd, np.sin(kt), np.cos(kt)))
        self._odd_factor = np.ascontiguousarray(np.where(odd, -np.cos(kt), np.sin(kt)))
        self._theta_weight = np.full(points, 1.0 / points)
        # what a coefficient of each block moves in F per phi' and per phi / s at each angle: the
        # family's vectors, their components even under theta -> -theta times e, the odd ones o
        even = np.arange(6) % 2 == 0
        self._variations = np.ascontiguousarray(np.stack([
            variation_vectors(k, np.array([code]))[0][None] * np.where(even, e[:, None, None], o[:, None, None])
            for k, code, e, o in zip(self._wave, self._fields, self._even_factor, self._odd_factor)]))
        # the same as at most two components per block and kind: their indices and values (the
        # compiled Hessian's sparse form; an unused component has index 0 and value 0)
        B = len(self.blocks)
        self._var_index = np.zeros((B, 2, 2), dtype=np.int64)
        self._var_value = np.zeros((B, points, 2, 2))
        for b, (k, code) in enumerate(zip(self._wave, self._fields)):
            for alpha, g in enumerate(variation_vectors(k, np.array([code]))[0]):
                nz = np.flatnonzero(g)
                self._var_index[b, alpha, :nz.size] = nz
                self._var_value[b, :, alpha, :nz.size] = self._variations[b, :, alpha][:, nz]
        #: each block's inverse angular mean of its field's factor squared: 1 for ``k = 0``, else 2
        self.inverse_scale = np.where(self._wave == 0.0, 1.0, 2.0)
        g0 = self.compiled_gradient(np.zeros(self.dof))
        #: ``omega_0^2 M^-1 g(0)`` (s-2): the rounding of the pre-stretch's equilibrium, added
        #: back as in :attr:`model.full.axisymmetric.AxisymmetricFull.bias`
        self.bias = model.omega0_2 * np.concatenate(
            [self.inverse_scale[b] * (model.inverse_mass @ g0[b * self.order:(b + 1) * self.order])
             for b in range(len(self.blocks))])
        #: the index of the block ``W_0``, where the pressure acts
        self.load_block = self.blocks.index((0, "W", "even"))

    def block(self, k: int, field: str, parity: str = "even") -> slice:
        """The coordinates of the field ``"U"``, ``"V"`` or ``"W"`` of harmonic ``k`` (of the
        cosine blocks, or of their companions: ``parity = "odd"``)."""
        b = self.blocks.index((int(k), field, parity))
        return slice(b * self.order, (b + 1) * self.order)

    def highest_frequency(self) -> float:
        """An upper bound of the highest natural frequency (rad s-1) of the harmonics' linear
        motion about the pre-stretch (it bounds the explicit time step): the largest of their
        families' in ``U, V, W`` (:attr:`model.full.families.FullFamily.omega_max`; a
        companion has its cosine block's frequencies)."""
        from .families import FullFamily

        if self._highest is None:
            self._highest = max(FullFamily.build(self.model, k).omega_max for k in self.harmonics)
        return self._highest

    def fields(self, q, rho, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The displacements ``(u, v, w)`` (over ``Re``; radial, circumferential, transverse)
        of the coordinates ``q`` (``(..., dof)``, over ``Re``: one state or many, e.g. a
        motion's samples) at the undeformed points ``(rho, theta)`` (arrays of one shape;
        ``rho`` over ``Re``), each ``(..., *rho.shape)``: each block's radial function times
        its angular factor, ``e`` for ``U`` and ``W``, ``o`` for ``V`` (the class docstring).
        The radial basis is evaluated once for all states and blocks."""
        rho, theta = np.broadcast_arrays(np.asarray(rho, float), np.asarray(theta, float))
        q = np.asarray(q, float)
        blocks = q.reshape(q.shape[:-1] + (len(self.blocks), self.order))
        radial = self.model.state.basis.evaluate(blocks, rho.ravel())[0]  # (..., blocks, points)
        kt = np.outer(self._wave, theta.ravel())
        odd = np.array([parity == "odd" for _, _, parity in self.blocks])[:, None]
        v = self._fields == FIELD_V
        factor = np.where(v[:, None], np.where(odd, -np.cos(kt), np.sin(kt)), np.where(odd, np.sin(kt), np.cos(kt)))
        terms = radial * factor
        shape = q.shape[:-1] + rho.shape
        return tuple((terms[..., self._fields == code, :].sum(axis=-2)).reshape(shape)
                     for code in (FIELD_U, FIELD_V, FIELD_W))

    @property
    def odd(self) -> np.ndarray:
        """``(dof,)``: which coordinates are the companions' (odd under ``theta -> -theta``)."""
        return np.repeat([parity == "odd" for _, _, parity in self.blocks], self.order)

    def rotation(self, phi: float) -> np.ndarray:
        """``(2 dof, 2 dof)``: the state ``(q, q')`` of the pattern turned by ``phi`` (rad),
        ``f(theta) -> f(theta - phi)``: each (cosine, companion) pair of blocks of harmonic
        ``k`` turns by ``k phi``, the rest is left alone.  Needs :attr:`companions`."""
        out = np.eye(self.dof)
        for b, c, k in self._pairs():
            cos, sin = math.cos(k * phi), math.sin(k * phi)
            out[b, b], out[b, c], out[c, b], out[c, c] = cos, -sin, sin, cos
        return block_diag(out, out)

    def rotation_generator(self) -> np.ndarray:
        """``(2 dof, 2 dof)`` (rad-1): the derivative of :meth:`rotation` at ``phi = 0``;
        ``(a, b) -> k (-b, a)`` for each pair."""
        g = np.zeros((self.dof, self.dof))
        for b, c, k in self._pairs():
            g[b, c], g[c, b] = -k, k
        return block_diag(g, g)

    def _pairs(self):
        # (a cosine block's coordinates, its companion's, k) for k >= 1: paired entry by entry
        if not self.companions:
            raise ValueError("the rotations need the companions (HarmonicFull(..., companions=True))")
        for k, f, parity in self.blocks:
            if parity == "even" and k > 0:
                b, c = self.block(k, f), self.block(k, f, "odd")
                yield np.arange(b.start, b.stop), np.arange(c.start, c.stop), k

    def _tables(self):
        m = self.model
        return (*m.kernel_tables, self._fields, self._wave, self._even_factor, self._odd_factor, self._theta_weight)

    def compiled_gradient(self, q) -> np.ndarray:
        """``d energy / dq`` (``(dof,)``) by the compiled loop (:func:`harmonic_gradient`)."""
        out = np.empty(self.dof)
        B = len(self.blocks)
        harmonic_gradient(*self._tables(), np.ascontiguousarray(q, dtype=float), out, np.empty(B), np.empty(B),
                          np.empty(B), np.empty(B))
        return out

    def compiled_hessian(self, q) -> np.ndarray:
        """``d^2 energy / dq^2`` (``(dof, dof)``) by the compiled loop (:func:`harmonic_hessian`)."""
        out = np.empty((self.dof, self.dof))
        harmonic_hessian(*self._tables(), self._var_index, self._var_value, np.ascontiguousarray(q, dtype=float), out)
        return out

    def relaxed(self, q) -> np.ndarray:
        """``q`` (``(dof,)``, over ``Re``) with its ``U`` and ``V`` blocks replaced by those that
        make the energy stationary at its ``W`` blocks: the in-plane displacement that a
        quasi-static transverse deflection carries (Newton on :meth:`compiled_gradient` and
        :meth:`compiled_hessian` from the given in-plane blocks; the harmonics' form of
        :meth:`model.full.axisymmetric.AxisymmetricFull.relaxed`).

        Raises
        ------
        ArithmeticError
            When Newton's steps do not fall below ``1e-14`` of the largest coordinate in 50.
        """
        inplane = np.concatenate([np.arange(self.dof)[self.block(k, f, parity)]
                                  for k, f, parity in self.blocks if f != "W"])
        q = np.array(q, float)
        for _ in range(50):
            step = -np.linalg.solve(self.compiled_hessian(q)[np.ix_(inplane, inplane)],
                                    self.compiled_gradient(q)[inplane])
            q[inplane] += step
            if np.abs(step).max() < 1e-14 * (1.0 + np.abs(q).max()):
                return q
        raise ArithmeticError("the in-plane displacement at the given deflection did not converge")

    def _fields_on_grid(self, q):
        # u, u_s, u_theta, v, v_s, v_theta, w_s, w_theta at (theta, s): (T, points) each; a block's
        # field is e (U, W) or o (V), e' = -k o and o' = k e
        b = self.model.state.basis
        zero = np.zeros((self.theta.size, b.s.size), dtype=np.result_type(q, float))
        out = {key: zero.copy() for key in ("u", "us", "ut", "v", "vs", "vt", "ws", "wt")}
        for i, (k, f, _) in enumerate(self.blocks):
            c = q[i * self.order:(i + 1) * self.order]
            value, slope = c @ b.phi, c @ b.dphi
            e, o = self._even_factor[i][:, None], self._odd_factor[i][:, None]
            if f == "U":
                out["u"] += value * e
                out["us"] += slope * e
                out["ut"] -= k * value * o
            elif f == "V":
                out["v"] += value * o
                out["vs"] += slope * o
                out["vt"] += k * value * e
            else:
                out["ws"] += slope * e
                out["wt"] -= k * value * o
        return out

    def _columns(self, q):
        # a1, a2 at (theta, s): (T, points, 3) each
        m, b = self.model, self.model.state.basis
        f = self._fields_on_grid(q)
        s = b.s
        a1 = np.stack([m.dr0 + f["us"], f["vs"], f["ws"]], axis=-1)
        a2 = np.stack([(f["ut"] - f["v"]) / s, (m.r0 + f["u"] + f["vt"]) / s, f["wt"] / s], axis=-1)
        return a1, a2

    def gradient(self, q) -> np.ndarray:
        """``d energy / dq`` by numpy (:func:`model.full.surface.gradient` on the grid, projected
        on each block's variations): the reference of :meth:`compiled_gradient`."""
        b = self.model.state.basis
        p1, p2 = surface.gradient(self.model.membrane.material, *self._columns(q))
        stress = np.concatenate([p1, p2], axis=-1)  # (T, points, 6)
        # per block, point and kind of variation (per phi', per phi / s): the angular mean of P . g
        along = np.einsum("t,tpi,btai->bpa", self._theta_weight, stress, self._variations)
        return ((along[:, :, 0] * (b.s * b.weights)) @ b.dphi.T + (along[:, :, 1] * b.weights) @ b.phi.T).ravel()

    def hessian(self, q) -> np.ndarray:
        """``d^2 energy / dq^2`` by numpy (:func:`model.full.surface.hessian` on the grid): the
        reference of :meth:`compiled_hessian`."""
        b = self.model.state.basis
        moduli = surface.hessian(self.model.membrane.material, *self._columns(q))  # (T, points, 6, 6)
        pairs = np.einsum("t,btai,tpij,ctdj->pbcad", self._theta_weight, self._variations, moduli, self._variations)
        radial = np.stack([b.dphi, b.phi / b.s])  # per phi' and per phi / s: (2, order, points)
        H = np.einsum("ajp,pbcad,dmp,p->bjcm", radial, pairs, radial, b.s * b.weights)
        return H.reshape(self.dof, self.dof)

    def energy(self, q):
        """``(1 / 2 pi) int int W / C1 s ds dtheta`` by numpy (:mod:`model.full.surface`; complex
        for complex ``q``, the complex-step derivatives of the tests)."""
        b = self.model.state.basis
        density = surface.energy(self.model.membrane.material, *self._columns(q))  # (T, points)
        return self._theta_weight @ density @ (b.s * b.weights)

    def kinetic(self, v) -> float:
        """The kinetic energy in the units of :meth:`energy` (``(1/2) v^T M v / omega_0^2``)."""
        o, mass = self.order, self.model.mass_block
        return 0.5 * sum(float(v[b * o:(b + 1) * o] @ mass @ v[b * o:(b + 1) * o]) / self.inverse_scale[b]
                         for b in range(len(self.blocks))) / self.model.omega0_2

    def motion(self, y0, dt: float, steps: int, every: int = 1, P0: float = 0.0, Omega: float = 0.0,
               rate: float = 0.0, matrix=None) -> np.ndarray:
        """``steps`` RK4 steps of ``dt`` (s) from ``y0`` (over ``Re``) under ``P0 cos(Omega t)``
        (Pa) and the damping ``rate I + matrix`` (s-1; ``matrix`` ``(dof, dof)`` or None): the
        states every ``every`` steps, ``(steps // every + 1, 2 dof)`` (:func:`harmonic_motion`)."""
        m = self.model
        record = np.empty((steps // every + 1, 2 * self.dof))
        harmonic_motion(*self._tables(), m.inverse_mass, self.inverse_scale, m.omega0_2, self.bias, float(rate),
                        matrix, m.load, self.load_block, float(P0), float(Omega), np.asarray(y0, float), float(dt),
                        int(steps), int(every), record)
        return record

    def variational(self, y0, dt: float, steps: int, P0: float, Omega: float, rate: float, matrix,
                    parameter: int) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`motion` to the last step with the flow's derivative ``(2 dof, 2 dof + 1)`` in
        ``y0`` and, in the last column, in ``parameter`` (:func:`harmonic_variational`)."""
        m = self.model
        return harmonic_variational(*self._tables(), self._var_index, self._var_value, m.inverse_mass,
                                    self.inverse_scale, m.omega0_2, self.bias, float(rate), matrix, m.load, self.load_block, float(P0),
                                    float(Omega), int(parameter), np.asarray(y0, float), float(dt), int(steps))


@dataclass(frozen=True)
class HarmonicForced:
    """The stroboscopic map of :class:`HarmonicFull` under ``P0 cos(Omega t)`` with ``steps``
    RK4 steps per period and the damping ``rate I + matrix`` (s-1; ``matrix`` ``(dof, dof)``,
    or ``(0, 0)`` for none) (:class:`model.protocol.StroboscopicMap`).  States
    ``(Re q, Re q')`` (m, m s-1), as the axisymmetric map's (:class:`model.full.forced.ForcedFull`);
    :meth:`amplitude` measures ``probe @ q`` (m; default: ``w(0.5 Re, 0)`` of every harmonic,
    :meth:`probe_vector`).  ``eigenvalues`` (s-1): of the damped linear motion of every harmonic
    about the pre-stretch; where RK4's step leaves their stability region (at another
    ``Omega``, :meth:`varied`) the map returns NaN states, as the axisymmetric map does (empty,
    the default: no guard; :meth:`model.full.forced.ForcedFull.perturbed_family` gives them)."""

    model: HarmonicFull
    P0: float
    Omega: float
    steps: int
    rate: float
    matrix: np.ndarray
    probe: np.ndarray | None = None
    eigenvalues: np.ndarray = default_field(default_factory=lambda: np.zeros(0))

    @property
    def dof(self) -> int:
        """Coordinates: :attr:`HarmonicFull.dof`."""
        return self.model.dof

    @property
    def period(self) -> float:
        """Forcing period ``2 pi / Omega`` (s)."""
        return 2.0 * math.pi / self.Omega

    @property
    def parameters(self) -> tuple[str, ...]:
        """``Omega`` and ``P0``."""
        return PARAMETERS

    def value(self, parameter: str) -> float:
        """The current value of ``Omega`` or ``P0``."""
        if parameter not in PARAMETERS:
            raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(PARAMETERS)}")
        return float(getattr(self, parameter))

    def varied(self, parameter: str, value: float) -> HarmonicForced:
        """The same map (its steps per period kept) with ``Omega`` or ``P0`` set to ``value``."""
        self.value(parameter)
        return replace(self, **{parameter: float(value)})

    def state_scale(self, Omega: float | None = None) -> np.ndarray:
        """:func:`model.protocol.state_scale` at this map's ``Omega`` or at ``Omega``."""
        return state_scale(self.dof, self.Omega if Omega is None else Omega)

    @property
    def stable_step(self) -> bool:
        """Whether RK4's step keeps every mode of :attr:`eigenvalues` within its stability region."""
        return stable(self.eigenvalues, self.period / self.steps)

    def _motion(self, y, steps: int, every: int) -> np.ndarray:
        re = self.model.model.membrane.Re
        if not self.stable_step:
            return np.full((steps // every + 1, 2 * self.dof), np.nan)
        return self.model.motion(np.asarray(y, float) / re, self.period / self.steps, steps, every, self.P0,
                                 self.Omega, self.rate, matrix_or_none(self.matrix)) * re

    def advance(self, y, periods: int = 1) -> np.ndarray:
        """The state after ``periods`` forcing periods from ``y`` at ``t = 0``."""
        n = periods * self.steps
        return self._motion(y, n, n)[-1]

    def advance_batch(self, states, periods: int = 1) -> np.ndarray:
        """:meth:`advance` of each row of ``states`` ``(N, 2 dof)``; a new array."""
        states = np.array(states, dtype=float, ndmin=2)
        return np.array([self.advance(y, periods) for y in states]).reshape(states.shape)

    def _variational(self, y, parameter: int):
        re = self.model.model.membrane.Re
        if not self.stable_step:
            n = 2 * self.dof
            return np.full(n, np.nan), np.full((n, n), np.nan), np.full(n, np.nan)
        yT, big = self.model.variational(np.asarray(y, float) / re, self.period / self.steps, self.steps, self.P0,
                                         self.Omega, self.rate, matrix_or_none(self.matrix), parameter)
        return yT * re, big[:, :-1], big[:, -1] * re

    def monodromy(self, y) -> tuple[np.ndarray, np.ndarray]:
        """``P(y)`` and ``dP/dy`` (the RK4 variational equations: exact for the discrete map)."""
        yT, phi, _ = self._variational(y, NO_PARAMETER)
        return yT, phi

    def monodromy_parameter(self, y, parameter: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``P(y)``, ``dP/dy`` and ``dP/d parameter`` (``"Omega"`` at fixed steps per period, or
        ``"P0"``)."""
        self.value(parameter)
        return self._variational(y, OMEGA if parameter == "Omega" else PRESSURE)

    def multipliers(self, y) -> np.ndarray:
        """Floquet multipliers at ``y`` by decreasing modulus."""
        return sorted_multipliers(self.monodromy(y)[1])

    def probe_vector(self, rho: float, harmonics=None) -> np.ndarray:
        """``(dof,)``: ``w(rho, 0) = probe @ q`` summed over ``harmonics`` (default: all)."""
        m = self.model.model
        phi, _ = m.state.basis.evaluate(np.eye(m.order), np.array([rho / m.membrane.Re]))
        out = np.zeros(self.dof)
        for k in self.model.harmonics if harmonics is None else harmonics:
            out[self.model.block(k, "W")] = phi[:, 0]
        return out

    def amplitude(self, y, periods: int = 1) -> float:
        """``max_t |probe @ q(t)|`` (m) over ``periods`` periods from ``y``: the largest RK4
        sample refined by a parabola (:func:`model.forced.periodic_peak`); NaN when the motion
        does not stay finite."""
        probe = self.probe_vector(0.5 * self.model.model.membrane.Re) if self.probe is None else self.probe
        w = self._motion(y, periods * self.steps, 1)[:, :self.dof] @ probe
        return periodic_peak(w, periods * self.steps) if np.all(np.isfinite(w)) else math.nan
