"""The Galerkin reduced-order model (:mod:`model.rom`) as a job's model (``[model] kind = "rom"``).

Its options are today's analysis options: ``modes``, ``prestretch`` and ``steps`` in the
analysis' own table (docs/options.md); ``[model]`` takes ``kind`` only.
"""

from __future__ import annotations

from sweep.models.base import Model


class RomModel(Model):
    """The ROM of the analysis' ``modes`` on its ``prestretch``, RK4 with ``steps`` per period."""

    name = "rom"
    required_grid = ("delta", "delta_o")
    rom_features = True

    def forced_map(self, point, model_options, options, modes=None, default_steps=None):
        # imported here: a job file names its model at validation, which compiles nothing
        from model.forced import DEFAULT_STEPS, ForcedMap
        from sweep.analyses import options as opt

        modes = options.modes if modes is None else modes
        rom = opt.rom_for(point.membrane, options.prestretch, tuple(modes))
        steps = opt.steps_for(point.membrane, options.prestretch, options.modes, options.steps,
                              default_steps or DEFAULT_STEPS)
        return ForcedMap.from_loading(rom, point.loading, steps, point.damping)


ROM = RomModel()
