"""Free vibration of the membrane on the two-dimensional finite-element mesh: the independent
check of the full model's nonlinear motion (docs/model.md, "The two-dimensional
finite-element check").

The three Cartesian displacement components ``D = (d_x, d_y, d_z)`` (over ``Re``) on the
scalar basis of an :class:`model.fe_annulus.AnnulusMesh` (coordinates over ``Re``) about its
pre-stretch (:func:`model.fe_annulus.solve_fe_prestretch`): the exact energy
``h C1 Re^2 int W / C1 dA`` of :mod:`model.full.surface` with the deformation gradient's
columns ``a_j = e_j + dD/dX_j``, the kinetic energy ``(1/2) Gamma h Re^4 int |D'|^2 dA`` (the
consistent mass ``M = int phi_k phi_l dA`` of each component), both edges held at their
values in the start (the pre-stretch for the states of :meth:`FeMotion.lift`).  Lagrange's
equations are

    M D'' = -omega_0^2 f(D),     omega_0^2 = C1 / (Gamma Re^2),

``f`` the gradient of ``int W / C1 dA`` -- the full model's equations (docs/model.md,
"Axisymmetric motion") without its polar reduction.  The force is a sum over the quadrature
points: with the sparse operators ``G_j`` that give ``dD/dX_j`` at the points,
``f = G_1^T (w P_1) + G_2^T (w P_2)`` (``P_j = dW/da_j``, ``w`` the quadrature weights); the
motion uses the same sum compiled as one loop over the elements (:mod:`model.fe_kernels`).
Time integration by the classical Runge-Kutta scheme (the full model's), stable for
``omega_max dt < 2.8``: at half of that limit the transverse motion takes about a thousand
steps per period on 16 elements across, where RK4's phase error, ``(omega dt)^4 / 120``, is
below 1e-10 -- far below the mesh's error.  (The central-difference scheme of explicit
structural codes errs by ``(omega dt)^2 / 24`` at the same step, 2e-6, and with the step
bound to the mesh its error falls only as ``h^2``, below the elements' order.)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

from model.fe_annulus import FePrestretch, linear_operators, ray_nodes
from model.fe_kernels import fe_force
from model.full import surface
from model.full.linear import transverse_mode

#: Fraction of RK4's stability limit ``2.8 / omega_max`` the time step takes (RK4 damps the
#: mesh's fastest modes, excited by the lifted start, by about 5 % per step there).
STABILITY_FRACTION = 0.5
#: ``omega_max dt`` of the harmonics' reference motion (:func:`harmonic_reference`), the
#: product of its RK4 step with the harmonics' highest frequency.  RK4's phase error on the
#: fast in-plane modes falls as ``(omega dt)^4``.  From rest at a 5 cm orbit's deflection
#: (delta = 1.5, order 16, harmonics 0..3) plus 1 cm of n = 1, the in-plane fields relaxed
#: to it (:meth:`model.full.harmonic.HarmonicFull.relaxed`), halving the step moves u and v
#: by 1.2e-5 and 6.0e-6 of their largest values from 2.0 (near RK4's limit of 2.8), by
#: 6.6e-8 and 1.2e-8 from 0.25, the value here (orders 3.7 and 3.6 from 0.5;
#: ``tests/test_fe_motion.py``); w and its odd part move by 9e-10 and 4e-9.  A larger step
#: would do for the check's purpose; this one is kept because the reference costs little
#: beside the mesh's integration (0.8 s for two periods on 24 functions, harmonics 0..3,
#: against about 10 s on 16 elements across).
REFERENCE_STEP = 0.25


@dataclass(frozen=True, eq=False)
class FeMotion:
    """The free motion of the membrane on the mesh of ``state`` (build with :meth:`build`).

    Attributes
    ----------
    state : FePrestretch
    basis : skfem.Basis
        The scalar basis; a displacement field is ``(3, basis.N)`` (scaled by ``Re``).
    rest : numpy.ndarray
        The pre-stretched state ``(3, N)``: the pre-stretch in-plane, ``d_z = 0``.
    free : numpy.ndarray
        The scalar dofs off both edges.
    """

    state: FePrestretch
    basis: object
    rest: np.ndarray
    free: np.ndarray
    gradient_x: sp.csr_matrix
    gradient_y: sp.csr_matrix
    weights: np.ndarray
    #: what :func:`model.fe_kernels.fe_force` takes before the state: the law, each element's
    #: dofs ``(elements, 6)``, the basis functions' derivatives ``(elements, points, 6)`` in
    #: ``X`` and ``Y`` and the weights ``(elements, points)``
    kernel_tables: tuple
    mass: sp.csc_matrix
    mass_factor: object
    omega0_2: float
    #: the highest natural frequency (rad s-1) of the mesh about the pre-stretch, in-plane or
    #: transverse (it bounds the time step)
    omega_max: float

    @classmethod
    def build(cls, state: FePrestretch) -> FeMotion:
        """The operators of the motion about ``state``."""
        m = state.mesh.membrane
        omega0_2 = m.C1 / (m.Gamma * m.Re**2)
        *_, largest_inplane = _highest_eigenvalue(state, "UV")
        # the transverse basis, mass and free dofs serve every component
        basis, free, mass_free, largest_transverse = _highest_eigenvalue(state, "W")
        largest = max(largest_inplane, largest_transverse)
        nodes = basis.N
        points = basis.X.shape[1]
        elements = basis.nelems
        rows = np.arange(elements * points).reshape(elements, points)
        grads = np.array([basis.basis[i][0].grad for i in range(basis.Nbfun)])  # (functions, 2, elements, points)
        cols = np.broadcast_to(basis.element_dofs[:, :, None], (basis.Nbfun, elements, points))
        shape = (elements * points, nodes)
        operators = [sp.csr_matrix((grads[:, j].ravel(), (np.broadcast_to(rows, cols.shape).ravel(), cols.ravel())),
                                   shape=shape) for j in range(2)]
        local = [np.ascontiguousarray(grads[:, j].transpose(1, 2, 0)) for j in range(2)]
        tables = (m.material, np.ascontiguousarray(basis.element_dofs.T, dtype=np.int64), *local,
                  np.ascontiguousarray(basis.dx))
        rest = np.zeros((3, nodes))
        for c, dofs in enumerate(state.basis.split_indices()):
            rest[c] = state.d[dofs]
        return cls(state, basis, rest, free, operators[0], operators[1], basis.dx.ravel(), tables, mass_free,
                   spla.splu(mass_free), omega0_2, float(np.sqrt(omega0_2 * largest)))

    def columns(self, D):
        """``a1``, ``a2`` (``(points, 3)``) of the deformation ``X + D``."""
        a1 = (self.gradient_x @ D.T)
        a2 = (self.gradient_y @ D.T)
        a1[:, 0] += 1.0
        a2[:, 1] += 1.0
        return a1, a2

    def energy(self, D) -> float:
        """``int W / C1 dA`` (the energy over ``h C1 Re^2``)."""
        return float(surface.energy(self.state.mesh.membrane.material, *self.columns(D)) @ self.weights)

    def force(self, D) -> np.ndarray:
        """``f = d energy / dD`` (``(3, N)``) by sparse products (the reference of
        :meth:`compiled_force`)."""
        p1, p2 = surface.gradient(self.state.mesh.membrane.material, *self.columns(D))
        return (self.gradient_x.T @ (self.weights[:, None] * p1) + self.gradient_y.T @ (self.weights[:, None] * p2)).T

    def compiled_force(self, D) -> np.ndarray:
        """:meth:`force` by the compiled element loop (:func:`model.fe_kernels.fe_force`)."""
        out = np.empty((3, self.basis.N))
        fe_force(*self.kernel_tables, np.ascontiguousarray(D, dtype=float), out)
        return out

    def acceleration(self, D) -> np.ndarray:
        """``D''`` (s-2) on the free dofs (``(3, free)``)."""
        return -self.omega0_2 * self.mass_factor.solve(np.ascontiguousarray(self.compiled_force(D)[:, self.free].T)).T

    def kinetic(self, V) -> float:
        """``(1/2) V^T M V`` over ``omega_0^2`` for velocities ``(3, free)``: the kinetic energy in
        the units of :meth:`energy`."""
        return 0.5 * float(sum(v @ (self.mass @ v) for v in V)) / self.omega0_2

    def polar_nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """The scaled undeformed radius and the angle (rad) of every node, ``(N,)`` each."""
        X = self.basis.doflocs
        return np.hypot(X[0], X[1]), np.arctan2(X[1], X[0])

    def lift_fields(self, u, v, w):
        """The field ``(3, N)``: the rest state plus the displacement ``u e_r + v e_theta + w
        e_z`` given at the nodes (``(N,)`` each, in units of ``Re``; :meth:`polar_nodes`)."""
        _, theta = self.polar_nodes()
        cos, sin = np.cos(theta), np.sin(theta)
        return self.rest + np.stack([u * cos - v * sin, u * sin + v * cos, np.broadcast_to(w, cos.shape)])

    def lift(self, u, w):
        """The field ``(3, N)``: the rest state plus the axisymmetric displacement ``u(rho) e_r +
        w(rho) e_z`` (callables of the scaled undeformed radius, in units of ``Re``)."""
        rho, _ = self.polar_nodes()
        return self.lift_fields(u(rho), 0.0, w(rho))

    def probe(self, rho) -> sp.csr_matrix:
        """The rows that evaluate a scalar field at the undeformed points ``(rho, 0)`` (scaled;
        one row per radius of ``rho``, a number or an array).

        The ray ``theta = 0`` is made of element edges whose midpoints lie at the mean radius
        of their ends (:meth:`model.fe_annulus.AnnulusMesh.build`), so that along it a P2 field
        is the quadratic in ``rho`` through its three nodal values on the edge: exact."""
        if self.state.mesh.element != "P2":
            raise ValueError(f"element = {self.state.mesh.element!r} is invalid: the probe needs P2")
        on_ray = ray_nodes(self.basis.doflocs)
        r = self.basis.doflocs[0, on_ray]  # vertex, midpoint, vertex, midpoint, ..., vertex
        radii = np.atleast_1d(np.asarray(rho, float))
        outside = radii[(radii < r[0] * (1.0 - 1e-12)) | (radii > r[-1] * (1.0 + 1e-12))]
        if outside.size:
            raise ValueError(f"rho = {float(outside[0])!r} is invalid: must lie in [{r[0]:g}, {r[-1]:g}]")
        edge = np.clip(np.searchsorted(r[::2], radii, side="right") - 1, 0, r.size // 2 - 1)
        cols = on_ray[2 * edge[:, None] + np.arange(3)]  # (radii, 3): the edge's three nodes
        x = r[2 * edge[:, None] + np.arange(3)]
        weights = np.stack([np.prod([(radii - x[:, k]) / (x[:, i] - x[:, k]) for k in range(3) if k != i], axis=0)
                            for i in range(3)], axis=1)
        rows = np.repeat(np.arange(radii.size), 3)
        return sp.csr_matrix((weights.ravel(), (rows, cols.ravel())), shape=(radii.size, self.basis.N))

    def motion(self, D0, dt: float, steps: int, record) -> None:
        """The free motion from rest at ``D0`` by ``steps`` RK4 steps of ``dt`` (s);
        ``record(step, D, V)`` is called on the displacement (``(3, N)``) and the velocities of
        the free dofs (``(3, free)``, s-1) at ``t = step dt``, ``step = 0 .. steps``."""
        D = np.array(D0, float)
        x = D[:, self.free].copy()
        v = np.zeros_like(x)

        def rate(x_, v_):
            D[:, self.free] = x_
            return v_, self.acceleration(D)

        record(0, D, v)
        for step in range(1, steps + 1):
            k1 = rate(x, v)
            k2 = rate(x + 0.5 * dt * k1[0], v + 0.5 * dt * k1[1])
            k3 = rate(x + 0.5 * dt * k2[0], v + 0.5 * dt * k2[1])
            k4 = rate(x + dt * k3[0], v + dt * k3[1])
            x = x + dt / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
            v = v + dt / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
            D[:, self.free] = x
            record(step, D, v)

    def time_step(self) -> float:
        """:data:`STABILITY_FRACTION` of RK4's limit ``2.8 / omega_max`` (s)."""
        return STABILITY_FRACTION * 2.8 / self.omega_max


def _highest_eigenvalue(state: FePrestretch, fields: str):
    """The basis of ``fields``, its dofs off the edges, the mass there and the largest
    eigenvalue of the stiffness over the mass about the pre-stretch (scaled)."""
    basis, K, mass = linear_operators(state, fields)
    free = np.setdiff1d(np.arange(basis.N), basis.get_dofs().all())
    mass_free = mass[free][:, free].tocsc()
    largest = spla.eigsh(K[free][:, free].tocsc(), k=1, M=mass_free, which="LA", return_eigenvectors=False, tol=1e-6)[0]
    return basis, free, mass_free, float(largest)


class FeOrbitCheck(NamedTuple):
    """The motion on the mesh from the turning point of a full-model free orbit
    (:func:`check_free_orbit`)."""

    #: frequency (rad s-1) of the motion on the mesh, from the instants of its extrema of ``w``
    #: at the probe (NaN when they are not one per half period)
    omega: float
    #: the range (rad s-1) of the frequencies ``pi / (t_(k+1) - t_k)`` of its half periods
    #: (``t_0 = 0``, the start at rest): the motion from the lifted start also carries the
    #: mesh's other modes, and a frequency difference below this range is not resolved
    omega_spread: float
    #: ``max |w_fe - w_full|`` over the instants and radii, over ``max |w_full|``
    w_deviation: float
    #: the same for the radial displacement ``u`` (from the pre-stretch)
    u_deviation: float
    #: the time step (s)
    dt: float


def extremum_times(signal, dt: float) -> np.ndarray:
    """Instants (s) of the interior extrema of ``signal`` (sampled every ``dt`` from ``t = 0``),
    each at the vertex of the parabola through its sample and the two neighbours."""
    s = np.asarray(signal, float)
    i = 1 + np.flatnonzero((s[1:-1] - s[:-2]) * (s[2:] - s[1:-1]) < 0)
    left, mid, right = s[i - 1], s[i], s[i + 1]
    return dt * (i + 0.5 * (left - right) / (left - 2.0 * mid + right))


def check_free_orbit(motion: FeMotion, free, q0, period: float, periods: int, rho,
                     samples: int = 64) -> FeOrbitCheck:
    """Integrate the mesh's motion from rest at the full model's orbit state ``q0`` and
    compare it with the orbit.

    Parameters
    ----------
    motion : FeMotion
    free : model.full.free.FreeFull
        The full model whose free periodic orbit from rest at ``q0`` has ``period`` (s).
    periods : int
        Periods integrated (>= 1).
    rho : array_like
        Undeformed radii (m) on the ray ``theta = 0`` where ``u`` and ``w`` are compared, at
        ``samples`` instants per period.

    Returns
    -------
    FeOrbitCheck
        The deviations over the ``periods`` periods; the frequency from the instants
        ``t_1 .. t_2P`` of the extrema of ``w`` at ``free.probe_rho`` (the trace runs a quarter
        period longer, so that the last is interior), the slope of ``k = omega t_k / pi`` by
        least squares through the origin, and the range of its half periods' frequencies;
        both NaN when the trace does not have exactly ``2 periods`` extrema there (other
        modes bending ``w`` into extra ones).
    """
    re = motion.state.mesh.membrane.Re
    basis, order = free.model.state.basis, free.model.order
    q0 = np.asarray(q0, float)
    D0 = motion.lift(lambda s: basis.evaluate(q0[:order], s)[0], lambda s: basis.evaluate(q0[order:], s)[0])
    rows = motion.probe(np.asarray(rho, float) / re)
    probe = motion.probe(free.probe_rho / re)
    every = int(np.ceil(period / samples / motion.time_step()))
    steps = periods * samples * every
    extra = samples * every // 4  # a quarter period more for the trace
    trace, u, w = np.empty(steps + extra + 1), [], []

    def record(step, D, V):
        trace[step] = (probe @ D[2])[0]
        if step % every == 0 and step < steps:
            u.append(rows @ (D[0] - motion.rest[0]))
            w.append(rows @ D[2])

    dt = period / (samples * every)
    motion.motion(D0, dt, steps + extra, record)
    u_full, w_full = free.snapshots(q0, period, samples, rho, periods=periods)
    u_fe, w_fe = re * np.array(u), re * np.array(w)
    times = extremum_times(trace, dt)
    omega = spread = np.nan
    if times.size == 2 * periods:
        k = np.arange(1, times.size + 1)
        omega = np.pi * float(k @ times) / float(times @ times)
        spread = float(np.ptp(np.pi / np.diff(np.concatenate([[0.0], times]))))
    return FeOrbitCheck(omega, spread, float(np.abs(w_fe - w_full).max() / np.abs(w_full).max()),
                        float(np.abs(u_fe - u_full).max() / np.abs(u_full).max()), dt)


class HarmonicReference(NamedTuple):
    """The full model's undamped free motion on its circumferential harmonics from rest at a
    state (:func:`harmonic_reference`): what :func:`check_harmonic_motion` compares a mesh with."""

    #: the :class:`model.full.harmonic.HarmonicFull` it ran on
    harmonic: object
    #: the coordinates ``(samples periods + 1, dof)`` (over ``Re``) at ``t = k period / samples``
    coordinates: np.ndarray
    #: the time unit (s), the periods integrated and the samples per period
    period: float
    periods: int
    samples: int
    #: the RK4 step (s)
    dt: float


def asymmetric_start(harmonic, q, size: float) -> np.ndarray:
    """``(dof,)``: the coordinates (over ``Re``) on ``harmonic``
    (:class:`model.full.harmonic.HarmonicFull`) of the axisymmetric state ``q`` (``(U, W)``,
    over ``Re``: a free orbit's of :class:`model.full.free.FreeFull`) plus ``size`` (m) of the
    lowest transverse mode of its wave number ``n`` (:func:`wave_number`) about the pre-stretch
    (its largest ``|w|``; :func:`model.full.linear.transverse_mode`) on the harmonic ``n``.
    ``q`` may hold fewer radial functions per field than ``harmonic``: the Legendre-Galerkin
    functions do not depend on the order (:mod:`model.full.radial`), so the same displacement
    fields (from each order's own pre-stretch) take zeros on the functions added."""
    n = wave_number(harmonic)
    model = harmonic.model
    out = np.zeros(harmonic.dof)
    U, W = np.split(np.asarray(q, float), 2)
    if U.size > model.order:
        raise ValueError(f"q holds {U.size} radial functions per field: more than the model's {model.order}")
    out[harmonic.block(0, "U")][:U.size], out[harmonic.block(0, "W")][:W.size] = U, W
    out[harmonic.block(n, "W")] = size / model.membrane.Re * transverse_mode(model.state, n)[1]
    return out


def wave_number(harmonic) -> int:
    """The lowest nonzero circumferential harmonic of ``harmonic``
    (:class:`model.full.harmonic.HarmonicFull`): the wave number ``n`` of its asymmetric motion,
    whose part on the odd multiples of ``n`` is ``w(theta) - w(theta + pi / n)``, halved.

    Raises
    ------
    ValueError
        When ``harmonic`` has no nonzero harmonic, or one that is not a multiple of ``n``.
    """
    n = min((k for k in harmonic.harmonics if k > 0), default=0)
    if n == 0 or any(k % n for k in harmonic.harmonics):
        raise ValueError(f"harmonics = {list(harmonic.harmonics)} is invalid here: 0 and multiples of a wave "
                         "number n >= 1, at least n itself")
    return n


def harmonic_reference(harmonic, q0, period: float, periods: int, samples: int = 64,
                       step: float = REFERENCE_STEP) -> HarmonicReference:
    """The undamped free motion of ``harmonic`` (:class:`model.full.harmonic.HarmonicFull`)
    from rest at ``q0`` (``(dof,)``, over ``Re``) for ``periods`` of ``period`` (s), sampled
    ``samples`` times per period, by RK4 with the largest whole fraction of the sampling
    interval whose product with the harmonics' highest frequency is at most ``step``
    (default :data:`REFERENCE_STEP`; RK4 is stable below 2.8)."""
    per_sample = int(np.ceil(period / samples * harmonic.highest_frequency() / step))
    dt = period / (samples * per_sample)
    q0 = np.asarray(q0, float)
    states = harmonic.motion(np.concatenate([q0, np.zeros_like(q0)]), dt, periods * samples * per_sample, per_sample)
    return HarmonicReference(harmonic, states[:, :harmonic.dof], float(period), int(periods), int(samples), dt)


class FeHarmonicCheck(NamedTuple):
    """The motion on the mesh from rest at a state of the full model on circumferential
    harmonics, against the harmonics' own motion (:func:`check_harmonic_motion`)."""

    #: ``max |w_fe - w_h|`` over the instants and the nodes, over ``max |w_h|``
    w_deviation: float
    #: the same for ``w(rho, theta) - w(rho, theta + pi / n)``, twice the part of ``w`` on
    #: the odd multiples of ``n`` (:func:`wave_number`; for ``n = 1`` the odd harmonics): the
    #: asymmetric motion of ``n`` (and 3n, ...) alone
    odd_deviation: float
    #: the same for the radial displacement ``u`` from the pre-stretch
    u_deviation: float
    #: the same for the circumferential displacement ``v``
    v_deviation: float
    #: the mesh's time step (s)
    dt: float


def check_harmonic_motion(motion: FeMotion, reference: HarmonicReference, step_fraction: float = STABILITY_FRACTION
                          ) -> FeHarmonicCheck:
    """Integrate the mesh's motion from rest at the start of ``reference`` (the full model on
    its circumferential harmonics, :func:`harmonic_reference`) and compare the two at the
    mesh's nodes, where a P2 field's values are its coefficients (no interpolation), at the
    reference's samples.  The mesh's step is the largest whole fraction of the sampling
    interval within ``step_fraction`` of RK4's stability limit ``2.8 / omega_max``.

    Returns
    -------
    FeHarmonicCheck
        The odd part compares every node with the node it turns into by ``pi / n``
        (``n`` the reference's :func:`wave_number`; ``(-x, -y)`` for ``n = 1``).

    Raises
    ------
    ValueError
        From :func:`turned_nodes`.
    """
    harmonic, period, samples = reference.harmonic, reference.period, reference.samples
    rho, theta = motion.polar_nodes()
    cos, sin = np.cos(theta), np.sin(theta)
    partner = turned_nodes(motion, wave_number(harmonic))
    every = int(np.ceil(period / samples / (step_fraction * 2.8 / motion.omega_max)))
    fe = []

    def record(step, D, V):
        if step % every == 0:
            dx, dy, dz = D - motion.rest
            fe.append(np.stack([dx * cos + dy * sin, -dx * sin + dy * cos, dz]))

    motion.motion(motion.lift_fields(*harmonic.fields(reference.coordinates[0], rho, theta)),
                  period / (samples * every), reference.periods * samples * every, record)
    own = np.stack(harmonic.fields(reference.coordinates, rho, theta), axis=1)
    fe = np.array(fe)

    def odd(w):
        return w - w[:, partner]

    return FeHarmonicCheck(_deviation(fe[:, 2], own[:, 2]), _deviation(odd(fe[:, 2]), odd(own[:, 2])),
                           _deviation(fe[:, 0], own[:, 0]), _deviation(fe[:, 1], own[:, 1]),
                           period / (samples * every))


def turned_nodes(motion: FeMotion, n: int) -> np.ndarray:
    """``(N,)``: for each node of the mesh of ``motion``, the node it turns into by ``pi / n``
    about the centre: ``w - w[turned_nodes(motion, n)]`` is twice the part of a nodal field
    ``w`` on the odd multiples of the wave number ``n``.

    Raises
    ------
    ValueError
        When a node does not turn into a node (the mesh's elements around are not a multiple
        of ``2 n``; :meth:`model.fe_annulus.AnnulusMesh.build` repeats one sector around).
    """
    X = motion.basis.doflocs.T
    half_wave = np.pi / n
    turn = np.array([[np.cos(half_wave), -np.sin(half_wave)], [np.sin(half_wave), np.cos(half_wave)]])
    distance, partner = cKDTree(X).query(X @ turn.T)
    if np.any(distance > 1e-9 * np.abs(X).max()):
        raise ValueError(f"n = {n} is invalid here: a node of the mesh does not turn into a node by pi / {n} "
                         f"(its elements around must be a multiple of {2 * n})")
    return partner


def _deviation(a, b) -> float:
    # max |a - b| over max |b|
    return float(np.abs(a - b).max() / np.abs(b).max())


#: Radii (scaled, from edge to edge) and angles of the polar grid on which
#: :func:`reference_error` compares two harmonic motions.
REFERENCE_GRID = (41, 64)


class ReferenceChange(NamedTuple):
    """How far the harmonics' motion moves with its discretisation refined
    (:func:`reference_error`): largest changes over the largest values of the finer motion."""

    #: of ``w``
    w: float
    #: of ``w(rho, theta) - w(rho, theta + pi / n)``, the part on the odd multiples of the
    #: wave number ``n`` (the asymmetric motion)
    odd: float
    #: of the radial displacement ``u``
    u: float
    #: of the circumferential displacement ``v``
    v: float


def reference_error(reference: HarmonicReference, finer: HarmonicReference) -> ReferenceChange:
    """How far ``reference`` moves when its discretisation is refined: the largest
    ``|w - w_finer|`` over the instants and a polar grid (:data:`REFERENCE_GRID`, angles
    ``2 pi j / 64``) over the largest ``|w_finer|``, and the same for ``w(rho, theta) - w(rho,
    theta + pi / n)`` (``n`` the reference's :func:`wave_number`), ``u`` and ``v`` -- the
    measures of :class:`FeHarmonicCheck` -- against ``finer``, the same start on more harmonics,
    more radial functions or with a smaller step (:func:`harmonic_reference`), sampled at the
    same instants."""
    m = reference.harmonic.model.membrane
    radii, angles = REFERENCE_GRID
    rho, theta = np.meshgrid(np.linspace(m.Ro / m.Re, 1.0, radii), 2.0 * np.pi * np.arange(angles) / angles,
                             indexing="ij")
    half_wave = np.pi / wave_number(reference.harmonic)
    (u, v, w), (u_f, v_f, w_f) = (r.harmonic.fields(r.coordinates, rho, theta) for r in (reference, finer))
    odd, odd_f = (w_ - r.harmonic.fields(r.coordinates, rho, theta + half_wave)[2]
                  for w_, r in ((w, reference), (w_f, finer)))
    return ReferenceChange(_deviation(w, w_f), _deviation(odd, odd_f), _deviation(u, u_f), _deviation(v, v_f))
