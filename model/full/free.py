"""The full model's axisymmetric free vibration behind :class:`model.protocol.FreeVibration`.

:class:`FreeFull` is what the backbone methods of :mod:`model.backbone` take of the
axisymmetric full model (:class:`model.full.axisymmetric.AxisymmetricFull`): coordinates
``q = (U, W)``, the Legendre-Galerkin coefficients of ``u / Re`` and ``w / Re``.

* The undamped flow and its derivative: fixed-step RK4 with the variational equations
  ``dq' = dv``, ``dv' = -omega_0^2 M^-1 H(q) dq`` (``H`` the energy's Hessian), the exact
  derivative of the discrete scheme.  RK4 is stable for ``omega_max dt < 2.8``; the
  in-plane waves of the discretisation are far faster than the transverse motion
  (``omega_max`` is about 85 times the lowest frequency at order 16 and grows like the
  order squared), so the steps are raised to ``duration * omega_max(q0) / 2`` when the
  caller's are fewer (``omega_max`` at the starting state, where a backbone orbit is at
  its largest deflection and tension).
* The symmetry of the free orbits: the energy is even in ``W`` at fixed ``U`` (reflection
  ``w -> -w``), so the fundamental orbit from rest satisfies ``q(t + T/2) = S q(t)`` with
  ``S = diag(+1 on U, -1 on W)``; with the time reversibility its quarter-period conditions
  are ``W(T/4) = 0`` and ``U'(T/4) = 0`` (:attr:`FreeFull.odd` marks the coordinates that
  change sign; :func:`model.backbone.free_orbit` reads it).  ``u`` swings at twice the
  frequency of ``w``.
* Lightly damped free decays (peak-to-peak method): the compiled RK4 free motion
  (:func:`model.full.axisymmetric_kernels.rk4_motion`) with the extrema of ``w`` at the probe
  located between steps on the cubic Hermite interpolant of ``(q, q')``.

On a model with ``u`` held at zero (``AxisymmetricFull(..., inplane=False)``) the coordinates
are ``W`` alone (every one odd), as :class:`model.full.forced.ForcedFull` keeps them: the
compiled loops run on ``(U, W)`` with ``U`` at rest.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.linalg import eigh

from .axisymmetric import AxisymmetricFull
from .axisymmetric_kernels import NO_PARAMETER, rk4_variational
from .forced import linear_system

#: RK4 steps per linear period at least, in the decays and the extent of an orbit.
STEPS_PER_PERIOD = 1024
#: RK4 time step over the stability limit ``2.8 / omega_max`` at most.
STABILITY_FRACTION = 2.0 / 2.8
#: Largest relative numerical damping of the fastest mode over one flow (:meth:`FreeFull.steps_for`).
FASTEST_MODE_DECAY = 0.1
#: Most RK4 steps of one flow: a state whose highest frequency asks for more is a Newton iterate
#: gone astray, rejected (an orbit's quarter period takes a few thousand steps even at order 32;
#: one iterate near the delta = 1.1 turn at order 12 asked for 1.4e7).
MAX_FLOW_STEPS = 200_000


class DecayExtrema(NamedTuple):
    """Extrema of ``w(t) = probe @ q(t)`` along free decays (as :class:`model.dopri.Extrema`).

    Attributes
    ----------
    times : (N, max_count) ndarray
        Instants (s), NaN past ``count``.
    states : (N, max_count, 2 dof) ndarray
        States there, NaN past ``count``.
    count : (N,) ndarray of int
    """

    times: np.ndarray
    states: np.ndarray
    count: np.ndarray


class FreeFull:
    """The axisymmetric free vibration of the full model (:class:`model.protocol.FreeVibration`).

    Parameters
    ----------
    model : AxisymmetricFull
    probe_rho : float, optional
        Undeformed radius (m) of the measured ``w(probe_rho, 0)``; default ``0.5 Re``, the ROM's.
    """

    def __init__(self, model: AxisymmetricFull, probe_rho: float | None = None):
        self.model = model
        m = model.membrane
        self.probe_rho = 0.5 * m.Re if probe_rho is None else float(probe_rho)
        o = model.order
        u = model.moving.size - o  # the U coordinates: none when u is held
        phi, _ = model.state.basis.evaluate(np.eye(o), np.array([self.probe_rho / m.Re]))
        #: ``w(probe_rho) = probe @ q`` (m): only the ``W`` block
        self.probe = np.concatenate([np.zeros(u), m.Re * phi[:, 0]])
        #: the coordinates that change sign under ``w -> -w``: the ``W`` block
        self.odd = np.concatenate([np.zeros(u, bool), np.ones(o, bool)])

    def __str__(self) -> str:
        held = "" if self.model.inplane else ", u held at zero"
        return f"the axisymmetric full model of order {self.model.order}{held} (probe at rho = {self.probe_rho:g} m)"

    @property
    def dof(self) -> int:
        """Coordinates ``2 order`` (``U`` then ``W``), or ``order`` (``W``) with ``u`` held;
        states ``(q, q')``."""
        return self.model.moving.size

    @property
    def length(self) -> float:
        """The outer radius ``Re`` (m)."""
        return self.model.membrane.Re

    def _compiled_coordinates(self, q) -> np.ndarray:
        # the coordinates q (dof) in the compiled loops' q = (U, W), a held U at zero
        q = np.asarray(q, float)
        if q.shape != (self.dof,):
            raise ValueError(f"coordinates shape {q.shape} is invalid: expected ({self.dof},)")
        out = np.zeros(self.model.dof)
        out[self.model.moving] = q
        return out

    def _compiled_state(self, y) -> np.ndarray:
        # the state y = (q, q') in the compiled loops' (q, q'), a held U at rest
        y = np.asarray(y, float)
        if y.shape != (2 * self.dof,):
            raise ValueError(f"state shape {y.shape} is invalid: expected ({2 * self.dof},) = (q, q')")
        out = np.zeros(2 * self.model.dof)
        out[self.model.state_indices] = y
        return out

    def linear_frequencies(self) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (rad s-1, ascending) and vectors (columns) of the motion about the
        pre-stretch: the radial in-plane (``U``) and transverse (``W``) families of n = 0,
        uncoupled there (the transverse ones alone with ``u`` held)."""
        mass, stiffness = linear_system(self.model)
        lam, vec = eigh(stiffness, mass)
        return np.sqrt(lam), vec

    def highest_frequency(self, q) -> float:
        """The largest frequency (rad s-1) of the motion linearised about the state ``q``."""
        m = self.model
        lam = eigh(m.restricted(m.compiled_hessian(self._compiled_coordinates(q))), m.moving_mass,
                   eigvals_only=True)[-1]
        return float(np.sqrt(m.omega0_2 * max(lam, 0.0)))

    def steps_for(self, q0, duration: float, steps: int) -> int:
        """``steps``, raised to keep RK4 within :data:`STABILITY_FRACTION` of its stability
        limit at ``omega_max(q0)`` and to keep its numerical damping of that fastest mode over
        ``duration`` below :data:`FASTEST_MODE_DECAY`.

        RK4 damps a mode of ``y = omega dt`` by ``|R(iy)| ~ 1 - y^6/144`` per step: over ``N``
        steps by ``N y^6 / 144``.  A mode the scheme wipes out over an orbit's quarter period
        leaves the orbit conditions insensitive to its coordinate (at order 32 and 256 steps
        the Newton matrix had a singular value of 2e-11 from the two highest in-plane modes),
        so ``N >= ((omega_max duration)^6 / (144 FASTEST_MODE_DECAY))^(1/5)``."""
        phase = duration * self.highest_frequency(q0)
        stable = np.ceil(phase / (2.8 * STABILITY_FRACTION))
        undamped = np.ceil((phase**6 / (144.0 * FASTEST_MODE_DECAY)) ** 0.2)
        return max(int(steps), int(stable), int(undamped))

    def acceleration(self, q, v) -> np.ndarray:
        """``q''`` of the undamped motion."""
        moving = self.model.moving
        return self.model.acceleration(self._compiled_coordinates(q), self._compiled_coordinates(v))[moving]

    def flow(self, y0, duration: float, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """State after ``duration`` (s) of the undamped motion from ``y0`` by at least ``steps``
        RK4 steps (:meth:`steps_for`), and its derivative in ``y0`` (the variational
        equations of the same steps).  Raises ``numpy.linalg.LinAlgError`` when the state asks for
        more than :data:`MAX_FLOW_STEPS` steps."""
        m = self.model
        y = np.array(y0, dtype=float)
        steps = self.steps_for(y[:self.dof], duration, steps)
        if steps > MAX_FLOW_STEPS:
            # rejected as a failed solve: the continuation halves its step (model.backbone)
            raise np.linalg.LinAlgError(f"a state whose fastest mode asks for {steps} RK4 steps (more than "
                                        f"{MAX_FLOW_STEPS})")
        keep = m.state_indices
        y, big = rk4_variational(*m.kernel_tables, m.inverse_masses, m.omega0_2, m.bias, 0.0, None, m.load, 0.0, 0.0,
                                 NO_PARAMETER, self._compiled_state(y), m.state_tangents, duration / steps, steps)
        return y[keep], big[keep, :-1]

    def decay_rate(self, c: float) -> float:
        """``c / (Gamma h)`` (s-1), the damping coefficient of every coordinate (the viscous
        pressure acts on the whole velocity: mass-proportional; amplitudes decay at half of it)."""
        return float(self.model.membrane.damping_rate(c))

    def _time_step(self, q0) -> float:
        omega_lin = self.linear_frequencies()[0][0]
        return min(2.0 * np.pi / omega_lin / STEPS_PER_PERIOD, 2.8 * STABILITY_FRACTION / self.highest_frequency(q0))

    def decay_extrema(self, y0, t_end: float, max_count: int, c: float, rtol: float, atol: float) -> DecayExtrema:
        """Up to ``max_count`` successive extrema of ``w`` at the probe along free decays under
        the viscous damping ``c`` from the rows of ``y0`` until ``t_end`` (s).  Fixed RK4
        steps (:data:`STEPS_PER_PERIOD`, or the stability limit); ``rtol`` and ``atol``
        (the protocol's, for adaptive integrators) are not used."""
        y0 = np.atleast_2d(np.asarray(y0, float))
        N, n = y0.shape[0], self.dof
        times = np.full((N, max_count), np.nan)
        states = np.full((N, max_count, 2 * n), np.nan)
        count = np.zeros(N, np.int64)
        for j in range(N):
            dt = self._time_step(y0[j, :n])
            steps = int(np.ceil(t_end / dt))
            record = self.model.free_motion(self._compiled_state(y0[j]), steps * dt, steps, c=c)
            record = record[:, self.model.state_indices]
            t, s = hermite_extrema(record, dt, self.probe, max_count)
            count[j] = t.size
            times[j, :t.size], states[j, :t.size] = t, s
        return DecayExtrema(times, states, count)

    def orbit(self, q0, period: float):
        """The states of one period of the free motion from rest at ``q0`` (rows; at least
        :data:`STEPS_PER_PERIOD` RK4 steps, or the stability limit) and the time step (s)."""
        q0 = np.asarray(q0, float)
        steps = max(STEPS_PER_PERIOD, int(np.ceil(period / self._time_step(q0))))
        record = self.model.free_motion(self._compiled_state(np.concatenate([q0, np.zeros(self.dof)])), period, steps)
        return record[:, self.model.state_indices], period / steps

    def snapshots(self, q0, period: float, samples: int, rho, periods: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """``(u, w)`` (m), each ``(periods samples, len(rho))``: the displacements at the undeformed
        radii ``rho`` (m) at ``samples`` equally spaced instants ``t = j T / samples`` of each of
        ``periods`` periods of the orbit from rest at ``q0`` (the first at rest, the largest
        deflection), by the integration of :meth:`orbit` (its step count raised to a multiple
        of ``samples``)."""
        q0 = np.asarray(q0, float)
        steps = max(STEPS_PER_PERIOD, int(np.ceil(period / self._time_step(q0))))
        steps = samples * -(-steps // samples)
        start = self._compiled_state(np.concatenate([q0, np.zeros(self.dof)]))
        record = self.model.free_motion(start, periods * period, periods * steps,
                                        every=steps // samples)[:periods * samples]
        b, o, re = self.model.state.basis, self.model.order, self.model.membrane.Re
        s = np.asarray(rho, float) / re  # the basis' scaled radius
        return re * b.evaluate(record[:, :o], s)[0], re * b.evaluate(record[:, o:2 * o], s)[0]

    def extent(self, q0, period: float, radii: int = 201) -> tuple[float, float, float]:
        """``(max |u|, max |v|, max |w|)`` (m) over one period of the orbit from rest at ``q0``
        and over ``radii`` equally spaced radii of the membrane (``v`` vanishes: the motion is
        axisymmetric)."""
        record, _ = self.orbit(q0, period)
        b = self.model.state.basis
        s = np.linspace(b.s_in, b.s_out, radii)
        o, u = self.model.order, self.dof - self.model.order  # W: the last o coordinates
        re = self.model.membrane.Re
        w = re * b.evaluate(record[:, u:self.dof], s)[0]
        return (float(np.abs(re * b.evaluate(record[:, :o], s)[0]).max()) if u else 0.0), 0.0, float(np.abs(w).max())


def hermite_extrema(record, dt: float, probe, max_count: int):
    """Instants and states of the extrema of ``w = probe @ q`` along the states ``record``
    (rows ``(q, q')`` every ``dt`` from ``t = 0``): where ``probe @ q'`` changes sign between
    two rows, the root of the derivative of the cubic Hermite interpolant of ``w`` in the
    step, and the Hermite interpolant of ``(q, q')`` there.  At most ``max_count``."""
    n = record.shape[1] // 2
    q, v = record[:, :n], record[:, n:]
    w, wv = q @ probe, v @ probe
    flips = np.flatnonzero(np.sign(wv[1:]) * np.sign(wv[:-1]) < 0)[:max_count]
    times, states = [], []
    for i in flips:
        m0, m1 = dt * wv[i], dt * wv[i + 1]
        a = 6.0 * w[i] + 3.0 * m0 - 6.0 * w[i + 1] + 3.0 * m1
        b = -6.0 * w[i] - 4.0 * m0 + 6.0 * w[i + 1] - 2.0 * m1
        roots = np.roots([a, b, m0]) if a != 0.0 else np.array([-m0 / b])
        real = roots[np.isreal(roots)].real
        real = real[(real >= 0.0) & (real <= 1.0)]
        x = float(real[0]) if real.size else float(m0 / (m0 - m1))
        h00, h10, h01, h11 = 2 * x**3 - 3 * x**2 + 1, x**3 - 2 * x**2 + x, -2 * x**3 + 3 * x**2, x**3 - x**2
        d00, d10, d01, d11 = 6 * x**2 - 6 * x, 3 * x**2 - 4 * x + 1, -6 * x**2 + 6 * x, 3 * x**2 - 2 * x
        qx = h00 * q[i] + h10 * dt * v[i] + h01 * q[i + 1] + h11 * dt * v[i + 1]
        vx = (d00 * q[i] + d10 * dt * v[i] + d01 * q[i + 1] + d11 * dt * v[i + 1]) / dt
        times.append((i + x) * dt)
        states.append(np.concatenate([qx, vx]))
    return np.array(times), np.array(states).reshape(len(times), 2 * n)
