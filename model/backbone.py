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
* :func:`continue_free_orbits` -- continuation in amplitude of the free periodic orbits of the
  conservative system (``c = 0``).  The potential is even in ``q`` and the system
  reversible, so the fundamental orbit that starts at rest, ``q'(0) = 0``, satisfies
  ``q(t + T/2) = -q(t)`` and hence ``q(T/4) = 0``: Newton on ``(q(0), T/4)`` with
  ``w(0) = -A``, the Jacobian from the variational equations of the RK4 scheme
  (the model's ``flow``).

Sign conventions.  ``w(0.5 Re, 0) = probe @ q``; the paper's ``phi_10`` is negative
inside the annulus, so ``w`` and ``q_10`` have opposite signs.  The *modal amplitude*
of mode k is half the swing of ``q_k`` from the peak of ``w`` to its trough,
``(q_k(trough of w) - q_k(peak of w)) / 2``: positive for ``A_10`` in the paper's
normalisation, and of either sign for the higher modes (their phase relative to mode 1).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

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
    q0 = np.array(q_guess, dtype=float)
    tau = float(quarter_guess)
    y0 = np.zeros(2 * K)
    jac = np.zeros((K + 1, K + 1))
    res = np.zeros(K + 1)
    for _ in range(max_iter):
        if not (np.all(np.isfinite(q0)) and np.isfinite(tau) and tau > 0.0):
            break
        y0[:K] = q0
        yq, phi = free.flow(y0, tau, steps)
        res[:K] = yq[:K]
        res[K] = probe @ q0 + amplitude
        jac[:K, :K] = phi[:K, :K]
        jac[:K, K] = yq[K:]
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


def continue_free_orbits(free: FreeVibration, amplitudes, steps: int = 256, max_halvings: int = 6) -> Backbone:
    """Backbone by continuation of free periodic orbits (``c = 0``, ``P0 = 0``).

    Natural-parameter continuation in the amplitude, from the linear mode at the smallest
    target upwards; a failed Newton halves the amplitude step (at most ``max_halvings``
    times) before the rest of the branch is marked not converged.

    Parameters
    ----------
    free : FreeVibration
    amplitudes : array_like
        Targets of ``max |w(rho_probe, 0, t)|`` (m), > 0, any order.
    steps : int
        RK4 steps per quarter period of the shooting.

    Returns
    -------
    Backbone
        ``amplitude`` in the order given.  The amplitude of an orbit is ``|w|`` at its
        turning point, the maximum of ``|w|`` over the orbit.
    """
    amps = np.asarray(amplitudes, dtype=float).ravel()
    if amps.size == 0 or not np.all(np.isfinite(amps)) or np.any(amps <= 0.0):
        raise ValueError(f"amplitudes = {amplitudes!r} is invalid: need finite values > 0 (m)")
    K = free.dof
    omega = np.full(amps.size, np.nan)
    modal = np.full((amps.size, K), np.nan)
    done = np.zeros(amps.size, dtype=bool)
    w_lin, v = linear_mode(free)
    a_prev, q_prev, tau_prev = 0.0, v, 0.5 * np.pi / w_lin
    for idx in np.argsort(amps, kind="stable"):
        target = amps[idx]
        ok = True
        while a_prev < target and ok:
            a_try, halvings = target, 0
            while True:
                # Scale the previous orbit (the linear mode at the start) to the new amplitude.
                guess = q_prev * (a_try / a_prev) if a_prev > 0.0 else v * a_try
                q0, period, conv = free_orbit(free, a_try, guess, tau_prev, steps)
                if conv:
                    a_prev, q_prev, tau_prev = a_try, q0, period / 4.0
                    break
                halvings += 1
                if halvings > max_halvings:
                    ok = False
                    break
                a_try = a_prev + 0.5 * (a_try - a_prev)
        if not ok:
            break
        omega[idx] = 2.0 * np.pi / (4.0 * tau_prev)
        modal[idx] = q_prev
        done[idx] = True
    return Backbone(amps, omega, modal, done)


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


def peak_to_peak(free: FreeVibration, amplitudes, c: float = 0.05, cycles: int = 8, rtol: float = 1e-10,
                 steps: int = 256) -> Backbone:
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
    rate = free.decay_rate(c)
    # Start so that the target is reached about half-way through the recorded cycles.
    start = amps * np.exp(0.5 * rate * 0.5 * cycles * 2.0 * np.pi / w_lin)
    if K == 1:
        q0, ok = v[None, :] * start[:, None], np.ones(amps.size, dtype=bool)
    else:
        orbits = continue_free_orbits(free, start, steps)
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
