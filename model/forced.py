"""The stroboscopic (Poincare) map of the forced ROM at one parameter point.

A :class:`ForcedMap` owns what every forced analysis needs: the ROM, the forcing
(damping rate ``c/(Gamma h)``, pressure ``P0``, frequency ``Omega``) and the number of
RK4 steps per forcing period ``T = 2 pi / Omega``.  It offers the map ``P`` itself (one
state or a batch, any number of periods), its derivative (the monodromy matrix, exact for
the discrete RK4 map), the Floquet multipliers and the one amplitude estimator of the
project.  Shooting, continuation, stepped sweeps and basins take a ``ForcedMap``; the
numba kernels underneath take the :class:`model.rom.RomTables` and the
:class:`model.rom.Forcing` tuple.

Amplitude (docs/model.md, "Amplitude"): ``max_t |w(rho_probe, 0, t)|`` over the periods of
an orbit, from the RK4 samples, with the largest sample refined by the vertex of the
parabola through it and its neighbours (error ~ (2 pi / steps)^4 relative, ~1e-7 at 128
steps per period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial

import numba as nb
import numpy as np

from .damping import NO_MATRIX, DampingLaw, Viscous
from .damping_kernels import matrix_or_none
from .families import Family, family_monodromy
from .integrate import OMEGA, PRESSURE, monodromy, monodromy_parameter, rk4_one_mode, rk4_steps
from .params import Loading
from .protocol import PARAMETERS, Companions, KernelArguments, PerturbedFamily, sorted_multipliers, state_scale
from .rom import Forcing, Rom, acceleration_mismatch, build_rom, lean_radial_points, linear_frequencies, linear_system
from .waves import o2_rom, rotation, rotation_generator

#: RK4 steps per forcing period of shooting, continuation and stepped sweeps.  At
#: delta = 1.1, Omega = 33.5, c = 0.05 the fold values in P0 change by 2e-6 (relative) from
#: 128 to 256 steps and by 3e-5 from 64 to 128 steps (tests/test_shooting.py).
DEFAULT_STEPS = 128


def damping_terms(rom: Rom, damping: DampingLaw) -> tuple[float, np.ndarray]:
    """``(rate, matrix)`` of the law ``damping`` on ``rom`` (:meth:`model.damping.DampingLaw.terms`
    on :func:`model.rom.linear_system`; per-mode constants in the order of the mode set)."""
    m = rom.membrane
    if isinstance(damping, Viscous):  # a scalar rate: no linear system (nor its kernel's compilation)
        return damping.terms(np.eye(1), np.eye(1), m.Gamma * m.h)
    return damping.terms(*linear_system(rom), m.Gamma * m.h, order=np.arange(rom.dof))


#: The family damping terms already built, by (family, membrane, law): a continuation
#: asks for them at every point of its branch.  Bounded; each entry keeps its family alive,
#: so that the family's id in the key is not reused.
_FAMILY_DAMPING: dict = {}
_FAMILY_DAMPING_SIZE = 64


def family_damping(fam, membrane, damping: DampingLaw) -> tuple[float, np.ndarray]:
    """``(rate, matrix)`` of the law ``damping`` on the perturbations of family ``fam`` (the
    ROM's :class:`model.families.Family` or the full model's
    :class:`model.full.families.FullFamily`: its ``linear_system(membrane)``; per-mode
    constants by increasing frequency).  Built once per family, membrane and law."""
    if isinstance(damping, Viscous):
        return damping.terms(np.eye(1), np.eye(1), membrane.Gamma * membrane.h)
    if isinstance(getattr(damping, "zeta", None), tuple):
        raise ValueError(f"zeta = {list(damping.zeta)} is invalid for a family: one ratio for every mode (a list "
                         "follows the ROM's mode set, of which the family blocks are not part)")
    key = (id(fam), membrane, damping)
    if key not in _FAMILY_DAMPING:
        if len(_FAMILY_DAMPING) >= _FAMILY_DAMPING_SIZE:
            _FAMILY_DAMPING.pop(next(iter(_FAMILY_DAMPING)))
        _FAMILY_DAMPING[key] = (fam, damping.terms(*fam.linear_system(membrane), membrane.Gamma * membrane.h))
    return _FAMILY_DAMPING[key][1]


def mixed_rom(rom: Rom, family: Family) -> Rom:
    """The ROM of ``rom``'s axisymmetric modes followed by the family's cosine modes, on
    ``rom``'s pre-stretch."""
    return build_rom(rom.prestretch, list(rom.modes) + list(family.modes), probe_rho=rom.probe_rho)


def asymmetric_part(rom: Rom, axisymmetric: int) -> Rom:
    """``rom`` with the probe of its first ``axisymmetric`` modes zeroed, so that
    :meth:`ForcedMap.amplitude` measures ``max_t |w_asym(rho_probe, 0, t)|``."""
    probe = rom.tables.probe.copy()
    probe[:axisymmetric] = 0.0
    return replace(rom, tables=rom.tables._replace(probe=probe))


def steps_per_period(rom: Rom, base: int) -> int:
    """RK4 steps per forcing period that integrate the fastest mode of ``rom`` as
    accurately as ``base`` steps integrate the slowest.

    ``base`` is a default validated for one mode (:data:`DEFAULT_STEPS`,
    :data:`model.basins.DEFAULT_STEPS`).  With ``n`` steps of ``h = T / n`` per period, a
    mode of frequency ``omega`` gathers an RK4 error of ``n (h omega)^5 ~ omega^5 / n^4``
    per period, so equal accuracy takes ``n = base (omega_max / omega_min)^(5/4)``
    (linear frequencies of the set, :func:`model.rom.linear_frequencies`), rounded up to a
    multiple of 8.  One mode: ``base``; modes (1..3, 0) at delta = 1.1, delta_o = 0.2
    (frequency ratio 3.07): 64 -> 264 and 128 -> 528.

    Parameters
    ----------
    rom : Rom
    base : int
        Steps per period for the slowest mode.

    Returns
    -------
    int
    """
    if rom.dof == 1:  # (without the Jacobian's compilation, 1 s of a cold one-mode run)
        return int(base)
    omega = linear_frequencies(rom)[0]
    return max(int(base), 8 * math.ceil(base * float(omega[-1] / omega[0]) ** 1.25 / 8 - 1e-9))


@dataclass(frozen=True)
class ForcedMap:
    """The stroboscopic map of a forced ROM at one point ``(Omega, P0)`` and damping law:
    the ROM's implementation of :class:`model.protocol.StroboscopicMap`, with the
    capabilities ``family_monodromy``, ``kernel_arguments`` and ``lean``.

    Build with :meth:`from_loading` or :meth:`build`.  The forcing values are not validated
    here (a continuation corrector may step slightly outside the physical range);
    :class:`Loading` and the laws of :mod:`model.damping` validate user input.

    Parameters
    ----------
    rom : Rom
        The reduced-order model.
    forcing : Forcing
        ``(damping_rate (s-1), P0 (Pa), Omega (rad s-1), damping_matrix (s-1))``.
    steps : int
        RK4 steps per forcing period.
    damping : DampingLaw, optional
        The law ``forcing``'s damping terms come from (:meth:`build`); None: the rate of
        ``forcing`` as given, a viscous law (its matrix must be empty).
    """

    rom: Rom
    forcing: Forcing
    steps: int = DEFAULT_STEPS
    damping: DampingLaw | None = None

    def __post_init__(self):
        if isinstance(self.steps, bool) or not isinstance(self.steps, (int, np.integer)) or self.steps < 1:
            raise ValueError(f"steps = {self.steps!r} is invalid: must be an integer >= 1")
        if self.forcing.damping_matrix.shape not in ((0, 0), (self.rom.dof, self.rom.dof)):
            raise ValueError(f"damping_matrix shape {self.forcing.damping_matrix.shape} is invalid: expected "
                             f"({self.rom.dof}, {self.rom.dof}) or (0, 0)")

    @classmethod
    def build(cls, rom: Rom, P0: float, Omega: float, damping: DampingLaw, steps: int = DEFAULT_STEPS) -> ForcedMap:
        """The map of ``rom`` under the pressure ``P0 cos(Omega t)`` (Pa, rad s-1) with the
        damping law ``damping`` (:mod:`model.damping`)."""
        rate, matrix = damping_terms(rom, damping)
        return cls(rom, Forcing(rate, float(P0), float(Omega), matrix), int(steps), damping)

    @classmethod
    def from_loading(cls, rom: Rom, loading: Loading, steps: int = DEFAULT_STEPS,
                     damping: DampingLaw | None = None) -> ForcedMap:
        """The map of ``rom`` under ``loading``: its viscous ``c`` (the rate ``c/(Gamma h)``),
        or the law ``damping`` (then ``loading.c`` must be 0 or ``damping`` that viscous law)."""
        if damping is None:
            damping = Viscous(loading.c)
        elif loading.c != 0.0 and damping != Viscous(loading.c):
            raise ValueError(f"c = {loading.c!r} is invalid with the {damping.name} damping law: the law "
                             "carries the damping (c must be 0)")
        return cls.build(rom, loading.P0, loading.Omega, damping, steps)

    def with_rom(self, rom: Rom) -> ForcedMap:
        """The same forcing, steps and damping law on another ROM (its damping terms rebuilt)."""
        if self.damping is None:
            return ForcedMap(rom, self.forcing, self.steps)
        return ForcedMap.build(rom, self.forcing.P0, self.forcing.Omega, self.damping, self.steps)

    def perturbed_family(self, family: Family) -> PerturbedFamily:
        """What :func:`model.families.perturbation_growth` integrates to check ``family``'s
        multipliers (the optional capability of :mod:`model.protocol`): the map of the mixed
        ROM of this ROM's axisymmetric modes followed by the family's cosine modes
        (:func:`mixed_rom`), each of the family's modal coordinates perturbed alike and
        measured by the Euclidean norm."""
        mixed = self.with_rom(mixed_rom(self.rom, family))
        asymmetric = replace(mixed, rom=asymmetric_part(mixed.rom, self.rom.dof))  # only the probe differs
        return PerturbedFamily(mixed, asymmetric, tuple(range(self.rom.dof, mixed.dof)), asymmetric.rom.tables.probe,
                               np.ones(len(family.modes)), None)

    def companions(self, family: Family) -> Companions:
        """The O(2) ROM (:func:`model.waves.o2_rom`: this ROM's axisymmetric modes, the
        family's cosine modes and their sine companions), where the standing waves of
        :meth:`perturbed_family`'s mixed ROM have their stability against turning and the
        rotating waves live (the optional capability of :mod:`model.protocol`)."""
        o2 = self.with_rom(o2_rom(self.rom, family))
        modes = o2.rom.modes
        Ka, M = self.rom.dof, len(family.radial)
        return Companions(o2, np.array([n < 0 for _, n in modes] * 2), rotation_generator(modes),
                          partial(rotation, modes), np.arange(Ka, Ka + M), np.arange(Ka + M, Ka + 2 * M))

    @property
    def radial_points(self) -> int:
        """Radial Gauss-Legendre points of the ROM's quadrature."""
        return self.rom.radial_points

    def lean(self, sample, rtol: float) -> ForcedMap:
        """The map on the fewest radial quadrature points that leave its accelerations
        unchanged to ``rtol`` on the states ``sample()`` (``(S, 2K)``, called only when
        the ROM integrates by quadrature: a one-mode ROM runs its force table), or this map
        (:func:`model.rom.lean_radial_points`; the optional ``lean`` capability of
        :mod:`model.protocol`)."""
        if self.rom.tables.table_max > 0.0:
            return self
        points = lean_radial_points(self.rom, sample(), rtol)
        if points >= self.rom.radial_points:
            return self
        return self.with_rom(build_rom(self.rom.prestretch, self.rom.modes, radial_points=points))

    def acceleration_mismatch(self, reference: ForcedMap, states) -> float:
        """Largest relative difference of this map's undamped accelerations from those of
        ``reference`` (the same modes) on ``states`` (:func:`model.rom.acceleration_mismatch`)."""
        return acceleration_mismatch(self.rom, reference.rom, states)

    @property
    def parameters(self) -> tuple[str, ...]:
        """What :meth:`varied` takes: ``Omega``, ``P0`` and the damping law's constants."""
        return PARAMETERS + (self.damping or Viscous()).parameters()

    @property
    def period(self) -> float:
        """Forcing period ``2 pi / Omega`` (s)."""
        return 2.0 * np.pi / self.forcing.Omega

    @property
    def dof(self) -> int:
        """Number of modal coordinates K (the state has 2K components)."""
        return self.rom.dof

    def varied(self, parameter: str, value: float) -> ForcedMap:
        """The same map with ``parameter`` set to ``value``: ``"Omega"`` (rad s-1), ``"P0"``
        (Pa) or a constant of the damping law (:attr:`parameters`; ``"c"`` (N s m-3) for
        the viscous law)."""
        if parameter == "Omega":
            forcing = self.forcing._replace(Omega=float(value))
        elif parameter == "P0":
            forcing = self.forcing._replace(P0=float(value))
        elif parameter == "c" and (self.damping is None or isinstance(self.damping, Viscous)):
            # a scalar rate: no terms to build (a fold curve in c varies it at every corrector step)
            forcing = self.forcing._replace(damping_rate=self.rom.membrane.damping_rate(float(value)))
            law = None if self.damping is None else self.damping.replaced("c", float(value))
            return ForcedMap(self.rom, forcing, self.steps, law)
        elif parameter in self.parameters:
            return ForcedMap.build(self.rom, self.forcing.P0, self.forcing.Omega,
                                   (self.damping or Viscous()).replaced(parameter, float(value)), self.steps)
        else:
            raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(self.parameters)}")
        return ForcedMap(self.rom, forcing, self.steps, self.damping)  # dataclasses.replace costs 2.7x this per call

    def family_monodromy(self, y, fam: Family) -> np.ndarray:
        """The monodromy block ``(2M, 2M)`` of family ``fam`` along the axisymmetric orbit
        from ``y`` (:func:`model.families.family_monodromy`), the perturbations damped by
        this map's law on the family's own linear problem."""
        rate, matrix = self.family_damping_terms(fam)
        return family_monodromy(np.asarray(y, dtype=float), 0.0, self.period, self.steps, self.rom.tables,
                                self.forcing, fam.tables, rate, matrix_or_none(matrix))

    def family_damping_terms(self, fam: Family) -> tuple[float, np.ndarray]:
        """``(rate, matrix)`` (s-1) damping the perturbations of family ``fam``: this map's own
        rate for the viscous law (mass-proportional), else :func:`family_damping`; the matrix
        is ``(0, 0)`` when there is none."""
        if self.damping is None or isinstance(self.damping, Viscous):
            return self.forcing.damping_rate, NO_MATRIX
        return family_damping(fam, self.rom.membrane, self.damping)

    def value(self, parameter: str) -> float:
        """The current value of ``parameter`` (:attr:`parameters`)."""
        if parameter in PARAMETERS:
            return float(getattr(self.forcing, parameter))
        if parameter not in self.parameters:
            raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(self.parameters)}")
        if self.damping is None:  # a bare rate: the viscous c it stands for
            return self.forcing.damping_rate * self.rom.membrane.Gamma * self.rom.membrane.h
        return float(getattr(self.damping, parameter))

    def state_scale(self, Omega: float | None = None) -> np.ndarray:
        """:func:`state_scale` at this map's ``Omega`` or at ``Omega``."""
        return state_scale(self.dof, self.forcing.Omega if Omega is None else Omega)

    @property
    def kernel_arguments(self) -> KernelArguments:
        """The ROM's tables, forcing and steps for the compiled loops of the algorithms
        (the optional capability of :mod:`model.protocol`)."""
        return KernelArguments(self.rom.tables, self.forcing, self.steps)

    def _state(self, y) -> np.ndarray:
        y = np.array(y, dtype=float)
        if y.shape != (2 * self.dof,):
            raise ValueError(f"state shape {y.shape} is invalid: expected ({2 * self.dof},) = (q, q')")
        return y

    def advance(self, y, periods: int = 1) -> np.ndarray:
        """``P^periods(y)``: a new state (m, m s-1) after ``periods`` forcing periods from ``t = 0``."""
        y = self._state(y)
        work = np.empty((6, y.size))
        h = self.period / self.steps
        for _ in range(periods):
            rk4_steps(y, 0.0, h, self.steps, self.rom.tables, self.forcing, work)
        return y

    def advance_batch(self, states, periods: int = 1) -> np.ndarray:
        """``P^periods`` applied to each row of ``states`` ``(N, 2K)``; returns a new array."""
        out = np.array(states, dtype=float, ndmin=2)
        if out.ndim != 2 or out.shape[1] != 2 * self.dof:
            raise ValueError(f"states shape {np.shape(states)} is invalid: expected (N, {2 * self.dof})")
        _advance_batch(out, periods, self.period / self.steps, self.steps, self.rom.tables, self.forcing)
        return out

    def monodromy(self, y) -> tuple[np.ndarray, np.ndarray]:
        """``P(y)`` and the monodromy matrix ``Phi = dP/dy`` (RK4 variational equations).

        Returns
        -------
        yT : (2K,) array
        phi : (2K, 2K) array
        """
        return monodromy(self._state(y), 0.0, self.period, self.steps, self.rom.tables, self.forcing)

    def monodromy_parameter(self, y, parameter: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``P(y)``, ``Phi = dP/dy`` and ``dP/d parameter`` (``"Omega"``: at fixed steps per
        period, the period following ``Omega``; ``"P0"``), from one integration of the RK4
        variational equations: exact derivatives of the discrete map.

        Returns
        -------
        yT : (2K,) array
        phi : (2K, 2K) array
        dparam : (2K,) array
        """
        if parameter not in PARAMETERS:
            raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(PARAMETERS)}")
        return monodromy_parameter(self._state(y), 0.0, self.period, self.steps, self.rom.tables, self.forcing,
                                   OMEGA if parameter == "Omega" else PRESSURE)

    def multipliers(self, y) -> np.ndarray:
        """Floquet multipliers at ``y`` (eigenvalues of :meth:`monodromy`), by decreasing modulus."""
        return sorted_multipliers(self.monodromy(y)[1])

    def amplitude(self, y, periods: int = 1) -> float:
        """``max_t |w(rho_probe, 0, t)|`` (m) over ``periods`` forcing periods from ``y`` at ``t = 0``.

        The samples are treated as periodic (the estimator is meant for periodic orbits of
        ``periods`` forcing periods); the largest one is refined by a parabola.  NaN when
        the trajectory does not stay finite.
        """
        if periods < 1:
            raise ValueError(f"periods = {periods!r} is invalid: must be >= 1")
        y = self._state(y)
        tab = self.rom.tables
        samples = periods * self.steps
        h = self.period / self.steps
        w = np.empty(samples + 1)
        done = _table_samples(y, samples, h, tab, self.forcing, w) if tab.table_max > 0.0 else 0
        if done < samples:
            _quadrature_samples(y, done, samples, h, tab, self.forcing, w)
        else:
            w[samples] = tab.probe @ y[:self.dof]
        return periodic_peak(w, samples)


@nb.njit(cache=True)
def _advance_batch(states, periods, h, steps, tab, forcing):
    work = np.empty((6, states.shape[1]))
    for i in range(states.shape[0]):
        y = states[i]
        for _ in range(periods):
            rk4_steps(y, 0.0, h, steps, tab, forcing, work)


@nb.njit(cache=True)
def _table_samples(y, samples, h, tab, forcing, w):
    # The one-mode table loop of model.integrate from t = 0, in place on y, recording
    # w[i] = probe q before each step (one call instead of one per step); returns the
    # steps done (fewer than samples where a stage leaves the table's range).
    stages = np.empty((samples, 4, 1))
    done = rk4_one_mode(y, 0.0, h, samples, tab.stiffness_table, tab.table_max, tab.k_force[0], tab.load[0],
                         forcing.damping_rate, forcing.P0, forcing.Omega, stages)
    for i in range(done):
        w[i] = tab.probe[0] * stages[i, 0, 0]
    return done


@nb.njit(cache=True)
def _quadrature_samples(y, done, samples, h, tab, forcing, w):
    # RK4 steps done .. samples on the quadrature, in place on y, recording w[i] = probe q
    # at every step from w[done] to w[samples] (a function of its own: a one-mode job
    # that stays in its table never compiles it).
    K = y.size // 2
    work = np.empty((6, y.size))
    w[done] = 0.0
    for k in range(K):
        w[done] += tab.probe[k] * y[k]
    t = done * h
    for i in range(done, samples):
        t = rk4_steps(y, t, h, np.int64(1), tab, forcing, work)  # not a literal: no second compilation
        s = 0.0
        for k in range(K):
            s += tab.probe[k] * y[k]
        w[i + 1] = s


def periodic_peak(w, samples: int) -> float:
    """The largest ``|w|`` (m) of the samples ``w[:samples]`` of a periodic orbit
    (``w[samples] = w[0]``), refined by the vertex of the parabola through it and its
    neighbours (the vertex formula holds for ``|w|`` when ``w`` keeps its sign over the three
    samples): the project's amplitude estimator (module docstring)."""
    best = int(np.argmax(np.abs(w[:samples])))
    a = abs(w[best])
    wm = abs(w[best - 1 if best > 0 else samples - 1])
    wp = abs(w[best + 1])
    den = wm - 2.0 * a + wp
    if den < 0.0:
        a = a - 0.125 * (wp - wm) ** 2 / den
    return float(a)
