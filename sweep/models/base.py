"""The contract between the sweep and a model: what a job's ``[model]`` table names.

A model turns one grid point (a :class:`~sweep.analyses.base.Point`) and an analysis'
options into the objects the algorithms of :mod:`model` take: for the forced analyses
(``response``, ``continuation``, ``basins``) a stroboscopic map
(:class:`model.protocol.StroboscopicMap`).  The analyses never build a model themselves.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from typing import Any, ClassVar

from sweep.job_errors import check_keys


class Model(ABC):
    """One kind of model a job can ask for (``[model] kind = name``)."""

    name: ClassVar[str]
    #: The keys of ``[model]`` besides ``kind``: key -> one-line description (docs/options.md).
    OPTIONS: ClassVar[Mapping[str, str]] = {}
    #: The grid keys of the membrane the model needs (the analyses add their forcing keys).
    required_grid: ClassVar[tuple[str, ...]] = ()
    #: Whether the analyses' ROM-only options (mode families, branch switching, curves in
    #: delta, the lean quadrature of the basins) apply to this model's maps.
    rom_features: ClassVar[bool] = False

    def parse_options(self, table: Mapping[str, Any]) -> Any:
        """Validate the ``[model]`` table (without ``kind``); raise
        :class:`~sweep.analyses.base.JobError` on bad input.  Default: no keys."""
        check_keys(table, "model", ("kind", *self.OPTIONS))
        return None

    @abstractmethod
    def forced_map(self, point, model_options: Any, options: Any, modes=None, default_steps: int | None = None):
        """The stroboscopic map of the model at ``point`` (its forcing, damping law and
        membrane) for an analysis with ``options``.

        ``modes`` overrides the analysis' mode set (a ROM's: the axisymmetric part of a
        mode set reduced by symmetry); ``default_steps`` is the analysis' number of time
        steps per forcing period where its options give none.  Models without modes or
        fixed steps ignore them.
        """
