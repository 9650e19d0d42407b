"""The full model of the membrane (:mod:`model.full`) as a job's model (``[model] kind = "full"``).

It keeps the in-plane displacements and their inertia that the ROM drops.  It runs
``static`` (its own pre-stretch, the minimum of the axisymmetric energy), ``linear``
(transverse and in-plane frequencies per wave number), ``backbone`` (the axisymmetric
free vibration, :class:`model.full.free.FreeFull`) and the forced analyses on axisymmetric
states (:class:`model.full.forced.ForcedFull`): their ``modes`` must be axisymmetric, and
name the ROM coordinates the results report (the fit of ``w`` by those mode shapes) and
the basins' lattices start from (``w`` the sum of those shapes, ``u`` at rest); curves of
bifurcation points in ``delta`` rebuild the model at each ``delta`` (:meth:`FullModel.rebuilt`); the
ROM's mixed mode sets, branch switching and family check are refused at validation.  Its
``continuation.families`` are the perturbations of each harmonic ``n`` in ``(U, V, W)``
(``inplane = false``: ``W`` alone) on the first ``radial`` functions of its basis
(:class:`model.full.families.FullFamily`).  Its resolution is ``[model] order``, the
number of radial Legendre-Galerkin functions per field; ``linear.basis`` overrides it per
task (a list of orders is a convergence study).  ``[model] inplane = false`` holds ``u`` at
zero: the ROM's hypothesis ``u = v = 0`` on the full model's radial discretisation, for every
analysis (families then ``W`` alone; ``linear`` gives the transverse frequencies, ``backbone``
no in-plane extents, orbit fields or FE check).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

from model.full.static import DEFAULT_ORDER
from sweep.analyses import options as opt
from sweep.job_errors import check_keys
from sweep.models.base import Model, per_wave_number

#: Largest radial order a job may ask for.
MAX_ORDER = 256


@dataclass(frozen=True)
class FullOptions:
    #: radial Legendre-Galerkin functions per field
    order: int
    #: whether the in-plane displacements move (False: held at zero, the ROM's hypothesis)
    inplane: bool = True


@functools.lru_cache(maxsize=8)
def full_prestretch_for(membrane, order: int):
    """The full model's pre-stretch (:func:`model.full.static.solve_full_prestretch`) of
    ``membrane`` on ``order`` radial functions (cached)."""
    from model.full.static import solve_full_prestretch

    return solve_full_prestretch(membrane, order)


@functools.lru_cache(maxsize=8)
def axisymmetric_for(membrane, order: int, inplane: bool):
    """The axisymmetric full model (:class:`model.full.axisymmetric.AxisymmetricFull`) about
    :func:`full_prestretch_for`, with ``u`` held at zero unless ``inplane`` (cached)."""
    from model.full.axisymmetric import AxisymmetricFull

    return AxisymmetricFull(full_prestretch_for(membrane, order), inplane)


@functools.lru_cache(maxsize=8)
def full_families_for(model, blocks: tuple[tuple[int, int], ...], fields: str):
    """The asymmetric families (:class:`model.full.families.FullFamily`) ``(n, radial count)``
    of the fields ``fields`` on the axisymmetric ``model`` (cached by the model: a map takes
    the families of its own model only)."""
    from model.full.families import FullFamily

    return tuple(FullFamily.build(model, n, radial, fields) for n, radial in blocks)


class FullModel(Model):
    """The membrane with in-plane displacements on ``order`` radial functions per field."""

    name = "full"
    required_grid = ("delta", "delta_o")
    prestretch_kinds = ("numeric",)
    axisymmetric_states = True
    circumferential_harmonics = True

    OPTIONS = {"order": f"radial Legendre-Galerkin functions per displacement field (default {DEFAULT_ORDER}; "
                        f"4..{MAX_ORDER}); the pre-stretch and the frequencies converge spectrally with it "
                        "(docs/model.md, \"The full model\")",
               "inplane": "true (default): the in-plane displacements move with their inertia; false: u = v = 0 "
                          "held, the ROM's hypothesis on this radial discretisation (every analysis; families of "
                          "W alone; no in-plane frequencies, orbit fields or FE check)"}

    #: what a model with u held at zero does not provide
    NEEDS_INPLANE = ("inplane_frequencies",)

    def parse_options(self, table):
        check_keys(table, "model", ("kind", *self.OPTIONS))
        return FullOptions(opt.number(table, "model", "order", DEFAULT_ORDER, low=4, high=MAX_ORDER, integer=True),
                           opt.flag(table, "model", "inplane", True))

    def provides(self, method, model_options=None):
        if model_options is not None and not model_options.inplane and method in self.NEEDS_INPLANE:
            return False
        return super().provides(method, model_options)

    def orbit_extents(self, model_options):
        return "uvw" if model_options.inplane else "w"

    def state_size(self, model_options):
        # (U, W) or W alone, and their rates (model.full.forced.ForcedFull.dof)
        return 2 * (2 if model_options.inplane else 1) * model_options.order

    def forced_map(self, point, model_options, options, modes=None, default_steps=None):
        from model.damping import Viscous
        from model.forced import DEFAULT_STEPS
        from model.full.forced import ForcedFull, steps_per_period

        model = axisymmetric_for(point.membrane, model_options.order, model_options.inplane)
        damping = point.damping or Viscous(point.loading.c)
        steps = options.steps or steps_per_period(model, default_steps or DEFAULT_STEPS, damping)
        return ForcedFull.build(model, point.loading.P0, point.loading.Omega, damping, steps,
                                modes=options.modes if modes is None else modes)

    def family_limits(self, model_options):
        return model_options.order, model_options.inplane

    def families(self, point, model_options, options, modes, blocks):
        # the blocks are (n, 1..M): the full model refuses the mixed mode sets that name others
        fields = "UVW" if options.families.inplane else "W"
        return full_families_for(axisymmetric_for(point.membrane, model_options.order, model_options.inplane),
                                 tuple((n, len(radial)) for n, radial in blocks), fields)

    def rebuilt(self, point, model_options, options, fmap, family):
        # the map keeps the task's steps; a delta where they exceed RK4's bound (a lower delta
        # has faster in-plane modes) raises ArithmeticError, which ends the curve there
        from model.full.forced import STABLE_STEP

        def at(delta):
            model = axisymmetric_for(replace(point.membrane, delta=delta), model_options.order, model_options.inplane)
            fam = (None if family is None
                   else full_families_for(model, ((family.n, family.radial),), family.fields)[0])
            rebuilt = fmap.on_model(model)
            # the task's steps keep |lambda|_max dt <= STABLE_STEP at its delta; a lower delta
            # raises the fastest rate (and lowers the transverse frequencies): refuse a step
            # beyond the bound
            fastest = max(rebuilt.fastest, 0.0 if fam is None else fam.omega_max)
            if rebuilt.period / rebuilt.steps * fastest > STABLE_STEP:
                raise ArithmeticError(f"at delta = {delta:.6g} the RK4 step exceeds |lambda|_max dt = {STABLE_STEP:g} "
                                      f"(|lambda|_max = {fastest:.4g} s-1): continuation.steps >= "
                                      f"{math.ceil(rebuilt.period * fastest / STABLE_STEP)} reach it")
            return rebuilt, fam
        return at

    def free_vibration(self, point, model_options, options):
        from model.full.free import FreeFull

        return FreeFull(axisymmetric_for(point.membrane, model_options.order, model_options.inplane))

    def static_state(self, point, model_options, options):
        return full_prestretch_for(point.membrane, model_options.order)

    def natural_frequencies(self, point, model_options, options, basis):
        from model.full.linear import transverse_frequencies

        state = full_prestretch_for(point.membrane, basis or model_options.order)
        return per_wave_number(options.modes, lambda n, count: transverse_frequencies(state, n, count)), []

    def inplane_frequencies(self, point, model_options, options, basis):
        from model.full.linear import inplane_frequencies

        state = full_prestretch_for(point.membrane, basis or model_options.order)
        return per_wave_number(options.modes, lambda n, count: inplane_frequencies(state, n, count))


FULL = FullModel()
