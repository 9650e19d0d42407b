"""Adaptive Dormand-Prince 8(5,3) integration of the ROM, many trajectories per call.

The explicit pair DOP853 (Hairer, Norsett and Wanner, *Solving ODEs I*, section II.10)
with the standard step-size controller (error of order 8 estimated by the combined
5th/3rd order estimators, safety 0.9, factors in [0.2, 10]).  Its coefficients are
mathematical constants, taken from :mod:`scipy.integrate._ivp.dop853_coefficients` at
import time and passed to the kernels as arrays.

Two batched kernels, each looping over trajectories that may carry their own damping,
pressure and forcing frequency:

* :func:`solve` stops exactly at requested times (the step is shortened to land on each
  of them, no interpolation), for accuracy checks and energy conservation;
* :func:`extrema` records the extrema of the reported displacement
  ``w(t) = probe @ q(t)`` (zeros of ``probe @ q'``), each located by regula falsi
  (Illinois) on the length of a single DOP853 step from the start of the step that
  brackets it, so an extremum is as accurate as the integration itself.  This feeds the
  peak-to-peak backbone of :mod:`model.backbone` (Nandakumar and Chatterjee, 2005).

States are ``y = (q, q')`` as in :func:`model.rom.rhs`; the kernels see the
:class:`model.rom.RomTables` and arrays only.
"""

from __future__ import annotations

from typing import NamedTuple

import numba as nb
import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dop

from .rom import Forcing, Rom, rhs_unpacked, unpack

_NS = _dop.N_STAGES


class _Tableau(NamedTuple):
    # The DOP853 coefficients, contiguous float arrays for the kernels.
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    E3: np.ndarray
    E5: np.ndarray


_COEF = _Tableau(np.ascontiguousarray(_dop.A[:_NS, :_NS]), np.ascontiguousarray(_dop.B),
                 np.ascontiguousarray(_dop.C[:_NS]), np.ascontiguousarray(_dop.E3),
                 np.ascontiguousarray(_dop.E5))
_SAFETY = 0.9
_MIN_FACTOR = 0.2
_MAX_FACTOR = 10.0
#: Default largest number of attempted steps of one trajectory before it is declared failed.
MAX_STEPS = 50_000_000


@nb.njit(cache=True, fastmath={"contract", "reassoc", "arcp", "nsz"}, error_model="numpy", _nrt=False)
def _step(t, y, f0, h, model, coef, kst, tmp, g, y_new, f_new, rtol, atol):
    """One DOP853 step of size ``h`` from ``(t, y)`` with ``f0 = F(t, y)``.

    Fills ``y_new``, ``f_new = F(t + h, y_new)`` and returns the scaled error norm
    (accept the step when it is <= 1).  12 evaluations of the right-hand side.  No
    reference counts (``_nrt=False``, see the note in :mod:`model.rom`); numpy's error
    model and the fastmath freedoms that keep NaN and infinity meaningful (a diverging
    trajectory's error norm must stay NaN or inf, and be rejected).
    """
    A, B, C, E3, E5 = coef
    n = y.size
    for i in range(n):
        kst[0, i] = f0[i]
    for s in range(1, _NS):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += A[s, j] * kst[j, i]
            tmp[i] = y[i] + h * acc
        rhs_unpacked(t + C[s] * h, tmp, model, g[0, :n // 2], g[1:], kst[s])
    for i in range(n):
        acc = 0.0
        for j in range(_NS):
            acc += B[j] * kst[j, i]
        y_new[i] = y[i] + h * acc
    rhs_unpacked(t + h, y_new, model, g[0, :n // 2], g[1:], f_new)
    for i in range(n):
        kst[_NS, i] = f_new[i]
    e5 = 0.0
    e3 = 0.0
    for i in range(n):
        sc = atol + rtol * max(abs(y[i]), abs(y_new[i]))
        a5 = 0.0
        a3 = 0.0
        for j in range(_NS + 1):
            a5 += E5[j] * kst[j, i]
            a3 += E3[j] * kst[j, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / np.sqrt((e5 + 0.01 * e3) * n)


@nb.njit(cache=True)
def _initial_step(y, f, rtol, atol):
    """A conservative first step (Hairer's first guess ``0.01 |y| / |f|``)."""
    d0 = 0.0
    d1 = 0.0
    for i in range(y.size):
        sc = atol + rtol * abs(y[i])
        d0 += (y[i] / sc) ** 2
        d1 += (f[i] / sc) ** 2
    if d0 < 1e-10 or d1 < 1e-10:
        return 1e-6
    return 0.01 * np.sqrt(d0 / d1)


@nb.njit(cache=True)
def _new_size(h, err):
    """Step size after a step of size ``h`` with error norm ``err``."""
    if err == 0.0:
        return h * _MAX_FACTOR
    return h * min(_MAX_FACTOR, max(_MIN_FACTOR, _SAFETY * err ** (-1.0 / 8.0)))


@nb.njit(cache=True)
def _workspace(n, points):
    # Stage derivatives, a stage state, the force (row 0 of g) with the force kernel's
    # work rows (g[1:], rom.force_work), and the current / proposed state and derivative
    # of one trajectory.
    return (np.empty((_NS + 1, n)), np.empty(n), np.empty((3, max(points, n // 2))), np.empty(n), np.empty(n),
            np.empty(n), np.empty(n))


@nb.njit(cache=True)
def _start(i, y, y0, t0, tab, c_damp, p_load, omega, g, f, rtol, atol):
    # Load trajectory i's initial state and forcing, evaluate F there; returns the
    # trajectory's model (model.rom.unpack: the tables and its forcing) and its first step size.
    model = unpack(tab, Forcing(c_damp[i], p_load[i], omega[i], np.zeros((0, 0))))
    y[:] = y0[i]
    rhs_unpacked(t0, y, model, g[0, :y.size // 2], g[1:], f)
    return model, _initial_step(y, f, rtol, atol)


@nb.njit(cache=True)
def _solve_kernel(y0, t0, t_eval, tab, c_damp, p_load, omega, rtol, atol, coef, max_steps, out, nfev):
    N, n = y0.shape
    kst, tmp, g, y, f, y_new, f_new = _workspace(n, tab.weight.size)
    for i in range(N):
        t = t0
        model, h = _start(i, y, y0, t0, tab, c_damp, p_load, omega, g, f, rtol, atol)
        evals = 1
        attempts = 0
        for j in range(t_eval.size):
            while t < t_eval[j] and attempts < max_steps:
                clipped = t + h >= t_eval[j]
                hs = t_eval[j] - t if clipped else h
                err = _step(t, y, f, hs, model, coef, kst, tmp, g, y_new, f_new, rtol, atol)
                evals += _NS
                attempts += 1
                if err <= 1.0:
                    t = t_eval[j] if clipped else t + hs
                    y[:] = y_new
                    f[:] = f_new
                    h = max(h, _new_size(hs, err)) if clipped else _new_size(hs, err)
                else:
                    h = _new_size(hs, err)
            if attempts >= max_steps:
                out[i, j:] = np.nan
                break
            out[i, j] = y
        nfev[i] = evals


@nb.njit(cache=True)
def _probe_rate(y, probe):
    K = probe.size
    v = 0.0
    for k in range(K):
        v += probe[k] * y[K + k]
    return v


@nb.njit(cache=True)
def _extrema_kernel(y0, t0, t_end, w_stop, tab, c_damp, p_load, omega, rtol, atol, coef, max_steps,
                    times, states, count, nfev):
    N, n = y0.shape
    K = n // 2
    cap = times.shape[1]
    probe = tab.probe
    kst, tmp, g, y, f, y_new, f_new = _workspace(n, tab.weight.size)
    y_s = np.empty(n)
    f_s = np.empty(n)
    for i in range(N):
        t = t0
        model, h = _start(i, y, y0, t0, tab, c_damp, p_load, omega, g, f, rtol, atol)
        evals = 1
        found = 0
        attempts = 0
        v_old = _probe_rate(y, probe)
        while t < t_end and found < cap and attempts < max_steps:
            hs = min(h, t_end - t)
            err = _step(t, y, f, hs, model, coef, kst, tmp, g, y_new, f_new, rtol, atol)
            evals += _NS
            attempts += 1
            if err > 1.0:
                h = _new_size(hs, err)
                continue
            v_new = _probe_rate(y_new, probe)
            if (v_old > 0.0 and v_new <= 0.0) or (v_old < 0.0 and v_new >= 0.0):
                # Illinois regula falsi on the step length s in (0, hs].
                a, fa, b, fb = 0.0, v_old, hs, v_new
                side = 0
                s = hs
                for _ in range(60):
                    s = (a * fb - b * fa) / (fb - fa)
                    if not (a < s < b):
                        s = 0.5 * (a + b)
                    _step(t, y, f, s, model, coef, kst, tmp, g, y_s, f_s, rtol, atol)
                    evals += _NS
                    fs = _probe_rate(y_s, probe)
                    if fs == 0.0 or b - a <= 4e-16 * (abs(t) + hs):
                        break
                    if (fs > 0.0) == (fa > 0.0):
                        a, fa = s, fs
                        if side == -1:
                            fb *= 0.5
                        side = -1
                    else:
                        b, fb = s, fs
                        if side == 1:
                            fa *= 0.5
                        side = 1
                    if abs(fs) <= 1e-15 * (abs(v_old) + abs(v_new)):
                        break
                times[i, found] = t + s
                states[i, found] = y_s
                found += 1
                w_ext = 0.0
                for k in range(K):
                    w_ext += probe[k] * y_s[k]
                if abs(w_ext) < w_stop:
                    t = t + hs
                    y[:] = y_new
                    f[:] = f_new
                    break
            t = t + hs
            y[:] = y_new
            f[:] = f_new
            v_old = v_new
            h = _new_size(hs, err)
        count[i] = found
        nfev[i] = evals


def _batch(rom: Rom, y0, c, P0, Omega):
    """Validated ``(N, 2K)`` states and per-trajectory ``(c_damp, P0, Omega)`` arrays."""
    m = rom.membrane
    y0 = np.ascontiguousarray(np.atleast_2d(np.asarray(y0, dtype=float)))
    if y0.ndim != 2 or y0.shape[1] != 2 * rom.dof:
        raise ValueError(f"y0 shape {y0.shape} is invalid: need (N, {2 * rom.dof}) for {rom.dof} modes")
    if not np.all(np.isfinite(y0)):
        raise ValueError("y0 is invalid: the initial states must be finite")
    N = y0.shape[0]
    out = []
    for name, v, low in (("c", c, 0.0), ("P0", P0, 0.0), ("Omega", Omega, None)):
        arr = np.broadcast_to(np.asarray(v, dtype=float), (N,)).copy()
        if not np.all(np.isfinite(arr)) or (low is not None and np.any(arr < low)) \
                or (low is None and np.any(arr <= 0.0)):
            raise ValueError(f"{name} = {v!r} is invalid: must be finite and "
                             + (f">= {low}" if low is not None else "> 0"))
        out.append(arr)
    return y0, m.damping_rate(out[0]), out[1], out[2]


def _tolerances(rtol, atol):
    if not (1e-15 <= rtol < 1.0) or not (atol > 0.0):
        raise ValueError(f"rtol = {rtol!r}, atol = {atol!r} is invalid: need 1e-15 <= rtol < 1 and atol > 0")
    return float(rtol), float(atol)


def solve(rom: Rom, y0, t_eval, *, c=0.0, P0=0.0, Omega=1.0, t0=0.0, rtol=1e-10, atol=1e-12,
          max_steps=MAX_STEPS):
    """Integrate a batch of trajectories and return their states at ``t_eval``.

    Parameters
    ----------
    rom : Rom
        The reduced-order model (:func:`model.rom.build_rom`).
    y0 : (2K,) or (N, 2K) array_like
        Initial states ``(q, q')`` at ``t0`` (m, m s-1 per unit mode shape).
    t_eval : array_like
        Increasing output times (s), all ``>= t0``; the integrator lands on each exactly.
    c, P0, Omega : float or (N,) array_like
        Damping (N s m-3), pressure amplitude (Pa) and forcing frequency (rad s-1), one
        value for all trajectories or one per trajectory.
    t0 : float
        Initial time (s); the forcing is ``P0 cos(Omega t)``.
    rtol, atol : float
        Relative and absolute tolerances of the local error (per component).
    max_steps : int
        Attempted steps allowed per trajectory.

    Returns
    -------
    states : (N, len(t_eval), 2K) ndarray
        NaN from the point where a trajectory exceeded ``max_steps``.
    nfev : (N,) ndarray of int
        Right-hand side evaluations per trajectory.
    """
    y0, cd, p, om = _batch(rom, y0, c, P0, Omega)
    rtol, atol = _tolerances(rtol, atol)
    t_eval = np.ascontiguousarray(np.atleast_1d(np.asarray(t_eval, dtype=float)))
    if t_eval.ndim != 1 or t_eval.size == 0 or np.any(np.diff(t_eval) < 0) or t_eval[0] < t0:
        raise ValueError(f"t_eval = {t_eval!r} is invalid: need a non-empty increasing sequence >= t0 = {t0}")
    out = np.empty((y0.shape[0], t_eval.size, y0.shape[1]))
    nfev = np.zeros(y0.shape[0], dtype=np.int64)
    _solve_kernel(y0, float(t0), t_eval, rom.tables, cd, p, om, rtol, atol, _COEF, int(max_steps), out, nfev)
    return out, nfev


class Extrema(NamedTuple):
    """Extrema of ``w(t) = probe @ q(t)`` along a batch of trajectories.

    Attributes
    ----------
    times : (N, max_count) ndarray
        Instants (s) of the extrema, NaN past ``count``.
    states : (N, max_count, 2K) ndarray
        States there (``probe @ q'`` vanishes), NaN past ``count``.
    count : (N,) ndarray of int
        Number of extrema found per trajectory.
    nfev : (N,) ndarray of int
        Right-hand side evaluations per trajectory.
    """

    times: np.ndarray
    states: np.ndarray
    count: np.ndarray
    nfev: np.ndarray


def extrema(rom: Rom, y0, t_end, max_count, *, w_stop=0.0, c=0.0, P0=0.0, Omega=1.0,
            t0=0.0, rtol=1e-10, atol=1e-12, max_steps=MAX_STEPS) -> Extrema:
    """Integrate a batch of trajectories and record the extrema of ``w(rho_probe, 0, t)``.

    Each trajectory stops at ``t_end``, after ``max_count`` extrema, or right after an
    extremum with ``|w| < w_stop`` (m), whichever comes first.  Other parameters as in
    :func:`solve`.
    """
    y0, cd, p, om = _batch(rom, y0, c, P0, Omega)
    rtol, atol = _tolerances(rtol, atol)
    max_count = int(max_count)
    if max_count < 1 or not t_end > t0:
        raise ValueError(f"max_count = {max_count!r}, t_end = {t_end!r} is invalid: need max_count >= 1 "
                         f"and t_end > t0 = {t0}")
    N = y0.shape[0]
    times = np.full((N, max_count), np.nan)
    states = np.full((N, max_count, y0.shape[1]), np.nan)
    count = np.zeros(N, dtype=np.int64)
    nfev = np.zeros(N, dtype=np.int64)
    _extrema_kernel(y0, float(t0), float(t_end), float(w_stop), rom.tables, cd, p, om, rtol, atol,
                    _COEF, int(max_steps), times, states, count, nfev)
    return Extrema(times, states, count, nfev)
