"""What the algorithms need of a model at one parameter point: the map protocol, and the
free-vibration protocol of the backbones.

Shooting (:mod:`model.shooting`), continuation (:mod:`model.continuation`), two-parameter
curves (:mod:`model.codim2`), stepped responses (:mod:`model.response`) and basins
(:mod:`model.basins`) take any object with the members of :class:`StroboscopicMap`: the
stroboscopic (Poincare) map of a periodically forced, second-order model whose state is
``y = (q, q')`` with ``dof`` coordinates ``q``.  :class:`model.forced.ForcedMap` (the ROM)
is one implementation; ``tests/escape_oscillator.py`` (Thompson's escape oscillator) is
another, registered for job files by ``tests/escape_model.py`` (docs/architecture.md).

Optional capabilities, asked for with ``getattr(fmap, name, None)``; an algorithm falls
back without them:

``family_monodromy(y, family)``
    The monodromy block of an asymmetric symmetry family along an axisymmetric orbit
    (stability per family: continuation ``families``, codim-2 curves of family points).
    Without it, no family option can be used.
``kernel_arguments``
    :class:`KernelArguments`: the arrays the package's compiled ROM loops take (the
    basins' lock-step slots, the compiled settling loop of stepped responses, the
    compiled one-mode Newton search).  Without it these algorithms advance states with
    ``advance_batch`` / ``advance`` from Python, one period at a time.
``modal_section(states)``
    The ROM's modal coordinates and velocities ``(..., 2K)`` of states ``(..., 2 dof)`` for
    a map whose state is not made of them (the full model: the fit of ``w`` by the mode
    shapes); the results' ``modal_coordinate`` axes.  Without it the state is its own
    modal section (:func:`modal_section`).
``modal_lift(coordinates)``
    The state ``(..., 2 dof)`` of modal coordinates and velocities ``(..., 2K)`` (the full
    model: ``w`` the sum of the mode shapes fitted on its basis, ``u`` at rest), of which
    ``modal_section`` gives the coordinates back to the fit error; the basins' lattices of
    initial conditions.  Without it the modal coordinates are
    the state (:func:`modal_lift`).
``perturbed_family(family)``
    :class:`PerturbedFamily`: the nonlinear model in which a family's perturbations grow
    from an axisymmetric orbit, to check the family's multipliers by time integration
    (continuation ``family_check``, :func:`model.families.perturbation_growth`).  A model
    whose choice of that nonlinear model is open takes it as keywords (the full model's
    ``harmonics``).
``companions(family)``
    :class:`Companions`: the model of ``perturbed_family`` with the family's sine
    companions (the group O(2)), where a standing wave of the family has its stability
    against turning (branch switching's ``switched_stable_o2``,
    :func:`model.waves.standing_wave_stability`) and the rotating waves live
    (:func:`model.waves.continue_rotating_waves`).
``lean(sample, rtol)`` with ``acceleration_mismatch(reference, states)``
    A cheaper map that is the same to ``rtol`` on the states ``sample()`` (the ROM's
    fewest radial quadrature points), and how far it is from the original on other
    states (the basins' fast method checks it again on the attractors it finds).  Without
    it the basins use the map as it is.

The backbone methods (:mod:`model.backbone`) take any object with the members of
:class:`FreeVibration`: the free motion of the same kind of model (:class:`model.free.FreeRom`
for the ROM).  Optional capability: ``frequency_bound()``, an upper bound of the backbone's
frequency (the ROM's Eq. 29; NaN without it).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple, Protocol, runtime_checkable

import numpy as np

#: The forcing parameters every map can be varied in and differentiated by
#: (``monodromy_parameter``): the continuation and stepped-sweep parameters.
PARAMETERS = ("Omega", "P0")


@runtime_checkable
class StroboscopicMap(Protocol):
    """The stroboscopic map ``P`` of a forced model at one parameter point.

    Attributes
    ----------
    dof : int
        Coordinates ``q``; the state ``y = (q, q')`` has ``2 dof`` components.
    period : float
        The forcing period ``T = 2 pi / Omega`` (s): ``P`` advances a state by ``T`` from
        ``t = 0``.
    parameters : tuple of str
        What :meth:`varied` and :meth:`value` take: ``"Omega"``, ``"P0"`` and the damping
        law's constants.
    """

    dof: int

    @property
    def period(self) -> float: ...

    @property
    def parameters(self) -> tuple[str, ...]: ...

    def value(self, parameter: str) -> float:
        """The current value of ``parameter``."""

    def varied(self, parameter: str, value: float) -> StroboscopicMap:
        """The same map with ``parameter`` set to ``value``."""

    def state_scale(self, Omega: float | None = None) -> np.ndarray:
        """Weights ``S`` (``(2 dof,)``) of the norm ``|S y|`` of Newton residuals and
        convergence tests, at this map's frequency or at ``Omega``."""

    def advance(self, y, periods: int = 1) -> np.ndarray:
        """``P^periods(y)``, a new array."""

    def advance_batch(self, states, periods: int = 1) -> np.ndarray:
        """``P^periods`` of each row of ``states`` ``(N, 2 dof)``, a new array."""

    def monodromy(self, y) -> tuple[np.ndarray, np.ndarray]:
        """``P(y)`` and ``dP/dy``."""

    def monodromy_parameter(self, y, parameter: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``P(y)``, ``dP/dy`` and ``dP/d parameter`` for ``"Omega"`` (at fixed steps per
        period) or ``"P0"``."""

    def multipliers(self, y) -> np.ndarray:
        """Floquet multipliers at ``y``, by decreasing modulus."""

    def amplitude(self, y, periods: int = 1) -> float:
        """The reported amplitude (m) of the orbit of ``periods`` periods from ``y``."""


@runtime_checkable
class FreeVibration(Protocol):
    """The free (unforced) motion of a second-order model with state ``y = (q, q')``.

    Attributes
    ----------
    dof : int
        Coordinates ``q``; states have ``2 dof`` components.
    probe : (dof,) ndarray
        The measured displacement is ``w = probe @ q`` (m): the amplitude of a backbone is
        the largest ``|w|`` over an orbit.
    length : float
        A length scale of the model (m), for absolute tolerances.

    Optional capabilities (read with ``getattr``): ``odd``, a ``(dof,)`` bool mask of the
    coordinates that change sign under the orbits' half-period symmetry (all of them when
    absent: ``q(t + T/2) = -q(t)``); ``acceleration(q, v)``, ``q''`` of the undamped motion,
    needed when some coordinates are not odd; ``extent(q0, period)``, the largest
    ``(|u|, |v|, |w|)`` (m) over the orbit from rest at ``q0`` and the membrane (a model
    with in-plane motion); ``frequency_bound()``, an upper bound of the backbone's frequency.
    """

    dof: int
    probe: np.ndarray
    length: float

    def linear_frequencies(self) -> tuple[np.ndarray, np.ndarray]:
        """Small-amplitude frequencies (rad s-1, ascending) and their modal vectors
        (columns, ``(dof, dof)``)."""

    def flow(self, y0, duration: float, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """State after ``duration`` (s) of the undamped motion from ``y0`` in ``steps``
        time steps, and its derivative in ``y0`` (exact for the discrete scheme)."""

    def decay_rate(self, c: float) -> float:
        """Decay rate (s-1) of the amplitude under the viscous damping ``c`` (N s m-3)."""

    def decay_extrema(self, y0, t_end: float, max_count: int, c: float, rtol: float, atol: float):
        """Up to ``max_count`` successive extrema of ``w`` of free decays under the viscous
        damping ``c`` from the rows of ``y0`` (``(N, 2 dof)``) until ``t_end`` (s): a record
        with ``times`` ``(N, max_count)``, ``states`` ``(N, max_count, 2 dof)`` and
        ``count`` ``(N,)``."""


class PerturbedFamily(NamedTuple):
    """What :func:`model.families.perturbation_growth` integrates to check a family's
    Floquet multipliers (the optional capability ``perturbed_family`` of the maps)."""

    #: the map of the nonlinear model holding the axisymmetric coordinates first (in the
    #: order of the axisymmetric map's state) and the family's among the rest
    fmap: Any
    #: the same map whose ``amplitude`` measures the asymmetric displacement alone
    #: (``max_t |probe @ q(t)|``)
    asymmetric_map: Any
    #: the indices of the family's coordinates in it
    asymmetric: tuple[int, ...]
    #: ``(dof,)``: the asymmetric displacement ``w_asym(rho_probe, 0) = probe @ q`` (m)
    probe: np.ndarray
    #: ``(len(asymmetric),)``: the shape of the initial perturbation (largest entry 1); None:
    #: along the family's dominant Floquet mode at the orbit (:func:`model.families.floquet_start`)
    start: np.ndarray | None
    #: ``(2 A, 2 A)`` for ``A = len(asymmetric)``: the quadratic form whose root measures the
    #: perturbation ``(x, x')`` (None: the Euclidean norm)
    metric: np.ndarray | None


class Companions(NamedTuple):
    """A model with a family's sine companions, symmetric under every rotation and the
    reflection (O(2); the optional capability ``companions`` of the maps).  Its coordinates
    begin with those of the family's mixed model (:attr:`PerturbedFamily.fmap`), which begin
    with the axisymmetric map's, in the same order: a state of either is one of this model
    with the other coordinates zero (:func:`model.families.embedded`); the standing waves are
    the states whose companion coordinates vanish."""

    #: the map of the model with the companions
    fmap: Any
    #: ``(2 dof,)`` bool: the companions' coordinates and velocities (odd under the reflection)
    odd: np.ndarray
    #: ``(2 dof, 2 dof)`` (rad-1): the generator of the rotations acting on a state
    generator: np.ndarray
    #: ``rotation(phi)`` ``(2 dof, 2 dof)``: the state of the pattern turned by ``phi`` (rad)
    rotation: Callable[[float], np.ndarray]
    #: the indices in ``q`` of the family's coordinates (in the order of its block) and of
    #: their companions: each (cosine, companion) pair turns by ``n phi``
    cosine: np.ndarray
    sine: np.ndarray


class KernelArguments(NamedTuple):
    """The optional ``kernel_arguments`` capability of a map: what the compiled ROM loops take.

    Attributes
    ----------
    tables : model.rom.RomTables
    forcing : model.rom.Forcing
    steps : int
        RK4 steps per forcing period.
    """

    tables: Any
    forcing: Any
    steps: int


def kernel_arguments(fmap) -> KernelArguments | None:
    """``fmap.kernel_arguments``, or None for a map without the capability."""
    return getattr(fmap, "kernel_arguments", None)


def modal_section(fmap, states) -> np.ndarray:
    """The modal coordinates and velocities ``(..., 2K)`` of ``states``: ``fmap.modal_section``,
    or the states themselves for a map without the capability."""
    section = getattr(fmap, "modal_section", None)
    return np.asarray(states) if section is None else section(states)


def modal_lift(fmap, coordinates) -> np.ndarray:
    """The states ``(..., 2 dof)`` of the modal coordinates and velocities ``coordinates``:
    ``fmap.modal_lift``, or the coordinates themselves for a map without the capability."""
    lift = getattr(fmap, "modal_lift", None)
    return np.asarray(coordinates) if lift is None else lift(coordinates)


def state_scale(dof: int, omega: float) -> np.ndarray:
    """Diagonal of ``S``: 1 for the K displacements, ``1/Omega`` (s) for the K velocities.

    Displacements and velocities weigh alike in the norm ``|S y|`` of Newton residuals
    and convergence tests.
    """
    return np.concatenate([np.ones(dof), np.full(dof, 1.0 / omega)])


def sorted_multipliers(phi: np.ndarray) -> np.ndarray:
    """Eigenvalues of ``phi`` sorted by decreasing modulus, then by decreasing imaginary
    and real part (a conjugate pair: positive imaginary part first); all NaN when ``phi``
    is not finite (a diverged integration: the caller reports it, nothing raises)."""
    if not np.all(np.isfinite(phi)):
        return np.full(phi.shape[0], np.nan + 0j)
    mu = _eigenvalues_2x2(*phi.ravel().tolist()) if phi.shape == (2, 2) else None
    if mu is None:
        mu = np.linalg.eigvals(phi).astype(complex)
    return mu[np.lexsort((-mu.real, -mu.imag, -np.abs(mu)))]


def _eigenvalues_2x2(a: float, b: float, c: float, d: float) -> np.ndarray | None:
    # Eigenvalues of [[a, b], [c, d]] (finite) in closed form, or None when the formula
    # overflows (LAPACK then decides): a one-mode branch asks at every point, and numpy's
    # eigvals costs 10 us a call there against 1 us.  The discriminant is formed as
    # ((a - d)/2)^2 + bc, free of the cancellation of tr^2/4 - det; of two real roots the
    # larger in modulus comes from the sum without cancellation, the other from the
    # determinant.
    half = 0.5 * (a + d)
    e = 0.5 * (a - d)
    disc = e * e + b * c
    if not (math.isfinite(half) and math.isfinite(disc)):
        return None
    if disc < 0.0:
        root = math.sqrt(-disc)
        return np.array([complex(half, root), complex(half, -root)])
    big = half + math.copysign(math.sqrt(disc), half)
    small = (a * d - b * c) / big if big != 0.0 else 0.0
    return np.array([big, small], dtype=complex) if math.isfinite(big) and math.isfinite(small) else None
