"""Textbook forced oscillators behind the map protocol (model.protocol.StroboscopicMap).

``x'' + beta x' + k1 x + k2 x^2 + k3 x^3 = F sin(Omega t)``, by default (k1, k2, k3) =
(1, -1, 0): Thompson's escape equation ``x'' + beta x' + x - x^2 = F sin(Omega t)`` (J. M. T. Thompson,
Proc. R. Soc. Lond. A 421, 1989): a softening, asymmetric one-well oscillator whose periodic
responses period-double on the way to escape.  The membrane ROM is odd in its coordinates,
and its symmetric (w(t + T/2) = -w(t)) responses cannot period-double (docs/model.md,
"Symmetry families"), so period doubling is exercised on this oscillator, through the same
continuation code (``model.continuation.continue_orbits`` takes any object with this
interface).  ``P0`` is the amplitude ``F``; the damping ``beta`` is the map's parameter
``c`` (its viscous law), so that job files spell it as for the membrane.

With (k1, k2, k3) = (0, 0, 1) it is Ueda's oscillator (Y. Ueda, J. Stat. Phys. 20, 1979;
``ueda_map``), chaotic at beta = 0.05, F = 7.5, Omega = 1 (his forcing is ``cos t``, a
shift of the time origin by a quarter period, which leaves its exponents alone).
"""

from collections import namedtuple
from dataclasses import dataclass, replace

import numba as nb
import numpy as np

Forcing = namedtuple("Forcing", "damping_rate P0 Omega")


@nb.njit(cache=True)
def _rk4(y, beta, F, omega, h, steps, variational, which, k1, k2, k3):
    # RK4 steps of the state and, when asked, of the variational matrix (2 x 3: the third
    # column the derivative in Omega (which = 1, at fixed steps per period) or F (2)).
    x, v = y[0], y[1]
    phi = np.zeros((2, 3))
    phi[0, 0] = phi[1, 1] = 1.0
    kx, kv, kp = np.empty(4), np.empty(4), np.empty((4, 2, 3))
    for i in range(steps):
        t = i * h
        for s in range(4):
            f = 0.0 if s == 0 else (h if s == 3 else 0.5 * h)
            cx = x + f * kx[s - 1] if s else x
            cv = v + f * kv[s - 1] if s else v
            cp = phi + f * kp[s - 1] if s else phi
            forcing = np.sin(omega * (t + f))
            kx[s] = cv
            kv[s] = -beta * cv - (k1 + (k2 + k3 * cx) * cx) * cx + F * forcing
            if variational:
                for c in range(3):
                    kp[s, 0, c] = cp[1, c]
                    kp[s, 1, c] = -(k1 + (2.0 * k2 + 3.0 * k3 * cx) * cx) * cp[0, c] - beta * cp[1, c]
                if which == 1:
                    kp[s, 0, 2] -= kx[s] / omega
                    kp[s, 1, 2] -= kv[s] / omega
                elif which == 2:
                    kp[s, 1, 2] += forcing
        x += h / 6.0 * (kx[0] + 2.0 * kx[1] + 2.0 * kx[2] + kx[3])
        v += h / 6.0 * (kv[0] + 2.0 * kv[1] + 2.0 * kv[2] + kv[3])
        if variational:
            phi = phi + h / 6.0 * (kp[0] + 2.0 * kp[1] + 2.0 * kp[2] + kp[3])
    return np.array([x, v]), phi


@nb.njit(cache=True)
def _rk4_from(y, beta, F, omega, h, t, k1, k2, k3):
    # One RK4 step of the state from time t.
    def f(t, x, v):
        return v, -beta * v - (k1 + (k2 + k3 * x) * x) * x + F * np.sin(omega * t)
    x, v = y[0], y[1]
    k1x, k1v = f(t, x, v)
    k2x, k2v = f(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v)
    k3x, k3v = f(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v)
    k4x, k4v = f(t + h, x + h * k3x, v + h * k3v)
    return np.array([x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x), v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v)])


def rhs(beta, F, omega, stiffness=(1.0, -1.0, 0.0)):
    """The right-hand side for scipy's ``solve_ivp``."""
    k1, k2, k3 = stiffness
    return lambda t, y: [y[1], -beta * y[1] - (k1 + (k2 + k3 * y[0]) * y[0]) * y[0] + F * np.sin(omega * t)]


@dataclass(frozen=True)
class EscapeMap:
    """Stroboscopic map of the oscillator (RK4, ``steps`` per period); ``stiffness`` is
    (k1, k2, k3), the escape equation's by default."""

    beta: float
    forcing: Forcing
    steps: int = 128
    stiffness: tuple = (1.0, -1.0, 0.0)
    dof = 1
    parameters = ("Omega", "P0", "c")

    @property
    def period(self):
        return 2.0 * np.pi / self.forcing.Omega

    def value(self, parameter):
        return self.beta if parameter == "c" else float(getattr(self.forcing, parameter))

    def varied(self, parameter, value):
        if parameter == "c":
            return replace(self, beta=float(value))
        return replace(self, forcing=self.forcing._replace(**{parameter: float(value)}))

    def state_scale(self, Omega=None):
        return np.array([1.0, 1.0 / (self.forcing.Omega if Omega is None else Omega)])

    def _flow(self, y, variational, which=0):
        f = self.forcing
        return _rk4(np.asarray(y, dtype=float), self.beta, f.P0, f.Omega, self.period / self.steps, self.steps,
                    variational, which, *self.stiffness)

    def monodromy(self, y):
        yT, phi = self._flow(y, True)
        return yT, phi[:, :2]

    def monodromy_parameter(self, y, parameter):
        yT, phi = self._flow(y, True, 1 if parameter == "Omega" else 2)
        return yT, phi[:, :2], phi[:, 2]

    def advance(self, y, periods=1):
        for _ in range(periods):
            y = self._flow(y, False)[0]
        return y

    def advance_batch(self, states, periods=1):
        return np.array([self.advance(y, periods) for y in np.asarray(states, dtype=float)]).reshape(-1, 2)

    def multipliers(self, y):
        mu = np.linalg.eigvals(self.monodromy(y)[1])
        return mu[np.argsort(-np.abs(mu))]

    def amplitude(self, y, periods=1):
        """``max |x|`` over the RK4 samples of ``periods`` periods from ``y``."""
        best = abs(float(y[0]))
        h = self.period / self.steps
        z = np.asarray(y, dtype=float)
        for i in range(periods * self.steps):
            z = _rk4_from(z, self.beta, self.forcing.P0, self.forcing.Omega, h, i * h, *self.stiffness)
            best = max(best, abs(float(z[0])))
        return best


def ueda_map(steps: int = 256) -> EscapeMap:
    """Ueda's chaotic oscillator ``x'' + 0.05 x' + x^3 = 7.5 sin t``."""
    return EscapeMap(0.05, Forcing(0.0, 7.5, 1.0), steps, (0.0, 0.0, 1.0))
