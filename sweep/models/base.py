"""The contract between the sweep and a model: what a job's ``[model]`` table names.

A model turns one grid point (a :class:`~sweep.analyses.base.Point`) and an analysis'
options into the objects the algorithms of :mod:`model` take: for the forced analyses
(``response``, ``continuation``, ``basins``) a stroboscopic map
(:class:`model.protocol.StroboscopicMap`); for ``backbone`` its free vibration
(:class:`model.protocol.FreeVibration`); for ``static`` its static state and for
``linear`` its natural frequencies (and, for a model with in-plane motion, its in-plane
ones).  Every method is optional: an analysis names the methods it calls (:attr:`sweep.analyses.base.Analysis.model_needs`) and a job
whose model does not provide them (:meth:`Model.provides`) is refused at validation.  The
analyses never build a model themselves.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from sweep.job_errors import check_keys


def per_wave_number(modes, solve) -> np.ndarray:
    """The frequency of each mode ``(m, n)`` of ``modes``: the m-th of ``solve(|n|, count)``,
    called once per wave number with ``count`` the largest m of that wave number (a sine
    companion ``(m, -n)`` has the frequencies of its cosine mode)."""
    by_n: dict[int, np.ndarray] = {}
    omega = np.empty(len(modes))
    for k, (m, signed_n) in enumerate(modes):
        n = abs(signed_n)
        if n not in by_n:
            by_n[n] = solve(n, max(a for a, b in modes if abs(b) == n))
        omega[k] = by_n[n][m - 1]
    return omega


class Model:
    """One kind of model a job can ask for (``[model] kind = name``)."""

    name: ClassVar[str]
    #: The keys of ``[model]`` besides ``kind``: key -> one-line description (docs/options.md).
    OPTIONS: ClassVar[Mapping[str, str]] = {}
    #: The grid keys of the membrane the model needs (the analyses add their forcing keys).
    required_grid: ClassVar[tuple[str, ...]] = ()
    #: Whether the analyses' ROM-only options (mixed mode sets, mode-set sweeps, tongues, the
    #: modal coordinates of the waves) apply to this model's maps.
    rom_features: ClassVar[bool] = False
    #: Whether the model's ``perturbed_family`` (:mod:`model.protocol`) takes ``harmonics``:
    #: the family check on the circumferential harmonics ``0, n, ..., K n``
    #: (``family_check.harmonics``; the full model).
    circumferential_harmonics: ClassVar[bool] = False
    #: Whether the model's forced maps hold axisymmetric states only (the forced analyses'
    #: ``modes`` must then be axisymmetric, ``(m, 0)``).
    axisymmetric_states: ClassVar[bool] = False
    #: The ``prestretch`` variants (:data:`model.prestretch.KINDS`) the analyses may ask of
    #: the model (a model that solves its own pre-stretch admits ``numeric`` only).
    prestretch_kinds: ClassVar[tuple[str, ...]] = ("analytic", "numeric", "fit")

    def provides(self, method: str, model_options: Any = None) -> bool:
        """Whether the model implements ``method`` (one of the methods below, which raise
        NotImplementedError unless a subclass overrides them), with the job's
        ``model_options`` when given (a model may provide less under some options)."""
        return getattr(type(self), method, None) is not getattr(Model, method, None)

    def orbit_extents(self, model_options: Any) -> str:
        """The displacement fields (of ``"uvw"``) whose largest magnitude over a free orbit
        and the membrane the model's free vibration measures
        (:meth:`model.full.free.FreeFull.extent`; the backbone's ``max_abs_<field>``); none
        by default."""
        return ""

    def state_size(self, model_options: Any) -> int:
        """The size of the forced maps' state when it is not their modal section (the
        continuation then stores it as ``section_state``, from which a study restarts); 0 when it is
        (the ROM: the state is its modal coordinates and velocities)."""
        return 0

    def parse_options(self, table: Mapping[str, Any]) -> Any:
        """Validate the ``[model]`` table (without ``kind``); raise
        :class:`~sweep.analyses.base.JobError` on bad input.  Default: no keys."""
        check_keys(table, "model", ("kind", *self.OPTIONS))
        return None

    def forced_map(self, point, model_options: Any, options: Any, modes=None, default_steps: int | None = None):
        """The stroboscopic map of the model at ``point`` (its forcing, damping law and
        membrane) for an analysis with ``options``.

        ``modes`` overrides the analysis' mode set (a ROM's: the axisymmetric part of a
        mode set reduced by symmetry); ``default_steps`` is the analysis' number of time
        steps per forcing period where its options give none.  Models without modes or
        fixed steps ignore them.
        """
        raise NotImplementedError(f"model {self.name!r} has no stroboscopic map (forced analyses)")

    def free_vibration(self, point, model_options: Any, options: Any):
        """The free vibration (:class:`model.protocol.FreeVibration`) of the model at
        ``point`` for the ``backbone`` analysis with ``options``."""
        raise NotImplementedError(f"model {self.name!r} has no free vibration (backbone)")

    def static_state(self, point, model_options: Any, options: Any):
        """The static pre-stretched state at ``point`` for the ``static`` analysis: an
        object with ``radius(rho)``, ``stresses(rho)`` and ``traction()``
        (:class:`model.prestretch.Prestretch`)."""
        raise NotImplementedError(f"model {self.name!r} has no static state")

    def natural_frequencies(self, point, model_options: Any, options: Any, basis: int | None):
        """Natural frequencies (rad s-1) of the modes of ``options.modes`` at ``point`` for
        the ``linear`` analysis, with ``basis`` functions per wave number (None: the
        model's converged default), and a list of what did not converge (empty when all
        did)."""
        raise NotImplementedError(f"model {self.name!r} has no natural frequencies (linear)")

    def family_limits(self, model_options: Any) -> tuple[int, bool]:
        """``(largest radial count, in-plane)`` of the asymmetric families a job may ask of
        the model (``continuation.families``): the most radial functions per family, and
        whether its perturbations can carry in-plane fields (then their default)."""
        return 32, False

    def families(self, point, model_options: Any, options: Any, modes, blocks):
        """The asymmetric family blocks that the model's forced maps take
        (``family_monodromy``) at ``point`` for a continuation with ``options``, on the
        axisymmetric ``modes``: one per ``(n, radial indices)`` of ``blocks``."""
        raise NotImplementedError(f"model {self.name!r} has no asymmetric families")

    def rebuilt(self, point, model_options: Any, options: Any, fmap, family):
        """``delta -> (map, family)`` for a curve in ``delta`` (``continuation.bifurcation_curves``):
        ``fmap`` and the family block ``family`` (None for none) of ``point`` rebuilt on its
        membrane with that ``delta``, with the same modes, forcing, damping law and steps; an
        ArithmeticError where the model cannot be rebuilt ends the curve there with its message."""
        raise NotImplementedError(f"model {self.name!r} cannot be rebuilt at another delta")

    def inplane_frequencies(self, point, model_options: Any, options: Any, basis: int | None):
        """In-plane natural frequencies (rad s-1) at ``point`` for the ``linear`` analysis: for
        each mode ``(m, n)`` of ``options.modes`` the m-th in-plane frequency of wave number
        ``n``, with ``basis`` functions per field (None: the model's default)."""
        raise NotImplementedError(f"model {self.name!r} has no in-plane motion")
