"""Physical parameters of the membrane and of its loading.

Symbols follow the paper (Goncalves, Soares and Pamplona, IJSS 2011, sections 2-3):
``C1`` neo-Hookean constant (Eq. 1), ``h`` thickness, ``Gamma`` mass density, ``Re`` outer
radius, ``delta = Rf/Re`` radial stretch ratio and ``delta_o = Ro/Re`` inner radius ratio
(Eq. 20).  SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields


def _check(name: str, value: float, ok: bool, allowed: str) -> None:
    if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value) or not ok:
        raise ValueError(f"{name} = {value!r} is invalid: must be {allowed}")


@dataclass(frozen=True)
class Membrane:
    """A pre-stretched neo-Hookean annular membrane.

    Parameters
    ----------
    delta : float
        Radial stretch ratio ``Rf/Re`` (1), must be > 1.
    delta_o : float
        Inner radius ratio ``Ro/Re`` (1), in (0, 1).
    C1 : float
        Neo-Hookean constant (Pa), Eq. (1).
    h : float
        Undeformed thickness (m).
    Gamma : float
        Mass density (kg m-3); the mass per unit undeformed area is ``Gamma*h``.
    Re : float
        Undeformed outer radius (m).
    """

    delta: float = 1.1
    delta_o: float = 0.2
    C1: float = 0.17e6
    h: float = 1e-3
    Gamma: float = 2200.0
    Re: float = 1.0

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, int) and not isinstance(v, bool):
                object.__setattr__(self, f.name, float(v))
        _check("delta", self.delta, isinstance(self.delta, float) and self.delta > 1.0,
               "a finite number > 1 (delta = Rf/Re; at delta = 1 every frequency is 0)")
        _check("delta_o", self.delta_o, isinstance(self.delta_o, float) and 0.0 < self.delta_o < 1.0,
               "a finite number in the open interval (0, 1)")
        for name in ("C1", "h", "Gamma", "Re"):
            v = getattr(self, name)
            _check(name, v, isinstance(v, float) and v > 0.0, "a finite number > 0")

    @property
    def Ro(self) -> float:
        """Undeformed inner radius (m)."""
        return self.delta_o * self.Re

    @property
    def Rf(self) -> float:
        """Deformed outer radius (m)."""
        return self.delta * self.Re

    @property
    def wave_speed2(self) -> float:
        """``2 C1 / Gamma`` (m2 s-2): the factor between Galerkin eigenvalues and omega^2."""
        return 2.0 * self.C1 / self.Gamma


@dataclass(frozen=True)
class Loading:
    """Damping and harmonic pressure acting on the pre-stretched membrane (Eq. 24).

    Parameters
    ----------
    Omega : float
        Forcing frequency (rad s-1), > 0 (ignored when ``P0 == 0``).
    P0 : float
        Pressure amplitude (Pa), >= 0, on the projected area of the stretched membrane.
    c : float
        Viscous damping (N s m-3): pressure ``-c w_t`` per unit undeformed area, >= 0.
    """

    Omega: float = 1.0
    P0: float = 0.0
    c: float = 0.0

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, int) and not isinstance(v, bool):
                object.__setattr__(self, f.name, float(v))
        _check("Omega", self.Omega, isinstance(self.Omega, float) and self.Omega > 0.0, "a finite number > 0 (rad/s)")
        _check("P0", self.P0, isinstance(self.P0, float) and self.P0 >= 0.0, "a finite number >= 0 (Pa)")
        _check("c", self.c, isinstance(self.c, float) and self.c >= 0.0, "a finite number >= 0 (N s/m^3)")
