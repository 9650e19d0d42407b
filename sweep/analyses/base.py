"""The contract between the sweep runner and an analysis.

An analysis turns one *task* into a dictionary of fixed-shape numpy arrays.  A task is
one grid point (a :class:`Point`: the typed membrane and loading records) and one
*subtask* index: most analyses
have a single subtask per grid point, the basins analysis splits its lattice of initial
conditions into tiles, one subtask each.  The runner never looks inside the arrays: it
stores them with the shapes declared by :meth:`Analysis.variables` and writes them to the
result with dimensions ``(*grid_dims, *variable_dims)`` (``subtask`` after the grid's when
there are several), plus ``status`` and ``message`` per task; an analysis that must
restructure its result defines ``assemble`` (see :class:`Analysis`).

Kernels never see this module: it lives in ``sweep`` and only wraps ``model``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from dataclasses import fields as dataclass_fields
from typing import Any, ClassVar

import numpy as np

from model import damping as damping_laws
from model.damping import DampingLaw, Viscous
from model.materials import LAW_CONSTANTS
from model.params import Loading, Membrane, parameter_info
# the job-file errors are names of the analysis contract too (analyses raise them)
from sweep.job_errors import MISSING, JobError, JobErrors, check_keys  # noqa: F401

#: Values of the per-task ``status`` variable (CF ``flag_values``/``flag_meanings``).
STATUS_OK = 0
STATUS_NOT_CONVERGED = 1
STATUS_FAILED = 2
#: A grid point outside the job's ``[grid] cases``: not computed, the variables' fill values.
STATUS_SKIPPED = 3
STATUS_MEANINGS = "ok not_converged failed outside_cases"

def parameter_record(name: str) -> tuple[type, str, str]:
    """The record holding parameter ``name`` (:class:`~model.params.Membrane`,
    :class:`~model.params.Loading` or a damping law of :mod:`model.damping`) and the
    parameter's units and long name; ``c`` is the :class:`~model.params.Loading`'s."""
    try:
        return parameter_info(name)
    except KeyError:
        return damping_laws.parameter_info(name)


#: The constants of the damping laws (:mod:`model.damping`), by name.
DAMPING_KEYS = tuple(dict.fromkeys(p for law in damping_laws.LAWS.values() for p in law.parameters()))
#: The constants of the material laws (:mod:`model.materials`): ``C1`` and each law's own.
MATERIAL_KEYS = tuple(dict.fromkeys(("C1", *(k for ks in LAW_CONSTANTS.values() for k in ks))))
#: Grid keys a job may sweep, in canonical order, with the units and long names of the
#: parameter records (:mod:`model.params`, :mod:`model.damping`).
GRID_KEYS: dict[str, tuple[str, str]] = {
    key: parameter_record(key)[1:] for key in ("delta", "delta_o", "Omega", "P0", *DAMPING_KEYS, *MATERIAL_KEYS)}
#: The grid keys of the membrane's geometry.
GEOMETRY_KEYS = ("delta", "delta_o")
#: The keys of the ``[membrane]`` table: the :class:`~model.params.Membrane` fields but the
#: geometry's grid keys (the material constants may be in either place, not in both).
MEMBRANE_KEYS = tuple(f.name for f in dataclass_fields(Membrane) if f.name not in GEOMETRY_KEYS)


def membrane_attributes(membrane: Membrane, grid_keys=()) -> dict[str, Any]:
    """The result files' ``membrane_<key>`` attributes: the law and, of the ``[membrane]``
    keys that are not grid keys, those the law reads (``C2`` only for Mooney-Rivlin, ``Jm``
    only for Gent), with ``membrane_<key>_units`` for the material constants."""
    keys = [k for k in MEMBRANE_KEYS if k not in grid_keys
            and (k not in MATERIAL_KEYS or k == "C1" or k in LAW_CONSTANTS[membrane.law])]
    out = {f"membrane_{k}": getattr(membrane, k) for k in keys}
    out.update({f"membrane_{k}_units": GRID_KEYS[k][0] for k in keys if k in MATERIAL_KEYS})
    return out


@dataclass(frozen=True)
class DampingSpec:
    """The job's ``[damping]`` table.

    Parameters
    ----------
    law : DampingLaw
        The law (``[damping] law``, viscous by default) with the constants the table gives
        (the others at the law's defaults until the grid sets them per task).
    given : frozenset of str
        The constants the table gives.
    """

    law: DampingLaw = Viscous()
    given: frozenset[str] = frozenset()

    def missing(self, grid: Mapping[str, Any]) -> list[str]:
        """The law's constants neither in the table nor among the keys of ``grid``."""
        return [p for p in self.law.parameters() if p not in self.given and p not in grid]


#: A job without a ``[damping]`` table: the paper's viscous law, ``c`` from the grid.
DEFAULT_DAMPING = DampingSpec()


@dataclass(frozen=True)
class ModelSpec:
    """The job's ``[model]`` table: which registered model (:mod:`sweep.models`) computes
    the tasks, with its options.

    Parameters
    ----------
    kind : str
        ``[model] kind`` (``"rom"`` by default).
    options : object
        What the model's ``parse_options`` returned for the rest of the table.
    """

    kind: str = "rom"
    options: Any = None

    def model(self):
        """The registered :class:`sweep.models.base.Model` (imported on first use)."""
        from sweep import models
        return models.get(self.kind)

    def forced_map(self, point: Point, options: Any, modes=None, default_steps: int | None = None):
        """The stroboscopic map (:class:`model.protocol.StroboscopicMap`) of this model at
        ``point`` for an analysis with ``options`` (:meth:`sweep.models.base.Model.forced_map`)."""
        return self.model().forced_map(point, self.options, options, modes, default_steps)

    def free_vibration(self, point: Point, options: Any):
        """The free vibration (:class:`model.protocol.FreeVibration`) of this model at
        ``point`` (:meth:`sweep.models.base.Model.free_vibration`)."""
        return self.model().free_vibration(point, self.options, options)

    def static_state(self, point: Point, options: Any):
        """The static state of this model at ``point`` (:meth:`sweep.models.base.Model.static_state`)."""
        return self.model().static_state(point, self.options, options)

    def natural_frequencies(self, point: Point, options: Any, basis: int | None = None):
        """The natural frequencies of ``options.modes`` at ``point`` and what did not
        converge (:meth:`sweep.models.base.Model.natural_frequencies`)."""
        return self.model().natural_frequencies(point, self.options, options, basis)

    def families(self, point: Point, options: Any, modes, blocks):
        """The asymmetric family blocks of this model at ``point``
        (:meth:`sweep.models.base.Model.families`)."""
        return self.model().families(point, self.options, options, modes, blocks)

    def rebuilt(self, point: Point, options: Any, fmap, family):
        """``delta -> (map, family)`` of this model for curves in ``delta``
        (:meth:`sweep.models.base.Model.rebuilt`)."""
        return self.model().rebuilt(point, self.options, options, fmap, family)

    def inplane_frequencies(self, point: Point, options: Any, basis: int | None = None):
        """The in-plane natural frequencies of ``options.modes`` at ``point``
        (:meth:`sweep.models.base.Model.inplane_frequencies`)."""
        return self.model().inplane_frequencies(point, self.options, options, basis)


#: A job without a ``[model]`` table: the Galerkin ROM.
DEFAULT_MODEL = ModelSpec()


@dataclass(frozen=True)
class JobContext:
    """What an analysis' options may depend on besides its own table and the grid.

    Parameters
    ----------
    damping : DampingSpec
        The ``[damping]`` table.
    model : ModelSpec
        The ``[model]`` table.
    """

    damping: DampingSpec = DEFAULT_DAMPING
    model: ModelSpec = DEFAULT_MODEL


#: A job with neither ``[damping]`` nor ``[model]``.
DEFAULT_CONTEXT = JobContext()


@dataclass(frozen=True)
class Point:
    """One grid point of a job, as :meth:`Analysis.compute` receives it.

    Parameters
    ----------
    membrane : Membrane
        The ``[membrane]`` table and the grid's ``delta``, ``delta_o`` and material
        constants (``C1``, ``C2``, ``Jm``).
    loading : Loading
        The grid's ``Omega``, ``P0``, ``c`` (the record's defaults for keys that are not
        grid keys: an analysis that varies ``Omega`` or ``P0`` itself replaces them).
    grid : Mapping of str to float
        The grid values of this point, by grid key.
    damping : DampingLaw
        The job's damping law with this point's constants (for the viscous law, ``c`` is
        also ``loading.c``).
    model : ModelSpec
        The job's model (its :meth:`ModelSpec.forced_map` builds the map of this point).
    """

    membrane: Membrane
    loading: Loading
    grid: Mapping[str, float]
    damping: DampingLaw = Viscous()
    model: ModelSpec = DEFAULT_MODEL

    def value(self, name: str) -> float:
        """The value of parameter ``name`` at this point (a field of the membrane, the
        loading or the damping law)."""
        for record in (self.damping, self.loading, self.membrane):
            if hasattr(record, name):
                return float(getattr(record, name))
        raise KeyError(name)


@dataclass(frozen=True)
class Variable:
    """One output of a task, as the runner stores it.

    Parameters
    ----------
    name : str
        Variable name in the raw dataset.
    dims : tuple of str
        Dimension names beyond the grid's (and beyond ``subtask``).
    shape : tuple of int
        Shape of the array a task returns; ``len(shape) == len(dims)``.
    dtype : str
        numpy dtype string (``"f8"``, ``"i4"``, ``"i1"``).
    units : str
        CF ``units`` attribute (``"1"`` for dimensionless).
    long_name : str
        CF ``long_name`` attribute.
    fill : float or int
        Value of a task that has not produced this variable.
    attrs : Mapping
        Further attributes (``flag_values``, ``flag_meanings``, ...).
    """

    name: str
    dims: tuple[str, ...]
    shape: tuple[int, ...]
    dtype: str
    units: str
    long_name: str
    fill: float | int = np.nan
    attrs: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        # xarray makes a variable named after one of its dimensions a coordinate of it, and
        # a coordinate of several dimensions has no index: such files no longer combine
        if self.name in self.dims and self.dims != (self.name,):
            raise ValueError(f"Variable {self.name!r} is named after one of its dimensions {self.dims}: rename it")

    def blank(self) -> np.ndarray:
        """An array of the declared shape and dtype filled with ``fill``: where a task's
        output starts, so that what it does not reach stays padding."""
        return np.full(self.shape, self.fill, dtype=self.dtype)


def blank_outputs(variables) -> dict[str, np.ndarray]:
    """:meth:`Variable.blank` of each of ``variables``, by name."""
    return {v.name: v.blank() for v in variables}


def add_message(out: dict, text: str) -> None:
    """Append ``text`` to the task's ``message`` in ``out`` (``"; "`` between parts; nothing
    for an empty ``text``)."""
    out["message"] = "; ".join(m for m in (out.get("message", ""), text) if m)


class TaskError(Exception):
    """A task returned something else than its analysis declares (a bug of the analysis)."""


def check_result(result: object, variables: list[Variable]) -> None:
    """Check what :meth:`Analysis.compute` returned against its declarations.

    ``result`` must be a dict with exactly the declared variables (each of its declared
    shape), ``status`` (``STATUS_OK``, ``STATUS_NOT_CONVERGED`` or ``STATUS_FAILED``) and
    optionally a str ``message``.

    Raises
    ------
    TaskError
        Naming what differs.
    """
    if not isinstance(result, dict):
        raise TaskError(f"compute returned a {type(result).__name__}, not a dict")
    expected = {v.name for v in variables} | {"status"}
    if set(result) - {"message"} != expected:
        raise TaskError(f"compute returned the keys {sorted(result)}, expected "
                        f"{sorted(expected)} and optionally 'message'")
    for v in variables:
        shape = np.shape(result[v.name])
        if shape != v.shape:
            raise TaskError(f"compute returned {v.name!r} with shape {shape}, the analysis declares {v.shape}")
    codes = (STATUS_OK, STATUS_NOT_CONVERGED, STATUS_FAILED)
    if result["status"] not in codes:
        raise TaskError(f"compute returned status {result['status']!r}, expected one of {codes}")
    if not isinstance(result.get("message", ""), str):
        raise TaskError(f"compute returned a message of type {type(result['message']).__name__}, not str")


class Analysis(ABC):
    """One kind of computation a job can ask for (``[job] analysis = name``).

    Subclasses are stateless; everything a task needs travels in ``options`` (the
    validated option table) and ``point`` (a :class:`Point`).
    """

    name: ClassVar[str]
    #: The option table ``[<name>]``: key -> one-line description with the default and
    #: units; ``parse_options`` accepts exactly these keys and docs/options.md lists them.
    OPTIONS: ClassVar[Mapping[str, str]] = {}
    #: grid keys that must be present (each may still have length 1)
    required_grid: ClassVar[tuple[str, ...]] = ("delta", "delta_o")
    #: What the analysis asks of the job's model (:class:`sweep.models.base.Model`): the
    #: names of the methods it calls (``forced_map``, ``free_vibration``, ``static_state``,
    #: ``natural_frequencies``); a job whose model does not provide them is refused.
    model_needs: ClassVar[tuple[str, ...]] = ()

    @abstractmethod
    def parse_options(self, table: Mapping[str, Any], grid: Mapping[str, np.ndarray],
                      membrane: Membrane, context: JobContext = DEFAULT_CONTEXT) -> Any:
        """Validate the analysis' option table; raise :class:`JobError` on bad input.

        ``grid`` maps each grid key to its 1-D array of values; ``membrane`` is the
        membrane of the ``[membrane]`` table (its ``delta``, ``delta_o`` are the record's
        defaults, the grid sets them per task); ``context`` holds the ``[damping]`` and
        ``[model]`` tables.
        Returns an immutable, picklable options object (a frozen dataclass), whose ``repr``
        is stable.
        """

    @abstractmethod
    def variables(self, options: Any) -> list[Variable]:
        """The arrays every task returns (``status`` is added by the runner)."""

    def coords(self, options: Any) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict]]:
        """Coordinates of the non-grid dimensions: ``name -> (dims, values, attrs)``."""
        return {}

    def n_subtasks(self, options: Any) -> int:
        """Number of subtasks per grid point (tiles of a lattice)."""
        return 1

    @abstractmethod
    def compute(self, point: Point, options: Any, subtask: int) -> dict[str, np.ndarray]:
        """Compute one task.

        Returns ``{name: array}`` for every declared variable, ``"status"`` (one of the
        ``STATUS_*`` codes) and optionally ``"message"``, a short reason when the status is
        not ok (``"reached max_points = 400 (raise max_points)"``).  Numerical
        non-convergence is a status; an exception raised here is caught by the runner and
        stored as status failed with its type and message, and the sweep goes on.
        """

    def warmups(self, options: Any) -> list[Callable[[], None]]:
        """The compilation of the numba kernels this analysis uses, as independent calls.

        Before any task the runner makes these calls on every node, call ``i`` on the
        node's rank ``i`` modulo its ranks (on one rank, all of them), while the node's
        other ranks wait; then every rank loads the compiled kernels from the node's cache.
        On a node of several ranks the calls run concurrently, so two calls must not
        compile one cached kernel with different argument types: numba saves a kernel's
        signatures in one index file, and two processes adding different signatures at
        once can leave the index naming the other's code (numba issue 4807).  The same
        signatures added in the same order by two calls are safe (the same entries, written
        whole by either).
        tests/test_mode_sets.py checks this for the basins analysis.  Default: none.
        """
        return []

    #: ``assemble(raw, options)``: turns the raw merged Dataset, dims ``(*grid_dims,
    #: "subtask", *variable_dims)`` with ``status`` and ``message``, into the published one,
    #: in memory on rank 0.  None (the default) publishes the raw layout itself (without
    #: the ``subtask`` dimension when there is one subtask per point), streamed to the file
    #: in bounded memory; an analysis defines it only when it must restructure (basins).
    assemble = None

    def attributes(self, options: Any) -> dict[str, Any]:
        """Global attributes the result carries for this analysis (default none)."""
        return {}

    def coordinate_variables(self, options: Any) -> tuple[str, ...]:
        """Declared variables published as (non-index) coordinates of the variables that
        share their dimensions, e.g. the continued parameter along a branch, so that
        ``ds.amplitude.plot.line(x="Omega")`` works (default none)."""
        return ()

    def derived(self, ds, options: Any) -> dict:
        """Variables computed from the collected result ``ds`` (opened from the file) and
        appended to it: ``name -> DataArray`` (default none)."""
        return {}
