"""Mode sets as a sweep dimension: one job, several Galerkin mode sets, one result.

An analysis that takes ``modes`` accepts either one mode set or a list of them::

    modes = [[[1, 0]], [[1, 0], [2, 0]], [[1, 0], [2, 0], [3, 0]]]

The job then computes the analysis once per mode set at every grid point, and the result
gains a leading dimension ``mode_set`` whose coordinate is a readable label per set
(``"(1,0)+(2,0)"``, in the order given) with the number of modes ``n_modes``.  Variables
whose sizes depend on the set (along ``mode``, ``multiplier``, ``state``, ...) are padded
to the largest set: floats with NaN, integers with their declared fill value (``-1`` for
the mode coordinates ``m`` and ``n``, so a padded mode reads ``m = -1``); the coordinate
``<dim>_extent`` gives each set's own size of such a dimension.  A variable that some sets
do not have holds its fill value there (attribute ``absent_in_mode_sets``).
:func:`select` gives one set's part as a job of that set alone would.

How it runs: :class:`ModeSetSweep` wraps the analysis.  The mode set is the slow part of
the subtask index (subtask ``s * n + j`` is subtask ``j`` of set ``s``, ``n`` subtasks per
set), so the runner, the part logs and ``--resume`` see an ordinary analysis; the
wrapper's ``assemble`` splits the sets apart, lets the analysis assemble each one as it
would alone, pads them and joins them along ``mode_set``.  Such a result is therefore
merged in memory on rank 0 (like the basins), not streamed.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from functools import partial
from itertools import zip_longest
from typing import Any

import numpy as np

from .base import DEFAULT_CONTEXT, Analysis, JobError, Variable, check_result

#: Padding of integer variables and coordinates without a declared fill value.
INT_PAD = -1


def is_mode_set_list(value: Any) -> bool:
    """Whether a ``modes`` value is a list of mode sets (each a list of ``[m, n]`` pairs or
    ``{n, radial}`` tables) rather than one mode set."""
    return (isinstance(value, list) and bool(value)
            and all(isinstance(s, list) and bool(s) and all(isinstance(m, (list, Mapping)) for m in s)
                    for s in value))


def set_label(modes) -> str:
    """Readable label of a mode set: ``((1, 0), (2, 0))`` -> ``"(1,0)+(2,0)"``."""
    return "+".join(f"({m},{n})" for m, n in modes)


@dataclass(frozen=True)
class ModeSetOptions:
    """Options of a mode-set sweep.

    Parameters
    ----------
    sets : tuple
        The wrapped analysis' options, one per mode set, in the job's order.
    labels : tuple of str
        :func:`set_label` of each set.
    n_inner : int
        Subtasks per grid point of one set.
    """

    sets: tuple
    labels: tuple[str, ...]
    n_inner: int


class ModeSetSweep(Analysis):
    """An analysis run once per mode set (see the module docstring).

    Parameters
    ----------
    inner : Analysis
        The analysis of one mode set; its option table must have the key ``modes``.
    """

    def __init__(self, inner: Analysis):
        self.inner = inner
        self.name = inner.name
        self.OPTIONS = inner.OPTIONS
        self.required_grid = inner.required_grid
        self.model_needs = inner.model_needs

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT) -> ModeSetOptions:
        key = f"{self.name}.modes"
        sets = []
        for i, modes in enumerate(table["modes"]):
            try:
                sets.append(self.inner.parse_options({**table, "modes": modes}, grid, membrane, context))
            except JobError as exc:
                if exc.key == key or exc.key.startswith(key + "."):
                    raise JobError(f"{key}[{i}]{exc.key[len(key):]}", exc.value, exc.allowed) from None
                raise JobError(exc.key, exc.value, f"{exc.allowed} (with mode set {key}[{i}])") from None
        labels = tuple(set_label(o.modes) for o in sets)
        if len(set(labels)) != len(labels):
            raise JobError(key, table["modes"], "the mode sets must be distinct")
        n_inner = {self.inner.n_subtasks(o) for o in sets}
        if len(n_inner) != 1:
            raise JobError(key, table["modes"], "mode sets that give the same number of subtasks "
                                                f"(here they differ: {sorted(n_inner)})")
        options = ModeSetOptions(tuple(sets), labels, n_inner.pop())
        self._declared(options)  # the sets must agree on the dimensions of each variable
        return options

    def _declared(self, options: ModeSetOptions) -> dict[str, Variable]:
        """The union of the sets' variables, each at its largest shape."""
        out: dict[str, Variable] = {}
        for label, o in zip(options.labels, options.sets):
            for v in self.inner.variables(o):
                seen = out.get(v.name)
                if seen is None:
                    out[v.name] = v
                    continue
                if seen.dims != v.dims or seen.dtype != v.dtype:
                    raise JobError(f"{self.name}.modes", label,
                                   f"mode sets whose variable {v.name!r} has the same dimensions and type")
                out[v.name] = replace(seen, shape=tuple(map(max, seen.shape, v.shape)))
        return out

    def variables(self, options: ModeSetOptions) -> list[Variable]:
        return list(self._declared(options).values())

    def n_subtasks(self, options: ModeSetOptions) -> int:
        return len(options.sets) * options.n_inner

    def compute(self, point, options: ModeSetOptions, subtask: int) -> dict[str, np.ndarray]:
        s, j = divmod(subtask, options.n_inner)
        result = self.inner.compute(point, options.sets[s], j)
        check_result(result, self.inner.variables(options.sets[s]))  # as the runner would, before padding
        out = {k: result[k] for k in ("status", "message") if k in result}
        for v in self._declared(options).values():
            padded = v.blank()
            if v.name in result:
                value = np.asarray(result[v.name])
                padded[tuple(slice(0, n) for n in value.shape)] = value
            out[v.name] = padded
        return out

    def warmups(self, options: ModeSetOptions) -> list[Callable[[], None]]:
        # call i of every set in one call: each kernel is compiled by one rank, whatever the
        # argument types the sets give it (see Analysis.warmups)
        per_set = [self.inner.warmups(o) for o in options.sets]
        return [partial(_call_all, [c for c in calls if c is not None])
                for calls in zip_longest(*per_set)]

    def attributes(self, options: ModeSetOptions) -> dict[str, Any]:
        return self.inner.attributes(options.sets[0])

    def coordinate_variables(self, options: ModeSetOptions) -> tuple[str, ...]:
        return self.inner.coordinate_variables(options.sets[0])

    def assemble(self, raw, options: ModeSetOptions):
        """Each set's part of ``raw`` assembled as the analysis does alone, padded, joined
        along a leading ``mode_set`` dimension."""
        import pandas as pd
        import xarray as xr

        n = options.n_inner
        union = self._declared(options)
        parts, absent = [], {}
        for s, o in enumerate(options.sets):
            declared = self.inner.variables(o)
            sizes = {d: k for v in declared for d, k in zip(v.dims, v.shape)}
            part = raw[[v.name for v in declared] + [k for k in ("status", "message") if k in raw]]
            part = part.isel(subtask=slice(s * n, (s + 1) * n), **{d: slice(0, k) for d, k in sizes.items()})
            part = part.assign_coords(subtask=np.arange(n), **self.inner.coords(o))
            if self.inner.assemble is not None:
                part = self.inner.assemble(part, o)
            elif n == 1:
                part = part.squeeze("subtask", drop=True)
            part = part.set_coords([c for c in self.inner.coordinate_variables(o) if c in part])
            part = part.assign(self.inner.derived(part, o))
            parts.append(part)
        # a variable that a set does not have (continuation's point_family without families)
        # holds its fill value there, with its own type; the attribute names those sets
        names = set().union(*(p.data_vars for p in parts))
        for s, part in enumerate(parts):
            for name in names - set(part.data_vars):
                v = next(p[name] for p in parts if name in p.data_vars)
                shape = tuple(part.sizes.get(d, size) for d, size in zip(v.dims, v.shape))
                fill = union[name].fill if name in union else _fill(v.dtype, INT_PAD)
                parts[s] = parts[s].assign({name: (v.dims, np.full(shape, fill, v.dtype), v.attrs)})
                absent.setdefault(name, []).append(options.labels[s])
        sizes = [dict(p.sizes) for p in parts]
        described = _coordinate_names(parts, options.labels)
        parts = _padded(parts, {name: v.fill for name, v in union.items()})
        index = pd.Index(list(options.labels), name="mode_set")
        ds = xr.concat(parts, dim=index, data_vars="all", coords="all", compat="equals", join="exact")
        ds["mode_set"].attrs.update(long_name="Galerkin mode set: the (m,n) of its modes", units="1")
        for name, labels in absent.items():
            ds[name].attrs["absent_in_mode_sets"] = "; ".join(labels)
        for name, named in described.items():  # select() gives each set its own back
            ds[name].attrs["long_name"] = "; ".join(f"{label}: {long_name}" for label, long_name in named.items())
            ds[name].attrs[_NAME_BY_SET] = json.dumps(named)
        padded = {d for d in ds.dims if d != "mode_set" and len({z.get(d) for z in sizes}) > 1}
        extents = {f"{d}_extent": ("mode_set", np.array([z.get(d, 0) for z in sizes], np.int32),
                                   {"long_name": f"size of the dimension {d} in the set (the rest is padding)",
                                    "units": "1"}) for d in sorted(padded)}
        return ds.assign_coords(n_modes=("mode_set", np.array([len(o.modes) for o in options.sets], np.int32),
                                         {"long_name": "number of modes of the set", "units": "1"}), **extents)


#: Attribute of a coordinate that the sets describe differently: set label -> long name (JSON).
_NAME_BY_SET = "long_name_by_mode_set"


def _coordinate_names(parts, labels) -> dict[str, dict[str, str]]:
    """The long names of the coordinates that the sets describe differently (the basins
    lattice axes name each set's lattice mode), set label -> long name (the coordinate's
    name where a set gives none): concatenation keeps the first set's attributes only."""
    out = {}
    for name in set().union(*(p.coords for p in parts)):
        named = {label: p[name].attrs.get("long_name") or name for label, p in zip(labels, parts) if name in p.coords}
        if len(set(named.values())) > 1:
            out[name] = named
    return out


def _padded(parts: list, fills: Mapping[str, Any]) -> list:
    """The Datasets ``parts`` padded to common sizes: every dimension to its largest size,
    dimension coordinates taken from the part where it is largest."""
    sizes: dict[str, int] = {}
    for p in parts:
        for d, k in p.sizes.items():
            sizes[d] = max(sizes.get(d, 0), k)
    index = {d: next(p[d] for p in parts if p.sizes.get(d) == k and d in p.indexes)
             for d, k in sizes.items() if any(d in p.indexes for p in parts)}
    out = []
    for p in parts:
        short = {d for d, k in p.sizes.items() if k < sizes[d]}
        if not short:
            out.append(p)
            continue
        p = p.drop_vars([d for d in short if d in p.indexes])
        new = {}
        for name, var in p.variables.items():
            if not short & set(var.dims):
                continue
            fill = fills.get(name, INT_PAD) if var.dtype.kind in "iu" else _fill(var.dtype, INT_PAD)
            data = np.full(tuple(sizes[d] for d in var.dims), fill, dtype=var.dtype)
            data[tuple(slice(0, k) for k in var.shape)] = var.values
            new[name] = (var.dims, data, var.attrs)
        coords = [c for c in new if c in p.coords]
        p = p.drop_vars(list(new)).assign({k: v for k, v in new.items() if k not in coords})
        p = p.assign_coords({k: new[k] for k in coords}).assign_coords({d: index[d] for d in short if d in index})
        out.append(p)
    return out


def _fill(dtype, integer):
    """Padding of an array of ``dtype``: NaN, ``""``, ``integer`` or False."""
    kind = np.dtype(dtype).kind
    return np.nan if kind in "fc" else "" if kind in "OUS" else integer if kind in "iu" else False


def select(ds, label: str):
    """One mode set of a mode-set result, without its padding.

    Parameters
    ----------
    ds : xarray.Dataset
        A result with a ``mode_set`` dimension.
    label : str
        A value of ``ds.mode_set`` (``"(1,0)+(2,0)"``).

    Returns
    -------
    xarray.Dataset
        ``ds.sel(mode_set=label)`` cut back to the set's own sizes (the ``<dim>_extent``
        coordinates), without the variables the set does not have (attribute
        ``absent_in_mode_sets``) and without the mode-set coordinates: what a job of that
        mode set alone gives.
    """
    one = ds.sel(mode_set=label)
    extents = [c for c in one.coords if c.endswith("_extent") and c[:-len("_extent")] in one.dims]
    one = one.isel({c[:-len("_extent")]: slice(0, int(one[c])) for c in extents})
    absent = [v for v in one.data_vars if label in one[v].attrs.get("absent_in_mode_sets", "").split("; ")]
    one = one.drop_vars(["mode_set", "n_modes", *extents, *absent], errors="ignore").copy()  # own attributes
    for v in one.data_vars:
        one[v].attrs.pop("absent_in_mode_sets", None)
    for c in one.coords:
        if _NAME_BY_SET in one[c].attrs:
            one[c].attrs["long_name"] = json.loads(one[c].attrs.pop(_NAME_BY_SET))[label]
    return one


def _call_all(calls) -> None:
    # ModeSetSweep.warmups: the calls of one index, one after the other
    for call in calls:
        call()
