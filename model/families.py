"""Stability of axisymmetric motion with respect to the asymmetric mode families.

On an axisymmetric state ``w0(rho, t) = sum_k q_k(t) phi_k0(rho)`` (``w_theta = 0``) the
linearised dynamics of a perturbation ``dw = sum_j u_j(t) phi_jn(rho) cos(n theta)`` does
not couple to the axisymmetric modes or to another wave number: every cross term carries
``int cos(n theta) dtheta = 0`` or ``int cos(n theta) cos(n' theta) dtheta = 0``.  The
sine companions ``phi_jn(rho) sin(n theta)`` obey the same equations (rotation by
``pi / (2n)``).  So the monodromy matrix of a mixed mode set at an axisymmetric orbit splits
into the axisymmetric block and one block per *family* ``n``, twice each (docs/model.md,
"Symmetry families").

The block of family ``n`` follows from the Hessian of the transverse energy
(:func:`model.rom.force_jacobian`) at ``w_theta = 0`` with the theta integrals done in
closed form (``int cos^2 = int sin^2 = pi``)::

    J_jl(q) = pi int rho [W_aa phi_j' phi_l' + n^2 W_bb phi_j phi_l] drho

with ``W_aa``, ``W_bb`` the second derivatives of ``W / C1`` in the slopes at ``a = w0_rho``,
``b = 0`` (:func:`model.transverse.slope_hessian`); for the neo-Hookean law::

    W_aa = 2 - 2 rho^2 r^2 / D^2 + 8 rho^2 r^4 a^2 / D^3
    W_bb = 2 / rho^2 - 2 rho^2 r'^2 / D^2,       D = r^2 (r'^2 + a^2)

and the perturbation obeys ``u'' + D u' + diag(C1 / (Gamma M_j)) J(q(t)) u = 0`` with
``M_j = pi int rho phi_j^2 drho`` and ``D`` the damping law's on the family's own linear
problem (:func:`family_damping`; ``c / (Gamma h)`` for the paper's viscous pressure).  Only a
radial quadrature is needed, whatever ``n``.

:func:`family_monodromy` integrates this block along the axisymmetric orbit with the RK4
steps of :class:`model.forced.ForcedMap`, so that it is the exact derivative of the discrete
stroboscopic map restricted to the family, as :func:`model.integrate.monodromy` is for the
axisymmetric block.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numba as nb
import numpy as np

from . import rk4
from .linear import gauss_radial
from .modes import bessel_roots, mode_shape
from .prestretch import Prestretch
from .integrate import rk4_one_mode
from .rom import Rom, piecewise_chebyshev, rhs_unpacked, unpack
from .transverse import slope_hessian


class FamilyTables(NamedTuple):
    """Radial quadrature tables of one family block, as the kernels take them.

    Attributes
    ----------
    weight : (P,) ``pi rho`` times the Gauss weight (m2)
    inv_rho2, hoop2, radial2 : (P,) ``1 / rho^2`` (m-2), ``(r_o / rho)^2`` (1), ``r_o'^2`` (1)
    axis_slope : (Ka, P) ``phi_k0'`` of the axisymmetric modes of the ROM (m-1)
    slope : (M, P) ``phi_jn'`` of the family's modes (m-1)
    hoop : (M, P) ``n phi_jn`` (1), the amplitude of the theta slope ``psi_theta``
    k_force : (M,) ``C1 / (Gamma M_j)`` (m2 s-2 per unit of ``J u``)
    law : the membrane's material law (:mod:`model.materials`)
    table_max : float, ``|q|`` covered by the table of ``J`` (one-mode ROMs; 0: no table)
    jacobian_table : (M * M, pieces, degree + 1) piecewise Chebyshev coefficients of the
        entries of ``J`` (row-major) on ``[0, table_max]`` (``J`` is even in ``q``);
        empty otherwise
    """

    weight: np.ndarray
    inv_rho2: np.ndarray
    hoop2: np.ndarray
    radial2: np.ndarray
    axis_slope: np.ndarray
    slope: np.ndarray
    hoop: np.ndarray
    k_force: np.ndarray
    law: tuple
    table_max: float
    jacobian_table: np.ndarray


@dataclass(frozen=True)
class Family:
    """The perturbations of wave number ``n`` carried by radial modes ``radial``.

    Build with :func:`build_family`.
    """

    n: int
    radial: tuple[int, ...]
    alpha: np.ndarray
    tables: FamilyTables

    @property
    def modes(self) -> tuple[tuple[int, int], ...]:
        """The ``(m, n)`` pairs of the family (cosine companions)."""
        return tuple((m, self.n) for m in self.radial)

    @property
    def size(self) -> int:
        """Dimension ``2 M`` of the family's block of the monodromy matrix."""
        return 2 * len(self.radial)

    def linear_system(self, membrane) -> tuple[np.ndarray, np.ndarray]:
        """:func:`family_linear_system` of this family on ``membrane``: what a damping law
        is built on (:func:`model.forced.family_damping`)."""
        return family_linear_system(self, membrane)


def symmetry_blocks(modes) -> tuple[list[int], list[tuple[int, tuple[int, ...], list[int]]]]:
    """Split a mode set by symmetry: the axisymmetric modes, and one block per wave number
    and companion (cosine ``n > 0``, sine ``n < 0``).

    On the axisymmetric subspace a mixed ROM's monodromy matrix is block diagonal in these
    groups; a sine block has the multipliers of the cosine block with the same radial indices.

    Returns
    -------
    axisymmetric : list of int
        Indices (into ``modes``) of the ``n = 0`` modes.
    blocks : list of (n, radial, indices)
        Per signed wave number in order of appearance: ``|n|``, the radial indices ``m``
        (sorted), and the indices into ``modes`` in that order.
    """
    axisymmetric = [i for i, (_, n) in enumerate(modes) if n == 0]
    groups: dict[int, list[int]] = {}
    for i, (_, n) in enumerate(modes):
        if n != 0:
            groups.setdefault(n, []).append(i)
    blocks = []
    for n, idx in groups.items():
        idx = sorted(idx, key=lambda i: modes[i][0])
        blocks.append((abs(n), tuple(modes[i][0] for i in idx), idx))
    return axisymmetric, blocks


def build_family(prestretch: Prestretch, rom: Rom, n: int, radial, radial_points: int | None = None,
                 jacobian_table: bool = True) -> Family:
    """The family block of wave number ``n`` for the axisymmetric ``rom``.

    Parameters
    ----------
    prestretch : Prestretch
        The static solution ``rom`` was built on.
    rom : Rom
        An axisymmetric ROM (every ``n = 0``); its orbits carry the family.
    n : int
        Wave number, ``n >= 1``.
    radial : int or sequence of int
        Radial indices ``m`` of the family's modes; an integer ``M`` means ``1..M``.
    radial_points : int, optional
        Gauss-Legendre points on ``[Ro, Re]``; default: the ROM's own radial count, and at
        least ``16 + 8 M`` for ``M = max(radial)``.  Measured on the Fig. 14a resonant
        branch (|w(0.5 Re)| = 0.45 m, n = 1, 3, 5, 8, M = 2 and 8): the largest multiplier
        changes by less than 1e-12 from 48 to 256 points.
    jacobian_table : bool
        Tabulate ``J`` for one-mode ROMs that carry a force table (default; a few hundred
        ms); without it the kernels use the radial quadrature.
    """
    if any(nn for _, nn in rom.modes):
        raise ValueError(f"modes = {list(rom.modes)} is invalid here: the family blocks need an axisymmetric ROM (every n = 0)")
    if isinstance(n, bool) or int(n) != n or n < 1:
        raise ValueError(f"n = {n!r} is invalid: a family needs a wave number n >= 1")
    n = int(n)
    radial = tuple(range(1, int(radial) + 1)) if np.ndim(radial) == 0 else tuple(int(m) for m in radial)
    if not radial or min(radial) < 1 or len(set(radial)) != len(radial):
        raise ValueError(f"radial = {list(radial)} is invalid: need distinct radial indices m >= 1")
    m = prestretch.membrane
    nr = radial_points or max(rom.radial_points, 16 + 8 * max(radial))
    rho, wr = gauss_radial(m, nr)
    alpha = bessel_roots(n, m.delta_o, max(radial))[np.array(radial) - 1]
    phi, dphi = mode_shape(rho, alpha, n, m.Re, m.delta_o)
    _, axis_slope = mode_shape(rho, rom.alpha, 0, m.Re, m.delta_o)
    weight = np.pi * rho * wr
    mass = (phi**2 * weight).sum(axis=1)
    r, dr = prestretch.radius(rho), prestretch.slope(rho)
    tables = FamilyTables(weight=weight, inv_rho2=1.0 / rho**2, hoop2=(r / rho)**2, radial2=dr**2,
                          axis_slope=np.ascontiguousarray(axis_slope), slope=np.ascontiguousarray(dphi),
                          hoop=np.ascontiguousarray(n * phi), k_force=m.C1 / (m.Gamma * mass),
                          law=m.material, table_max=0.0, jacobian_table=np.zeros((0, 0, 1)))
    if rom.tables.table_max > 0.0 and jacobian_table:
        tables = tables._replace(table_max=rom.tables.table_max,
                                 jacobian_table=_jacobian_table(tables, rom.tables.table_max))
    return Family(n, radial, alpha, tables)


def _jacobian_table(fam: FamilyTables, q_max: float) -> np.ndarray:
    """Piecewise Chebyshev tables of ``J(q)`` for a one-mode axisymmetric ROM.

    ``J`` depends on ``q`` through ``a^2`` only (even, smooth); its entries are tabulated
    by :func:`model.rom.piecewise_chebyshev` to :data:`model.rom.TABLE_TOL` relative to the
    largest entry, so that one evaluation costs ``M^2`` Clenshaw sums instead of a
    quadrature.
    """
    return piecewise_chebyshev(lambda qs: _jacobian_values(qs, fam), q_max,
                               lambda v: np.abs(v).max(axis=1, keepdims=True))


@nb.njit(cache=True)
def _jacobian_values(qs, fam):
    # J(q) of the family by its quadrature at every one-mode coordinate q of qs, raveled
    # row by row: the values _jacobian_table interpolates, in one call.
    M = fam.k_force.size
    P = fam.weight.size
    iaa, ibb, jac, q = np.empty(P), np.empty(P), np.empty((M, M)), np.empty(1)
    out = np.empty((qs.size, M * M))
    for i in range(qs.size):
        q[0] = qs[i]
        _quadrature_jacobian(q, fam, iaa, ibb, jac)
        for j in range(M):
            for l in range(M):
                out[i, j * M + l] = jac[j, l]
    return out


@nb.njit(cache=True, error_model="numpy", _nrt=False)
def family_jacobian(q, fam, iaa, ibb, out):
    """``out[j, l] = J_jl(q)`` (m2 per unit of ``u``) of the family ``fam`` at the
    axisymmetric modal coordinates ``q``; ``iaa``, ``ibb`` are ``(P,)`` work arrays.

    One-mode ROMs read the table within its range, every other case the quadrature.  Called
    at every RK4 stage: no reference counts (``_nrt=False``, see the note in :mod:`model.rom`).
    """
    if fam.table_max > 0.0 and abs(q[0]) < fam.table_max:
        _table_jacobian(fam.jacobian_table, fam.table_max, abs(q[0]), out)
        return
    _quadrature_jacobian(q, fam, iaa, ibb, out)


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def _table_jacobian(coef, q_max, x, out):
    # J from its table at |q| = x < q_max: one piece lookup, a Clenshaw sum per entry of
    # the upper triangle.
    M = out.shape[0]
    pieces = coef.shape[1]
    width = q_max / pieces
    i = min(int(x / width), pieces - 1)
    t = 2.0 * (x - i * width) / width - 1.0
    for j in range(M):
        for l in range(j, M):
            c = coef[j * M + l, i]
            b1 = 0.0
            b2 = 0.0
            for k in range(c.size - 1, 0, -1):
                b1, b2 = 2.0 * t * b1 - b2 + c[k], b1
            out[j, l] = t * b1 - b2 + c[0]
            out[l, j] = out[j, l]


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def _quadrature_jacobian(q, fam, iaa, ibb, out):
    P = fam.weight.size
    for p in range(P):
        a = 0.0
        for k in range(q.size):
            a += q[k] * fam.axis_slope[k, p]
        _, _, waa, _, wbb = slope_hessian(fam.law, a, 0.0, fam.inv_rho2[p], fam.hoop2[p], fam.radial2[p])
        iaa[p] = waa * fam.weight[p]
        ibb[p] = wbb * fam.weight[p]
    M = out.shape[0]
    for j in range(M):
        for l in range(j, M):
            acc = 0.0
            for p in range(P):
                acc += iaa[p] * fam.slope[j, p] * fam.slope[l, p] + ibb[p] * fam.hoop[j, p] * fam.hoop[l, p]
            out[j, l] = acc
            out[l, j] = acc


@nb.njit(cache=True)
def stage_coordinates(y0, t0, h, steps, tab, forcing, out):
    """The axisymmetric modal coordinates at the four RK4 stages of every step,
    ``out[i, s, :]`` ``(steps, 4, K)``, exactly as :func:`model.integrate.rk4_steps` meets
    them from ``y0`` at ``t0`` with step ``h`` (s): one-mode ROMs by the table loop of
    :mod:`model.integrate` while the stages stay in the table's range, every other case (or
    the whole period, when they leave it) by the general loop."""
    n = y0.size
    K = n // 2
    if tab.table_max > 0.0:
        done = rk4_one_mode(y0.copy(), t0, h, steps, tab.stiffness_table, tab.table_max, tab.k_force[0],
                             tab.load[0], forcing.damping_rate, forcing.P0, forcing.Omega, out)
        if done == steps:
            return
    _stage_loop(y0.copy(), t0, h, steps, unpack(tab, forcing), np.empty(n), np.empty((4, n)), np.empty(K),
                np.empty((2, tab.weight.size)), out)


@nb.njit(cache=True, _nrt=False)
def _stage_loop(y, t0, h, steps, model, ys, k, g, fw, out):
    # The general loop of stage_coordinates on work arrays allocated by the caller: no
    # reference counts at the right-hand side of every stage (see the note in model.rom).
    n = y.size
    K = n // 2
    for i in range(steps):
        t = t0 + i * h
        for s in range(4):
            f = rk4.stage_offset(s, h)
            for a in range(n):
                ys[a] = y[a] + f * k[s - 1, a] if s > 0 else y[a]
            for a in range(K):
                out[i, s, a] = ys[a]
            rhs_unpacked(t + f, ys, model, g, fw, k[s])
        for a in range(n):
            y[a] += rk4.step_factor(h) * rk4.combine(k[0, a], k[1, a], k[2, a], k[3, a])


@nb.njit(cache=True, fastmath=True, error_model="numpy", _nrt=False, inline="always")
def block_slope(ps, stiffness, row_scale, rate, matrix, out, s):
    """``out[s] = d/dt`` of the columns ``ps`` ``(2M, m)`` of ``(u, u')`` under
    ``u'' = -diag(row_scale) stiffness u - (rate + matrix) u'``: the RK4 stage slope of a
    family's variational block.  ``diag(row_scale) stiffness`` ``(M, M)`` in s-2, ``rate``
    (s-1), ``matrix`` ``(M, M)`` (s-1) or a ``(0, 0)`` array for none."""
    M = stiffness.shape[0]
    m = ps.shape[1]
    for r in range(M):
        for c in range(m):
            out[s, r, c] = ps[M + r, c]
            out[s, M + r, c] = -rate * ps[M + r, c]
        if matrix.shape[0] == M:
            for l in range(M):
                d = matrix[r, l]
                for c in range(m):
                    out[s, M + r, c] -= d * ps[M + l, c]
        for l in range(M):
            kj = row_scale[r] * stiffness[r, l]
            for c in range(m):
                out[s, M + r, c] -= kj * ps[l, c]


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def family_monodromy(y0, t0, period, steps, tab, forcing, fam, fam_rate, fam_matrix):
    """Monodromy block ``(2M, 2M)`` of family ``fam`` along the axisymmetric orbit from ``y0``.

    The axisymmetric state is advanced by the same RK4 steps as
    :func:`model.integrate.rk4_steps` (``period / steps`` each); the block's variational
    equations are integrated with it, stage by stage.

    Parameters
    ----------
    y0 : (2K,) array
        Axisymmetric state ``(q, q')`` at ``t0``.
    t0, period : float
        Start time and forcing period (s).
    steps : int
        RK4 steps per period.
    tab : model.rom.RomTables
        Tables of the axisymmetric ROM.
    forcing : model.rom.Forcing
    fam : FamilyTables
    fam_rate : float
        The scalar part of the perturbations' damping (s-1).
    fam_matrix : (M, M) array or None
        Its matrix part (:func:`model.forced.family_damping`), None for a scalar law.

    Returns
    -------
    (2M, 2M) array
        ``d u(t0 + T) / d u(t0)`` for ``u = (u, u')`` of the family.
    """
    K = y0.size // 2
    M = fam.k_force.size
    P = fam.weight.size
    m = 2 * M
    h = period / steps
    stages = np.empty((steps, 4, K))
    stage_coordinates(y0, t0, h, steps, tab, forcing, stages)
    phi = np.eye(m)
    kp = np.empty((4, m, m))
    ps = np.empty((m, m))
    iaa = np.empty(P)
    ibb = np.empty(P)
    jac = np.empty((M, M))
    table = fam.table_max > 0.0
    coef = fam.jacobian_table
    matrix = np.zeros((0, 0)) if fam_matrix is None else fam_matrix
    for i in range(steps):
        for s in range(4):
            rk4.stage_matrix(phi, kp, s, h, ps)
            if table and abs(stages[i, s, 0]) < fam.table_max:
                _table_jacobian(coef, fam.table_max, abs(stages[i, s, 0]), jac)
            else:
                family_jacobian(stages[i, s], fam, iaa, ibb, jac)
            block_slope(ps, jac, fam.k_force, fam_rate, matrix, kp, s)
        rk4.step_matrix(phi, kp, h)
    return phi


def family_linear_system(fam: Family, membrane) -> tuple[np.ndarray, np.ndarray]:
    """Mass matrix and tangent stiffness of family ``fam`` at the pre-stretched rest state,
    the family's counterpart of :func:`model.rom.linear_system`: ``Gamma h M_j`` (kg) on the
    diagonal and ``C1 h J(0)`` (N m-1).  ``membrane`` is the :class:`model.params.Membrane`
    the family was built for."""
    M = len(fam.radial)
    P = fam.tables.weight.size
    jac = np.empty((M, M))
    zero = np.zeros(fam.tables.axis_slope.shape[0])
    _quadrature_jacobian(zero, fam.tables, np.empty(P), np.empty(P), jac)
    mass = membrane.C1 / (membrane.Gamma * fam.tables.k_force)  # M_j (m2)
    return np.diag(membrane.Gamma * membrane.h * mass), membrane.C1 * membrane.h * jac


def embedded(state, dof: int) -> np.ndarray:
    """A state ``(q, q')`` of a ROM whose modes are the first ones of a ROM of ``dof`` modes, as
    a state of the larger one: the other coordinates zero."""
    state = np.asarray(state, dtype=float)
    K0 = state.size // 2
    if state.shape != (2 * K0,) or K0 > dof:
        raise ValueError(f"state shape {state.shape} is invalid: expected (2 K0,) with K0 <= {dof}")
    y = np.zeros(2 * dof)
    y[:K0], y[dof:dof + K0] = state[:K0], state[K0:]
    return y


#: How far a decaying perturbation is followed by :func:`perturbation_growth`: to this fraction
#: of its size after the settling periods.  Far below it the rounding of the force, which
#: feeds the asymmetric coordinates about 1e-12 m s-2 at an axisymmetric state of 0.15 m (the
#: full model at order 12), sets a floor of about 1e-16 m that a fast decay would reach (a
#: multiplier of 0.87 from 1e-9 m in 120 periods) and bias the rate upward; a light damping's
#: decay (0.998 per period) never comes near it.
DECAY_FLOOR = 1e-4


def floquet_start(block) -> np.ndarray:
    """``(2 A,)``: the real part of the eigenvector of the largest multiplier of a family's
    monodromy block ``(2 A, 2 A)``, scaled and turned so that its largest displacement entry
    is 1 (the real part of a complex vector can otherwise lose its displacement): a start of
    :func:`perturbation_growth` along the dominant Floquet mode (for a complex pair, in its
    plane)."""
    mu, vec = np.linalg.eig(block)
    v = vec[:, np.argmax(np.abs(mu))]
    x = v[:v.size // 2]
    # turned so that its largest displacement is real: the real part then holds it in full
    return np.real(v / x[np.argmax(np.abs(x))])


#: The largest displacement (m) of a perturbation that :func:`perturbation_growth` fits as
#: linear: past it the family's nonlinearity, not its multipliers, sets the growth.
GROWTH_LIMIT = 1e-5


class PerturbationGrowth(NamedTuple):
    """What :func:`perturbation_growth` measured.

    Attributes
    ----------
    growth : float
        The largest multiplier modulus of the family as seen by the integration.
    saturated : tuple of float
        ``(min, max)`` of ``w_asym(rho_probe, 0)`` (m) over the last tenth of the
        ``saturate`` periods, NaN without ``saturate``.
    state : (2 K,) array
        The mixed model's state at the end of the integration (after the ``saturate``
        periods): where a classification of the state reached starts
        (:func:`model.lyapunov.lyapunov_spectrum`).
    """

    growth: float
    saturated: tuple[float, float]
    state: np.ndarray


def perturbation_growth(fmap, state, asymmetric, periods: int = 100, settle: int = 20,
                        size: float = 1e-9, limit: float = GROWTH_LIMIT, saturate: int = 0,
                        probe=None, start=None, metric=None) -> PerturbationGrowth:
    """Growth per period of a small asymmetric perturbation, by integrating the nonlinear ROM.

    The independent check of :func:`family_monodromy`: ``fmap`` is the map of a mixed model
    whose first coordinates are the axisymmetric ones, followed by the family's (the ROM's
    :meth:`model.forced.ForcedMap.perturbed_family`, the full model's
    :meth:`model.full.forced.ForcedFull.perturbed_family`); ``state`` an axisymmetric
    periodic state of the axisymmetric map; the coordinates ``asymmetric`` (indices into the
    mixed model's) start at ``size`` (m) times ``start`` (``(A,)``: their shape, at rest;
    ``(2 A,)``: their shape and their velocities' (s-1); default: all ones, at rest).  After
    ``settle`` periods (for the dominant Floquet modes to take over) the norm of the
    asymmetric part ``(x, x')`` of the state, ``sqrt((x, x') metric (x, x')^T)`` (default:
    Euclidean), is recorded once per period for up to ``periods`` more, stopping early once a
    displacement exceeds ``limit`` (m; the perturbation must stay linear) or the norm falls
    below :data:`DECAY_FLOOR` of its first value (rounding), and the rate is
    the least-squares slope of its logarithm.  The fit averages the beats of complex pairs
    (a single ratio of norms does not: the Floquet vectors are not orthogonal); an energy
    norm (``metric``) keeps a pair's rotation from modulating the norm.  A start whose share
    of the dominant Floquet mode is small biases the fit: the full model's family in its
    lowest mode about the pre-stretch, at 33.81 rad/s with a dominant multiplier of 1.0175
    among pairs of 0.998, fits 1.0100 over periods 20..120 and 1.0175 only over 220..400
    (:func:`floquet_start` gives a start along the dominant mode).  With
    ``saturate > 0`` the integration goes on for that many periods more and the range of the
    asymmetric displacement at the probe over the stroboscopic samples of the last tenth is
    reported: where the perturbation grows, the size of the state it saturates at, and
    whether that state is periodic (a period-one orbit gives a range of zero width), with
    ``probe`` (``(dof,)``, needed then) giving the asymmetric displacement
    ``w_asym(rho_probe, 0) = probe @ q``.

    Returns
    -------
    PerturbationGrowth
    """
    K = fmap.dof
    z = embedded(state, K)
    idx = list(asymmetric) + [K + i for i in asymmetric]
    start = np.ones(len(asymmetric)) if start is None else np.asarray(start, float)
    z[idx[:start.size]] = size * start

    def norm(z):
        x = z[idx]
        return float(np.linalg.norm(x) if metric is None else np.sqrt(x @ metric @ x))

    z = fmap.advance(z, settle)
    norms = [norm(z)]
    for _ in range(periods):
        z = fmap.advance(z)
        norms.append(norm(z))
        if np.abs(z[list(asymmetric)]).max() > limit or norms[-1] < DECAY_FLOOR * norms[0]:
            break
    if len(norms) < 6:
        raise ValueError(f"limit = {limit} is invalid here: it or the decay floor {DECAY_FLOOR:g} reached after "
                         f"{len(norms) - 1} periods; start smaller or raise it")
    slope = np.polyfit(np.arange(len(norms)), np.log(norms), 1)[0]
    saturated = (np.nan, np.nan)
    if saturate > 0:
        if probe is None:
            raise ValueError("probe = None is invalid with saturate > 0: give the asymmetric displacement's vector")
        z = fmap.advance(z, saturate - max(saturate // 10, 1))
        samples = []
        for _ in range(max(saturate // 10, 1)):
            z = fmap.advance(z)
            samples.append(float(np.asarray(probe) @ z[:K]))
        saturated = (float(min(samples)), float(max(samples)))
    return PerturbationGrowth(float(np.exp(slope)), saturated, z)
