"""Nonlinear Galerkin reduced-order model of the transverse dynamics (Eqs. 30-31).

``w(rho, theta, t) = sum_k q_k(t) psi_k``, ``psi_k = phi_k(rho) cos(n_k theta)`` over a set
of (m, n) modes with the paper's normalisation (:mod:`model.modes`); a negative ``n`` denotes
the sine companion ``phi_{m|n|}(rho) sin(|n| theta)`` of mode (m, |n|), so that motions that
break the reflection symmetry theta -> -theta (travelling waves, rotated standing waves) can
be represented.  With the exact
transverse energy of the membrane's law (no Taylor truncation; docs/model.md, "Transverse
energy"; for the neo-Hookean law ``W / C1 = I1 - 3``)::

    D  = r'^2 r^2 + r'^2 w_theta^2 + r^2 w_rho^2
    I1 = r'^2 + w_rho^2 + (r^2 + w_theta^2)/rho^2 + rho^2 / D
    Gamma h M q'' + c M q' + C1 h g(q) = P0 cos(Omega t) f

with ``g_k = dU/dq_k = int int rho (W_a psi_k,rho + W_b psi_k,theta) / C1 dtheta drho``
(``a = w_rho``, ``b = w_theta``; the pointwise terms of :mod:`model.transverse`), ``M`` the (diagonal) modal mass, ``c`` the viscous
damping per unit undeformed area and ``f_k = int int psi_k r r' dtheta drho`` the
pressure load on the projected stretched area.

The integrals are evaluated by Gauss-Legendre in rho and the uniform (trapezoidal) rule in
theta, flattened into one list of quadrature points ``p``; the kernels below see only these
tables (:class:`RomTables`) and scalars.  State vectors are ``y = (q, q')``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numba as nb
import numpy as np
from numpy.polynomial import chebyshev as C

from .linear import gauss_radial
from .modes import bessel_roots, mode_shape
from .damping import NO_MATRIX
from .damping_kernels import add_matrix_damping
from .params import Membrane
from .prestretch import Prestretch
from .materials import extensibility, has_limit
from .transverse import energy_density, first_invariant, slope_factors, slope_hessian


class RomTables(NamedTuple):
    """Quadrature tables of one ROM, as passed to the numba kernels.

    Attributes
    ----------
    weight : (P,) quadrature weight times ``rho`` (m2)
    inv_rho2 : (P,) ``1 / rho^2`` (m-2)
    hoop2 : (P,) ``(r_o / rho)^2``, the squared hoop stretch of the pre-stretch (1)
    radial2 : (P,) ``r_o'^2``, the squared radial stretch (1)
    b_rho : (K, P) ``psi_k,rho`` (m-1)
    b_theta : (K, P) ``psi_k,theta`` (1)
    k_force : (K,) ``C1 / (Gamma M_k)`` (m2 s-2 per unit of ``g``)
    load : (K,) ``f_k / (Gamma h M_k)``: modal acceleration per Pa of pressure
    probe : (K,) ``phi_k(rho_probe)`` so that ``w(rho_probe, 0) = probe @ q``
    axisymmetric : bool, every mode has ``n = 0`` (``b_theta`` is zero and skipped)
    law : the membrane's material law (:mod:`model.materials`): the kernels compile one
        specialisation per law type
    table_max : float, ``|q|`` covered by the one-mode force table (0: no table)
    stiffness_table, slope_table : (pieces, degree + 1) piecewise Chebyshev coefficients
        of ``g(q)/q`` and ``dg/dq`` on ``[0, table_max]`` (one-mode ROMs, see
        :func:`_force_table`); empty otherwise
    """

    weight: np.ndarray
    inv_rho2: np.ndarray
    hoop2: np.ndarray
    radial2: np.ndarray
    b_rho: np.ndarray
    b_theta: np.ndarray
    k_force: np.ndarray
    load: np.ndarray
    probe: np.ndarray
    axisymmetric: bool
    law: tuple
    table_max: float
    stiffness_table: np.ndarray
    slope_table: np.ndarray


class Forcing(NamedTuple):
    """The forcing of the modal equations at one parameter point, as the kernels take it.

    Attributes
    ----------
    damping_rate : float
        The scalar part of the damping (s-1): ``c / (Gamma h)`` for the paper's viscous
        pressure (:mod:`model.damping`).
    P0 : float
        Pressure amplitude (Pa).
    Omega : float
        Forcing frequency (rad s-1); the pressure is ``P0 cos(Omega t)``.
    damping_matrix : (K, K) array
        The matrix part of the damping (s-1), ``q'' = ... - (damping_rate I +
        damping_matrix) q'``; :data:`model.damping.NO_MATRIX` (empty, the default) for a
        scalar law.
    """

    damping_rate: float
    P0: float
    Omega: float
    damping_matrix: np.ndarray = NO_MATRIX


@dataclass(frozen=True)
class Rom:
    """A reduced-order model ready for the kernels.

    Build with :func:`build_rom`.  ``tables`` feed the kernels; the remaining fields
    describe the model for reports.
    """

    membrane: Membrane
    modes: tuple[tuple[int, int], ...]
    alpha: np.ndarray
    mass: np.ndarray          # M_k (m2)
    forcing: np.ndarray       # f_k (m2)
    probe_rho: float
    radial_points: int
    theta_points: int         # the uniform rule's points on [0, 2 pi) (folded: the tables hold nt // 2 + 1)
    tables: RomTables
    prestretch: Prestretch    # the static solution it was built on

    @property
    def dof(self) -> int:
        """Number of modal coordinates K."""
        return len(self.modes)

    def displacement(self, q, rho, theta=0.0):
        """Transverse displacement ``w`` (m) at ``(rho, theta)`` for modal coordinates ``q``.

        ``q`` may carry leading batch axes; its last axis is the mode index.
        """
        m = self.membrane
        vals = np.array([mode_shape(rho, a, abs(n), m.Re, m.delta_o)[0] * _angular(n, theta)
                         for a, (_, n) in zip(self.alpha, self.modes)])
        return np.tensordot(np.asarray(q), vals, axes=([-1], [0]))


def _angular(n, theta):
    # cos(n theta) for n >= 0, the sine companion sin(|n| theta) for n < 0
    return np.cos(n * theta) if n >= 0 else np.sin(-n * theta)


def _angular_slope(n, theta):
    # d/dtheta of _angular
    return -n * np.sin(n * theta) if n >= 0 else -n * np.cos(-n * theta)


def _reflected_theta_rule(nt: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``nt``-point uniform rule on ``[0, 2 pi)`` folded onto ``[0, pi]`` for integrands
    even in ``theta``: the points ``theta_j = 2 pi j / nt``, ``j = 0 .. nt // 2``, with the
    weight ``2 pi / nt`` doubled for every point whose mirror ``2 pi - theta_j`` is another
    point of the rule (all but ``0`` and, for even ``nt``, ``pi``).

    Without sine companions (every ``n >= 0``) ``w`` is even in ``theta`` for every ``q``, so
    ``w_rho`` and ``I1`` are even, ``w_theta`` and ``dI1/dw_theta`` odd, and the integrands
    of ``M``, ``f``, ``g`` and ``dg/dq`` even: the folded rule gives the sums of the full
    rule (to rounding) with ``nt // 2 + 1`` of its ``nt`` points.
    """
    j = np.arange(nt // 2 + 1)
    weight = np.where((j == 0) | (2 * j == nt), 1.0, 2.0) * (2 * np.pi / nt)
    return 2 * np.pi * j / nt, weight


def default_quadrature(modes) -> tuple[int, int]:
    """Radial and angular points for ``modes``; ``theta_points`` is 0 when every n is 0.

    At large amplitude the integrand of the exact energy sharpens near the crest of
    ``w`` (``rho^2/D`` has complex poles close to the real axis), so the rules are sized
    for the amplitudes of the paper's analyses.  Measured relative error of the force
    against 384 radial (320 angular) points, delta = 1.1, delta_o = 0.2:
    one mode, 64 points: 4e-14 at |w| = 0.4 m, 1e-13 at 0.8 m (5e-8 at 0.8 m for
    delta_o = 0.4); modes (1..3, 0), 160 points: 1e-13 at 0.4 m, 1e-10 at 0.8 m;
    mixed set (1,0), (2,0), (1,1), (1,2) with 96 angular points: 1e-14 at |w| = 0.1 m,
    1e-6 at 0.4 m with large n > 0 content.  Pass larger counts to :func:`build_rom`
    when the tolerance in use asks for it (tests/test_rom.py shows the convergence).
    """
    mmax = max(m for m, _ in modes)
    nmax = max(abs(n) for _, n in modes)
    radial = (64 if mmax == 1 else 64 + 32 * mmax) + 8 * nmax
    return radial, (0 if nmax == 0 else 32 + 32 * nmax)


#: The radial rules :func:`lean_radial_points` tries, fewest first.
LEAN_RADIAL_POINTS = (32, 48, 64, 96, 128)


def lean_radial_points(rom: Rom, states, rtol: float = 1e-10) -> int:
    """The fewest radial points with which ``rom`` is unchanged on ``states``.

    :func:`default_quadrature` sizes the radial rule for the largest amplitudes of the
    paper's analyses (``|w|`` up to 0.8 m).  An analysis that knows the states it visits
    can use fewer points: this returns the first rule of :data:`LEAN_RADIAL_POINTS` (below
    ``rom.radial_points``) whose ROM gives the undamped modal accelerations of Eq. (31),
    elastic force and pressure load at ``P0 = 1`` Pa, within ``rtol`` times their largest
    magnitude over ``states`` of ``rom``'s, at every state; else ``rom.radial_points``.

    Parameters
    ----------
    rom : Rom
        The reference ROM (its pre-stretch, angular rule and probe are kept).
    states : (M, 2K) array
        States ``(q, q')`` (m, m s-1) the analysis will visit.
    rtol : float
        Tolerance relative to the largest acceleration.
    """
    exact = _accelerations(rom, states)
    bound = rtol * np.abs(exact).max()
    for n in LEAN_RADIAL_POINTS:
        if n >= rom.radial_points:
            break
        lean = build_rom(rom.prestretch, rom.modes, rom.probe_rho, n, rom.theta_points, force_table=False)
        if np.abs(_accelerations(lean, states) - exact).max() <= bound:
            return n
    return rom.radial_points


def acceleration_mismatch(rom: Rom, reference: Rom, states) -> float:
    """Largest difference between the undamped modal accelerations of ``rom`` and of
    ``reference`` (Eq. 31: elastic force and the load at ``P0 = 1`` Pa) over ``states``
    ``(M, 2K)``, relative to the largest acceleration of ``reference`` there."""
    exact = _accelerations(reference, states)
    return float(np.abs(_accelerations(rom, states) - exact).max() / np.abs(exact).max())


def _accelerations(rom: Rom, states) -> np.ndarray:
    # (M, K) undamped modal accelerations at P0 = 1 Pa, cos = 1 (m s-2)
    tab = rom.tables
    g, work, out = np.empty(rom.dof), force_work(tab), np.empty((len(states), rom.dof))
    for i, y in enumerate(np.asarray(states, dtype=float)):
        elastic_force(np.ascontiguousarray(y[:rom.dof]), tab, g, work)
        out[i] = tab.load - tab.k_force * g
    return out


def build_rom(prestretch: Prestretch, modes, probe_rho: float | None = None,
              radial_points: int | None = None, theta_points: int | None = None,
              force_table: bool = True) -> Rom:
    """Assemble the Galerkin ROM of Eq. (31) for ``modes`` on ``prestretch``.

    Parameters
    ----------
    prestretch : Prestretch
        Static solution; its membrane fixes geometry and material.
    modes : sequence of (m, n)
        Mode indices, ``m >= 1``, no repeats; ``n >= 0`` for ``phi_mn cos(n theta)``,
        ``n < 0`` for the sine companion ``phi_{m|n|} sin(|n| theta)``.
    probe_rho : float, optional
        Undeformed radius (m) of the reported displacement ``w(probe_rho, 0)``; default
        ``0.5 Re`` (the paper's point).  Must lie inside ``(Ro, Re)``.
    radial_points, theta_points : int, optional
        Gauss-Legendre points on ``[Ro, Re]`` and uniform points on ``[0, 2 pi)``;
        defaults from :func:`default_quadrature`.  ``theta_points = 0`` means the
        axisymmetric shortcut and is only allowed when every ``n`` is 0.  Without sine
        companions (every ``n >= 0``) the angular rule is folded onto ``[0, pi]``
        (:func:`_reflected_theta_rule`, ``theta_points // 2 + 1`` points, the same sums).
    force_table : bool
        Build the one-mode force table (:func:`_force_table`, 10-20 ms; default).
        Without it one-mode ROMs use the quadrature: slower kernels, for ROMs rebuilt often
        (curves in ``delta``).
    """
    m = prestretch.membrane
    modes = tuple((int(a), int(b)) for a, b in modes)
    if not modes:
        raise ValueError("modes = [] is invalid: give at least one (m, n) pair")
    for mm, nn in modes:
        if mm < 1:
            raise ValueError(f"mode = ({mm}, {nn}) is invalid: need m >= 1 (and n >= 0, or n < 0 for a sine companion)")
    if len(set(modes)) != len(modes):
        raise ValueError(f"modes = {list(modes)} is invalid: a mode is repeated")
    probe_rho = 0.5 * m.Re if probe_rho is None else float(probe_rho)
    if not m.Ro < probe_rho < m.Re:
        raise ValueError(f"probe_rho = {probe_rho!r} is invalid: must lie in (Ro, Re) = ({m.Ro}, {m.Re}) m")
    nr_def, nt_def = default_quadrature(modes)
    nr = radial_points or nr_def
    nt = nt_def if theta_points is None else int(theta_points)
    if nt < 0 or (nt == 0 and any(n for _, n in modes)):
        raise ValueError(f"theta_points = {nt} is invalid: must be >= 1 (0, the axisymmetric shortcut, only when "
                         "every n is 0)")
    rho, wr = gauss_radial(m, nr)
    if nt == 0:
        theta, wt = np.zeros(1), np.array([2 * np.pi])
    elif all(n >= 0 for _, n in modes):
        theta, wt = _reflected_theta_rule(nt)
    else:
        theta, wt = 2 * np.pi * np.arange(nt) / nt, np.full(nt, 2 * np.pi / nt)
    alpha = np.array([bessel_roots(abs(n), m.delta_o, mm)[-1] for mm, n in modes])
    shapes = [mode_shape(rho, a, abs(n), m.Re, m.delta_o) for a, (_, n) in zip(alpha, modes)]
    angular = np.array([_angular(n, theta) for _, n in modes])
    angular_slope = np.array([_angular_slope(n, theta) for _, n in modes])
    K, P = len(modes), rho.size * theta.size
    b_rho = np.stack([np.outer(s[1], angular[k]).ravel() for k, s in enumerate(shapes)]).reshape(K, P)
    b_theta = np.stack([np.outer(s[0], angular_slope[k]).ravel() for k, s in enumerate(shapes)]).reshape(K, P)
    psi = np.stack([np.outer(s[0], angular[k]).ravel() for k, s in enumerate(shapes)])
    rr = np.repeat(rho, theta.size)
    wq = np.outer(wr, wt).ravel()
    r, dr = prestretch.radius(rr), prestretch.slope(rr)
    mass = (psi**2 * (wq * rr)).sum(axis=1)
    forcing = (psi * (wq * r * dr)).sum(axis=1)
    probe = np.array([mode_shape(probe_rho, a, abs(n), m.Re, m.delta_o)[0] * _angular(n, 0.0)
                      for a, (_, n) in zip(alpha, modes)])
    tables = RomTables(
        weight=wq * rr, inv_rho2=1.0 / rr**2, hoop2=(r / rr)**2, radial2=dr**2,
        b_rho=np.ascontiguousarray(b_rho), b_theta=np.ascontiguousarray(b_theta),
        k_force=m.C1 / (m.Gamma * mass), load=forcing / (m.Gamma * m.h * mass), probe=probe,
        axisymmetric=nt == 0, law=m.material, table_max=0.0, stiffness_table=np.zeros((0, 1)), slope_table=np.zeros((0, 1)))
    if K == 1 and nt == 0 and force_table:
        tables = tables._replace(**_force_table(tables, _table_reach(tables, TABLE_MAX_W * m.Re / np.abs(psi).max())))
    return Rom(m, modes, alpha, mass, forcing, probe_rho, nr, nt, tables, prestretch)


#: The one-mode force table covers ``max |w|`` up to this many times ``Re``.
TABLE_MAX_W = 4.0
TABLE_DEGREE = 7
#: Relative accuracy of the table against the quadrature it replaces.
TABLE_TOL = 1e-13


#: A law with a limit of extensibility (Gent) is tabulated only where its margin
#: (:func:`model.materials.extensibility`) stays above this at every point: ``W_1 <= 4``.
TABLE_MIN_EXTENSIBILITY = 0.25


def _table_reach(tab: RomTables, q_max: float) -> float:
    """``q_max``, or less for a law with a limit of extensibility: the largest ``|q|`` of
    4096 steps up to ``q_max`` below which the margin stays above
    :data:`TABLE_MIN_EXTENSIBILITY` at every quadrature point (the force grows without bound
    towards the limit; the kernels use the quadrature beyond the table)."""
    if not has_limit(tab.law):
        return q_max
    qs = np.linspace(0.0, q_max, 4097)
    i1 = first_invariant(qs[:, None] * tab.b_rho[0], 0.0, tab.inv_rho2, tab.hoop2, tab.radial2)
    ok = extensibility(tab.law, i1).min(axis=1) >= TABLE_MIN_EXTENSIBILITY
    return float(qs[-1] if ok.all() else qs[max(int(np.argmin(ok)) - 1, 0)])


def _force_table(tab: RomTables, q_max: float) -> dict:
    """Piecewise Chebyshev tables of the one-mode force, built from the exact quadrature.

    For one axisymmetric mode the force is a scalar odd function, ``g(q) = q s(q)`` with
    ``s`` even and smooth; ``s`` and ``dg/dq`` are tabulated on ``[0, q_max]`` by
    :func:`piecewise_chebyshev` to :data:`TABLE_TOL` relative.  One evaluation then costs
    a Clenshaw sum instead of a quadrature; the tables reproduce the quadrature to ~1e-13,
    far below every tolerance in use (tests).  Beyond ``q_max`` the kernels fall back to
    the quadrature.
    """
    coef = piecewise_chebyshev(lambda qs: _stiffness_and_slope(qs, tab), q_max, np.abs)
    return {"table_max": float(q_max), "stiffness_table": coef[0].copy(), "slope_table": coef[1].copy()}


def _stiffness_and_slope(qs, tab: RomTables) -> np.ndarray:
    """``(g(q) / q, dg/dq)`` of a one-mode axisymmetric ROM by its quadrature at every ``q``
    of ``qs``, shape ``(N, 2)``: the values :func:`_force_table` interpolates.

    The sums of :func:`axisymmetric_force_jacobian` for ``K = 1``, with ``w_rho = q b``
    (``b = psi_rho``): ``g / q = sum_p c_a w b^2`` and ``dg/dq = sum_p W_aa w b^2``
    (:func:`model.transverse.slope_hessian`), in numpy on blocks of ``q``: a table takes a
    few hundred values, about a millisecond here, where a compiled kernel cost 0.8 s of
    compilation in a cold start and 0.15 s of loading from the cache.
    """
    b = tab.b_rho[0]
    wb2 = tab.weight * b * b
    hoop2, radial2, inv_rho2 = tab.hoop2, tab.radial2, tab.inv_rho2
    out = np.empty((qs.size, 2))
    block = 4096
    for i in range(0, qs.size, block):
        ca, _, waa, _, _ = slope_hessian(tab.law, qs[i:i + block, None] * b, 0.0, inv_rho2, hoop2, radial2)
        out[i:i + block, 0] = ca @ wb2
        out[i:i + block, 1] = waa @ wb2
    return out


def piecewise_chebyshev(exact, q_max: float, scale) -> np.ndarray:
    """Tables of smooth functions of ``|q|`` on ``[0, q_max]`` for :func:`table_eval`.

    ``2^j`` equal pieces of degree :data:`TABLE_DEGREE` interpolate ``exact(qs)`` (an
    ``(N, V)`` array of V functions at the N points ``qs``) at Chebyshev nodes; ``j`` is
    doubled from 16 pieces until the error at points between the nodes, divided by
    ``scale(exact(qs))`` (elementwise, broadcast against ``(N, V)``), is below
    :data:`TABLE_TOL` (or 4096 pieces are reached).

    Returns
    -------
    (V, pieces, degree + 1) array
        Chebyshev coefficients of each function on each piece.
    """
    deg = TABLE_DEGREE
    nodes = np.cos(np.pi * (np.arange(deg + 1) + 0.5) / (deg + 1))
    pieces = 16
    while True:
        width = q_max / pieces
        at_nodes = ((np.arange(pieces)[:, None] + 0.5 * (1 + nodes)) * width).ravel()
        vals = exact(at_nodes).reshape(pieces, deg + 1, -1)                      # (pieces, nodes, V)
        V = vals.shape[2]
        fit = C.chebfit(nodes, vals.transpose(1, 0, 2).reshape(deg + 1, -1), deg)  # (deg + 1, pieces V)
        coef = fit.reshape(deg + 1, pieces, V).transpose(2, 1, 0).copy()          # (V, pieces, deg + 1)
        check = (np.arange(pieces)[:, None] + np.array([0.17, 0.5, 0.83])).ravel() * width
        i = np.minimum((check / width).astype(int), pieces - 1)
        t = 2.0 * (check - i * width) / width - 1.0
        ref = exact(check)
        approx = C.chebval(t, coef[:, i].transpose(2, 0, 1), tensor=False).T    # (N, V)
        err = float(np.max(np.abs(approx - ref) / scale(ref)))
        if err < TABLE_TOL or pieces >= 4096:
            return coef
        pieces *= 2


@nb.njit(cache=True, fastmath=True, inline="always")
def _table_piece(pieces, q_max, x):
    # The piece of a table of `pieces` equal pieces on [0, q_max) containing x, and x
    # mapped to [-1, 1] on it.  The index is clamped on both sides: on x86 a NaN x
    # converts to the most negative integer, which must not become a read before the table.
    width = q_max / pieces
    i = max(0, min(int(x / width), pieces - 1))
    return i, 2.0 * (x - i * width) / width - 1.0


@nb.njit(cache=True, fastmath=True, inline="always")
def table_eval(coef, q_max, x):
    """Clenshaw sum of the piece of a force table ``coef`` containing ``x`` in ``[0, q_max)``."""
    n = coef.shape[1]
    i, t = _table_piece(coef.shape[0], q_max, x)
    b1 = 0.0
    b2 = 0.0
    for k in range(n - 1, 0, -1):
        b1, b2 = 2.0 * t * b1 - b2 + coef[i, k], b1
    return t * b1 - b2 + coef[i, 0]


@nb.njit(cache=True, fastmath=True, inline="always")
def table_eval_pair(coef_a, coef_b, q_max, x):
    """:func:`table_eval` of two tables with the same pieces (the stiffness and slope tables
    of :func:`_force_table`) at ``x``: one piece lookup, the two Clenshaw sums interleaved."""
    n = coef_a.shape[1]
    i, t = _table_piece(coef_a.shape[0], q_max, x)
    a1 = 0.0
    a2 = 0.0
    b1 = 0.0
    b2 = 0.0
    for k in range(n - 1, 0, -1):
        a1, a2 = 2.0 * t * a1 - a2 + coef_a[i, k], a1
        b1, b2 = 2.0 * t * b1 - b2 + coef_b[i, k], b1
    return t * a1 - a2 + coef_a[i, 0], t * b1 - b2 + coef_b[i, 0]


def force_work(tab: RomTables) -> np.ndarray:
    """Work space of :func:`elastic_force` and :func:`rhs` for the tables ``tab``: a
    ``(2, P)`` array (``P`` quadrature points)."""
    return np.empty((2, tab.weight.size))


@nb.njit(cache=True, fastmath=True)
def elastic_force(q, tab, out, work):
    """``out[k] = g_k(q) = dU/dq_k`` (m2 per unit q), the exact elastic force of the law.

    ``U = int int W / C1 rho dtheta drho`` (``I1 - 3`` for the neo-Hookean law); the
    physical generalised force is ``C1 h g``.  ``tab`` is a :class:`RomTables`, ``work`` a :func:`force_work` array
    (the caller's, so that hot loops allocate nothing).  One-mode ROMs read the force
    table (:func:`_force_table`) within its range, every other case the quadrature
    (:func:`axisymmetric_force`, :func:`general_force`).
    """
    _force(q, tab.table_max, tab.stiffness_table, tab.weight, tab.inv_rho2, tab.hoop2, tab.radial2, tab.b_rho, tab.b_theta,
           tab.axisymmetric, tab.law, out, work)


@nb.njit(cache=True, inline="always")
def _force(q, table_max, stiffness_table, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, out, work):
    # The force from the tables' arrays: the one-mode table within its range, else the
    # quadrature kernel of the case (inlined into elastic_force and rhs_unpacked).
    if table_max > 0.0 and abs(q[0]) < table_max:
        out[0] = q[0] * table_eval(stiffness_table, table_max, abs(q[0]))
    elif axisymmetric:
        axisymmetric_force(q, law, weight, inv_rho2, hoop2, radial2, b_rho, out, work[0])
    else:
        general_force(q, law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, out, work[0], work[1])


# The quadrature kernels run over the quadrature points innermost so that the loops
# vectorise: numpy's error model (no zero test before the division, which keeps a loop
# scalar), the caller's work rows (no allocation), and one kernel per case (a kernel with
# both cases in branches is 1.6x slower).  3 modes, 160 points: 600 -> 210 ns per force.

@nb.njit(cache=True, inline="always")
def _project(q, basis, out):
    # out[p] = sum_k q[k] basis[k, p]: a slope of w at every quadrature point (inlined, so
    # it compiles with the caller's error model and vectorises there).
    P = basis.shape[1]
    for p in range(P):
        out[p] = q[0] * basis[0, p]
    for k in range(1, q.size):
        qk = q[k]
        for p in range(P):
            out[p] += qk * basis[k, p]


@nb.njit(cache=True, inline="always")
def _point_3(q, b_rho, p):
    # The three basis values at quadrature point p and the slope w_rho there, for the
    # written-out three-mode kernels below.
    c0 = b_rho[0, p]
    c1 = b_rho[1, p]
    c2 = b_rho[2, p]
    return c0, c1, c2, q[0] * c0 + q[1] * c1 + q[2] * c2


@nb.njit(cache=True, inline="always")
def _axisymmetric_force_3(q, law, weight, inv_rho2, hoop2, radial2, b_rho, out):
    # axisymmetric_force for three modes written out: one pass over the quadrature points,
    # the slope, the force and its three shares in registers (vectorised over the points;
    # inlined: compiled with the caller's flags).  Four modes written out with rows that
    # are not constants (zero-padded) vectorised worse: 1.3-1.8x slower than this.
    g0 = g1 = g2 = 0.0
    for p in range(weight.size):
        c0, c1, c2, a = _point_3(q, b_rho, p)
        f = a * slope_factors(law, a, 0.0, inv_rho2[p], hoop2[p], radial2[p])[0] * weight[p]
        g0 += f * c0
        g1 += f * c1
        g2 += f * c2
    out[0], out[1], out[2] = g0, g1, g2


@nb.njit(cache=True, fastmath=True, error_model="numpy", _nrt=False)
def axisymmetric_force(q, law, weight, inv_rho2, hoop2, radial2, b_rho, out, a):
    """:func:`elastic_force` by quadrature for a set of axisymmetric modes (every n = 0: no
    ``w_theta`` terms), from the law and the arrays of :class:`RomTables`; ``a`` is a
    ``(P,)`` work array.  For kernels that unpack the tables once and call it at every
    stage.  Three modes are written out: one pass over the quadrature points."""
    K = q.size
    P = weight.size
    if K == 3:
        _axisymmetric_force_3(q, law, weight, inv_rho2, hoop2, radial2, b_rho, out)
        return
    _project(q, b_rho, a)
    for p in range(P):
        ap = a[p]
        a[p] = ap * slope_factors(law, ap, 0.0, inv_rho2[p], hoop2[p], radial2[p])[0] * weight[p]
    for k in range(K):
        acc = 0.0
        for p in range(P):
            acc += a[p] * b_rho[k, p]
        out[k] = acc


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def general_force(q, law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, out, a, b):
    """:func:`elastic_force` by quadrature for any mode set, from the law and the arrays of
    :class:`RomTables`; ``a``, ``b`` are ``(P,)`` work arrays."""
    K = q.size
    P = weight.size
    _project(q, b_rho, a)
    _project(q, b_theta, b)
    for p in range(P):
        ap = a[p]
        bp = b[p]
        ca, cb = slope_factors(law, ap, bp, inv_rho2[p], hoop2[p], radial2[p])
        a[p] = ap * ca * weight[p]
        b[p] = bp * cb * weight[p]
    for k in range(K):
        acc = 0.0
        for p in range(P):
            acc += a[p] * b_rho[k, p] + b[p] * b_theta[k, p]
        out[k] = acc


@nb.njit(cache=True, inline="always")
def _slopes(q, tab, p):
    # (w_rho, w_theta) at quadrature point p.
    a = 0.0
    b = 0.0
    for k in range(q.size):
        a += q[k] * tab.b_rho[k, p]
        b += q[k] * tab.b_theta[k, p]
    return a, b


@nb.njit(cache=True)
def force_jacobian(q, tab, out):
    """``out[k, l] = d g_k / d q_l`` in closed form (the Hessian of U).

    It allocates its work space; :func:`force_and_jacobian` takes the caller's, and the
    variational equations (:mod:`model.integrate`) call the quadrature kernels
    :func:`axisymmetric_force_jacobian` / :func:`general_force_jacobian` directly.
    """
    force_and_jacobian(q, tab, np.empty(q.size), out, np.empty((7, tab.weight.size)))


@nb.njit(cache=True)
def force_and_jacobian(q, tab, g, jac, work):
    """:func:`elastic_force` into ``g`` and :func:`force_jacobian` into ``jac`` in one pass
    over the quadrature points (what every stage of the variational equations needs);
    ``work`` is a ``(7, P)`` scratch array."""
    if tab.table_max > 0.0 and abs(q[0]) < tab.table_max:
        x = abs(q[0])
        g[0] = q[0] * table_eval(tab.stiffness_table, tab.table_max, x)
        jac[0, 0] = table_eval(tab.slope_table, tab.table_max, x)
    elif tab.axisymmetric:
        axisymmetric_force_jacobian(q, tab.law, tab.weight, tab.inv_rho2, tab.hoop2, tab.radial2, tab.b_rho, g, jac, work)
    else:
        general_force_jacobian(q, tab.law, tab.weight, tab.inv_rho2, tab.hoop2, tab.radial2, tab.b_rho, tab.b_theta, g, jac,
                               work)


@nb.njit(cache=True, inline="always")
def _axisymmetric_force_jacobian_3(q, law, weight, inv_rho2, hoop2, radial2, b_rho, g, jac):
    # axisymmetric_force_jacobian for three modes written out, as _axisymmetric_force_3:
    # one pass over the quadrature points, the force and the six distinct entries of the
    # Jacobian accumulated in registers (inlined: compiled with the caller's flags)
    f0 = f1 = f2 = j00 = j01 = j02 = j11 = j12 = j22 = 0.0
    for p in range(weight.size):
        c0, c1, c2, a = _point_3(q, b_rho, p)
        ca, _, waa, _, _ = slope_hessian(law, a, 0.0, inv_rho2[p], hoop2[p], radial2[p])
        w = weight[p]
        fa = a * ca * w
        iaa = waa * w
        f0 += fa * c0
        f1 += fa * c1
        f2 += fa * c2
        j00 += iaa * c0 * c0
        j01 += iaa * c0 * c1
        j02 += iaa * c0 * c2
        j11 += iaa * c1 * c1
        j12 += iaa * c1 * c2
        j22 += iaa * c2 * c2
    g[0], g[1], g[2] = f0, f1, f2
    jac[0, 0], jac[1, 1], jac[2, 2] = j00, j11, j22
    jac[0, 1] = jac[1, 0] = j01
    jac[0, 2] = jac[2, 0] = j02
    jac[1, 2] = jac[2, 1] = j12


@nb.njit(cache=True, fastmath=True, error_model="numpy", _nrt=False)
def axisymmetric_force_jacobian(q, law, weight, inv_rho2, hoop2, radial2, b_rho, g, jac, work):
    """:func:`axisymmetric_force` into ``g`` and its Jacobian into ``jac`` in one pass,
    sharing the slopes and the metric; ``work`` is a ``(7, P)`` array.  Three modes are
    written out, as in :func:`axisymmetric_force`."""
    K = q.size
    P = weight.size
    if K == 3:
        _axisymmetric_force_jacobian_3(q, law, weight, inv_rho2, hoop2, radial2, b_rho, g, jac)
        return
    a, fa, iaa = work[0], work[2], work[4]
    _project(q, b_rho, a)
    for p in range(P):
        ap = a[p]
        ca, _, waa, _, _ = slope_hessian(law, ap, 0.0, inv_rho2[p], hoop2[p], radial2[p])
        w = weight[p]
        fa[p] = ap * ca * w
        iaa[p] = waa * w
    for k in range(K):
        acc = 0.0
        for p in range(P):
            acc += fa[p] * b_rho[k, p]
        g[k] = acc
        for l in range(k, K):
            acc = 0.0
            for p in range(P):
                acc += iaa[p] * b_rho[k, p] * b_rho[l, p]
            jac[k, l] = acc
            jac[l, k] = acc


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def general_force_jacobian(q, law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, g, jac, work):
    """:func:`general_force` into ``g`` and its Jacobian into ``jac`` in one pass, sharing
    the slopes and the metric; ``work`` is a ``(7, P)`` array."""
    K = q.size
    P = weight.size
    a, b, fa, fb, iaa, iab, ibb = work[0], work[1], work[2], work[3], work[4], work[5], work[6]
    _project(q, b_rho, a)
    _project(q, b_theta, b)
    for p in range(P):
        ap = a[p]
        bp = b[p]
        ca, cb, waa, wab, wbb = slope_hessian(law, ap, bp, inv_rho2[p], hoop2[p], radial2[p])
        w = weight[p]
        fa[p] = ap * ca * w
        fb[p] = bp * cb * w
        iaa[p] = waa * w
        iab[p] = wab * w
        ibb[p] = wbb * w
    for k in range(K):
        acc = 0.0
        for p in range(P):
            acc += fa[p] * b_rho[k, p] + fb[p] * b_theta[k, p]
        g[k] = acc
        for l in range(k, K):
            acc = 0.0
            for p in range(P):
                bk = b_rho[k, p]
                tk = b_theta[k, p]
                bl = b_rho[l, p]
                tl = b_theta[l, p]
                acc += iaa[p] * bk * bl + iab[p] * (bk * tl + tk * bl) + ibb[p] * tk * tl
            jac[k, l] = acc
            jac[l, k] = acc


@nb.njit(cache=True)
def strain_energy(q, tab):
    """``U(q) - U(0) = int int (W(q) - W(0)) / C1 rho dtheta drho`` (m2); times ``C1 h`` in J
    (``W / C1 = I1 - 3`` for the neo-Hookean law)."""
    P = tab.weight.size
    e = 0.0
    for p in range(P):
        a, b = _slopes(q, tab, p)
        inv_rho2, hoop2, radial2 = tab.inv_rho2[p], tab.hoop2[p], tab.radial2[p]
        e += (energy_density(tab.law, a, b, inv_rho2, hoop2, radial2)
              - energy_density(tab.law, 0.0, 0.0, inv_rho2, hoop2, radial2)) * tab.weight[p]
    return e


@nb.njit(cache=True)
def rhs(t, y, tab, forcing, g, work, out):
    """Right-hand side of the ROM, ``y' = F(t, y)``, with ``y = (q, q')`` (Eq. 31).

    Parameters
    ----------
    t : float
        Time (s).
    y : (2K,) array
        State.
    tab : RomTables
    forcing : Forcing
        Damping rate (s-1), pressure amplitude (Pa) and frequency (rad s-1).
    g : (K,) array
        Work space for the elastic force.
    work : (2, P) array
        Work space of :func:`elastic_force` (:func:`force_work`).
    out : (2K,) array
        Receives ``y'``.
    """
    rhs_unpacked(t, y, unpack(tab, forcing), g, work, out)


@nb.njit(cache=True)
def unpack(tab, forcing):
    """The arrays of ``tab`` and the numbers of ``forcing`` as the plain tuple
    :func:`rhs_unpacked` takes: ``(table_max, stiffness_table, weight, inv_rho2, hoop2, radial2, b_rho,
    b_theta, axisymmetric, law, k_force, load, damping_rate, P0, Omega, damping_matrix)``."""
    return (tab.table_max, tab.stiffness_table, tab.weight, tab.inv_rho2, tab.hoop2, tab.radial2, tab.b_rho, tab.b_theta,
            tab.axisymmetric, tab.law, tab.k_force, tab.load, forcing.damping_rate, forcing.P0, forcing.Omega,
            forcing.damping_matrix)


# Reference counts in hot helpers.  numba increments and decrements the reference count
# of every array a function receives (an atomic operation each) unless its pruning pass
# proves the pair redundant, which it does not across branches that call other functions
# (nor for the arguments of a function inlined with inline="always").  A helper handed a
# dozen arrays at every stage then pays ~100 ns on top of its arithmetic: the one-mode
# force through _force, 10 ns as a loop body, 110 ns as a call.  Helpers called per stage
# or per period that allocate nothing are therefore compiled with _nrt=False (numba's
# option for code without managed memory, which it uses itself): no reference counts,
# and functions inlined into them inherit that.  Measured: DOP853 per evaluation, 1 mode
# 186 -> 35-40 ns, 3 modes 350 -> 200 ns; the one-mode basins tile 1.34 -> 1.17 s.
# axisymmetric_force is one of them: its three-mode branch, inlined, took ~100 ns more
# than the same loop alone until the function was compiled so.

@nb.njit(cache=True, inline="always")
def rhs_unpacked(t, y, model, g, work, out):
    """:func:`rhs` on the tuple of :func:`unpack`, for kernels that evaluate it at every
    stage: made once per integration, it spares handing the records down at every call.
    Inline it into a helper compiled with ``_nrt=False`` (see the note above): inlined into
    a function that counts references, it pays one count per array per call."""
    (table_max, stiffness_table, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, k_force, load,
     c_damp, p_load, omega, damping_matrix) = model
    K = g.size
    _force(y[:K], table_max, stiffness_table, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, axisymmetric, law, g, work)
    pt = p_load * np.cos(omega * t)
    for k in range(K):
        out[k] = y[K + k]
        out[K + k] = -c_damp * y[K + k] - k_force[k] * g[k] + pt * load[k]
    if damping_matrix.shape[0] > 0:
        add_matrix_damping(damping_matrix, y[K:], out[K:])


def linear_frequencies(rom: Rom) -> tuple[np.ndarray, np.ndarray]:
    """Small-amplitude frequencies of the ROM and their modal vectors.

    The linearisation ``q'' = -diag(k_force) J(0) q`` of Eq. (31), ``J`` the closed-form
    Jacobian of the elastic force; the same as :func:`model.linear.galerkin_frequencies`
    on the same basis.

    Returns
    -------
    omega : (K,) ndarray
        Frequencies in ascending order (rad s-1).
    vectors : (K, K) ndarray
        Column ``j`` is the modal vector of ``omega[j]`` (unnormalised).
    """
    K = rom.dof
    jac = np.empty((K, K))
    force_jacobian(np.zeros(K), rom.tables, jac)
    d = np.sqrt(rom.tables.k_force)
    lam, u = np.linalg.eigh(d[:, None] * jac * d[None, :])
    return np.sqrt(lam), d[:, None] * u


def linear_system(rom: Rom) -> tuple[np.ndarray, np.ndarray]:
    """Mass matrix and tangent stiffness of the pre-stretched rest state in the ROM's
    coordinates, ``M q'' + K0 q = 0`` at small amplitude: what a damping law needs
    (:meth:`model.damping.DampingLaw.terms`).

    Returns
    -------
    mass : (K, K) ndarray
        ``Gamma h M_k`` on the diagonal (kg).
    stiffness : (K, K) ndarray
        ``C1 h J(0)`` (N m-1), ``J`` the Jacobian of the elastic force.
    """
    m = rom.membrane
    K = rom.dof
    jac = np.empty((K, K))
    force_jacobian(np.zeros(K), rom.tables, jac)
    return np.diag(m.Gamma * m.h * rom.mass), m.C1 * m.h * 0.5 * (jac + jac.T)


def total_energy(rom: Rom, y) -> float:
    """Kinetic plus strain energy (J) of state ``y`` relative to the pre-stretched rest state."""
    m = rom.membrane
    K = rom.dof
    y = np.asarray(y, dtype=float)
    kin = 0.5 * m.Gamma * m.h * float(np.sum(rom.mass * y[K:] ** 2))
    return kin + m.C1 * m.h * strain_energy(y[:K].copy(), rom.tables)
