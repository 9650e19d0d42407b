"""The ``symmetry_breaking`` feature of the ``continuation`` analysis: the responses that lose
the half-period symmetry.

The transverse force is odd in ``w``, so a response to ``P0 cos(Omega t)`` can be symmetric in
time, ``w(t + T/2) = -w(t)``.  Where a real multiplier of the axisymmetric block passes +1
without a fold, that response gives way to a pair of axisymmetric responses without the
symmetry (docs/model.md, "Bifurcation test functions").  With ``symmetry_breaking =
{max_points = N}`` the first such branch point of the branch is switched at
(:func:`model.switching.follow_time_symmetry_breaking`) and the new branch followed for at most
N points, with the multipliers of the branch's families along it: the responses a slow sweep
follows past the point, and their stability to the asymmetric families.  Where the new branch
meets the symmetric one again (at a second such point, a saddle-node of the new branch) the
continuation goes on along the pair's image, the same amplitudes and multipliers: N need not
be larger than that.  Any model with
forced maps (the ROM's axisymmetric modes, the full model with u free or held).

Outputs over ``broken_point``: ``broken_<parameter>``, ``broken_amplitude``,
``broken_stable`` (the families' multipliers included, as ``stable``), ``broken_point_type``,
``broken_point_family``, ``broken_multiplier_modulus`` (the axisymmetric block's own),
``broken_modal_coordinate`` (``broken_point``, ``mode``) and with ``families``
``broken_family_multiplier_modulus`` (``broken_point``, ``family``).  A branch without such a
point leaves them padding; reaching N points is not a failure.
"""

from __future__ import annotations

import numpy as np

from model.continuation import BRANCH_POINT
from model.protocol import modal_section
from model.switching import follow_time_symmetry_breaking

from . import options as opt
from .base import GRID_KEYS, JobError, Variable, blank_outputs
from .branch_features import BranchFeature, kind_attrs

_FLAGS = {"flag_values": np.array([-1, 0, 1], np.int8), "flag_meanings": "padding unstable stable"}


def symmetry_breaking_option(table, section) -> int:
    """``symmetry_breaking = {max_points = N}`` -> N, 0 without the option."""
    value = table.get("symmetry_breaking")
    if value is None:
        return 0
    name = f"{section}.symmetry_breaking"
    if not isinstance(value, dict):
        raise JobError(name, value, "must be a table {max_points = N}")
    for key in value:
        if key != "max_points":
            raise JobError(f"{name}.{key}", value[key], "unknown key (the table is {max_points = N})")
    return opt.number(value, name, "max_points", integer=True, low=2, high=100_000)


class TimeSymmetryBreaking(BranchFeature):
    """``symmetry_breaking``: the branch born where the response loses its half-period symmetry."""

    def enabled(self, options):
        return bool(options.broken_points)

    def variables(self, options):
        if not self.enabled(options):
            return []
        n, p, bp = options.broken_points, options.parameter, ("broken_point",)
        out = [
            Variable(f"broken_{p}", bp, (n,), "f8", GRID_KEYS[p][0],
                     f"{p} along the branch without the half-period symmetry, from its branch point"),
            Variable("broken_amplitude", bp, (n,), "f8", "m", "max over one period of |w(0.5 Re, 0, t)|"),
            Variable("broken_stable", bp, (n,), "i1", "1", "stability of the periodic response (the families' "
                     "multipliers included)", -1, _FLAGS),
            Variable("broken_point_type", bp, (n,), "i1", "1", "kind of point on that branch", -1, kind_attrs()),
            Variable("broken_point_family", bp, (n,), "i2", "1", "wave number n of the block a located point "
                     "belongs to (0: axisymmetric block and regular points)", -1),
            Variable("broken_multiplier_modulus", bp, (n,), "f8", "1",
                     "largest Floquet multiplier modulus of the axisymmetric block"),
            Variable("broken_modal_coordinate", ("broken_point", "mode"), (n, len(options.modes)), "f8", "m",
                     "modal coordinate q_mn on the stroboscopic section"),
        ]
        if options.families is not None:
            out.append(Variable("broken_family_multiplier_modulus", ("broken_point", "family"),
                                (n, len(options.families.n)), "f8", "1",
                                "largest Floquet multiplier modulus of the family's block"))
        return out

    def coords(self, options):
        if not self.enabled(options):
            return {}
        return {"broken_point": (("broken_point",), np.arange(options.broken_points, dtype=np.int32),
                                 {"long_name": "index along the branch without the half-period symmetry",
                                  "units": "1"})}

    def compute(self, ctx):
        """The outputs, and "" as the problem also when the branch has no such point."""
        options, br, p = ctx.options, ctx.branch, ctx.options.parameter
        out = blank_outputs(self.variables(options))
        points = np.flatnonzero((br.kind == BRANCH_POINT) & (br.family == 0))
        if not points.size:
            return out, ""
        i = int(points[0])
        try:
            sw = follow_time_symmetry_breaking(ctx.fmap, p, options.start, options.stop, br.state[i], br.value[i],
                                               families=ctx.families, ds_max=options.ds_max,
                                               max_points=options.broken_points)
        except (RuntimeError, ArithmeticError, np.linalg.LinAlgError) as exc:
            return out, f"symmetry breaking at {p} = {br.value[i]:.9g}: {type(exc).__name__}: {exc}"
        m, K = sw.value.size, len(options.modes)
        out[f"broken_{p}"][:m], out["broken_amplitude"][:m] = sw.value, sw.amplitude
        out["broken_stable"][:m], out["broken_point_type"][:m] = sw.stable, sw.kind
        out["broken_point_family"][:m] = sw.family
        out["broken_multiplier_modulus"][:m] = np.abs(sw.multipliers).max(axis=1)
        out["broken_modal_coordinate"][:m] = modal_section(ctx.fmap, sw.state)[:, :K]
        if options.families is not None:
            out["broken_family_multiplier_modulus"][:m] = np.nanmax(np.abs(sw.family_multipliers), axis=-1)
        problem = "" if sw.complete or m >= options.broken_points else f"symmetry-broken branch: {sw.message}"
        return out, problem


#: The feature, in the order of the continuation's features.
TIME_SYMMETRY_FEATURES = (TimeSymmetryBreaking(),)
