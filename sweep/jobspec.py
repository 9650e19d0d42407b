"""Job files: read, validate whole, and describe a sweep before anything is computed.

A job file is TOML with the tables ``[job]``, ``[model]``, ``[membrane]`` and ``[damping]``
(optional), ``[grid]`` and ``[<analysis>]`` (the analysis' options).  Every problem raises
:class:`~sweep.analyses.base.JobError` naming the dotted key, the value and what is
allowed; every problem found is reported (a malformed file, a missing ``[job]`` table or
an unknown analysis stop the validation at once).
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from model.damping import LAWS, DampingLaw, Viscous
from model.materials import LAW_CONSTANTS
from model.params import Loading, Membrane, ParameterError
from sweep import analyses, models
from sweep.analyses.base import (DAMPING_KEYS, DEFAULT_MODEL, GEOMETRY_KEYS, GRID_KEYS, MATERIAL_KEYS, MEMBRANE_KEYS,
                                 MISSING, Analysis,
                                 DampingSpec, JobContext, JobError, JobErrors, ModelSpec, Point, check_keys,
                                 parameter_record)
from sweep.analyses.mode_sets import ModeSetSweep, is_mode_set_list
from sweep.grid import TaskLayout, default_chunk


_JOB_KEYS = ("name", "analysis", "chunk")
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")
_GRID_FORMS = ("a number, a non-empty list of numbers, or a table {start=, stop=, num=} "
               "(with scale = \"log\" for geometric spacing)")


@dataclass(frozen=True, eq=False)
class Job:
    """A validated job.

    Parameters
    ----------
    name : str
        ``[job] name``; the default output is ``<name>.nc``.
    analysis_name : str
        ``[job] analysis``.
    analysis : Analysis
        The analysis object.
    options : object
        What ``analysis.parse_options`` returned.
    membrane : Membrane
        The ``[membrane]`` table on the record's defaults (``delta``, ``delta_o`` are set
        per task from the grid).
    damping : DampingSpec
        The ``[damping]`` table (the viscous law without one).
    model : ModelSpec
        The ``[model]`` table (the ROM without one).
    layout : TaskLayout
        Grid, tasks and chunks.
    text : str
        The job file text, stored in the results.
    """

    name: str
    analysis_name: str
    analysis: Analysis
    options: Any
    membrane: Membrane
    damping: DampingSpec
    model: ModelSpec
    layout: TaskLayout
    text: str

    @property
    def sha256(self) -> str:
        """Hex SHA-256 of the job file text (a resume must match it)."""
        return job_hash(self.text)

    def point(self, t: int) -> tuple[Point, int]:
        """The :class:`~sweep.analyses.base.Point` of task ``t`` and its subtask index."""
        values, subtask = self.layout.task(t)
        return grid_point(self.membrane, values, self.damping.law, self.model), subtask


def grid_point(membrane: Membrane, values: Mapping[str, float], damping: DampingLaw = Viscous(),
               model: ModelSpec = DEFAULT_MODEL) -> Point:
    """The typed records of one grid point: ``values`` (grid key -> value) replace the
    fields of ``membrane``, of the :class:`~model.params.Loading` defaults and the constants
    of the damping law ``damping`` (the viscous law's ``c`` is also the loading's)."""
    law = dataclasses.replace(damping, **{k: v for k, v in values.items() if k in damping.parameters()})
    loading = {k: v for k, v in values.items() if k in ("Omega", "P0")}
    if isinstance(law, Viscous):
        loading["c"] = law.c
    fields = {k: v for k, v in values.items() if k not in loading and k not in DAMPING_KEYS}
    return Point(dataclasses.replace(membrane, **fields), Loading(**loading), dict(values), law, model)


def job_hash(text: str) -> str:
    """Hex SHA-256 of a job file text."""
    return hashlib.sha256(text.encode()).hexdigest()


def read_job_text(path: str | Path) -> str:
    """Read a job file.

    Raises
    ------
    JobError
        If the file cannot be read as UTF-8 text.
    """
    try:
        return Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise JobError("job file", str(path), "an existing file (no such file)") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise JobError("job file", str(path), f"a readable UTF-8 text file ({exc})") from None


def load_job(path: str | Path) -> Job:
    """Read and validate a job file (:func:`read_job_text` then :func:`parse_job`)."""
    return parse_job(read_job_text(path), str(path))


def parse_job(text: str, source: str = "<job>") -> Job:
    """Validate a job file text whole.

    Parameters
    ----------
    text : str
        TOML text.
    source : str
        File name, for the message of a TOML syntax error.

    Returns
    -------
    Job

    Raises
    ------
    JobError
        Naming the key, the value and what is allowed; :class:`JobErrors` (one line per
        problem) when there are several.  A malformed file, a missing ``[job]`` table or an
        unknown analysis stop the validation at once.
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise JobError("job file", source, f"TOML syntax is required: {exc}") from None

    errors: list[JobError] = []

    def checked(validate, *args, default=None):
        """``validate(*args)``, or ``default`` with its JobError recorded."""
        try:
            return validate(*args)
        except JobError as exc:
            errors.append(exc)
            return default

    job = _table(doc, "job", required=True)
    checked(check_keys, job, "job", _JOB_KEYS)
    name = checked(_job_name, job.get("name", MISSING))
    analysis_name = _string("job.analysis", job.get("analysis", MISSING))
    analysis = analyses.get(analysis_name)
    options_table = doc.get(analysis_name)
    if "modes" in analysis.OPTIONS and isinstance(options_table, dict) \
            and is_mode_set_list(options_table.get("modes")):
        analysis = ModeSetSweep(analysis)

    tables = ("job", "model", "membrane", "damping", "grid", analysis_name)
    for key, value in doc.items():
        if key not in tables:
            allowed = ", ".join(f"[{t}]" for t in tables)
            errors.append(JobError(key, value, f"unknown table; the tables are {allowed}"))

    model = checked(lambda: _model(_table(doc, "model", required=False)))
    if model is not None:
        checked(_model_provides, model, analysis, analysis_name)
    membrane = checked(lambda: _membrane(_table(doc, "membrane", required=False)))
    damping = checked(lambda: _damping(_table(doc, "damping", required=False)))
    grid_table = checked(lambda: _table(doc, "grid", required=True))
    grid = None if grid_table is None else checked(lambda: _grid({k: v for k, v in grid_table.items()
                                                                   if k != "cases"}))
    cases = ()
    required_ok = False
    if grid is not None:
        cases = checked(lambda: _cases(grid_table["cases"], grid) if "cases" in grid_table else (), default=())
        if membrane is not None:
            checked(_material_grid, membrane, _table(doc, "membrane", required=False), grid)
        if damping is not None and model is not None:
            checked(_damping_grid, damping, grid)
            required_ok = checked(_required_grid, analysis, analysis_name, grid, damping, model, default=False)
    options = None
    if required_ok and membrane is not None:
        options = checked(lambda: analysis.parse_options(_table(doc, analysis_name, required=False), grid,
                                                         membrane, JobContext(damping, model)))
    chunk = checked(lambda: _integer("job.chunk", job["chunk"], 1, "an integer > 0 (tasks per chunk)")
                    if "chunk" in job else None)
    if errors:
        raise errors[0] if len(errors) == 1 else JobErrors(errors)

    n_subtasks = analysis.n_subtasks(options)
    n_tasks = math.prod(len(v) for v in grid.values()) * n_subtasks
    layout = TaskLayout(tuple(grid), tuple(grid.values()), n_subtasks, chunk or default_chunk(n_tasks), cases)
    return Job(name, analysis_name, analysis, options, membrane, damping, model, layout, text)


def _table(doc: Mapping, key: str, *, required: bool) -> dict:
    if key not in doc:
        if required:
            raise JobError(key, MISSING, f"a [{key}] table is required")
        return {}
    if not isinstance(doc[key], dict):
        raise JobError(key, doc[key], f"a [{key}] table")
    return doc[key]


def _string(key: str, value: Any) -> str:
    if not isinstance(value, str) or not value:
        raise JobError(key, value, "a non-empty string")
    return value


#: Longest job name: the output ``<name>.nc``, its parts directory and temporary files
#: must fit the 255-byte file names of common file systems.
MAX_NAME = 200


def _job_name(value: Any) -> str:
    if not isinstance(value, str) or not _NAME.fullmatch(value) or len(value) > MAX_NAME:
        raise JobError("job.name", value, "a string of letters, digits, '.', '_', '-' "
                       f"starting with a letter or digit, at most {MAX_NAME} characters "
                       "(it names the output file)")
    return value


def _integer(key: str, value: Any, minimum: int, allowed: str) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum:
        raise JobError(key, value, allowed)
    return value


def _record_value(key: str, name: str, value: Any, record: type) -> float:
    """``value`` validated as field ``name`` of ``record`` (Membrane, Loading or a damping
    law); the record's own rule, reported as a :class:`JobError` on the job-file ``key``."""
    try:
        return getattr(record(**{name: value}), name)
    except ParameterError as exc:
        raise JobError(key, value, exc.allowed) from None


def _membrane(table: Mapping) -> Membrane:
    """``[membrane]``: the law (neo-Hookean by default), its constants and the rest of the
    :class:`~model.params.Membrane` fields but the geometry's grid keys, validated as one
    record (a constant is checked against the table's law)."""
    check_keys(table, "membrane", MEMBRANE_KEYS)
    try:
        return Membrane(**table)
    except ParameterError as exc:
        raise JobError(f"membrane.{exc.name}", exc.value, exc.allowed) from None


def _material_grid(membrane: Membrane, table: Mapping, grid: Mapping[str, np.ndarray]) -> None:
    """Material constants on the grid: once (not in ``[membrane]`` too) and of the job's
    law (their values are checked by :func:`_axis`); the law's own constants given in one
    of the two places (a law without them would silently be neo-Hookean)."""
    for key in grid:
        if key not in MATERIAL_KEYS:
            continue
        if key != "C1" and key not in LAW_CONSTANTS[membrane.law]:
            raise JobError(f"grid.{key}", grid[key].tolist(),
                           f"a constant of another material law; this job's law is {membrane.law!r} "
                           "([membrane] law), whose constants are "
                           + ", ".join(("C1", *LAW_CONSTANTS[membrane.law])))
        if key in table:
            raise JobError(f"grid.{key}", grid[key].tolist(), f"set in [membrane] already (one place for {key})")
    for key in LAW_CONSTANTS[membrane.law]:
        if key not in table and key not in grid:
            raise JobError(f"membrane.{key}", MISSING, f"law = {membrane.law!r} needs its constant {key} "
                           f"({GRID_KEYS[key][0]}) in [membrane] or [grid]")


def _damping(table: Mapping) -> DampingSpec:
    """``[damping]``: ``law`` (viscous by default) and the law's constants."""
    name = table.get("law", "viscous")
    if name not in LAWS:
        raise JobError("damping.law", name, "one of " + ", ".join(f'"{n}"' for n in LAWS))
    law = LAWS[name]
    check_keys(table, "damping", ("law", *law.parameters()))
    constants = {k: v for k, v in table.items() if k != "law"}
    for key, value in constants.items():
        if isinstance(value, list) and key == "zeta":
            _record_value(f"damping.{key}", key, value, law)
        else:
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise JobError(f"damping.{key}", value, "a number" + (" or a list of numbers (one per mode)"
                                                                      if key == "zeta" else ""))
            _record_value(f"damping.{key}", key, value, law)
    return DampingSpec(law(**constants), frozenset(constants))


def _damping_grid(damping: DampingSpec, grid: Mapping[str, np.ndarray]) -> None:
    """Grid keys that are damping constants must be constants of the job's law, and not
    also set in ``[damping]``."""
    law = damping.law
    for key in grid:
        if key not in DAMPING_KEYS:
            continue
        if key not in law.parameters():
            raise JobError(f"grid.{key}", grid[key].tolist(),
                           f"a constant of another damping law; this job's law is {law.name} ([damping] law), "
                           f"whose constants are {', '.join(law.parameters())}")
        if key in damping.given:
            raise JobError(f"grid.{key}", grid[key].tolist(), f"set in [damping] already (one place for {key})")


def _model(table: Mapping) -> ModelSpec:
    """``[model]``: ``kind`` (``"rom"`` by default) and the model's own keys."""
    kind = table.get("kind", "rom")
    if not isinstance(kind, str):
        raise JobError("model.kind", kind, "a string naming a registered model")
    model = models.get(kind)
    return ModelSpec(kind, model.parse_options(table))


def _model_provides(model: ModelSpec, analysis: Analysis, analysis_name: str) -> None:
    """Refuse an analysis that asks the job's model for what it does not provide
    (:attr:`sweep.analyses.base.Analysis.model_needs`, :meth:`sweep.models.base.Model.provides`)."""
    missing = [m for m in analysis.model_needs if not model.model().provides(m, model.options)]
    if missing:
        options = " with its [model] options" if model.options is not None else ""
        raise JobError("job.analysis", analysis_name, f"an analysis that model {model.kind!r} can run{options} "
                       f"(this one needs its {', '.join(missing)}, which it does not provide)")


def _required_grid(analysis: Analysis, analysis_name: str, grid: Mapping[str, np.ndarray],
                   damping: DampingSpec, model: ModelSpec) -> bool:
    """Whether the analysis' ``required_grid`` keys are present; a required damping key
    (``c``) stands for every constant of the job's law, in the grid or in ``[damping]``,
    and the membrane keys (``delta``, ``delta_o``) are required only of a model that has
    them (:attr:`sweep.models.base.Model.required_grid`)."""
    errors = []
    own = model.model().required_grid
    needed = [k for k in analysis.required_grid if k not in GEOMETRY_KEYS or k in own]
    for key in needed:
        if key in DAMPING_KEYS:
            errors += [JobError(f"grid.{k}", MISSING, f"analysis {analysis_name!r} needs the damping law's {k} "
                                                      "in [grid] or [damping]") for k in damping.missing(grid)]
        elif key not in grid:
            errors.append(JobError(f"grid.{key}", MISSING, f"analysis {analysis_name!r} needs grid keys "
                                   + ", ".join(needed)))
    if errors:
        raise errors[0] if len(errors) == 1 else JobErrors(errors)
    return True


def _cases(value: Any, grid: Mapping[str, np.ndarray]) -> tuple:
    """``[grid] cases``: a non-empty list of tables of grid values, e.g. the (delta, Omega)
    pairs of a figure, instead of the full product."""
    key = "grid.cases"
    if not isinstance(value, list) or not value:
        raise JobError(key, value, "a non-empty list of tables {grid key = value}")
    out = []
    for case in value:
        if not isinstance(case, Mapping) or not case:
            raise JobError(key, case, "each case must be a non-empty table {grid key = value}")
        for k, v in case.items():
            if k not in grid:
                raise JobError(key, case, f"case keys must be grid keys of this job ({', '.join(grid)}); "
                                          f"{k!r} is not")
            if isinstance(v, bool) or not isinstance(v, (int, float)) \
                    or not np.any(np.isclose(grid[k], v, rtol=1e-12, atol=0.0)):
                raise JobError(key, case, f"{k} = {v!r} is not a value of grid.{k}")
        out.append(tuple(sorted((k, float(v)) for k, v in case.items())))
    return tuple(out)


def _grid(table: Mapping) -> dict[str, np.ndarray]:
    check_keys(table, "grid", (*GRID_KEYS, "cases"))
    if not table:
        raise JobError("grid", table, "at least one of the keys " + ", ".join(GRID_KEYS))
    return {key: _axis(key, table[key]) for key in GRID_KEYS if key in table}


def _axis(key: str, spec: Any) -> np.ndarray:
    """Values of one grid key from a number, a list or ``{start, stop, num[, scale]}``
    (``scale = "linear"``, the default, or ``"log"``: geometric spacing, start and stop > 0)."""
    record = parameter_record(key)[0]
    if key in MATERIAL_KEYS:  # checked as a constant of the law that has it
        record = partial(Membrane, law=next((law for law, keys in LAW_CONSTANTS.items() if key in keys),
                                            "neo-hookean"))

    def value(subkey: str, v: Any) -> float:
        return _record_value(subkey, key, v, record)

    dotted = f"grid.{key}"
    if isinstance(spec, dict):
        check_keys(spec, dotted, ("start", "stop", "num", "scale"))
        for sub in ("start", "stop", "num"):
            if sub not in spec:
                raise JobError(f"{dotted}.{sub}", MISSING, "start, stop and num are all required")
        start, stop = value(f"{dotted}.start", spec["start"]), value(f"{dotted}.stop", spec["stop"])
        num = _integer(f"{dotted}.num", spec["num"], 1, "an integer >= 1 (number of values)")
        scale = spec.get("scale", "linear")
        if scale not in ("linear", "log"):
            raise JobError(f"{dotted}.scale", scale, '"linear" (the default) or "log"')
        if scale == "log" and not (start > 0 and stop > 0):
            raise JobError(dotted, spec, 'start > 0 and stop > 0 with scale = "log"')
        values = np.geomspace(start, stop, num) if scale == "log" else np.linspace(start, stop, num)
    elif isinstance(spec, list):
        if not spec:
            raise JobError(dotted, spec, _GRID_FORMS + "; an empty list gives an empty grid")
        values = np.array([value(f"{dotted}[{i}]", v) for i, v in enumerate(spec)])
    elif isinstance(spec, (int, float)) and not isinstance(spec, bool):
        values = np.array([value(dotted, spec)])
    else:
        raise JobError(dotted, spec, _GRID_FORMS)
    unique, counts = np.unique(values, return_counts=True)
    if (counts > 1).any():
        raise JobError(dotted, spec, f"distinct values ({float(unique[counts > 1][0])!r} repeats)")
    return values.astype(np.float64)
