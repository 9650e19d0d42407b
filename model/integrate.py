"""Fixed-step integration of the ROM for stroboscopic (Poincare) sampling.

The classical fourth-order Runge-Kutta scheme with an integer number of steps per forcing
period ``2 pi / Omega``, so that every ``steps``-th state is a point of the stroboscopic
map.  :func:`rk4_steps` advances one state by a number of steps in place (the building
block of :class:`model.forced.ForcedMap`); :func:`monodromy` integrates the state together
with the variational equations and returns the monodromy matrix of the stroboscopic map
(shooting, Floquet multipliers), and :func:`monodromy_parameter` also the derivative of the
map in ``Omega`` or ``P0`` (continuation).

All kernels take the :class:`model.rom.RomTables` and a :class:`model.rom.Forcing` tuple,
except the lock-step kernels, which advance a batch of trajectories together (basins):
:func:`rk4_one_mode_lockstep` for one-mode ROMs, each RK4 stage one loop over the batch,
which the compiler vectorises with hardware gathers from the force table, and
:func:`rk4_quadrature_lockstep` for any mode set, with the quadrature force computed for
the whole batch at each quadrature point.

One-mode ROMs carry a force table (:func:`model.rom.build_rom`); for them the kernels run
a scalar loop that reads the table (about five times faster than the general loop, whose
calls pass the whole table set), and hand over to the general loop for the rest of the
period if the state leaves the table's range.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from . import rk4
from .damping_kernels import add_matrix_damping, add_matrix_damping_columns, matrix_or_none
from .noalias import NoAliasCompiler
from .transverse import slope_factors
from .rom import (TABLE_DEGREE, axisymmetric_force, axisymmetric_force_jacobian, general_force,
                  general_force_jacobian, table_eval, table_eval_pair)


@nb.njit(cache=True, fastmath=True, inline="always")
def _accel(q, v, cos_t, coef, q_max, k_force, load, c_damp, p_load):
    # One-mode acceleration q'' from the force table (|q| < q_max); cos_t = cos(Omega t).
    return -c_damp * v - k_force * q * table_eval(coef, q_max, abs(q)) + p_load * cos_t * load


@nb.njit(cache=True, fastmath=True)
def rk4_one_mode(y, t0, h, steps, coef, q_max, k_force, load, c_damp, p_load, omega, stages):
    """RK4 steps of the one-mode ROM from its force table, in place.

    Scalars rather than the :class:`model.rom.Forcing` tuple: this loop is the one-mode
    hot path.  The range of the table is tested before each evaluation (no NaN sentinel:
    fastmath assumes none); the forcing is evaluated at two times per step, the last
    stage's reused as the next step's first.

    Parameters
    ----------
    y : (2,) float array
        State ``(q, q')`` at ``t0`` (m, m s-1); receives the state after the steps done.
    t0, h : float
        Start time and step (s).
    steps : int
    coef, q_max : the table (``RomTables.stiffness_table``, ``table_max``)
    k_force, load, c_damp, p_load, omega : float
        ``RomTables.k_force[0]``, ``load[0]`` and the :class:`model.rom.Forcing` fields.
    stages : (steps, 4, 1) array or (0, 4, 1) array
        When it has rows, ``stages[i, s, 0]`` receives the coordinate at stage ``s`` of
        step ``i`` (:mod:`model.families` needs them).

    Returns
    -------
    int
        Steps done: fewer than ``steps`` when a stage would leave the table's range (``y``
        is then the last state inside it).
    """
    record = stages.shape[0] > 0
    q = y[0]
    v = y[1]
    c0 = np.cos(omega * t0)
    for i in range(steps):
        t = t0 + i * h
        if abs(q) >= q_max:
            break
        c_half = np.cos(omega * (t + rk4.stage_offset(1, h)))
        c_end = np.cos(omega * (t + rk4.stage_offset(3, h)))
        a1 = _accel(q, v, c0, coef, q_max, k_force, load, c_damp, p_load)
        q2 = q + rk4.stage_offset(1, h) * v
        v2 = v + rk4.stage_offset(1, h) * a1
        if abs(q2) >= q_max:
            break
        a2 = _accel(q2, v2, c_half, coef, q_max, k_force, load, c_damp, p_load)
        q3 = q + rk4.stage_offset(2, h) * v2
        v3 = v + rk4.stage_offset(2, h) * a2
        if abs(q3) >= q_max:
            break
        a3 = _accel(q3, v3, c_half, coef, q_max, k_force, load, c_damp, p_load)
        q4 = q + rk4.stage_offset(3, h) * v3
        v4 = v + rk4.stage_offset(3, h) * a3
        if abs(q4) >= q_max:
            break
        a4 = _accel(q4, v4, c_end, coef, q_max, k_force, load, c_damp, p_load)
        if record:
            stages[i, 0, 0] = q
            stages[i, 1, 0] = q2
            stages[i, 2, 0] = q3
            stages[i, 3, 0] = q4
        q += rk4.step_factor(h) * rk4.combine(v, v2, v3, v4)
        v += rk4.step_factor(h) * rk4.combine(a1, a2, a3, a4)
        c0 = c_end
    else:
        i = steps
    y[0] = q
    y[1] = v
    return i


#: Trajectories advanced together by :func:`rk4_one_mode_lockstep` in the basins: enough
#: to fill the vector registers several times over (measured on the Fig. 19a lattice,
#: 100 x 100: 18.4, 19.8 and 24.0 ns per trajectory and RK4 step with 64, 32 and 16).
LOCKSTEP_WIDTH = 64


def lockstep_table(tab) -> np.ndarray:
    """The one-mode stiffness table of ``tab`` (:class:`model.rom.RomTables`) transposed to
    ``(degree + 1, pieces)``, contiguous: the layout :func:`rk4_one_mode_lockstep` gathers from."""
    if tab.table_max <= 0.0:
        raise ValueError("the ROM has no force table: lock-step integration needs a one-mode ROM")
    return np.ascontiguousarray(tab.stiffness_table.T)


@nb.njit(cache=True, fastmath=True, error_model="numpy", pipeline_class=NoAliasCompiler)
def rk4_one_mode_lockstep(q, v, t0, h, steps, coef_t, q_max, k_force, load, c_damp, p_load, omega, reach):
    """Advance ``B`` one-mode trajectories ``(q[b], v[b])`` (m, m s-1) in place by ``steps`` RK4
    steps of size ``h`` (s) from ``t0``, all in lock-step.

    The same arithmetic as the scalar table loop of :func:`rk4_steps` (Eq. 31 with the force
    ``g(q) = q T(|q|)`` read from the piecewise Chebyshev table ``T``), with each stage one
    loop over the batch; the loop vectorises (gathers of the table coefficients).

    Parameters
    ----------
    q, v : (B,) arrays
        Modal coordinates and velocities, advanced in place.
    coef_t : (degree + 1, pieces) array
        :func:`lockstep_table` of the ROM.
    q_max, k_force, load, c_damp, p_load, omega : float
        Table range (m), ``C1/(Gamma M)``, load per Pa, damping rate (s-1), ``P0`` (Pa),
        ``Omega`` (rad s-1).
    reach : (B,) array
        Receives the largest ``|q|`` met at any stage.  A trajectory with
        ``reach[b] >= q_max`` left the table's range: its result is meaningless and it
        must be advanced again from its start by :func:`rk4_steps`.

    Notes
    -----
    Compiled with :class:`model.noalias.NoAliasCompiler`: ``q``, ``v``, ``coef_t`` and
    ``reach`` must be four distinct arrays.
    """
    B = q.size
    pieces = coef_t.shape[1]
    inv_width = pieces / q_max
    last = pieces - 0.5
    top = np.uint64(pieces - 1)
    qs = np.empty(B)
    vs = np.empty(B)
    acc = np.empty(B)
    dq = np.empty(B)
    dv = np.empty(B)
    far = np.zeros(B)
    for i in range(steps):
        t = t0 + i * h
        for s in range(4):
            # stage s at t + (0, h/2, h/2, h), from the previous stage's slopes
            if s == 0:
                ct = np.cos(omega * t)
                for b in range(B):
                    qs[b] = q[b]
                    vs[b] = v[b]
            else:
                f = rk4.stage_offset(s, h)
                ct = np.cos(omega * (t + f))
                for b in range(B):
                    qs[b] = q[b] + f * vs[b]
                    vs[b] = v[b] + f * acc[b]
            for b in range(B):
                x = abs(qs[b])
                far[b] = max(far[b], x)
                u = min(x * inv_width, last)  # clamped: out-of-range stages read the last piece
                j = min(np.uint64(u), top)  # unsigned (no wraparound test); in range even for NaN
                tc = 2.0 * (u - np.float64(j)) - 1.0
                b1 = coef_t[TABLE_DEGREE, j]
                b2 = 0.0
                for k in range(TABLE_DEGREE - 1, 0, -1):
                    b1, b2 = 2.0 * tc * b1 - b2 + coef_t[k, j], b1
                acc[b] = tc * b1 - b2 + coef_t[0, j]  # the table value T(|q|)
            for b in range(B):
                acc[b] = -c_damp * vs[b] - k_force * qs[b] * acc[b] + p_load * ct * load
            if s == 0:
                for b in range(B):
                    dq[b] = vs[b]
                    dv[b] = acc[b]
            else:
                w = rk4.stage_weight(s)
                for b in range(B):
                    dq[b] += w * vs[b]
                    dv[b] += w * acc[b]
        for b in range(B):
            q[b] += rk4.step_factor(h) * dq[b]
            v[b] += rk4.step_factor(h) * dv[b]
    for b in range(B):  # element by element: an array assignment compiles a costly error path
        reach[b] = far[b]


@nb.njit(cache=True, inline="always")
def _column_slopes(ys, basis, p, count, out):
    # out[b] = sum_k ys[k, b] basis[k, p]: a slope of w at quadrature point p for each of the
    # first count columns (inlined: compiled with the caller's flags, vectorised across b)
    for b in range(count):
        out[b] = ys[0, b] * basis[0, p]
    for k in range(1, basis.shape[0]):
        bk = basis[k, p]
        for b in range(count):
            out[b] += ys[k, b] * bk


@nb.njit(cache=True, inline="always")
def _add_column_forces(s, basis, p, count, acc):
    # acc[k, b] += s[b] basis[k, p]: quadrature point p's share of the forces of each column
    for k in range(basis.shape[0]):
        bk = basis[k, p]
        for b in range(count):
            acc[k, b] += s[b] * bk


#: Mode count up to which :func:`rk4_quadrature_lockstep` writes the modes of an
#: axisymmetric set out (padded with zero modes): one loop over the trajectories per
#: quadrature point instead of 2 K + 1.  Scratch measurements, ns per trajectory and step:
#: three modes, 32 points, about 110 -> 80; 160 points, 514 -> 358.  From three modes on:
#: with two the general loops are as fast (82 both), with one faster (67 against 75).
UNROLLED_MODES = 4


@nb.njit(cache=True, inline="always")
def quadrature_lockstep_pays(count):
    """True when :func:`rk4_quadrature_lockstep` on ``count`` trajectories (padded to a
    multiple of 8) is faster per trajectory than the scalar loop of :func:`rk4_steps`.

    Measured with three modes, ns per trajectory and step, lock-step against scalar: 32
    quadrature points, 334 / 299 with 8 trajectories, 186 / 344 with 10, 113 / 338 with
    16; 160 points, 1408 / 749 with 8, 736 / 881 with 10, 458 / 854 with 16 (a block of 8
    runs in the compiler's scalar remainder loop).
    """
    return count > 8


@nb.njit(cache=True, fastmath=True, error_model="numpy", pipeline_class=NoAliasCompiler)
def rk4_quadrature_lockstep(y, count, t0, h, steps, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force,
                            load, c_damp, p_load, omega, damping_matrix):
    """Advance the trajectories ``y[:, :count]`` in place by ``steps`` RK4 steps of size ``h``
    (s) from ``t0``, all in lock-step, with the quadrature force (any mode set).

    The RK4 steps of :func:`rk4_steps` on the quadrature (Eq. 31 with the force of
    :func:`model.rom.axisymmetric_force` or :func:`model.rom.general_force`; equal up to
    rounding, the sums reassociated), reorganised so that every inner loop runs over the
    trajectories: at each quadrature point the slopes of all trajectories, one division
    each, and their contributions to the forces (three or four axisymmetric modes in one
    loop, :data:`UNROLLED_MODES`).  The loops vectorise across trajectories, with no
    horizontal sums; one trajectory at a time, the loops over the 32-160 quadrature points
    are short and every force ends in ``K`` reductions.

    Parameters
    ----------
    y : (2K, B) array
        States, one trajectory per column (modal coordinates (m), then velocities (m s-1)),
        advanced in place.
    count : int
        Columns to advance (the first ``count``; the others are left as they are).
    t0, h : float
        Start time and step (s).
    steps : int
        RK4 steps.
    weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load
        The arrays, flag and material law of :class:`model.rom.RomTables` (``b_theta``
        unused when ``axisymmetric``).
    c_damp, p_load, omega : float
        Damping rate (s-1), ``P0`` (Pa), ``Omega`` (rad s-1).
    damping_matrix : (K, K) array or None
        The matrix part of the damping (:class:`model.rom.Forcing`), None for a scalar law
        (:func:`model.damping_kernels.matrix_or_none`).

    Notes
    -----
    Compiled with :class:`model.noalias.NoAliasCompiler`: ``y`` must not overlap the tables.
    """
    n, B = y.shape
    K = n // 2
    P = weight.size
    fused = axisymmetric and 3 <= K <= UNROLLED_MODES
    rows = UNROLLED_MODES if fused else K
    basis = np.zeros((rows, P))  # b_rho, with zero rows up to UNROLLED_MODES when fused
    for k in range(K):
        for p in range(P):
            basis[k, p] = b_rho[k, p]
    qs = np.zeros((rows, B))  # the stage's modal coordinates (zero rows beyond K)
    vs = np.empty((K, B))     # the stage's velocities
    acc = np.empty((rows, B))  # the stage's forces, then accelerations
    dy = np.empty((n, B))     # the weighted sum of the stages' slopes
    sa = np.empty(B)          # w_rho at one quadrature point
    sb = np.empty(B)          # w_theta at one quadrature point
    for i in range(steps):
        t = t0 + i * h
        for s in range(4):
            f = rk4.stage_offset(s, h)
            ct = np.cos(omega * (t + f))
            for k in range(K):
                for b in range(count):
                    qs[k, b] = y[k, b] + f * vs[k, b] if s > 0 else y[k, b]
                    vs[k, b] = y[K + k, b] + f * acc[k, b] if s > 0 else y[K + k, b]
            for k in range(rows):
                for b in range(count):
                    acc[k, b] = 0.0
            if fused:
                _add_axisymmetric_forces_unrolled(qs, basis, law, weight, inv_rho2, hoop2, radial2, count, acc)
            else:
                for p in range(P):
                    _column_slopes(qs, b_rho, p, count, sa)
                    w = weight[p]
                    if axisymmetric:
                        for b in range(count):
                            a = sa[b]
                            sa[b] = w * a * slope_factors(law, a, 0.0, inv_rho2[p], hoop2[p], radial2[p])[0]
                    else:
                        _column_slopes(qs, b_theta, p, count, sb)
                        for b in range(count):
                            a = sa[b]
                            c = sb[b]
                            ca, cb = slope_factors(law, a, c, inv_rho2[p], hoop2[p], radial2[p])
                            sa[b] = w * a * ca
                            sb[b] = w * c * cb
                    _add_column_forces(sa, b_rho, p, count, acc)
                    if not axisymmetric:
                        _add_column_forces(sb, b_theta, p, count, acc)
            pt = p_load * ct
            for k in range(K):
                kf = k_force[k]
                lk = pt * load[k]
                for b in range(count):
                    acc[k, b] = -c_damp * vs[k, b] - kf * acc[k, b] + lk
            if damping_matrix is not None:
                add_matrix_damping_columns(damping_matrix, vs, count, acc)
            w = rk4.stage_weight(s)
            for k in range(K):
                for b in range(count):
                    dy[k, b] = w * vs[k, b] + (dy[k, b] if s > 0 else 0.0)
                    dy[K + k, b] = w * acc[k, b] + (dy[K + k, b] if s > 0 else 0.0)
        for k in range(n):
            for b in range(count):
                y[k, b] += rk4.step_factor(h) * dy[k, b]


@nb.njit(cache=True, inline="always")
def _add_axisymmetric_forces_unrolled(qs, basis, law, weight, inv_rho2, hoop2, radial2, count, acc):
    # acc[k, b] += the axisymmetric quadrature force of column b, for UNROLLED_MODES (4)
    # modes written out (zero rows of basis beyond the ROM's): one loop over the columns
    # per quadrature point, slope, force and its shares in registers (inlined: compiled
    # with the caller's flags)
    for p in range(weight.size):
        c0 = basis[0, p]
        c1 = basis[1, p]
        c2 = basis[2, p]
        c3 = basis[3, p]
        w = weight[p]
        inv_rho2p = inv_rho2[p]
        hoop2p = hoop2[p]
        d2 = radial2[p]
        for b in range(count):
            a = qs[0, b] * c0 + qs[1, b] * c1 + qs[2, b] * c2 + qs[3, b] * c3
            g = w * a * slope_factors(law, a, 0.0, inv_rho2p, hoop2p, d2)[0]
            acc[0, b] += g * c0
            acc[1, b] += g * c1
            acc[2, b] += g * c2
            acc[3, b] += g * c3


@nb.njit(cache=True)
def rk4_steps(y, t0, h, steps, tab, forcing, work):
    """Advance ``y`` (in place) by ``steps`` RK4 steps of size ``h`` from ``t0``.

    ``forcing`` is a :class:`model.rom.Forcing`; ``work`` is a ``(6, 2K)`` scratch array (``K`` =
    number of modes).  Returns the time reached.
    """
    if tab.table_max > 0.0:
        done = rk4_one_mode(y, t0, h, steps, tab.stiffness_table, tab.table_max, tab.k_force[0],
                             tab.load[0], forcing.damping_rate, forcing.P0, forcing.Omega, np.empty((0, 4, 1)))
        t0 = t0 + done * h
        steps -= done
    if steps <= 0:
        return t0
    return _rk4_quadrature(y, t0, h, steps, tab.weight, tab.inv_rho2, tab.hoop2, tab.radial2, tab.b_rho, tab.b_theta,
                           tab.axisymmetric, tab.law, tab.k_force, tab.load, forcing.damping_rate, forcing.P0,
                           forcing.Omega, forcing.damping_matrix, work)


@nb.njit(cache=True)
def _rk4_quadrature(y, t0, h, steps, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load,
                    c_damp, p_load, omega, damping_matrix, work):
    # rk4_steps on the quadrature force (the right-hand side of model.rom.rhs, stage by
    # stage), the tables' arrays unpacked once: handing the RomTables record down to the
    # force at every stage costs about as much as the force itself (3 modes: 2.05 -> 0.8 us
    # per step; through model.rom.rhs_unpacked, 1.3 us).  A one-mode ROM whose stages left
    # its force table continues here on the quadrature (the same force to ~1e-13).
    n = y.size
    K = n // 2
    stages = work[:4]
    tmp = work[4]
    g = work[5, :K]
    scratch = np.empty((2, weight.size))
    t = t0
    for _ in range(steps):
        for s in range(4):
            f = rk4.stage_offset(s, h)
            if s == 0:
                for i in range(n):
                    tmp[i] = y[i]
            else:
                for i in range(n):
                    tmp[i] = y[i] + f * stages[s - 1, i]
            if axisymmetric:
                axisymmetric_force(tmp[:K], law, weight, inv_rho2, hoop2, radial2, b_rho, g, scratch[0])
            else:
                general_force(tmp[:K], law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, g, scratch[0], scratch[1])
            pt = p_load * np.cos(omega * (t + f))
            for i in range(K):
                stages[s, i] = tmp[K + i]
                stages[s, K + i] = -c_damp * tmp[K + i] - k_force[i] * g[i] + pt * load[i]
            if damping_matrix.shape[0] > 0:
                add_matrix_damping(damping_matrix, tmp[K:], stages[s, K:])
        for i in range(n):
            y[i] += rk4.step_factor(h) * rk4.combine(stages[0, i], stages[1, i], stages[2, i], stages[3, i])
        t += h
    return t


#: Codes of the parameter whose derivative :func:`monodromy_parameter` integrates with the state.
NO_PARAMETER, OMEGA, PRESSURE = 0, 1, 2


@nb.njit(cache=True, fastmath=True, error_model="numpy", _nrt=False)
def _aug_rhs(t, z, n, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load, c_damp, p_load, omega,
             damping_matrix, which, g, jac, work, out):
    # z = (y, V) with V = [Phi | dy/dlambda] stored row-major (n rows, n + 1 columns; n
    # without a parameter);
    # V' = A V plus, in the last column, dF/dlambda: for P0 the load (0, f cos(Omega t));
    # for Omega at fixed steps per period -F/Omega (the map in the phase tau = Omega t is
    # RK4 on F/Omega with fixed steps, so this is the derivative of the discrete map).
    # A = [[0, I], [-diag(k) J(q), -(c I + D)]] (D the damping matrix, skipped when empty);
    # rows are contiguous, so the updates vectorise.
    # The tables come unpacked (see _rk4_quadrature), the force and Jacobian by quadrature.
    # No reference counts (_nrt=False, see the note in model.rom): 650 -> 500 ns per stage
    # with 3 modes.
    K = n // 2
    w = n + 1 if which != NO_PARAMETER else n
    if axisymmetric:
        axisymmetric_force_jacobian(z[:K], law, weight, inv_rho2, hoop2, radial2, b_rho, g, jac, work)
    else:
        general_force_jacobian(z[:K], law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, g, jac, work)
    pt = p_load * np.cos(omega * t)
    for k in range(K):
        out[k] = z[K + k]
        out[K + k] = -c_damp * z[K + k] - k_force[k] * g[k] + pt * load[k]
    if damping_matrix is not None:
        add_matrix_damping(damping_matrix, z[K:n], out[K:n])
    for i in range(K):
        top = n + i * w
        vel = n + (K + i) * w
        for col in range(w):
            out[top + col] = z[vel + col]
            out[vel + col] = -c_damp * z[vel + col]
        if damping_matrix is not None:
            for l in range(K):
                d = damping_matrix[i, l]
                src = n + (K + l) * w
                for col in range(w):
                    out[vel + col] -= d * z[src + col]
        for l in range(K):
            kj = k_force[i] * jac[i, l]
            src = n + l * w
            for col in range(w):
                out[vel + col] -= kj * z[src + col]
    if which == OMEGA:
        for i in range(n):
            out[n + i * w + n] -= out[i] / omega
    elif which == PRESSURE:
        ct = np.cos(omega * t)
        for i in range(K):
            out[n + (K + i) * w + n] += load[i] * ct


@nb.njit(cache=True, fastmath={"contract"})
def monodromy_one_mode(y0, t0, h, steps, tab, forcing, which, phi, dparam):
    """:func:`monodromy_parameter` of a one-mode ROM from its force tables, compiled, for
    compiled callers (a Newton iteration).

    Fused multiply-adds only, no reassociation: the state and matrix stay bit for bit
    those of :func:`monodromy` whatever the parameter (the compiler specialises the loop
    on it).

    Parameters
    ----------
    y0 : (2,) float array
        State at ``t0``.
    t0, h : float
        Start time and RK4 step (s).
    steps : int
    tab : model.rom.RomTables
        With a force table (``table_max > 0``).
    forcing : model.rom.Forcing
    which : int
        :data:`OMEGA`, :data:`PRESSURE` or :data:`NO_PARAMETER`.
    phi : (2, 2) float array
        Receives the monodromy matrix.
    dparam : (2,) float array
        Receives the derivative in the parameter (zeros for :data:`NO_PARAMETER`).

    Returns
    -------
    q, v : float
        The state after the steps.
    ok : bool
        False when a stage leaves the table's range (``phi``, ``dparam`` then unset).
    """
    coef = tab.stiffness_table
    slope = tab.slope_table
    q_max = tab.table_max
    k_force = tab.k_force[0]
    load = tab.load[0]
    c_damp = forcing.damping_rate
    p_load = forcing.P0
    omega = forcing.Omega
    q = y0[0]
    v = y0[1]
    p00, p01, p10, p11 = 1.0, 0.0, 0.0, 1.0
    zq, zv = 0.0, 0.0
    ks = np.empty(4)
    kv = np.empty(4)
    kp = np.empty((4, 4))
    kz = np.empty((4, 2))
    c0 = np.cos(omega * t0)
    for i in range(steps):
        t = t0 + i * h
        cq = q
        cv = v
        c00, c01, c10, c11 = p00, p01, p10, p11
        cz, czv = zq, zv
        c_half = np.cos(omega * (t + rk4.stage_offset(1, h)))
        c_end = np.cos(omega * (t + rk4.stage_offset(3, h)))
        for s in range(4):
            if abs(cq) >= q_max:
                return q, v, False
            cos_t = c0 if s == 0 else (c_end if s == 3 else c_half)
            stiffness, kk = table_eval_pair(coef, slope, q_max, abs(cq))
            a = -c_damp * cv - k_force * cq * stiffness + p_load * cos_t * load
            kk *= -k_force
            ks[s] = cv
            kv[s] = a
            kp[s, 0] = c10
            kp[s, 1] = c11
            kp[s, 2] = kk * c00 - c_damp * c10
            kp[s, 3] = kk * c01 - c_damp * c11
            kz[s, 0] = czv
            kz[s, 1] = kk * cz - c_damp * czv
            if which == OMEGA:
                kz[s, 0] -= cv / omega
                kz[s, 1] -= a / omega
            elif which == PRESSURE:
                kz[s, 1] += load * cos_t
            if s < 3:
                f = rk4.stage_offset(s + 1, h)
                cq = q + f * ks[s]
                cv = v + f * kv[s]
                c00 = p00 + f * kp[s, 0]
                c01 = p01 + f * kp[s, 1]
                c10 = p10 + f * kp[s, 2]
                c11 = p11 + f * kp[s, 3]
                cz = zq + f * kz[s, 0]
                czv = zv + f * kz[s, 1]
        hs = rk4.step_factor(h)
        q += hs * rk4.combine(ks[0], ks[1], ks[2], ks[3])
        v += hs * rk4.combine(kv[0], kv[1], kv[2], kv[3])
        p00 += hs * rk4.combine(kp[0, 0], kp[1, 0], kp[2, 0], kp[3, 0])
        p01 += hs * rk4.combine(kp[0, 1], kp[1, 1], kp[2, 1], kp[3, 1])
        p10 += hs * rk4.combine(kp[0, 2], kp[1, 2], kp[2, 2], kp[3, 2])
        p11 += hs * rk4.combine(kp[0, 3], kp[1, 3], kp[2, 3], kp[3, 3])
        zq += hs * rk4.combine(kz[0, 0], kz[1, 0], kz[2, 0], kz[3, 0])
        zv += hs * rk4.combine(kz[0, 1], kz[1, 1], kz[2, 1], kz[3, 1])
        c0 = c_end
    phi[0, 0] = p00
    phi[0, 1] = p01
    phi[1, 0] = p10
    phi[1, 1] = p11
    dparam[0] = zq
    dparam[1] = zv
    return q, v, True


def monodromy_parameter(y0, t0, period, steps, tab, forcing, which):
    """State after one period, the monodromy matrix and the derivative of the map in a
    forcing parameter, all from the RK4 variational equations.

    The variational equations are integrated with the same RK4 steps as the state, so
    the matrix and the derivative are exact for the discrete stroboscopic map.  One-mode
    ROMs run the table loop; where a stage leaves the table's range, the period is
    integrated again on the quadrature (a compiled function of its own, so a one-mode job
    that never leaves the table never compiles it: 3 s of a cold start).

    Parameters
    ----------
    y0 : (2K,) float array
        State at ``t0``.
    t0, period : float
        Start time and forcing period (s).
    steps : int
        RK4 steps per period.
    tab : model.rom.RomTables
    forcing : model.rom.Forcing
    which : int
        :data:`OMEGA` (``dP/dOmega`` at fixed steps per period, the period changing with
        ``Omega``), :data:`PRESSURE` (``dP/dP0``) or :data:`NO_PARAMETER` (zeros).

    Returns
    -------
    yT : (2K,) array
    phi : (2K, 2K) array
    dparam : (2K,) array
    """
    if tab.table_max > 0.0:
        phi = np.empty((2, 2))
        dparam = np.empty(2)
        q, v, ok = monodromy_one_mode(y0, t0, period / steps, steps, tab, forcing, which, phi, dparam)
        if ok:
            return np.array([q, v]), phi, dparam
    return _monodromy_parameter_quadrature(y0, t0, period, steps, tab, forcing, which,
                                           matrix_or_none(forcing.damping_matrix))


@nb.njit(cache=True)
def _monodromy_parameter_quadrature(y0, t0, period, steps, tab, forcing, which, damping_matrix):
    # monodromy_parameter on the quadrature force, for any mode set (the damping matrix
    # None for a scalar law: model.damping_kernels)
    n = y0.size
    K = n // 2
    w = n + 1 if which != NO_PARAMETER else n
    m = n + n * w
    z = np.zeros(m)
    for i in range(n):  # element by element: an array assignment compiles a costly error path
        z[i] = y0[i]
        z[n + i * w + i] = 1.0
    k1 = np.empty(m)
    k2 = np.empty(m)
    k3 = np.empty(m)
    k4 = np.empty(m)
    tmp = np.empty(m)
    g = np.empty(K)
    jac = np.empty((K, K))
    work = np.empty((7, tab.weight.size))
    h = period / steps
    t = t0
    arrays = (tab.weight, tab.inv_rho2, tab.hoop2, tab.radial2, tab.b_rho, tab.b_theta, tab.axisymmetric, tab.law, tab.k_force, tab.load,
              forcing.damping_rate, forcing.P0, forcing.Omega, damping_matrix)
    _monodromy_quadrature(z, n, t, h, steps, *arrays, which, g, jac, work, k1, k2, k3, k4, tmp)
    # V row by row (no reshape: its error path alone costs seconds of compilation)
    phi = np.empty((n, n))
    dparam = np.zeros(n)
    for i in range(n):
        for j in range(n):
            phi[i, j] = z[n + i * w + j]
        if which != NO_PARAMETER:
            dparam[i] = z[n + i * w + n]
    return z[:n].copy(), phi, dparam


@nb.njit(cache=True)
def _monodromy_quadrature(z, n, t, h, steps, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load,
                          c_damp, p_load, omega, damping_matrix, which, g, jac, work, k1, k2, k3, k4, tmp):
    # The RK4 loop of monodromy_parameter on z = (y, V), the tables unpacked once.
    m = z.size
    for _ in range(steps):
        _aug_rhs(t, z, n, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load, c_damp, p_load, omega,
                 damping_matrix, which, g, jac, work, k1)
        for i in range(m):
            tmp[i] = z[i] + rk4.stage_offset(1, h) * k1[i]
        _aug_rhs(t + rk4.stage_offset(1, h), tmp, n, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load, c_damp,
                 p_load, omega, damping_matrix, which, g, jac, work, k2)
        for i in range(m):
            tmp[i] = z[i] + rk4.stage_offset(2, h) * k2[i]
        _aug_rhs(t + rk4.stage_offset(2, h), tmp, n, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load, c_damp,
                 p_load, omega, damping_matrix, which, g, jac, work, k3)
        for i in range(m):
            tmp[i] = z[i] + rk4.stage_offset(3, h) * k3[i]
        _aug_rhs(t + rk4.stage_offset(3, h), tmp, n, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load, c_damp, p_load,
                 omega, damping_matrix, which, g, jac, work, k4)
        for i in range(m):
            z[i] += rk4.step_factor(h) * rk4.combine(k1[i], k2[i], k3[i], k4[i])
        t += h


def monodromy(y0, t0, period, steps, tab, forcing):
    """State after one period and the monodromy matrix ``d y(t0+T) / d y(t0)``
    (:func:`monodromy_parameter` without a parameter).

    Returns
    -------
    yT : (2K,) array
    phi : (2K, 2K) array
    """
    yT, phi, _ = monodromy_parameter(y0, t0, period, steps, tab, forcing, NO_PARAMETER)
    return yT, phi
