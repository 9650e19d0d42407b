"""Validation helpers for analysis option tables (``[<analysis>]`` in a job file).

Every helper raises :class:`~sweep.analyses.base.JobError` naming the dotted key, the
value and what is allowed, so that analyses validate their tables in a few lines.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from model.forced import PARAMETERS as FORCING_PARAMETERS
from model.prestretch import KINDS

from .base import DEFAULT_DAMPING, GRID_KEYS, MISSING, DampingSpec, JobError


def number(table, section: str, key: str, default=None, *, low=None, high=None,
           low_open=False, integer=False) -> float | int:
    """A finite number (or integer) option with optional bounds."""
    if key not in table:
        if default is None:
            raise JobError(f"{section}.{key}", None, "this option is required")
        return default
    v = table[key]
    kind = "an integer" if integer else "a number"
    if isinstance(v, bool) or not isinstance(v, (int, float)) or (integer and not isinstance(v, int)):
        raise JobError(f"{section}.{key}", v, f"must be {kind}")
    if not math.isfinite(v):
        raise JobError(f"{section}.{key}", v, f"must be a finite {kind[2:] if integer else 'number'}")
    if low is not None and (v <= low if low_open else v < low):
        raise JobError(f"{section}.{key}", v, f"must be {'>' if low_open else '>='} {low}")
    if high is not None and v > high:
        raise JobError(f"{section}.{key}", v, f"must be <= {high}")
    return int(v) if integer else float(v)


def flag(table, section: str, key: str, default: bool) -> bool:
    """A boolean option."""
    v = table.get(key, default)
    if not isinstance(v, bool):
        raise JobError(f"{section}.{key}", v, "must be true or false")
    return v


def choice(table, section: str, key: str, allowed, default=None) -> str:
    """A string option from a fixed set."""
    v = table.get(key, default)
    if v is None:
        raise JobError(f"{section}.{key}", None, f"this option is required: one of {', '.join(allowed)}")
    if v not in allowed:
        raise JobError(f"{section}.{key}", v, f"must be one of {', '.join(allowed)}")
    return v


def prestretch(table, section: str, context=None, default: str = "numeric") -> str:
    """The ``prestretch`` option: ``analytic`` (Eq. 21), ``numeric`` (Eq. 15) or ``fit`` (Eq. 18),
    those of them the job's model solves (``context.model``: a
    :class:`~sweep.analyses.base.JobContext`; all three without one)."""
    kinds = KINDS if context is None else context.model.model().prestretch_kinds
    return choice(table, section, "prestretch", kinds, default)


#: Description of the ``modes`` option, shared by the analyses (docs/options.md).
MODES_HELP = ("list of [m, n] pairs (n < 0: the sine companion of (m, |n|)) and {n = N, radial = M} shorthands "
              "for [1, N] .. [M, N] (sine = true adds their sine companions) (default [[1, 0]]); or a list of "
              "such mode sets, [[[1, 0]], [[1, 0], [2, 0]]]: the analysis once per set, a mode_set dimension "
              "(docs/running.md)")


def modes(table, section: str, default=((1, 0),)) -> tuple[tuple[int, int], ...]:
    """The ``modes`` option: a non-empty list of distinct modes.

    Each item is a pair ``[m, n]`` (``m >= 1``; ``n >= 0`` for ``phi_mn cos(n theta)``,
    ``n < 0`` for the sine companion ``phi_m|n| sin(|n| theta)``), or a family shorthand
    ``{n = N, radial = M}``: the modes ``[1, N] .. [M, N]``, with ``sine = true`` their sine
    companions ``[m, -N]`` too (``N >= 1``).
    """
    v = table.get("modes", [list(p) for p in default])
    key = f"{section}.modes"
    if not isinstance(v, list) or not v:
        raise JobError(key, v, "must be a non-empty list of [m, n] pairs or {n, radial} tables")
    out = []
    for item in v:
        if isinstance(item, Mapping):
            if not {"n", "radial"} <= set(item) or not set(item) <= {"n", "radial", "sine"}:
                raise JobError(key, item, "a family shorthand is a table {n = N, radial = M} (optionally sine = true)")
            n = number(item, key, "n", integer=True, low=0)
            radial = number(item, key, "radial", integer=True, low=1, high=64)
            sine = flag(item, key, "sine", False)
            if sine and n == 0:
                raise JobError(key, item, "n = 0 has no sine companions")
            out += [(m, n) for m in range(1, radial + 1)] + ([(m, -n) for m in range(1, radial + 1)] if sine else [])
            continue
        if (not isinstance(item, list) or len(item) != 2
                or any(isinstance(x, bool) or not isinstance(x, int) for x in item)):
            raise JobError(key, item, "each mode must be a pair [m, n] of integers or a table {n, radial}")
        if item[0] < 1:
            raise JobError(key, item, "each mode needs m >= 1 (n >= 0, or n < 0 for a sine companion)")
        out.append((item[0], item[1]))
    if len(set(out)) != len(out):
        raise JobError(key, v, "modes must be distinct")
    return tuple(out)


def steps(table, section: str, base: int, low: int, high: int | None = 4096) -> int | None:
    """The ``steps`` option: RK4 steps per forcing period, an integer in ``[low, high]``
    (``high`` None: no upper bound), or ``"auto"`` (the default, returned as None):
    :func:`model.forced.steps_per_period` of the task's ROM with ``base``
    (:func:`sweep.models.rom.steps_for`)."""
    v = table.get("steps", "auto")
    if v == "auto":
        return None
    if isinstance(v, bool) or not isinstance(v, int) or v < low or (high is not None and v > high):
        allowed = f"an integer from {low} to {high}" if high is not None else f"an integer >= {low}"
        raise JobError(f"{section}.steps", v, f'must be "auto" or {allowed}')
    return v


def steps_help(base: int, which: str = "the set") -> str:
    """Description of the ``steps`` option (docs/options.md); ``which`` names the modes whose
    frequencies count."""
    return (f"RK4 steps per forcing period, or \"auto\" (default): {base} for one mode, for several "
            f"{base} x (highest / lowest linear frequency of {which})^(5/4), rounded up to a multiple of 8 "
            "(the fastest mode integrated as accurately as the slowest)")


def linspace(table, section: str, key: str, default=None, *, low=None, low_open=False,
             max_num: int = 100_000) -> tuple[float, float, int]:
    """A ``{start, stop, num}`` table (``num >= 1``); returns ``(start, stop, num)``."""
    v = table.get(key, default)
    full = f"{section}.{key}"
    if v is None:
        raise JobError(full, None, "this option is required: a table {start = , stop = , num = }")
    if not isinstance(v, Mapping) or set(v) != {"start", "stop", "num"}:
        raise JobError(full, v, "must be a table with exactly the keys start, stop, num")
    start = number(v, full, "start", low=low, low_open=low_open)
    stop = number(v, full, "stop", low=low, low_open=low_open)
    num = number(v, full, "num", integer=True, low=1, high=max_num)
    return start, stop, num


def forcing_parameter(table, section: str, grid, role: str, damping: DampingSpec = DEFAULT_DAMPING) -> str:
    """The ``parameter`` option of a forced analysis: ``Omega`` or ``P0``, varied by the
    analysis itself, so not a grid key; the other forcing key must be a grid key and the
    damping law's constants grid keys or set in ``[damping]``.

    ``role`` completes the messages, e.g. ``"is continued"``.
    """
    parameter = table.get("parameter", MISSING)
    if parameter not in FORCING_PARAMETERS:
        raise JobError(f"{section}.parameter", parameter, f"must be one of {', '.join(FORCING_PARAMETERS)}")
    if parameter in grid:
        raise JobError(f"{section}.parameter", parameter,
                       f"{parameter} {role}, so it must not also be a [grid] key")
    other = "P0" if parameter == "Omega" else "Omega"
    if other not in grid:
        raise JobError(f"grid.{other}", MISSING,
                       f"{section} in {parameter} needs {other} ({GRID_KEYS[other][0]}) in [grid]")
    for key in damping.missing(grid):
        raise JobError(f"grid.{key}", MISSING, f"{section} in {parameter} needs {key} ({GRID_KEYS[key][0]}) "
                                               "in [grid] or [damping]")
    return parameter


def damping_modes(damping: DampingSpec, section: str, modes, families) -> None:
    """A list of modal ratios (``[damping] zeta``) must have one ratio per mode of the
    analysis' ``modes``, and is refused where ``families`` is true (family blocks, which are
    no modes of the set and take one ratio for every mode)."""
    zeta = getattr(damping.law, "zeta", None)
    if not isinstance(zeta, tuple):
        return
    if families:
        raise JobError("damping.zeta", list(zeta), f"one ratio for every mode with asymmetric families in {section} "
                       "(the family blocks are not modes of the set)")
    if len(zeta) != len(modes):
        raise JobError("damping.zeta", list(zeta), f"one ratio, or one per mode of {section}.modes ({len(modes)})")


def rom_only(table, section: str, model, keys) -> None:
    """Refuse the options ``keys`` of ``table`` that need the ROM (mode families and what
    is built on them) when the job's model (a :class:`~sweep.analyses.base.ModelSpec`)
    has no ROM features."""
    given = [k for k in keys if k in table]
    if given and not model.model().rom_features:
        raise JobError(f"{section}.{given[0]}", table[given[0]],
                       f"needs the ROM's mode families; this job's model is {model.kind!r} ([model] kind)")


def model_modes(section: str, model, mode_list, table=None, modal_keys=()) -> None:
    """Refuse, for a model whose forced maps hold axisymmetric states only
    (:attr:`sweep.models.base.Model.axisymmetric_states`), ``modes`` that are not all
    axisymmetric (there they name the ROM coordinates the results report) and the options
    ``modal_keys`` of ``table`` that need the whole state in those coordinates."""
    if not model.model().axisymmetric_states:
        return
    if any(n != 0 for _, n in mode_list):
        raise JobError(f"{section}.modes", [list(m) for m in mode_list],
                       f"axisymmetric modes [m, 0] only: model {model.kind!r} ([model] kind) follows axisymmetric "
                       "states, and the modes name the ROM coordinates its results report")
    given = [k for k in modal_keys if table is not None and k in table]
    if given:
        raise JobError(f"{section}.{given[0]}", table[given[0]],
                       f"needs a model whose state is its modal coordinates (the ROM); this job's model is "
                       f"{model.kind!r} ([model] kind)")


def second_parameters(parameter: str, damping: DampingSpec) -> tuple[str, ...]:
    """The parameters a curve of bifurcation points may follow besides ``parameter``: the
    damping law's scalar constants (``c``, ``alpha``, ``beta``, ``zeta`` given as one
    ratio) and the other forcing parameter."""
    scalars = tuple(p for p in damping.law.parameters() if not isinstance(getattr(damping.law, p), tuple))
    return scalars + tuple(p for p in ("P0", "Omega") if p != parameter)


def mode_coords(mode_list) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict]]:
    """Coordinates ``m`` and ``n`` along a ``mode`` dimension."""
    arr = np.array(mode_list, dtype=np.int32).reshape(-1, 2)
    return {"m": (("mode",), arr[:, 0], {"long_name": "radial mode index m", "units": "1"}),
            "n": (("mode",), arr[:, 1], {"long_name": "circumferential wave number n (negative: the sine "
                                                      "companion sin(|n| theta))", "units": "1"})}


class FamiliesOption(NamedTuple):
    """The ``families`` option of a continuation."""

    #: the wave numbers n
    n: tuple[int, ...]
    #: radial functions per family (per field): a count, or the counts of a convergence study
    radial: int | tuple[int, ...]
    #: whether the perturbations carry the in-plane fields U, V besides W (models with
    #: in-plane motion only)
    inplane: bool = False


def increasing(values, key: str, what: str, low: int, high: int) -> tuple[int, ...]:
    """``values`` (a list) as a convergence study's sizes: distinct increasing integers from
    ``low`` to ``high``; otherwise one line saying that ``key`` must be ``what``."""
    if not (isinstance(values, list) and values
            and all(isinstance(v, int) and not isinstance(v, bool) and low <= v <= high for v in values)
            and values == sorted(set(values))):
        raise JobError(key, values, what)
    return tuple(values)


def families(table, section: str, mode_list, model=None) -> FamiliesOption | None:
    """The ``families = {n = [..], radial = M, inplane = ..}`` option or None;
    ``radial = [M1, M2, ..]`` (distinct, increasing) is a convergence study: ``M`` is then
    the tuple of counts.  ``model``: the job's :class:`~sweep.analyses.base.ModelSpec`, which
    bounds ``radial`` and says whether ``inplane`` may be true (its default)
    (:meth:`sweep.models.base.Model.family_limits`).

    The families need an axisymmetric mode set (their blocks are taken on axisymmetric
    orbits).
    """
    value = table.get("families")
    if value is None:
        return None
    key = f"{section}.families"
    if not isinstance(value, Mapping) or not {"n", "radial"} <= set(value) <= {"n", "radial", "inplane"}:
        raise JobError(key, value, "must be a table {n = [wave numbers >= 1], radial = radial modes per family"
                                   "[, inplane = true | false]}")
    ns = value["n"]
    if (not isinstance(ns, list) or not ns or any(isinstance(n, bool) or not isinstance(n, int) or n < 1 for n in ns)
            or len(set(ns)) != len(ns)):
        raise JobError(f"{key}.n", ns, "must be a non-empty list of distinct integers >= 1")
    high, inplane_allowed = (32, False) if model is None else model.model().family_limits(model.options)
    if isinstance(value["radial"], list):
        radial = increasing(value["radial"], f"{key}.radial", f"an integer from 1 to {high}, or a list of distinct "
                            "increasing ones", 1, high)
    else:
        radial = number(value, key, "radial", integer=True, low=1, high=high)
    inplane = value.get("inplane", inplane_allowed)
    if not isinstance(inplane, bool):
        raise JobError(f"{key}.inplane", inplane, "must be true or false")
    if inplane and not inplane_allowed:
        raise JobError(f"{key}.inplane", inplane, "needs a model with in-plane displacements ([model] kind = "
                                                  "\"full\", inplane = true); this job's model has none")
    if any(n for _, n in mode_list):
        raise JobError(f"{section}.modes", [list(p) for p in mode_list],
                       "must be axisymmetric (every n = 0) when families are given")
    return FamiliesOption(tuple(ns), radial, inplane)
