"""Standing and rotating waves: the O(2) symmetry of a model with sine companions.

The forced membrane is unchanged by a rotation ``theta -> theta + phi`` and by the reflection
``theta -> -theta`` (the group O(2)).  So is the ROM of some axisymmetric modes ``(m, 0)``
plus the cosine modes ``(m, n)`` of one wave number and their sine companions ``(m, -n)``
(:func:`model.rom.build_rom`): writing the pattern of wave number ``n`` as
``sum_m (a_m cos(n theta) + b_m sin(n theta)) phi_mn(rho)``, the rotation ``R_phi`` (the
pattern turned by ``phi``: ``w(theta) -> w(theta - phi)``) turns every pair ``(a_m, b_m)`` by
the angle ``n phi`` and leaves the axisymmetric coordinates alone; the reflection flips the
signs of the ``b_m``.  Its generator (:func:`rotation_generator`) ``G = dR_phi/dphi`` at
``phi = 0`` sends ``(a_m, b_m)`` to ``n (-b_m, a_m)``.

Two kinds of solutions follow from the symmetry (Golubitsky, Stewart & Schaeffer, *Singularities
and Groups in Bifurcation Theory II*, ch. XVII):

* **Standing waves**: reflection-symmetric responses (every ``b_m = 0``), what branch
  switching follows in the cosine modes (:mod:`model.switching`).  Their monodromy matrix in
  the O(2) ROM splits into the cosine block (even perturbations: the stability the
  switching already reports) and the sine block (odd perturbations).  The sine block holds the
  multiplier 1 of the group orbit, with eigenvector ``G y`` (the standing wave turned a little
  is again a response), which :func:`deflated_multipliers` removes; the others decide
  whether the standing wave is stable against turning into a travelling pattern.
* **Rotating waves**: responses with ``y(t + T) = R_phi y(t)``, periodic in a frame that turns
  by ``phi`` per forcing period (relative periodic orbits), i.e. fixed points of the map
  ``y -> R_{-phi} P(y)`` with the drift ``phi`` an unknown.  At a Neimark-Sacker point of
  family ``n`` on an axisymmetric branch (the family's multipliers ``exp(+-i theta)``, twice:
  once for the cosine and once for the sine modes) a branch of them bifurcates with the drift
  ``-theta / n`` per period, together with a torus of standing waves; at most one of the two
  kinds is stable.  :func:`continue_rotating_waves` follows them by
  pseudo-arclength in ``(y, phi, parameter)`` with the phase condition
  ``(G y_pred) . (y - y_pred) = 0`` at each predicted point ``y_pred`` (scaled
  coordinates), which picks one member of each group orbit.

The algorithms take the model with a family's companions through the maps' ``companions``
capability (:class:`model.protocol.Companions`): the ROM's (:func:`o2_rom`, whose pairs are
described above) and the full model's circumferential harmonics with their companions
(:class:`model.full.harmonic.HarmonicFull`, each pair of harmonic ``k`` turning by ``k phi``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .continuation import LENGTH, bordered_newton, step, unit_tangent
from .families import Family, embedded
from .protocol import Companions, sorted_multipliers
from .rom import Rom, build_rom


def o2_rom(rom: Rom, family: Family) -> Rom:
    """The ROM of ``rom``'s axisymmetric modes, then the family's cosine modes, then their
    sine companions (the same order), on ``rom``'s pre-stretch."""
    modes = list(rom.modes) + list(family.modes) + [(m, -family.n) for m in family.radial]
    return build_rom(rom.prestretch, modes, probe_rho=rom.probe_rho)


def companion_pairs(modes) -> list[tuple[int, int, int]]:
    """``(i, j, n)``: the index of each cosine mode ``(m, n)``, ``n > 0``, whose sine companion
    ``(m, -n)`` is in ``modes``, the companion's index, and ``n``."""
    index = {tuple(mode): k for k, mode in enumerate(modes)}
    return [(i, index[(m, -n)], n) for i, (m, n) in enumerate(modes) if n > 0 and (m, -n) in index]


def rotation_generator(modes) -> np.ndarray:
    """``G`` (``(2K, 2K)``, rad-1): the derivative of the rotation of the state ``(q, q')`` by
    ``phi`` at ``phi = 0``; ``(a, b) -> n (-b, a)`` for each cosine/sine pair, zero elsewhere."""
    K = len(modes)
    g = np.zeros((2 * K, 2 * K))
    for i, j, n in companion_pairs(modes):
        for off in (0, K):
            g[off + i, off + j], g[off + j, off + i] = -n, n
    return g


def rotation(modes, phi: float) -> np.ndarray:
    """``R_phi`` (``(2K, 2K)``): the state of the pattern turned by ``phi`` (rad),
    ``w(theta) -> w(theta - phi)``; each cosine/sine pair turns by ``n phi``."""
    K = len(modes)
    r = np.eye(2 * K)
    for i, j, n in companion_pairs(modes):
        c, s = np.cos(n * phi), np.sin(n * phi)
        for off in (0, K):
            r[off + i, off + i], r[off + i, off + j] = c, -s
            r[off + j, off + i], r[off + j, off + j] = s, c
    return r


def deflated_multipliers(jac: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, float]:
    """The multipliers of ``jac`` with the one of ``direction`` removed.

    ``direction`` is (to rounding) an eigenvector of ``jac`` with multiplier 1: the generator
    of the group orbit applied to the state.  In an orthonormal basis whose first vector is
    ``direction``, ``jac`` is block upper triangular; the multipliers of its lower block are
    those of the motion across the group orbit.

    Returns
    -------
    multipliers : (n - 1,) complex array
        By decreasing modulus.
    neutral : float
        ``direction . jac direction / |direction|^2``: the removed multiplier (1 for an exact
        group orbit; the difference measures the discretisation's symmetry error).
    """
    t = np.asarray(direction, dtype=float)
    t = t / np.linalg.norm(t)
    q, _ = np.linalg.qr(np.column_stack([t, np.eye(t.size)]))
    b = q.T @ jac @ q
    return sorted_multipliers(b[1:, 1:]), float(t @ jac @ t)


@dataclass
class StandingWaveStability:
    """The stability of a standing wave in a model with a family's sine companions
    (:class:`model.protocol.Companions`).

    Attributes
    ----------
    even : complex array
        Multipliers of the cosine block (perturbations that keep the reflection symmetry):
        ``2 (Ka + M)`` of the O(2) ROM, twice the cosine coordinates of the full model's harmonics.
    odd : complex array
        Multipliers of the sine block (the companions) without the group orbit's.
    neutral : float
        The group orbit's multiplier as computed (1 up to the symmetry error of the map).
    coupling : float
        Largest entry of the monodromy matrix coupling the two blocks, relative to its largest
        entry (zero by the reflection symmetry, up to rounding).
    """

    even: np.ndarray
    odd: np.ndarray
    neutral: float
    coupling: float

    @property
    def stable(self) -> bool:
        """Every multiplier but the neutral one inside the unit circle."""
        return bool(max(np.abs(self.even).max(), np.abs(self.odd).max(initial=0.0)) < 1.0)


def standing_wave_stability(waves: Companions, y) -> StandingWaveStability:
    """:class:`StandingWaveStability` of the standing wave ``y`` (a state of ``waves.fmap``
    whose companion coordinates ``waves.odd`` vanish) of a model with sine companions (the
    maps' ``companions`` capability, :class:`model.protocol.Companions`: the O(2) ROM of
    :func:`o2_rom`, or the full model's harmonics with their companions)."""
    odd = np.asarray(waves.odd, dtype=bool)
    y = np.asarray(y, dtype=float)
    if np.any(y[odd] != 0.0):
        raise ValueError("y is not a standing wave: its sine coordinates must be zero")
    tangent = (waves.generator @ y)[odd]
    if np.linalg.norm(tangent) == 0.0:
        raise ValueError("y is axisymmetric: its group orbit is a point (no standing wave)")
    _, phi = waves.fmap.monodromy(y)
    even_idx, odd_idx = np.flatnonzero(~odd), np.flatnonzero(odd)
    scale = np.abs(phi).max()
    coupling = max(np.abs(phi[np.ix_(even_idx, odd_idx)]).max(), np.abs(phi[np.ix_(odd_idx, even_idx)]).max())
    rest, neutral = deflated_multipliers(phi[np.ix_(odd_idx, odd_idx)], tangent)
    return StandingWaveStability(sorted_multipliers(phi[np.ix_(even_idx, even_idx)]), rest, neutral,
                                 float(coupling / scale))


def neimark_sacker_direction(fmap, state, family) -> tuple[np.ndarray, float]:
    """The critical eigenvector of family ``family``'s block at the axisymmetric orbit ``state``
    and its angle: the multiplier ``exp(i theta)``, ``0 < theta < pi``, closest to the unit
    circle.

    Returns
    -------
    vector : (2M,) complex array
        Unit eigenvector ``(u, u')`` of the multiplier.
    theta : float
        Its argument (rad per forcing period).
    """
    mu, vec = np.linalg.eig(fmap.family_monodromy(state, family))
    upper = np.flatnonzero(mu.imag > 1e-12 * np.abs(mu))
    if upper.size == 0:
        raise ValueError("the family's block has no complex multipliers here: not a Neimark-Sacker point")
    k = upper[np.argmin(np.abs(np.abs(mu[upper]) - 1.0))]
    v = vec[:, k]
    return v / np.linalg.norm(v), float(np.angle(mu[k]))


@dataclass
class RotatingWaves:
    """A branch of rotating waves (:func:`continue_rotating_waves`).

    Attributes
    ----------
    value : (N,) array
        The continued parameter (rad s-1 or Pa).
    state : (N, 2K) array
        ``y(0)`` in the coordinates of the model with the companions; ``y(T) = R_drift y(0)``.
    drift : (N,) array
        ``phi`` (rad per forcing period): the angle the pattern turns in one period.
    amplitude : (N,) array
        ``max_t |w(rho_probe, 0, t)|`` (m) over one period (the probe sees the wave pass).
    wave_amplitude : (N,) array
        ``sqrt(sum_m a_m^2 + b_m^2)`` (m): the size of the family's pattern, constant along a
        rotating wave.
    multipliers : (N, 2K - 1) complex array
        Multipliers of ``y -> R_{-phi} P(y)`` without the group orbit's 1, by decreasing modulus.
    neutral : (N,) array
        The group orbit's multiplier as computed (1 up to rounding).
    stable : (N,) bool array
    complete : bool
        The branch left the parameter range.
    message : str
        Why the continuation stopped.
    """

    value: np.ndarray
    state: np.ndarray
    drift: np.ndarray
    amplitude: np.ndarray
    wave_amplitude: np.ndarray
    multipliers: np.ndarray
    neutral: np.ndarray
    stable: np.ndarray
    complete: bool
    message: str


class _RotatingProblem:
    """``H(x) = (s (P(y) - R_phi y), c . (x_y - anchor_y)) = 0`` in the scaled unknowns
    ``x = (s y, phi, (lambda - start) / span)``; ``c`` is the group tangent at the anchor."""

    def __init__(self, o2: Companions, parameter: str, start: float, stop: float):
        self.fmap, self.parameter, self.start, self.span = o2.fmap, parameter, start, abs(stop - start)
        self.lo, self.hi = min(start, stop), max(start, stop)
        self.s = o2.fmap.state_scale(None if parameter == "P0" else 0.5 * (start + stop)) / LENGTH
        self.rotation = o2.rotation
        self.g = o2.generator
        self.n = self.s.size
        self.phase = np.zeros(self.n)

    def pack(self, y, phi, lam):
        return np.concatenate([self.s * y, [phi, (lam - self.start) / self.span]])

    def unpack(self, x):
        return x[:self.n] / self.s, x[self.n], self.start + x[-1] * self.span

    def set_phase(self, x):
        """Fix the rotation by the group tangent at ``x``."""
        y = self.unpack(x)[0]
        c = self.s * (self.g @ y)
        self.phase, self.anchor = c / np.linalg.norm(c), x[:self.n].copy()

    def evaluate(self, x):
        y, phi, lam = self.unpack(x)
        yT, jac_y, dlam = self.fmap.varied(self.parameter, lam).monodromy_parameter(y, self.parameter)
        r = self.rotation(phi)
        h = np.empty(self.n + 1)
        h[:self.n] = self.s * (yT - r @ y)
        h[self.n] = self.phase @ (x[:self.n] - self.anchor)
        jac = np.zeros((self.n + 1, self.n + 2))
        jac[:self.n, :self.n] = (self.s[:, None] / self.s[None, :]) * (jac_y - r)
        jac[:self.n, self.n] = -self.s * (self.g @ r @ y)
        jac[:self.n, self.n + 1] = self.s * dlam * self.span
        jac[self.n, :self.n] = self.phase
        return h, jac, jac_y, r


def continue_rotating_waves(fmap, family, parameter: str, start: float, stop: float, state, value: float,
                            ds: float = 0.01, ds_min: float = 1e-6, ds_max: float = 0.05, max_points: int = 100,
                            tol: float = 1e-10) -> tuple[RotatingWaves, Companions]:
    """The rotating waves bifurcating at a Neimark-Sacker point of ``family``.

    Parameters
    ----------
    fmap : StroboscopicMap
        The map of the axisymmetric model (its continued parameter is overridden), with the
        capabilities ``family_monodromy`` and ``companions`` (:mod:`model.protocol`): the ROM's
        :class:`model.forced.ForcedMap` or the full model's :class:`model.full.forced.ForcedFull`.
    family
        The family whose multipliers cross the unit circle as a complex pair at the point.
    parameter, start, stop
        As for :func:`model.continuation.continue_orbits`; ``value`` must lie in the range.
    state : (2Ka,) array
        The axisymmetric orbit at the Neimark-Sacker point.
    value : float
        The parameter there.
    ds, ds_min, ds_max, max_points, tol
        As for :func:`model.continuation.continue_orbits`.

    Returns
    -------
    waves : RotatingWaves
        In the coordinates of the model with the companions.  The first point is the
        Neimark-Sacker point itself (wave amplitude 0, drift ``-theta / n``, multipliers NaN);
        the branch leaves it along the critical eigenvector at fixed parameter (the rotating
        waves grow like the square root of the parameter distance).
    o2 : Companions
        The model with the family's companions (its map at ``value``).
    """
    if not min(start, stop) <= value <= max(start, stop):
        raise ValueError(f"value = {value!r} is invalid: must lie in [{start}, {stop}]")
    at = fmap.varied(parameter, value)
    v, theta = neimark_sacker_direction(at, state, family)
    o2 = at.companions(family)
    fmap_o2 = o2.fmap
    F, K = o2.cosine.size, fmap_o2.dof
    y0 = embedded(state, K)
    direction = np.zeros(2 * K)
    for off, part in ((0, v[:F]), (K, v[F:])):  # a - i b along the eigenvector: the pattern turns
        direction[off + o2.cosine] = part.real
        direction[off + o2.sine] = -part.imag
    prob = _RotatingProblem(o2, parameter, float(start), float(stop))
    x = prob.pack(y0, -theta / family.n, value)
    t = np.concatenate([prob.s * direction, [0.0, 0.0]])
    t /= np.linalg.norm(t)
    wave = np.concatenate([o2.cosine, o2.sine])  # the family's displacements, cosine and sine
    pts = [(value, y0, -theta / family.n, fmap_o2.amplitude(y0), 0.0,
            np.full(2 * K - 1, np.nan + 0j), np.nan)]

    def record(x, jac_y, r):
        y, phi, lam = prob.unpack(x)
        mu, neutral = deflated_multipliers(r.T @ jac_y, prob.g @ y)
        pts.append((lam, y, phi, fmap_o2.varied(parameter, lam).amplitude(y), float(np.linalg.norm(y[wave])),
                    mu, neutral))

    def correct(guess, normal, anchor, sigma, tol):
        """Newton from ``guess`` with the phase fixed there: ``(x, jac, jac_y, r, iters)``."""
        prob.set_phase(guess)
        found = bordered_newton(prob.evaluate, guess, normal, anchor, sigma, tol, 8)
        return None if found is None else (found[0], found[1][1], found[1][2], found[1][3], found[2])

    message, complete = "max_points reached", False
    while len(pts) < max_points:
        result, t_new, ds = step(correct, unit_tangent, x, t, ds, ds_min, tol)
        if result is None:
            message = "step size fell below ds_min"
            break
        x, _, jac_y, r, iters = result
        t = t_new
        if not prob.lo <= prob.unpack(x)[2] <= prob.hi:
            complete, message = True, "left the parameter range"
            break
        record(x, jac_y, r)
        if iters <= 3:
            ds = min(2.0 * ds, ds_max)
    value_, state_, drift, amp, size, mu, neutral = (np.array(c) for c in zip(*pts))
    stable = np.abs(mu).max(axis=1) < 1.0  # NaN at the bifurcation point: False
    return RotatingWaves(value_, state_, drift, amp, size, mu, neutral, stable, complete, message), o2


@dataclass
class WaveMotion:
    """What a time integration of a model with a family's companions settles to (:func:`wave_motion`), from the
    stroboscopic samples of the last tenth of the integration.

    Attributes
    ----------
    drift : float
        Mean angle (rad per forcing period) the pattern turns per period: ``-arg(z_{k+1} /
        z_k) / n`` with ``z = a - i b`` of the family's largest cosine/sine pair; the drift of
        a rotating wave, 0 for a periodic standing one (``+-pi / n`` for a standing one of period two).
    drift_spread : float
        Range of that angle over the samples (0 for a rotating or a standing wave).
    wave_amplitude : float
        Mean of ``sqrt(sum_m a_m^2 + b_m^2)`` (m).
    wave_spread : float
        Range of it over the samples, relative to the mean (0 for a rotating wave and for a
        periodic standing wave; a standing wave on a torus swings).
    """

    drift: float
    drift_spread: float
    wave_amplitude: float
    wave_spread: float


def wave_motion(o2: Companions, y0, n: int, periods: int) -> WaveMotion:
    """Integrate the map ``o2.fmap`` of a model with a family's companions for ``periods``
    forcing periods from ``y0`` and describe the family's pattern over the last tenth
    (:class:`WaveMotion`): the check of a continued rotating or standing wave by time
    integration."""
    if periods < 20:
        raise ValueError(f"periods = {periods!r} is invalid: need at least 20")
    tail = max(periods // 10, 2)
    y = o2.fmap.advance(y0, periods - tail)
    ab = np.empty((tail, 2, o2.cosine.size))
    for k in range(tail):
        y = o2.fmap.advance(y)
        ab[k] = y[o2.cosine], y[o2.sine]
    size = np.sqrt((ab ** 2).sum(axis=(1, 2)))
    if not np.all(np.isfinite(size)) or size.min() == 0.0:
        raise ArithmeticError("the pattern is not finite or vanished exactly: no drift to read")
    largest = int(np.argmax(np.abs(ab[-1, 0] - 1j * ab[-1, 1])))
    z = ab[:, 0, largest] - 1j * ab[:, 1, largest]
    turn = -np.angle(z[1:] * np.conj(z[:-1])) / n
    return WaveMotion(float(turn.mean()), float(np.ptp(turn)), float(size.mean()), float(np.ptp(size) / size.mean()))
