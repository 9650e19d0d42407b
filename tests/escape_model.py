"""Thompson's escape oscillator (tests/escape_oscillator.py) registered as a job's model.

A model that is not the ROM, from a module outside ``model/``, behind the seams of
docs/architecture.md: registered for job files with
``SWEEP_EXTRA_MODELS="escape=escape_model:ESCAPE"`` (this directory on ``PYTHONPATH``),
chosen by ``[model] kind = "escape"``.  The grid's ``Omega``, ``P0`` (the amplitude ``F``)
and ``c`` (the damping ``beta``) set the map; it needs no membrane keys.
"""

from dataclasses import dataclass

from escape_oscillator import EscapeMap, Forcing
from model.damping import Viscous
from sweep.analyses import options as opt
from sweep.analyses.base import JobError
from sweep.models.base import Model


@dataclass(frozen=True)
class EscapeOptions:
    steps: int


class EscapeModel(Model):
    """``x'' + c x' + x - x^2 = P0 sin(Omega t)``, RK4 with ``steps`` per period."""

    name = "escape"
    OPTIONS = {"steps": "RK4 steps per forcing period (default 128)"}

    def parse_options(self, table):
        super().parse_options(table)
        return EscapeOptions(opt.number(table, "model", "steps", 128, integer=True, low=8))

    def forced_map(self, point, model_options, options, modes=None, default_steps=None):
        if not isinstance(point.damping, Viscous):
            raise JobError("damping.law", point.damping.name, "viscous for the escape oscillator")
        return EscapeMap(point.damping.c, Forcing(0.0, point.loading.P0, point.loading.Omega), model_options.steps)


ESCAPE = EscapeModel()
