"""The ROM's free vibration behind the protocol of :class:`model.protocol.FreeVibration`.

:class:`FreeRom` is what the backbone methods of :mod:`model.backbone` take of the
Galerkin ROM (:mod:`model.rom`): its undamped, unforced RK4 flow with the variational
equations (:func:`model.integrate.monodromy`), its lightly damped free decays
(:func:`model.dopri.extrema`), its small-amplitude frequencies and the probe point at
which the amplitude ``w(rho_probe, 0)`` is measured.  The algorithms of
:mod:`model.backbone` read nothing else of the ROM.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import dopri
from .integrate import monodromy
from .linear import frequency_bound
from .rom import Forcing, Rom, linear_frequencies

#: The forcing of the free vibration: no damping, no pressure (Omega is irrelevant).
_FREE = Forcing(0.0, 0.0, 1.0)


@dataclass(frozen=True)
class FreeRom:
    """The free vibration of ``rom`` (:class:`model.protocol.FreeVibration`).

    Parameters
    ----------
    rom : Rom
    """

    rom: Rom

    def __str__(self) -> str:
        return f"the ROM of {list(self.rom.modes)} (probe at rho = {self.rom.probe_rho:g} m)"

    @property
    def dof(self) -> int:
        """Modal coordinates ``K``; states are ``(q, q')``, ``2K`` components."""
        return self.rom.dof

    @property
    def probe(self) -> np.ndarray:
        """``(K,)``: ``w(rho_probe, 0) = probe @ q`` (m)."""
        return self.rom.tables.probe

    @property
    def length(self) -> float:
        """The outer radius ``Re`` (m): the length scale of absolute tolerances."""
        return self.rom.membrane.Re

    def linear_frequencies(self) -> tuple[np.ndarray, np.ndarray]:
        """Small-amplitude frequencies (rad s-1, ascending) and modal vectors (columns)
        of the ROM (:func:`model.rom.linear_frequencies`)."""
        return linear_frequencies(self.rom)

    def flow(self, y0, duration: float, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """State after ``duration`` (s) of the undamped, unforced motion from ``y0`` at
        ``t = 0`` by ``steps`` RK4 steps, and its derivative in ``y0`` (the variational
        equations of the same steps)."""
        return monodromy(y0, 0.0, duration, steps, self.rom.tables, _FREE)

    def decay_rate(self, c: float) -> float:
        """Decay rate (s-1) of the amplitude under the viscous damping ``c`` (N s m-3),
        ``c / (2 Gamma h)`` for every mode."""
        return self.rom.membrane.damping_rate(c)

    def decay_extrema(self, y0, t_end: float, max_count: int, c: float, rtol: float, atol: float):
        """Successive extrema of ``w(rho_probe, 0, t)`` of free decays under the viscous
        damping ``c`` from the rows of ``y0`` (DOP853, :func:`model.dopri.extrema`):
        a record with ``times`` and ``states`` ``(N, max_count[, 2K])`` and ``count``."""
        return dopri.extrema(self.rom, y0, t_end, max_count, c=c, rtol=rtol, atol=atol)

    def frequency_bound(self) -> float:
        """Eq. (29): the upper bound of the frequency of the mode that dominates the
        lowest linear mode (NaN for laws other than neo-Hookean)."""
        _, vectors = self.linear_frequencies()
        k = int(np.argmax(np.abs(vectors[:, 0] * np.sqrt(self.rom.mass))))
        return float(frequency_bound(self.rom.membrane, self.rom.alpha[k]))
