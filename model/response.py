"""Brute-force steady-state response of the forced ROM, stepped up and down (Figs. 13, 18).

One parameter (``Omega`` or ``P0``) takes the values of a list, first in increasing and
then in decreasing order; at every value the ROM is integrated period by period (the
stroboscopic map, :class:`model.protocol.StroboscopicMap`) from the steady state of the previous
value, until the map has settled.  The descending sweep starts from the last state of the
ascending one.  Both directions therefore follow a branch until it ends at a fold and jump
there: this is the independent cross-check of :mod:`model.continuation`.

Convergence criterion (no fixed transient).  With ``y_j`` the state after ``j`` periods and
``S`` of :func:`model.forced.state_scale`, the relative stroboscopic residual is::

    r_j = |S (y_{j+1} - y_j)| / (|S y_{j+1}| + atol)

A value is settled when ``r_j < tol`` for ``consecutive`` consecutive periods (at least
``min_periods`` periods are always run).  Near a stable fixed point with leading multiplier
``mu``, the remaining distance to it is about ``r / (1 - |mu|)`` relative: with the paper's
light damping ``|mu| ~ 0.998`` per period (c = 0.05), so the default ``tol = 1e-6`` leaves
~5e-4 relative error in the state and the amplitude, far below the resolution of a sweep.  ``consecutive`` periods guard against
a momentary small residual of a trajectory that is still moving (e.g. near a turning point
of a spiralling transient).  A value that has not settled after ``max_periods`` periods is
reported as not converged, and the sweep continues from where it stopped.

A brute-force bifurcation diagram (``poincare`` > 0 in :func:`stepped_sweep`): after the
settling (which then acts as the transient; a response that is not periodic uses all of
``max_periods``), ``poincare`` more periods are iterated with the Lyapunov spectrum along
them and the response classified (:mod:`model.lyapunov`); the next value starts from the
last of these points.
"""

from __future__ import annotations

from typing import NamedTuple

import numba as nb
import numpy as np

from .integrate import rk4_steps
from .lyapunov import classify, lyapunov_spectrum
from .protocol import PARAMETERS, StroboscopicMap, kernel_arguments

#: Blocks of the Lyapunov exponents' error estimate in a bifurcation diagram
#: (:func:`model.lyapunov.lyapunov_spectrum`): ``poincare`` is a multiple of it.
LYAPUNOV_BLOCKS = 10


class PoincareRecord(NamedTuple):
    """The bifurcation diagram of a stepped sweep; axes 0, 1 as in :class:`SweepResult`.

    Attributes
    ----------
    points : (2, N, P, 2K) array
        The ``P`` Poincare points after the transient at each value.
    exponents, error : (2, N, 2K) arrays
        The Lyapunov spectrum along them (s-1, decreasing) and its statistical error.
    kind : (2, N) int8 array
        :data:`model.lyapunov.KIND_NAMES` index.
    least_period : (2, N) int array
        Period in forcing periods of a periodic response (0 otherwise).
    rotation_number : (2, N) array
        Of a quasi-periodic response (NaN otherwise).
    """

    points: np.ndarray
    exponents: np.ndarray
    error: np.ndarray
    kind: np.ndarray
    least_period: np.ndarray
    rotation_number: np.ndarray

    @classmethod
    def empty(cls, N: int, P: int, n: int) -> PoincareRecord:
        return cls(np.full((2, N, P, n), np.nan), np.full((2, N, n), np.nan), np.full((2, N, n), np.nan),
                   np.full((2, N), -1, np.int8), np.zeros((2, N), np.int64), np.full((2, N), np.nan))


class SweepResult(NamedTuple):
    """Steady states of a stepped sweep; axis 0 is the direction (0 up, 1 down).

    Attributes
    ----------
    values : (N,) array
        The parameter values in increasing order (rad s-1 or Pa).
    amplitude : (2, N) array
        ``max_t |w(0.5 Re, 0, t)|`` over the last period (m), indexed like ``values``.
    state : (2, N, 2K) array
        ``y(0)`` reached at each value.
    converged : (2, N) bool array
        The criterion was met within ``max_periods``.
    periods : (2, N) int array
        Forcing periods integrated at each value (without the Poincare points).
    poincare : PoincareRecord or None
        The bifurcation diagram, when asked for.
    """

    values: np.ndarray
    amplitude: np.ndarray
    state: np.ndarray
    converged: np.ndarray
    periods: np.ndarray
    poincare: PoincareRecord | None = None


@nb.njit(cache=True)
def _period_test(y, prev, scale, tol, atol, run, j, consecutive, min_periods):
    # The test after period j: (-1, run) when the state is not finite, (1, run) when the
    # relative stroboscopic residual has stayed below tol for `consecutive` periods (and
    # j >= min_periods), (0, run) to go on; run counts the periods below tol in a row.
    num = 0.0
    den = 0.0
    for i in range(y.size):
        d = scale[i] * (y[i] - prev[i])
        num += d * d
        den += (scale[i] * y[i]) ** 2
    if not np.isfinite(num):
        return -1, run
    run = run + 1 if np.sqrt(num) < tol * (np.sqrt(den) + atol) else 0
    return (1 if run >= consecutive and j >= min_periods else 0), run


@nb.njit(cache=True)
def _settle(y, steps, tab, forcing, scale, tol, atol, consecutive, min_periods, max_periods, work, prev):
    # Integrate whole periods in place until the relative stroboscopic residual stays
    # below tol for `consecutive` periods; returns (periods, converged).
    period = 2.0 * np.pi / forcing.Omega
    h = period / steps
    run = 0
    n = y.size
    for j in range(1, max_periods + 1):
        for i in range(n):
            prev[i] = y[i]
        rk4_steps(y, 0.0, h, steps, tab, forcing, work)
        code, run = _period_test(y, prev, scale, tol, atol, run, j, consecutive, min_periods)
        if code != 0:
            return j, code == 1
    return max_periods, False


def _settle_at(fmap, y, tol, atol, consecutive, min_periods, max_periods, work, prev):
    """:func:`_settle` on ``fmap`` in place on ``y``; returns ``(periods, converged)``.  A
    map without ``kernel_arguments`` (:mod:`model.protocol`) is advanced period by period
    from Python, with the same test."""
    kernel = kernel_arguments(fmap)
    scale = fmap.state_scale()
    if kernel is not None:
        return _settle(y, kernel.steps, kernel.tables, kernel.forcing, scale, tol, atol,
                       consecutive, min_periods, max_periods, work, prev)
    run = 0
    for j in range(1, max_periods + 1):
        prev[:] = y
        y[:] = fmap.advance(y)
        code, run = _period_test(y, prev, scale, tol, atol, run, j, consecutive, min_periods)
        if code != 0:
            return j, code == 1
    return max_periods, False


def stepped_sweep(fmap: StroboscopicMap, parameter: str, values, tol: float = 1e-6, consecutive: int = 20,
                  min_periods: int = 20, max_periods: int = 30000, atol: float = 1e-12,
                  initial=None, poincare: int = 0, max_period: int = 16, perturbation: float = 0.0) -> SweepResult:
    """Steady-state amplitudes for ``parameter`` stepped up through ``values`` and back down.

    Parameters
    ----------
    fmap : StroboscopicMap
        The stroboscopic map with the fixed forcing and the RK4 steps per period; the
        swept parameter is replaced.
    parameter : {"Omega", "P0"}
    values : array_like
        Parameter values (any order; swept in increasing order, then decreasing).
    tol, consecutive, min_periods, max_periods, atol :
        The convergence criterion of the module docstring.
    initial : (2K,) array, optional
        State at the first (smallest) value; default rest.
    poincare : int
        Poincare points per value of the bifurcation diagram (module docstring), a
        multiple of :data:`LYAPUNOV_BLOCKS`; 0: none.
    max_period : int
        Longest period the diagram's classification looks for.
    perturbation : float
        Added to every coordinate (m) at the start of each value: a state with no part in
        some coordinates (rest, or an axisymmetric response of a ROM with asymmetric modes)
        keeps none by symmetry, so without it a symmetry-breaking instability is never seen.

    Returns
    -------
    SweepResult
    """
    if parameter not in PARAMETERS:
        raise ValueError(f"parameter = {parameter!r} is invalid: must be one of {', '.join(PARAMETERS)}")
    vals = np.sort(np.asarray(values, dtype=float).ravel())
    if vals.size == 0 or not np.all(np.isfinite(vals)):
        raise ValueError(f"values = {values!r} is invalid: need a non-empty list of finite numbers")
    if parameter == "Omega" and vals[0] <= 0 or parameter == "P0" and vals[0] < 0:
        raise ValueError(f"values = {values!r} is invalid: {parameter} must be "
                         + ("> 0" if parameter == "Omega" else ">= 0"))
    if poincare < 0 or poincare % LYAPUNOV_BLOCKS or 0 < poincare < 2 * max_period:
        raise ValueError(f"poincare = {poincare!r} is invalid: need 0 or a multiple of {LYAPUNOV_BLOCKS} "
                         f"of at least 2 max_period = {2 * max_period}")
    if tol <= 0 or consecutive < 1 or min_periods < 1 or max_periods < min_periods:
        raise ValueError(f"(tol, consecutive, min_periods, max_periods) = ({tol}, {consecutive}, {min_periods}, "
                         f"{max_periods}) is invalid: need tol > 0, consecutive >= 1, "
                         "1 <= min_periods <= max_periods")
    n = 2 * fmap.dof
    y = np.zeros(n) if initial is None else np.array(initial, dtype=float)
    if y.shape != (n,):
        raise ValueError(f"initial.shape = {y.shape} is invalid: expected ({n},)")
    N = vals.size
    amp = np.empty((2, N))
    states = np.empty((2, N, n))
    conv = np.zeros((2, N), dtype=bool)
    periods = np.zeros((2, N), dtype=np.int64)
    work = np.empty((6, n))
    prev = np.empty(n)
    diagram = PoincareRecord.empty(N, poincare, n) if poincare else None
    for d, order in enumerate((range(N), range(N - 1, -1, -1))):
        for i in order:
            at = fmap.varied(parameter, vals[i])
            y[:fmap.dof] += perturbation
            periods[d, i], conv[d, i] = _settle_at(at, y, tol, atol, consecutive, min_periods, max_periods,
                                                   work, prev)
            if diagram is not None:
                y[:] = _poincare_at(at, y, poincare, max_period, diagram, d, i)
            states[d, i] = y
            amp[d, i] = at.amplitude(y)
    return SweepResult(vals, amp, states, conv, periods, diagram)


def _poincare_at(fmap, y, points, max_period, diagram: PoincareRecord, d, i) -> np.ndarray:
    # The Poincare points, Lyapunov spectrum and kind of the response from y into the
    # diagram's [d, i]; returns the last point (the state the sweep goes on from).
    record = lyapunov_spectrum(fmap, y, points, LYAPUNOV_BLOCKS)
    kind = classify(fmap, record, max_period=max_period)
    diagram.points[d, i] = record.points
    diagram.exponents[d, i] = record.exponents
    diagram.error[d, i] = record.standard_error
    diagram.kind[d, i], diagram.least_period[d, i], diagram.rotation_number[d, i] = kind
    return record.points[-1]


def refine_jumps(fmap: StroboscopicMap, parameter: str, sweep: SweepResult, max_jumps: int = 2,
                 jump_fraction: float = 0.3, rtol: float = 1e-3, tol: float = 1e-6,
                 consecutive: int = 20, max_periods: int = 30000, atol: float = 1e-12) -> np.ndarray:
    """Locate the jumps of a stepped sweep with an adaptive step, still by brute force.

    A coarse step may kick the state out of a shrinking basin before the branch ends, so a
    jump of the coarse sweep (a step whose amplitude changes by more than
    ``jump_fraction`` of the larger amplitude) is only a hint.  From the last state before
    it, the parameter is marched on with half the coarse step: a value whose steady state
    (integrated from the previous one) stays within ``jump_fraction`` of the coarse jump
    height of the previous amplitude is accepted and the march goes on, possibly past the
    coarse jump; otherwise the step is halved.  Along a branch the amplitude changes
    continuously (like ``sqrt`` of the distance at a fold) while a jump keeps its height,
    so the march ends at the branch's end, to ``rtol`` relative.  A march that reaches the
    end of the sweep found no jump.

    Returns
    -------
    (2, max_jumps) array
        Jump locations (the last accepted value plus half the last step) per direction
        (0 up, 1 down), in sweep order, NaN padded.
    """
    out = np.full((2, max_jumps), np.nan)
    vals, amp = sweep.values, sweep.amplitude
    n = 2 * fmap.dof
    work = np.empty((6, n))
    prev = np.empty(n)

    def settle(y, value):
        at = fmap.varied(parameter, value)
        _settle_at(at, y, tol, atol, consecutive, consecutive, max_periods, work, prev)
        return at.amplitude(y)

    for d in range(2):
        order = np.arange(vals.size) if d == 0 else np.arange(vals.size)[::-1]
        end = vals[order[-1]]
        found = 0
        resume_after = None
        for i, j in zip(order[:-1], order[1:]):
            if resume_after is not None and (vals[i] - resume_after) * (1 if d == 0 else -1) <= 0:
                continue
            a_lo, a_hi = amp[d, i], amp[d, j]
            if found == max_jumps or not abs(a_hi - a_lo) > jump_fraction * max(a_lo, a_hi):
                continue
            height = abs(a_hi - a_lo)
            lo, y_lo, step = vals[i], sweep.state[d, i].copy(), 0.5 * (vals[j] - vals[i])
            while abs(step) > rtol * abs(lo + step) and (end - lo - step) * np.sign(step) >= 0:
                y = y_lo.copy()
                a = settle(y, lo + step)
                if abs(a - a_lo) < jump_fraction * height:
                    lo, y_lo, a_lo = lo + step, y, a
                else:
                    step *= 0.5
            if abs(step) <= rtol * abs(lo + step):
                out[d, found] = lo + 0.5 * step
                found += 1
                resume_after = lo + step
    return out
