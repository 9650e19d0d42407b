"""Frequency-amplitude relation (backbone) of the free nonlinear vibration (section 4.2).

Two independent methods on the free vibration of a model (Figs. 9-12), anything with the
members of :class:`model.protocol.FreeVibration` (the ROM's: :class:`model.free.FreeRom`):

* :func:`peak_to_peak` -- the method of Nandakumar and Chatterjee (2005) used by the paper
  on its finite element model: a lightly damped free decay is started on the first
  nonlinear mode at the largest amplitude and the extrema of ``w(t)`` at the probe
  point are recorded (:func:`model.dopri.extrema`).  For three successive extrema at
  ``T1 < Tm < T2`` (peak, trough, peak or trough, peak, trough),
  ``omega = 2 pi / (T2 - T1)`` and ``A = |w(Tm) - (w(T1) + w(T2))/2| / 2`` (the paper
  prints ``omega = 1/(T1 - T2)``, a frequency in Hz with the sign lost; we report rad/s).
  The samples, one per half cycle, are then interpolated at the requested amplitudes.
* :func:`backbone_branch` -- pseudo-arclength continuation of the free periodic orbits of the
  conservative system (``c = 0``) in the unknowns ``(q(0), T/4, A)``, through turning
  points of the amplitude (an internal resonance makes the branch turn back: near it two
  or more orbits share an amplitude); :func:`continue_free_orbits` solves the orbits at
  requested amplitudes on its stretch from the linear limit to the first turning point.  The potential is even in ``q`` and the system
  reversible, so the fundamental orbit that starts at rest, ``q'(0) = 0``, satisfies
  ``q(t + T/2) = -q(t)`` and hence ``q(T/4) = 0``: Newton on ``(q(0), T/4)`` with
  ``w(0) = -A``, the Jacobian from the variational equations of the RK4 scheme
  (the model's ``flow``).  A model whose energy is even in some coordinates only (the
  full model: in ``W`` at fixed in-plane ``U``) marks those that change sign in ``odd``
  (optional, with ``acceleration(q, v)``): its orbit satisfies ``q(t + T/2) = S q(t)``,
  and the conditions at ``T/4`` are ``q_i = 0`` for the odd and ``q_i' = 0`` for the
  others.

Sign conventions.  ``w(0.5 Re, 0) = probe @ q``; the paper's ``phi_10`` is negative
inside the annulus, so ``w`` and ``q_10`` have opposite signs.  The *modal amplitude*
of mode k is half the swing of ``q_k`` from the peak of ``w`` to its trough,
``(q_k(trough of w) - q_k(peak of w)) / 2``: positive for ``A_10`` in the paper's
normalisation, and of either sign for the higher modes (their phase relative to mode 1).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .continuation import bordered_newton, locate, step, unit_tangent
from .protocol import FreeVibration


class Backbone(NamedTuple):
    """A backbone curve sampled at requested amplitudes.

    Attributes
    ----------
    amplitude : (P,) ndarray
        Targets of ``max |w(rho_probe, 0, t)|`` (m).
    omega : (P,) ndarray
        Nonlinear free-vibration frequency (rad s-1); NaN where not converged.
    modal : (P, K) ndarray
        Modal amplitudes (see the module docstring); NaN where not converged.
    converged : (P,) ndarray of bool
    """

    amplitude: np.ndarray
    omega: np.ndarray
    modal: np.ndarray
    converged: np.ndarray


def linear_mode(free: FreeVibration):
    """Lowest small-amplitude frequency of the model and its mode.

    The lowest of its ``linear_frequencies``.

    Returns
    -------
    omega : float
        Lowest linear frequency (rad s-1).
    vector : (K,) ndarray
        Its modal vector, scaled so that ``probe @ vector = -1`` (``w = -1`` m at the probe).
    """
    omega, vectors = free.linear_frequencies()
    v = vectors[:, 0]
    scale = free.probe @ v
    if abs(scale) < 1e-12 * np.abs(v).max():
        raise ValueError(f"the lowest mode of {free} vanishes at the probe point: its backbone cannot be "
                         "measured there")
    return float(omega[0]), -v / scale


def free_orbit(free: FreeVibration, amplitude: float, q_guess, quarter_guess: float, steps: int = 256,
               tol: float = 1e-12, max_iter: int = 12):
    """Free periodic orbit of the undamped model through ``q(0)`` with ``w(0) = -amplitude``.

    Parameters
    ----------
    free : FreeVibration
    amplitude : float
        ``-w(rho_probe, 0, 0)`` (m) at the turning point.
    q_guess : (K,) array_like
        Initial guess of ``q(0)``.
    quarter_guess : float
        Initial guess of a quarter of the period (s).
    steps : int
        RK4 steps per quarter period.
    tol : float
        Newton stops when the update of ``q(0)`` relative to ``|q(0)|`` and of ``T/4``
        relative to ``T/4`` are below ``tol``.
    max_iter : int
        Newton iterations before giving up.

    Returns
    -------
    q0 : (K,) ndarray
        Turning point (modal coordinates) of the orbit.
    period : float
        Period (s).
    converged : bool
    """
    K = free.dof
    probe = free.probe
    odd = _odd(free)
    rows = np.where(odd, np.arange(K), K + np.arange(K))  # q_i(T/4) for odd i, q_i'(T/4) for the others
    q0 = np.array(q_guess, dtype=float)
    tau = float(quarter_guess)
    y0 = np.zeros(2 * K)
    jac = np.zeros((K + 1, K + 1))
    res = np.zeros(K + 1)
    for _ in range(max_iter):
        if not (np.all(np.isfinite(q0)) and np.isfinite(tau) and tau > 0.0):
            break
        y0[:K] = q0
        try:
            yq, phi = free.flow(y0, tau, steps)
        except np.linalg.LinAlgError:  # an iterate gone astray (model.full.free.MAX_FLOW_STEPS)
            break
        rate = yq[K:] if odd.all() else np.concatenate([yq[K:], free.acceleration(yq[:K], yq[K:])])
        res[:K] = yq[rows]
        res[K] = probe @ q0 + amplitude
        jac[:K, :K] = phi[rows, :K]
        jac[:K, K] = rate[rows]
        jac[K, :K] = probe
        try:
            dx = np.linalg.solve(jac, -res)
        except np.linalg.LinAlgError:
            break
        q0 = q0 + dx[:K]
        tau = tau + dx[K]
        if np.abs(dx[:K]).max() <= tol * np.abs(q0).max() and abs(dx[K]) <= tol * tau:
            return q0, 4.0 * tau, True
    return q0, 4.0 * tau, False


def _odd(free: FreeVibration) -> np.ndarray:
    """The coordinates that change sign under the orbit's half-period symmetry (all of
    them unless the model says otherwise with ``odd``)."""
    odd = getattr(free, "odd", None)
    return np.ones(free.dof, bool) if odd is None else np.asarray(odd, bool)


class BackboneBranch(NamedTuple):
    """A branch of free periodic orbits followed by pseudo-arclength from the linear limit.

    Attributes
    ----------
    amplitude : (N,) ndarray
        ``-w(rho_probe, 0, 0)`` (m) at the turning point of each orbit.
    omega : (N,) ndarray
        Frequency (rad s-1).
    q0 : (N, K) ndarray
        Turning points (``q'(0) = 0``).
    turning : (N,) bool ndarray
        The amplitude turns back between this point and the next (the amplitude
        component of the tangent changes sign).
    located_amplitude, located_omega : (T,) ndarrays
        Amplitudes (m) and frequencies (rad s-1) of the orbits located on the branch by
        arclength at the targets it crossed before it first turned back (the amplitudes
        equal the targets to the location's tolerance).
    located_q0 : (T, K) ndarray
        Their turning points.
    """

    amplitude: np.ndarray
    omega: np.ndarray
    q0: np.ndarray
    turning: np.ndarray
    located_amplitude: np.ndarray = np.empty(0)
    located_omega: np.ndarray = np.empty(0)
    located_q0: np.ndarray = np.empty((0, 0))

    @property
    def first_stretch(self) -> int:
        """Points from the linear limit to the first turning point (inclusive)."""
        turns = np.flatnonzero(self.turning)
        return int(turns[0]) + 1 if turns.size else self.amplitude.size


def _quarter_conditions(free: FreeVibration, q0, tau, steps):
    """The conditions at ``T/4`` of an orbit from rest at ``q0`` (module docstring) and their
    derivatives in ``q0`` and ``T/4``."""
    K = free.dof
    odd = _odd(free)
    rows = np.where(odd, np.arange(K), K + np.arange(K))  # q_i(T/4) for odd i, q_i'(T/4) for the others
    yq, phi = free.flow(np.concatenate([q0, np.zeros(K)]), tau, steps)
    rate = yq[K:] if odd.all() else np.concatenate([yq[K:], free.acceleration(yq[:K], yq[K:])])
    return yq[rows], phi[rows, :K], rate[rows]


#: Most points of a backbone branch (:func:`backbone_branch`).
MAX_BRANCH_POINTS = 400

#: Longest period of a free orbit the backbone branch admits, over the linear one: backbones
#: harden (shorter periods), an internal resonance bends them by a few per cent, not tenfold.
MAX_PERIOD_RATIO = 10.0


def backbone_branch(free: FreeVibration, a_max: float, steps: int = 256, ds_max: float = 0.05,
                    max_points: int = MAX_BRANCH_POINTS, tol: float = 1e-10, targets=()) -> BackboneBranch:
    """The backbone branch from the linear limit until the amplitude reaches ``a_max`` (m).

    Pseudo-arclength (predictor along the unit tangent, Newton on the bordered system,
    :func:`model.continuation.step`) in the scaled unknowns ``x = (|probe| q(0) / a_max,
    4 omega_lin T/4 / (2 pi), A / a_max)``: the conditions at ``T/4`` of
    :func:`free_orbit` (velocities scaled by the linear period) and ``probe . q(0) + A = 0``.
    The step ``ds`` (scaled arclength) grows by 1.5 after an easy corrector up to
    ``ds_max`` and is halved on failure, down to ``ds_max / 2^12``.  The branch starts at
    ``A = a_max / 1000``.  It ends at ``a_max``, after ``max_points``, when ``ds`` falls
    below its minimum, or when the amplitude returns to zero.

    Each of ``targets`` (m) that a step crosses while the amplitude still grows (before the
    first turn) is located on the step by arclength (:func:`model.continuation.locate`:
    the bordered system's corrector, well conditioned through internal resonances, where a
    Newton solve at fixed amplitude from the interpolated orbits can fail to converge); when
    the corrector fails inside the step, the step is halved and taken again, down to twice
    the smallest step, below which the step is kept and the target left to
    :func:`continue_free_orbits`' interpolation.  The branch's steps, and so where it is
    found to turn near closely spaced internal resonances, depend on the targets.
    """
    if not (np.isfinite(a_max) and a_max > 0.0):
        raise ValueError(f"a_max = {a_max!r} is invalid: need a finite amplitude > 0 (m)")
    K = free.dof
    w_lin, v = linear_mode(free)
    tau_lin = 0.5 * np.pi / w_lin
    qs = float(np.abs(free.probe).max()) / a_max  # scaled q per unit q
    odd = _odd(free)
    row_scale = np.where(odd, qs, qs * tau_lin)
    scale = np.concatenate([np.full(K, qs), [1.0 / tau_lin, 1.0 / a_max]])

    def evaluate(x):
        q0, tau, amp = x[:K] / qs, x[K] / scale[K], x[K + 1] * a_max
        if not 0.0 < tau <= MAX_PERIOD_RATIO * tau_lin:
            # a Newton iterate gone astray (at order 32 of the full model one asked for a
            # quarter period of 3e7 s, 1e11 RK4 steps): rejected, the step is halved
            raise np.linalg.LinAlgError(f"a quarter period {tau:g} s outside (0, {MAX_PERIOD_RATIO} T_lin / 4]")
        res, dq, dtau = _quarter_conditions(free, q0, tau, steps)
        g = np.concatenate([row_scale * res, [(free.probe @ q0 + amp) / a_max]])
        jac = np.zeros((K + 1, K + 2))
        jac[:K, :K] = row_scale[:, None] * dq / qs
        jac[:K, K] = row_scale * dtau / scale[K]
        jac[K, :K] = free.probe / (qs * a_max)
        jac[K, K + 1] = 1.0
        if not np.all(np.isfinite(g)) or not np.all(np.isfinite(jac)):
            raise np.linalg.LinAlgError("an orbit that is not finite")
        return g, jac

    def correct(x0, normal, anchor, sigma, tol):
        try:
            found = bordered_newton(evaluate, x0, normal, anchor, sigma, tol, 12)
        except np.linalg.LinAlgError:
            return None
        return None if found is None else (found[0], found[1][1], found[2])

    a0 = 1e-3 * a_max
    q0, period, ok = free_orbit(free, a0, v * a0, tau_lin, steps)
    if not ok:
        raise ArithmeticError(f"no free periodic orbit of {free} at the smallest amplitude {a0:g} m")
    x = np.concatenate([q0, [period / 4.0, a0]]) * scale
    e_amp = np.zeros(K + 2)
    e_amp[-1] = 1.0
    t = unit_tangent(evaluate(x)[1], e_amp)
    points, ds, ds_min = [x], ds_max, ds_max / 2**12
    tangents = [t]
    wanted = np.sort(np.asarray(targets, float).ravel()) / a_max
    located = []
    growing = True
    while len(points) < max_points and x[K + 1] < 1.0:
        res, t_new, used = step(correct, unit_tangent, x, t, ds, ds_min, tol)
        if res is None or not (res[0][K + 1] > 0.0 and res[0][K] > 0.0):
            break
        crossed = []
        if growing and t_new[K + 1] > 0.0 and res[0][K + 1] > x[K + 1]:
            for target in wanted[(wanted > x[K + 1]) & (wanted <= res[0][K + 1])]:
                found = locate(correct, lambda r: r[0][K + 1] - target, x, t, used, x[K + 1] - target,
                               res[0][K + 1] - target, tol)
                crossed.append(None if found is None else found[1][0])
            if any(c is None for c in crossed) and used >= 2.0 * ds_min:
                # the branch between the two points is not a graph over the step's hyperplanes
                # (an internal resonance): a shorter step
                ds = 0.5 * used
                continue
        else:
            growing = False
        located += [c for c in crossed if c is not None]
        x, t = res[0], t_new
        points.append(x)
        tangents.append(t)
        ds = min(ds_max, 1.5 * used) if res[2] <= 3 else used
    X = np.array(points) / scale
    T = np.array(tangents)
    turning = np.zeros(len(points), bool)
    turning[:-1] = np.sign(T[1:, K + 1]) != np.sign(T[:-1, K + 1])
    L = np.array(located).reshape(-1, K + 2) / scale
    return BackboneBranch(X[:, K + 1], 2.0 * np.pi / (4.0 * X[:, K]), X[:, :K], turning,
                          L[:, K + 1], 2.0 * np.pi / (4.0 * L[:, K]), L[:, :K])


def continue_free_orbits(free: FreeVibration, amplitudes, steps: int = 256, ds_max: float = 0.05,
                         branch: BackboneBranch | None = None) -> tuple[Backbone, BackboneBranch]:
    """Backbone at requested amplitudes: free periodic orbits of the undamped model.

    The orbits are solved (:func:`free_orbit`) at each target from the orbit the
    pseudo-arclength branch (:func:`backbone_branch`, up to the largest target) located there
    on its stretch from the linear limit to the first turning point of the amplitude, or
    else from its interpolated orbits; targets beyond that stretch (or beyond the branch's
    end) are not converged (NaN): the branch itself says what happens there.

    Parameters
    ----------
    free : FreeVibration
    amplitudes : array_like
        Targets of ``max |w(rho_probe, 0, t)|`` (m), > 0, any order.
    steps : int
        RK4 steps per quarter period of the shooting.
    ds_max : float
        Largest step of the branch (scaled arclength, :func:`backbone_branch`).
    branch : BackboneBranch, optional
        A branch already followed to at least the largest target.

    Returns
    -------
    Backbone
        ``amplitude`` in the order given.  The amplitude of an orbit is ``|w|`` at its
        turning point, the maximum of ``|w|`` over the orbit.
    BackboneBranch
    """
    amps = np.asarray(amplitudes, dtype=float).ravel()
    if amps.size == 0 or not np.all(np.isfinite(amps)) or np.any(amps <= 0.0):
        raise ValueError(f"amplitudes = {amplitudes!r} is invalid: need finite values > 0 (m)")
    K = free.dof
    if branch is None:
        branch = backbone_branch(free, float(amps.max()), steps, ds_max, targets=amps)
    omega = np.full(amps.size, np.nan)
    modal = np.full((amps.size, K), np.nan)
    done = np.zeros(amps.size, dtype=bool)
    n = branch.first_stretch
    a, q, tau = branch.amplitude[:n], branch.q0[:n], 0.5 * np.pi / branch.omega[:n]
    power = np.where(_odd(free), 1.0, 2.0)
    for j, target in enumerate(amps):
        if target > a[-1] * (1.0 + 1e-12):
            continue
        at = np.flatnonzero(np.abs(branch.located_amplitude - target) <= 1e-9 * target)
        if at.size:  # located on the branch
            guess, tau_guess = branch.located_q0[at[0]], 0.5 * np.pi / branch.located_omega[at[0]]
        elif target <= a[0]:  # below the branch's start: its first orbit, scaled
            guess, tau_guess = q[0] * (target / a[0]) ** power, tau[0]
        else:
            i = int(np.searchsorted(a, target))
            f = (target - a[i - 1]) / (a[i] - a[i - 1])
            guess, tau_guess = q[i - 1] + f * (q[i] - q[i - 1]), tau[i - 1] + f * (tau[i] - tau[i - 1])
        q0, period, conv = free_orbit(free, target, guess, tau_guess, steps)
        if conv:
            omega[j], modal[j], done[j] = 2.0 * np.pi / period, q0, True
    return Backbone(amps, omega, modal, done), branch


def decay_samples(times, states, probe):
    """Peak-to-peak samples of one free decay from its successive extrema of ``w``.

    Parameters
    ----------
    times : (E,) array_like
        Instants of successive extrema of ``w`` (s).
    states : (E, 2K) array_like
        States there.
    probe : (K,) array_like
        ``w = probe @ q``.

    Returns
    -------
    amplitude, omega : (S,) ndarrays
        ``A = |w(Tm) - (w(T1) + w(T2))/2| / 2`` (m) and ``2 pi / (T2 - T1)`` (rad s-1) for
        every triple ``T1 < Tm < T2`` of successive extrema with alternating signs of ``w``.
    modal : (S, K) ndarray
        ``(q_k(trough) - q_k(peak)) / 2`` with the two peaks (or troughs) averaged.
    """
    times = np.asarray(times, dtype=float)
    states = np.asarray(states, dtype=float)
    K = states.shape[1] // 2
    w = states[:, :K] @ np.asarray(probe, dtype=float)
    q = states[:, :K]
    mid = np.arange(1, times.size - 1)
    keep = (np.sign(w[mid - 1]) == np.sign(w[mid + 1])) & (np.sign(w[mid]) == -np.sign(w[mid - 1]))
    mid = mid[keep]
    side = 0.5 * (w[mid - 1] + w[mid + 1])
    amplitude = 0.5 * np.abs(w[mid] - side)
    omega = 2.0 * np.pi / (times[mid + 1] - times[mid - 1])
    sign = np.where(w[mid] < 0.0, 1.0, -1.0)
    modal = 0.5 * sign[:, None] * (q[mid] - 0.5 * (q[mid - 1] + q[mid + 1]))
    return amplitude, omega, modal


#: Cycles of each decay recorded by :func:`peak_to_peak`.
PEAK_CYCLES = 8


def decay_start(free: FreeVibration, amplitudes, c: float, cycles: int) -> np.ndarray:
    """Amplitudes (m) at which :func:`peak_to_peak` starts its decays: about half of the
    ``cycles`` recorded cycles above each target, decaying at half of ``free.decay_rate(c)``
    over the linear period."""
    w_lin = linear_mode(free)[0]
    return np.asarray(amplitudes, float) * np.exp(0.5 * free.decay_rate(c) * 0.5 * cycles * 2.0 * np.pi / w_lin)


def peak_to_peak(free: FreeVibration, amplitudes, c: float = 0.05, cycles: int = PEAK_CYCLES, rtol: float = 1e-10,
                 steps: int = 256, branch: BackboneBranch | None = None) -> Backbone:
    """Backbone by the peak-to-peak method on lightly damped free decays.

    One decay per target amplitude, all integrated in one batched call (the model's
    ``decay_extrema``): each starts at rest on the first nonlinear mode
    (the turning point of the free periodic orbit, :func:`continue_free_orbits`; the linear shape for
    one mode) slightly above its target, so that its ``cycles`` cycles straddle the
    target; the samples of :func:`decay_samples` are interpolated linearly in amplitude
    at the target.  Short decays rather than one long one: for several modes the free
    periodic orbit can be unstable (at ``delta = 1.1, delta_o = 0.2`` with modes
    (1,0),(2,0),(3,0) above ``|w| ~ 0.25 m``), and a long decay then drifts off it.

    Parameters
    ----------
    free : FreeVibration
    amplitudes : array_like
        Targets of ``max |w(rho_probe, 0, t)|`` (m), > 0.
    c : float
        Viscous damping of the decays (N s m-3), > 0.  Amplitudes decay as
        ``exp(-c t / (2 Gamma h))``: ``c = 0.05`` (the paper's value,
        ``c/(Gamma h) = 0.0227 s-1``) gives about 0.2 % per cycle near 33 rad/s, and
        the frequency bias of the damping, of relative order
        ``(c / (2 Gamma h omega))^2``, is below 1e-7.
    cycles : int
        Cycles recorded per decay (>= 2).
    rtol : float
        Relative tolerance of the DOP853 integration.
    steps : int
        RK4 steps per quarter period of the shooting for the starting shapes.
    branch : BackboneBranch, optional
        The backbone branch (:func:`backbone_branch`) followed to at least the largest start
        (:func:`decay_start`), shared with :func:`continue_free_orbits`.

    Returns
    -------
    Backbone
    """
    amps = np.asarray(amplitudes, dtype=float).ravel()
    if amps.size == 0 or not np.all(np.isfinite(amps)) or np.any(amps <= 0.0):
        raise ValueError(f"amplitudes = {amplitudes!r} is invalid: need finite values > 0 (m)")
    if not c > 0.0:
        raise ValueError(f"c = {c!r} is invalid: the peak-to-peak method needs a damped decay, c > 0 (N s/m^3)")
    if int(cycles) < 2:
        raise ValueError(f"cycles = {cycles!r} is invalid: must be an integer >= 2")
    cycles = int(cycles)
    K = free.dof
    w_lin, v = linear_mode(free)
    start = decay_start(free, amps, c, cycles)
    if K == 1:
        q0, ok = v[None, :] * start[:, None], np.ones(amps.size, dtype=bool)
    else:
        orbits, _ = continue_free_orbits(free, start, steps, branch=branch)
        q0, ok = orbits.modal, orbits.converged
    y0 = np.zeros((amps.size, 2 * K))
    y0[:, :K] = np.where(ok[:, None], q0, 0.0)
    # The linear period is the longest: the nonlinear backbone hardens.
    t_end = (cycles + 1) * 2.0 * np.pi / w_lin
    ext = free.decay_extrema(y0, t_end, 2 * cycles, c, rtol, 1e-14 * free.length)
    omega = np.full(amps.size, np.nan)
    modal = np.full((amps.size, K), np.nan)
    done = np.zeros(amps.size, dtype=bool)
    for j in np.flatnonzero(ok):
        n = int(ext.count[j])
        a_s, w_s, q_s = decay_samples(np.concatenate([[0.0], ext.times[j, :n]]),
                                      np.concatenate([y0[j:j + 1], ext.states[j, :n]]),
                                      free.probe)
        if a_s.size < 2 or not a_s.min() <= amps[j] <= a_s.max():
            continue
        order = np.argsort(a_s)
        omega[j] = np.interp(amps[j], a_s[order], w_s[order])
        modal[j] = [np.interp(amps[j], a_s[order], q_s[order, k]) for k in range(K)]
        done[j] = True
    return Backbone(amps, omega, modal, done)
