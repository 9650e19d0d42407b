"""The stroboscopic map of the forced axisymmetric full model behind
:class:`model.protocol.StroboscopicMap` (docs/model.md, "The full model", "Forced motion").

:class:`ForcedFull` is what shooting, continuation, stepped responses and basins take of the
axisymmetric full model (:class:`model.full.axisymmetric.AxisymmetricFull`) under the uniform
pressure ``P0 cos(Omega t)`` on the projected area of the pre-stretched membrane, in the fixed
``z`` direction, and a damping law of :mod:`model.damping` (the viscous pressure acts on both
velocity components: mass-proportional).  Its state is ``y = (Re q, Re q')``: the Legendre-
Galerkin coefficients of ``u`` and ``w`` in metres (``U`` then ``W``), so that the algorithms'
length scales (a continuation's 0.05 m) mean what they mean for the ROM.  On a model with ``u``
held at zero (``AxisymmetricFull(..., inplane=False)``) the state is ``(W, W')`` alone: the
compiled loops run on ``(U, W)`` with ``U`` at rest, and the map keeps the moving coordinates
(a held coordinate would add a multiplier 1 to every orbit).

The map is fixed-step RK4 (:func:`model.full.axisymmetric_kernels.rk4_motion`) with its exact
variational equations (:func:`model.full.axisymmetric_kernels.rk4_variational`).  The
fastest modes of the discretisation bound the step (the in-plane waves; with ``u`` held, the
highest transverse modes): :func:`steps_per_period` keeps ``|lambda|_max dt <= 2`` (RK4 is
stable to 2.6 in every direction of the left half-plane) with ``lambda`` the eigenvalues of the
damped linear motion about the pre-stretch, ``omega_max`` for a light damping and the fastest
decay for an overdamped stiffness-proportional one, for every ``Omega`` above half the lowest
transverse frequency.  RK4 damps
the fastest discrete modes there (the spectral discretisation's highest in-plane modes, above
100 times the lowest transverse frequency); the low in-plane modes an internal resonance can
involve are integrated with ``omega dt`` below 0.2.
With ``u`` free a deflection lowers ``omega_max`` (at ``delta = 1.1``, order 12, by 21 % at 0.3 m
and 36 % at 0.7 m; at ``delta = 2.0`` by 1.5 % at 0.7 m), so the pre-stretch's bound holds along
the orbits; with ``u`` held the fastest mode is transverse and stiffens (1.5 times at 0.3 m), so
the bound at ``Omega`` half the lowest frequency leaves large responses near the resonance a
margin of two and more, and a large response far below it needs ``steps`` given
(docs/model.md, "Forced motion").
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.linalg import block_diag, eigh

from model.damping import DampingLaw, Viscous
from model.damping_kernels import matrix_or_none
from model.forced import family_damping, periodic_peak
from model.modes import bessel_roots, mode_shape
from model.protocol import PARAMETERS, Companions, PerturbedFamily, sorted_multipliers, state_scale
from model.rk4 import stable

from .axisymmetric import AxisymmetricFull
from .axisymmetric_kernels import NO_PARAMETER, OMEGA, PRESSURE, rk4_motion, rk4_variational
from .families import FullFamily
from .family_kernels import family_monodromy
from .harmonic import HarmonicForced, HarmonicFull

#: RK4 step times the highest frequency of the discretisation, at most (stable below 2.8).
STABLE_STEP = 2.0


def linear_system(model: AxisymmetricFull) -> tuple[np.ndarray, np.ndarray]:
    """``(M, K0)``: the mass matrix and the tangent stiffness about the pre-stretch of the
    moving coordinates (``(U, W)``, or ``W`` with ``u`` held) in the scale of
    ``q'' = -M^-1 K0 q`` (s-2)."""
    return model.moving_mass, model.omega0_2 * model.restricted(model.hessian(np.zeros(model.dof)))


def damped_eigenvalues(mass, stiffness, rate: float, matrix) -> np.ndarray:
    """The eigenvalues (s-1) of the linear motion ``q'' = -M^-1 K q - (rate I + matrix) q'``
    (``mass``, ``stiffness`` in the scale of :func:`linear_system`; ``matrix`` (s-1) of the same
    size or empty for none): ``-zeta omega +- i omega sqrt(1 - zeta^2)`` per mode of a modal law."""
    n = mass.shape[0]
    damping = rate * np.eye(n) + (matrix if matrix.shape[0] else 0.0)
    return np.linalg.eigvals(np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(mass, stiffness), -damping]]))


def steps_per_period(model: AxisymmetricFull, base: int, damping: DampingLaw | None = None) -> int:
    """RK4 steps per forcing period: ``base``, raised to keep ``|lambda|_max dt <=``
    :data:`STABLE_STEP` down to ``Omega`` at half the lowest transverse frequency, with
    ``lambda`` the eigenvalues of the linear motion under the law ``damping``
    (:func:`damped_eigenvalues`; None: ``omega_max``, which bounds them unless the law
    overdamps the fastest modes).  A lower ``Omega`` needs more steps: the map returns NaN
    beyond RK4's stability limit."""
    system = mass, stiffness = linear_system(model)
    o = model.order  # the transverse block: the last o coordinates
    lowest = math.sqrt(eigh(stiffness[-o:, -o:], mass[-o:, -o:], eigvals_only=True)[0])
    fastest = model.highest_frequency()
    if damping is not None:
        fastest = max(fastest, float(np.abs(_law_terms(model, damping, system)[2]).max()))
    return max(int(base), math.ceil(2.0 * math.pi / (0.5 * lowest) * fastest / STABLE_STEP))


@dataclass(frozen=True)
class ForcedFull:
    """The stroboscopic map of the forced axisymmetric full model at one point ``(Omega, P0)``
    and damping law (:class:`model.protocol.StroboscopicMap`).

    Build with :meth:`build`.

    Parameters
    ----------
    model : AxisymmetricFull
    P0 : float
        Pressure amplitude (Pa).
    Omega : float
        Forcing frequency (rad s-1).
    damping : DampingLaw
    steps : int
        RK4 steps per forcing period.
    rate : float
        The law's mass-proportional part (s-1).
    matrix : (2 order, 2 order) ndarray
        The rest of the law (s-1) on the compiled loops' coordinates ``(U, W)`` (zero on a
        held ``U``), :data:`model.damping.NO_MATRIX` when none.
    probe : (dof,) ndarray
        ``w(probe_rho) = probe @ y[:dof]`` (the ``W`` block of the basis at ``0.5 Re``).
    omega_max : float
        The highest frequency of the discretisation (rad s-1).
    eigenvalues : (2 dof,) complex ndarray
        Of the damped linear motion about the pre-stretch (s-1, :func:`damped_eigenvalues`):
        where RK4's step takes one outside its stability region (:attr:`stable_step`) the map
        returns NaN states.
    section : (K, order) ndarray
        The ROM coordinates of ``w`` (:func:`modal_projection`) that :meth:`modal_section`
        reports; ``(0, order)`` for none.
    lift : (K, order) ndarray
        The ``W`` coefficients of the same mode shapes (:func:`mode_coefficients`), which
        :meth:`modal_lift` takes.
    probe_rho : float
        The radius (m) of :attr:`probe`.
    modes : tuple of (m, 0)
        The modes of :attr:`section` and :attr:`lift`.
    """

    model: AxisymmetricFull
    P0: float
    Omega: float
    damping: DampingLaw
    steps: int
    rate: float
    matrix: np.ndarray
    probe: np.ndarray
    omega_max: float
    eigenvalues: np.ndarray
    section: np.ndarray
    lift: np.ndarray
    probe_rho: float
    modes: tuple

    @classmethod
    def build(cls, model: AxisymmetricFull, P0: float, Omega: float, damping: DampingLaw | None = None,
              steps: int = 128, probe_rho: float | None = None, modes=()) -> ForcedFull:
        """The map of ``model`` under ``P0 cos(Omega t)`` with the law ``damping`` (None: no
        damping), ``steps`` RK4 steps per period (:func:`steps_per_period` gives enough), the
        amplitude measured at ``probe_rho`` (m; default ``0.5 Re``) and the ROM coordinates of
        the axisymmetric ``modes`` ``(m, 0)`` on the section (:meth:`modal_section`)."""
        m = model.membrane
        damping = Viscous() if damping is None else damping
        rate, matrix, eigenvalues = _law_terms(model, damping)
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise ValueError(f"steps = {steps!r} is invalid: must be an integer >= 1")
        rho = 0.5 * m.Re if probe_rho is None else float(probe_rho)
        phi, _ = model.state.basis.evaluate(np.eye(model.order), np.array([rho / m.Re]))
        probe = np.concatenate([np.zeros(model.moving.size - model.order), phi[:, 0]])
        modes = tuple((int(mm), int(n)) for mm, n in modes)
        return cls(model, float(P0), float(Omega), damping, int(steps), rate, matrix, probe,
                   model.highest_frequency(), eigenvalues, modal_projection(model, modes),
                   mode_coefficients(model, modes), rho, modes)

    def on_model(self, model: AxisymmetricFull) -> ForcedFull:
        """The same forcing, damping law, steps, probe radius and modes on ``model`` (another
        membrane's: curves in a membrane parameter rebuild the map)."""
        return ForcedFull.build(model, self.P0, self.Omega, self.damping, self.steps, self.probe_rho, self.modes)

    @property
    def dof(self) -> int:
        """Coordinates ``2 order`` (``U`` then ``W``, m), or ``order`` (``W``) with ``u``
        held; states ``(q, q')``."""
        return self.model.moving.size

    @property
    def period(self) -> float:
        """Forcing period ``2 pi / Omega`` (s)."""
        return 2.0 * math.pi / self.Omega

    @property
    def parameters(self) -> tuple[str, ...]:
        """``Omega``, ``P0`` and the damping law's constants."""
        return PARAMETERS + self.damping.parameters()

    def value(self, parameter: str) -> float:
        """The current value of ``parameter``."""
        if parameter in PARAMETERS:
            return float(getattr(self, parameter))
        if parameter not in self.parameters:
            raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(self.parameters)}")
        return float(getattr(self.damping, parameter))

    def varied(self, parameter: str, value: float) -> ForcedFull:
        """The same map (its steps per period kept) with ``parameter`` set to ``value``."""
        if parameter in PARAMETERS:
            return replace(self, **{parameter: float(value)})
        if parameter not in self.parameters:
            raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(self.parameters)}")
        law = self.damping.replaced(parameter, float(value))
        rate, matrix, eigenvalues = _law_terms(self.model, law)
        return replace(self, damping=law, rate=rate, matrix=matrix, eigenvalues=eigenvalues)

    def state_scale(self, Omega: float | None = None) -> np.ndarray:
        """:func:`model.protocol.state_scale` at this map's ``Omega`` or at ``Omega``."""
        return state_scale(self.dof, self.Omega if Omega is None else Omega)

    def _state(self, y) -> np.ndarray:
        # the state y in the compiled loops' coordinates, over Re
        y = np.asarray(y, dtype=float)
        if y.shape != (2 * self.dof,):
            raise ValueError(f"state shape {y.shape} is invalid: expected ({2 * self.dof},) = (q, q')")
        out = np.zeros(2 * self.model.dof)
        out[self.model.state_indices] = y / self.model.membrane.Re
        return out

    @property
    def fastest(self) -> float:
        """``|lambda|_max`` (s-1) of :attr:`eigenvalues`: ``omega_max``, or the fastest decay of
        an overdamped mode."""
        return float(np.abs(self.eigenvalues).max())

    @property
    def stable_step(self) -> bool:
        """Whether RK4's step keeps every mode of the damped linear motion about the
        pre-stretch within its stability region (:func:`model.rk4.stable`)."""
        return stable(self.eigenvalues, self.period / self.steps)

    def _motion(self, y, steps: int, every: int) -> np.ndarray:
        # the states (m) every `every` steps over `steps` steps from y (the compiled loops' state over Re)
        m = self.model
        record = np.empty((steps // every + 1, 2 * m.dof))
        if not self.stable_step:
            return np.full((record.shape[0], 2 * self.dof), np.nan)
        rk4_motion(*m.kernel_tables, m.inverse_masses, m.omega0_2, m.bias, self.rate, matrix_or_none(self.matrix),
                   m.load, self.P0, self.Omega, y, self.period / self.steps, steps, every, record)
        return record[:, m.state_indices] * m.membrane.Re

    def advance(self, y, periods: int = 1) -> np.ndarray:
        """``P^periods(y)``: the state after ``periods`` forcing periods from ``t = 0``."""
        return self._motion(self._state(y), periods * self.steps, periods * self.steps)[-1]

    def advance_batch(self, states, periods: int = 1) -> np.ndarray:
        """``P^periods`` applied to each row of ``states`` ``(N, 2 dof)``; a new array."""
        states = np.array(states, dtype=float, ndmin=2)
        if states.ndim != 2 or states.shape[1] != 2 * self.dof:
            raise ValueError(f"states shape {np.shape(states)} is invalid: expected (N, {2 * self.dof})")
        return np.array([self.advance(y, periods) for y in states]).reshape(states.shape)

    def _variational(self, y, parameter: int):
        m = self.model
        re = m.membrane.Re
        if not self.stable_step:
            n = 2 * self.dof
            return np.full(n, np.nan), np.full((n, n), np.nan), np.full(n, np.nan)
        keep = m.state_indices
        # the flow's derivative along the moving components only (a held U is not a column)
        yT, big = rk4_variational(*m.kernel_tables, m.inverse_masses, m.omega0_2, m.bias, self.rate,
                                  matrix_or_none(self.matrix), m.load, self.P0, self.Omega, parameter, self._state(y),
                                  m.state_tangents, self.period / self.steps, self.steps)
        big = big[keep]
        return yT[keep] * re, big[:, :-1], big[:, -1] * re

    def monodromy(self, y) -> tuple[np.ndarray, np.ndarray]:
        """``P(y)`` and ``dP/dy`` (the RK4 variational equations: exact for the discrete map)."""
        yT, phi, _ = self._variational(y, NO_PARAMETER)
        return yT, phi

    def monodromy_parameter(self, y, parameter: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``P(y)``, ``dP/dy`` and ``dP/d parameter`` (``"Omega"`` at fixed steps per period,
        or ``"P0"``), from one integration of the variational equations."""
        if parameter not in PARAMETERS:
            raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(PARAMETERS)}")
        return self._variational(y, OMEGA if parameter == "Omega" else PRESSURE)

    def family_monodromy(self, y, fam: FullFamily) -> np.ndarray:
        """The monodromy block ``(2 F M, 2 F M)`` of the asymmetric family ``fam``
        (:class:`model.full.families.FullFamily`) along the axisymmetric orbit from ``y``, at
        this map's RK4 steps (:func:`model.full.family_kernels.family_monodromy`), the
        perturbations damped by this map's law on the family's own linear problem (the viscous
        pressure: the map's rate).  NaN beyond RK4's stable step, for the orbit's or the
        family's damped linear motion (its highest frequency ``fam.omega_max`` grows with ``n``;
        a stiffness-proportional law can overdamp its fastest modes beyond it)."""
        if fam.model is not self.model:
            raise ValueError("fam is invalid here: a family of another model (build it on this map's model)")
        m = self.model
        dt = self.period / self.steps
        rate, matrix = family_damping(fam, m.membrane, self.damping)
        # a damping matrix can overdamp the family's fastest modes beyond omega_max (an
        # eigenvalue problem of the block's size: a few per cent of the block's integration)
        family_stable = (stable(damped_eigenvalues(*fam.linear_system(), rate, matrix), dt) if matrix.shape[0]
                         else dt * fam.omega_max < 2.8)
        if not (self.stable_step and family_stable):
            return np.full((fam.size, fam.size), np.nan)
        stages = np.empty((self.steps, 4, m.dof))
        rk4_motion(*m.kernel_tables, m.inverse_masses, m.omega0_2, m.bias, self.rate, matrix_or_none(self.matrix),
                   m.load, self.P0, self.Omega, self._state(y), dt, self.steps, self.steps, np.empty((2, 2 * m.dof)),
                   stages)
        law, phi, dphi, s, sw, _, r0, dr0 = m.kernel_tables
        return family_monodromy(law, phi, dphi, s, sw, r0, dr0, stages, fam.phi, fam.dphi, fam.variations,
                                fam.inverse_mass, m.omega0_2, rate, matrix_or_none(matrix), dt)

    def harmonic_map(self, harmonics, companions: bool = False) -> HarmonicForced:
        """The map of the full model on the circumferential ``harmonics`` (0 among them;
        :class:`model.full.harmonic.HarmonicFull`, with their sine ``companions`` when asked)
        at this map's forcing and RK4 steps, each harmonic damped by this map's law on its own
        linear problem (as :meth:`family_monodromy` damps a family: a companion as its cosine
        block, the torsion ``V_0`` as the family ``(0, "V")``), the amplitude measured at this
        map's probe radius on every harmonic.  ValueError where RK4's step is beyond the
        stability of the axisymmetric or a harmonic's damped linear motion (the map returns
        NaN states where a changed ``Omega`` takes it there)."""
        m = self.model
        if not self.stable_step:
            raise ValueError(f"steps = {self.steps} is invalid here: RK4's step leaves the stability region of the "
                             "axisymmetric damped linear motion")
        harmonic = HarmonicFull(m, harmonics, companions=companions)
        dt = self.period / self.steps
        blocks = [self.matrix if self.matrix.shape[0] else np.zeros((2 * m.order, 2 * m.order))]
        spectra = [self.eigenvalues]
        cosines = [(k, "UVW") for k in harmonic.harmonics[1:]]
        damped = {}  # (k, fields) -> (damping block, spectrum): a companion is damped as its cosine block
        for k, fields in cosines + ([(0, "V")] + cosines if companions else []):
            if (k, fields) not in damped:
                family = FullFamily.build(m, k, fields=fields)
                rate, matrix = family_damping(family, m.membrane, self.damping)
                spectrum = damped_eigenvalues(*family.linear_system(), rate, matrix)
                if not stable(spectrum, dt):
                    raise ValueError(f"steps = {self.steps} is invalid for the harmonic {k} ({fields}): RK4's step "
                                     "leaves the stability region of its damped linear motion")
                block = (matrix if matrix.shape[0] else 0.0) + (rate - self.rate) * np.eye(family.size // 2)
                damped[k, fields] = block, spectrum
            blocks.append(damped[k, fields][0])
            spectra.append(damped[k, fields][1])
        matrix = block_diag(*blocks)  # in the order of harmonic.blocks
        forced = HarmonicForced(harmonic, self.P0, self.Omega, self.steps, self.rate,
                                matrix if np.any(matrix) else np.zeros((0, 0)), eigenvalues=np.concatenate(spectra))
        return replace(forced, probe=forced.probe_vector(self.probe_rho))

    def perturbed_family(self, fam: FullFamily, harmonics: int = 2) -> PerturbedFamily:
        """What :func:`model.families.perturbation_growth` integrates to check ``fam``'s
        multipliers (the optional capability of :mod:`model.protocol`): :meth:`harmonic_map`
        on the harmonics ``0, n, ..., harmonics n`` (by default ``0, n, 2n``: the family's own
        harmonic and the one its square feeds; more to see whether a saturated state
        converges in them); the perturbation starts along the family's dominant Floquet mode (``start``
        None) and is measured in the energy norm of its linear problem about the pre-stretch,
        ``x^T K0 x + x'^T M x'`` (a start in every coefficient puts most of its energy in fast
        in-plane modes, more damped, that would dominate the fitted periods; the lowest linear
        mode shares its energy with pairs at the damping's modulus, perturbation_growth); the
        asymmetric displacement is ``w(probe_rho, 0) - w_0(probe_rho)``.  The family must carry
        ``U, V, W`` on all the model's radial functions (the harmonics' blocks).  ValueError
        for another family, ``harmonics`` below 2, or where RK4's step is beyond the stability
        of a harmonic's damped linear motion (:meth:`harmonic_map`)."""
        if isinstance(harmonics, bool) or not isinstance(harmonics, int) or harmonics < 2:
            raise ValueError(f"harmonics = {harmonics!r} is invalid: an integer, at least 2 (the harmonic 2 n that "
                             "the family's square feeds)")
        forced = self.harmonic_map(self._family_harmonics(fam, harmonics))
        n = forced.model.block(fam.n, "U").start, forced.model.block(fam.n, "W").stop
        mass, stiffness = fam.linear_system()
        probe = forced.probe_vector(self.probe_rho, forced.model.harmonics[1:])
        return PerturbedFamily(forced, replace(forced, probe=probe), tuple(range(*n)), probe, None,
                               block_diag(stiffness, mass))

    def companions(self, fam: FullFamily) -> Companions:
        """The map of :meth:`perturbed_family` with the sine companions of its harmonics
        (:meth:`harmonic_map`, ``companions``), where the standing waves of family ``fam``
        have their stability against turning and the rotating waves live (the optional
        capability of :mod:`model.protocol`); the family's coordinates are the blocks
        ``U, V, W`` of its harmonic."""
        forced = self.harmonic_map(self._family_harmonics(fam), companions=True)
        h = forced.model
        cosine, sine = (np.concatenate([np.arange(h.dof)[h.block(fam.n, f, parity)] for f in "UVW"])
                        for parity in ("even", "odd"))
        return Companions(forced, np.tile(h.odd, 2), h.rotation_generator(), h.rotation, cosine, sine)

    def _family_harmonics(self, fam: FullFamily, multiples: int = 2) -> tuple[int, ...]:
        if fam.model is not self.model:
            raise ValueError("fam is invalid here: a family of another model (build it on this map's model)")
        if fam.fields != "UVW" or fam.radial != self.model.order:
            raise ValueError(f"fam is invalid here: the nonlinear model needs the family in U, V, W on all "
                             f"{self.model.order} radial functions; it has {fam.fields} on {fam.radial}")
        return tuple(k * fam.n for k in range(multiples + 1))

    def modal_section(self, states) -> np.ndarray:
        """The ROM's modal coordinates and velocities ``(..., 2K)`` (m, m s-1) of the states
        ``(..., 2 dof)``: the least-squares fit of ``w`` and ``w_t`` by the mode shapes of
        :attr:`section` (the optional capability of :mod:`model.protocol`)."""
        states = np.asarray(states, float)
        o, dof = self.model.order, self.dof  # W: the last o coordinates
        return np.concatenate([states[..., dof - o:dof] @ self.section.T, states[..., 2 * dof - o:] @ self.section.T],
                              axis=-1)

    def modal_lift(self, coordinates) -> np.ndarray:
        """The states ``(..., 2 dof)`` of the ROM's modal coordinates and velocities
        ``(..., 2K)`` (m, m s-1) of :attr:`lift`'s modes: ``w = sum_k q_k psi_k`` and
        ``w_t = sum_k q_k' psi_k`` (each ``psi_k`` as its ``W`` coefficients), ``u = u_t = 0``
        (the optional capability of :mod:`model.protocol`; :meth:`modal_section` inverts it to
        the projection error of the mode shapes on the basis)."""
        coordinates = np.asarray(coordinates, float)
        K, o = self.lift.shape
        if coordinates.shape[-1] != 2 * K:
            raise ValueError(f"coordinates shape {coordinates.shape} is invalid: expected (..., {2 * K}) = (q, q')")
        dof = self.dof
        out = np.zeros(coordinates.shape[:-1] + (2 * dof,))
        out[..., dof - o:dof] = coordinates[..., :K] @ self.lift
        out[..., 2 * dof - o:] = coordinates[..., K:] @ self.lift
        return out

    def multipliers(self, y) -> np.ndarray:
        """Floquet multipliers at ``y`` (eigenvalues of :meth:`monodromy`), by decreasing modulus."""
        return sorted_multipliers(self.monodromy(y)[1])

    def amplitude(self, y, periods: int = 1) -> float:
        """``max_t |w(probe_rho, t)|`` (m) over ``periods`` forcing periods from ``y`` at ``t = 0``:
        the largest RK4 sample refined by a parabola (:func:`model.forced.periodic_peak`); NaN
        when the motion does not stay finite."""
        if periods < 1:
            raise ValueError(f"periods = {periods!r} is invalid: must be >= 1")
        record = self._motion(self._state(y), periods * self.steps, 1)
        w = record[:, :self.dof] @ self.probe
        return periodic_peak(w, periods * self.steps) if np.all(np.isfinite(w)) else math.nan



def _law_terms(model: AxisymmetricFull, law: DampingLaw, system=None) -> tuple[float, np.ndarray, np.ndarray]:
    """The damping law's mass-proportional rate (s-1), the rest of it (s-1) on the compiled
    loops' ``(U, W)`` (:data:`model.damping.NO_MATRIX` for none; a held ``U`` has no damping)
    and the eigenvalues of the damped linear motion (:func:`damped_eigenvalues`), from the
    linear system of the moving coordinates (``system``: :func:`linear_system`, when known)."""
    m = model.membrane
    system = linear_system(model) if system is None else system
    rate, matrix = law.terms(*system, m.Gamma * m.h)
    eigenvalues = damped_eigenvalues(*system, rate, matrix)
    if matrix.shape[0] and model.moving.size < model.dof:
        full = np.zeros((model.dof, model.dof))
        full[np.ix_(model.moving, model.moving)] = matrix
        matrix = full
    return float(rate), matrix, eigenvalues


def _mode_shapes(model: AxisymmetricFull, modes) -> np.ndarray:
    """The ROM's mode shapes ``psi_k`` (Eq. 26, :func:`model.modes.mode_shape`) of the
    axisymmetric ``modes`` ``(m, 0)`` at the basis' quadrature radii, ``(K, points)``."""
    if any(n != 0 for _, n in modes):
        raise ValueError(f"modes = {[list(m) for m in modes]} is invalid for the axisymmetric full model: "
                         "axisymmetric modes [m, 0] only")
    b, m = model.state.basis, model.membrane
    if not modes:
        return np.zeros((0, b.s.size))
    alpha = bessel_roots(0, m.delta_o, max(mm for mm, _ in modes))[[mm - 1 for mm, _ in modes]]
    return mode_shape(m.Re * b.s, alpha, 0, m.Re, m.delta_o)[0]


def modal_projection(model: AxisymmetricFull, modes) -> np.ndarray:
    """The matrix ``(K, order)`` from the ``W`` coefficients (m) of ``w`` to the coordinates
    ``q_k`` (m) of the ROM's mode shapes ``psi_k`` of the axisymmetric ``modes`` ``(m, 0)``
    (:func:`_mode_shapes`) that fit ``w`` best in ``int (w - sum q_k psi_k)^2 rho drho``:
    ``G^-1 B`` with ``G_kl = int psi_k psi_l s ds``, ``B_kj = int psi_k phi_j s ds``."""
    psi, b = _mode_shapes(model, modes), model.state.basis
    sw = b.s * b.weights
    return np.linalg.solve((psi * sw) @ psi.T, (psi * sw) @ b.phi.T)


def mode_coefficients(model: AxisymmetricFull, modes) -> np.ndarray:
    """The ``W`` coefficients ``(K, order)`` of the ROM's mode shapes ``psi_k`` of the
    axisymmetric ``modes`` (:func:`_mode_shapes`): the basis' best fit of each in
    ``int (psi_k - sum_j c_kj phi_j)^2 rho drho`` (each ``psi_k`` vanishes at both edges,
    as the basis functions do, so the fit converges spectrally with the order)."""
    psi, b = _mode_shapes(model, modes), model.state.basis
    return (model.inverse_mass @ ((b.phi * (b.s * b.weights)) @ psi.T)).T
