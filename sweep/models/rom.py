"""The Galerkin reduced-order model (:mod:`model.rom`) as a job's model (``[model] kind = "rom"``).

Its options are today's analysis options: ``modes``, ``prestretch``, ``steps`` and (for
``linear``) ``basis`` in the analysis' own table (docs/options.md); ``[model]`` takes
``kind`` only.  It runs every analysis: the forced ones on :class:`model.forced.ForcedMap`,
``backbone`` on :class:`model.free.FreeRom`, ``static`` on the pre-stretch of
:mod:`model.prestretch` and ``linear`` on the Galerkin solution of Eq. (25)
(:func:`model.linear.galerkin_frequencies`), which does not depend on the ROM's modes.
"""

from __future__ import annotations

import functools
from dataclasses import replace

from sweep.models.base import Model, per_wave_number


@functools.lru_cache(maxsize=8)
def prestretch_for(membrane, prestretch: str):
    """The ``prestretch`` solution (:func:`model.prestretch.solve_prestretch`) of
    ``membrane`` (cached)."""
    from model.prestretch import solve_prestretch

    return solve_prestretch(membrane, prestretch)


@functools.lru_cache(maxsize=8)
def rom_for(membrane, prestretch: str, modes: tuple[tuple[int, int], ...]):
    """The ROM of ``modes`` on the ``prestretch`` solution of ``membrane`` (cached: the
    tiles of a basins lattice and the tasks of a grid often share a membrane)."""
    from model.rom import build_rom

    return build_rom(prestretch_for(membrane, prestretch), modes)


@functools.lru_cache(maxsize=8)
def families_for(membrane, prestretch: str, modes: tuple[tuple[int, int], ...],
                 blocks: tuple[tuple[int, tuple[int, ...]], ...]):
    """The family blocks (:func:`model.families.build_family`) ``(n, radial indices)`` for
    the axisymmetric ROM of :func:`rom_for`."""
    from model.families import build_family

    ps = prestretch_for(membrane, prestretch)
    rom = rom_for(membrane, prestretch, modes)
    return tuple(build_family(ps, rom, n, radial) for n, radial in blocks)


def steps_for(membrane, prestretch: str, modes, steps: int | None, base: int) -> int:
    """The steps per period of a task: the option's value, or for ``"auto"``
    :func:`model.forced.steps_per_period` of the ROM of ``modes`` (:func:`rom_for`)."""
    from model.forced import steps_per_period

    return steps if steps is not None else steps_per_period(rom_for(membrane, prestretch, modes), base)


class RomModel(Model):
    """The ROM of the analysis' ``modes`` on its ``prestretch``, RK4 with ``steps`` per period."""

    name = "rom"
    required_grid = ("delta", "delta_o")
    rom_features = True

    def forced_map(self, point, model_options, options, modes=None, default_steps=None):
        # imported here: a job file names its model at validation, which compiles nothing
        from model.forced import DEFAULT_STEPS, ForcedMap

        modes = options.modes if modes is None else modes
        rom = rom_for(point.membrane, options.prestretch, tuple(modes))
        steps = steps_for(point.membrane, options.prestretch, options.modes, options.steps,
                          default_steps or DEFAULT_STEPS)
        return ForcedMap.from_loading(rom, point.loading, steps, point.damping)

    def rebuilt(self, point, model_options, options, fmap, family):
        # quadrature kernels, no tables: a rebuild costs milliseconds
        from model.families import build_family
        from model.prestretch import solve_prestretch
        from model.rom import build_rom

        def at(delta):
            ps = solve_prestretch(replace(point.membrane, delta=delta), options.prestretch)
            rom = build_rom(ps, fmap.rom.modes, force_table=False)
            fam = None if family is None else build_family(ps, rom, family.n, family.radial, jacobian_table=False)
            return fmap.with_rom(rom), fam
        return at

    def families(self, point, model_options, options, modes, blocks):
        return families_for(point.membrane, options.prestretch, tuple(modes), tuple(blocks))

    def free_vibration(self, point, model_options, options):
        from model.free import FreeRom

        return FreeRom(rom_for(point.membrane, options.prestretch, tuple(options.modes)))

    def static_state(self, point, model_options, options):
        return prestretch_for(point.membrane, options.prestretch)

    def natural_frequencies(self, point, model_options, options, basis):
        from model.linear import CHANGE_TOL, MAX_BASIS, galerkin_frequencies

        ps = prestretch_for(point.membrane, options.prestretch)
        problems = []

        def solve(n, count):
            omega, _, change = galerkin_frequencies(ps, n, count, basis=basis, full_output=True)
            if change >= CHANGE_TOL:
                problems.append(f"n = {n}: basis not converged at {MAX_BASIS} functions "
                                f"(last relative change {change:.1e})")
            return omega

        return per_wave_number(options.modes, solve), problems


ROM = RomModel()
