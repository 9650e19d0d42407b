"""The two-dimensional finite-element check (:mod:`model.fe_annulus`) as a job's model
(``[model] kind = "fe2d"``).

The membrane on a structured mesh of the annulus, Cartesian displacement components, no
polar reduction: an independent check of the full model.  It runs ``linear`` (transverse and
in-plane frequencies, each eigenvector labelled with its wave number); ``omega_approx`` is
NaN (it has no radial pre-stretch function for Eq. 28).  ``linear.basis`` sets the radial
elements per task, the circumferential ones in the ratio of ``[model]`` (a list is a mesh
refinement study; the result's ``model_radial`` and ``model_circumferential`` are those of
``[model]``, the meshes of the study scale them).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from model.fe_annulus import ELEMENTS, GRADINGS, MASSES
from sweep.analyses import options as opt
from sweep.job_errors import JobError, check_keys
from sweep.models.base import Model, per_wave_number


#: Most elements around the annulus a task may use.
MAX_AROUND = 2048


@dataclass(frozen=True)
class FeOptions:
    element: str
    radial: int
    circumferential: int
    grading: str
    mass: str


@functools.lru_cache(maxsize=4)
def fe_prestretch_for(membrane, radial: int, circumferential: int, element: str, grading: str):
    """The pre-stretch (:func:`model.fe_annulus.solve_fe_prestretch`) on the mesh (cached)."""
    from model.fe_annulus import AnnulusMesh, solve_fe_prestretch

    return solve_fe_prestretch(AnnulusMesh.build(membrane, radial, circumferential, element, grading))


@functools.lru_cache(maxsize=4)
def fe_motion_for(membrane, radial: int, circumferential: int):
    """The free motion (:class:`model.fe_motion.FeMotion`) on the P2 mesh with logarithmic
    grading (cached)."""
    from model.fe_motion import FeMotion

    return FeMotion.build(fe_prestretch_for(membrane, radial, circumferential, "P2", "logarithmic"))


class FeModel(Model):
    """The membrane on a 2-D mesh of ``radial`` x ``circumferential`` elements."""

    name = "fe2d"
    required_grid = ("delta", "delta_o")
    prestretch_kinds = ("numeric",)
    OPTIONS = {
        "element": "P2 (quadratic triangles on a quadratic mesh, default) | Q1 (bilinear quadrilaterals, straight "
                   "edges, the kind of the paper's FEM elements)",
        "radial": "elements across the annulus (default 16); linear.basis overrides it per task",
        "circumferential": "elements around it (default 8 radial; with linear.basis in the same ratio to radial)",
        "grading": "logarithmic (circles finer toward the inner edge, default) | uniform",
        "mass": "consistent (default) | lumped (row sums; Q1 only)",
    }

    def parse_options(self, table):
        check_keys(table, "model", ("kind", *self.OPTIONS))
        element = opt.choice(table, "model", "element", ELEMENTS, "P2")
        radial = opt.number(table, "model", "radial", 16, low=1, high=256, integer=True)
        circumferential = opt.number(table, "model", "circumferential", 8 * radial, low=8, high=MAX_AROUND,
                                     integer=True)
        mass = opt.choice(table, "model", "mass", MASSES, "consistent")
        if mass == "lumped" and element != "Q1":
            raise JobError("model.mass", mass, "consistent with element = 'P2' (row-sum lumping needs Q1)")
        return FeOptions(element, radial, circumferential, opt.choice(table, "model", "grading", GRADINGS,
                                                                       "logarithmic"), mass)

    def natural_frequencies(self, point, model_options, options, basis):
        return self._frequencies(point, model_options, options.modes, basis, "W"), []

    def inplane_frequencies(self, point, model_options, options, basis):
        return self._frequencies(point, model_options, options.modes, basis, "UV")

    @staticmethod
    def _frequencies(point, o: FeOptions, modes, basis, fields):
        from model.fe_annulus import fe_frequencies

        radial = basis or o.radial
        circumferential = o.circumferential if basis is None else \
            min(MAX_AROUND, max(8, round(basis * o.circumferential / o.radial)))
        state = fe_prestretch_for(point.membrane, radial, circumferential, o.element, o.grading)
        # one eigensolution gives every wave number
        by_n = fe_frequencies(state, fields, max(m for m, _ in modes), n_max=max(abs(n) for _, n in modes),
                              mass=o.mass)
        return per_wave_number(modes, lambda n, count: by_n[n])


FE2D = FeModel()
