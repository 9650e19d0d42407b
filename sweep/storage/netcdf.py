"""Merging the part logs into one NetCDF file (:func:`collect`), and reading back the
attributes of the run(s) that wrote it."""

from __future__ import annotations

import dataclasses
import datetime
import json
import math
import re
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from sweep import partlog, provenance
from sweep.analyses.base import GRID_KEYS, STATUS_FAILED, STATUS_OK, STATUS_SKIPPED, membrane_attributes, parameter_record
from sweep.errors import RunError
from sweep.jobspec import Job, parse_job
from sweep.storage.files import file_error, replace_atomically
from sweep.storage.lock import Lock
from sweep.storage.parts import MANIFEST, check_layout, part_logs, parts_dir, read_manifest, read_runs
from sweep.storage.tally import STATUS_FLAG_MEANINGS, STATUS_FLAG_VALUES, STATUS_MISSING, summarize

#: Bytes of task data buffered per write window of a streaming collect.
WINDOW_BYTES = 2**20


@dataclass
class CollectReport:
    """What :func:`collect` wrote.

    Parameters
    ----------
    path : pathlib.Path
        The NetCDF file.
    tasks_completed, tasks_total : int
        Tasks found in the parts, tasks of the job.
    counts : collections.Counter
        Tasks per status code.
    reasons : collections.Counter
        ``(status, message)`` of the tasks that are not ok, counted.
    notes : list of str
        Things the user should know (missing tasks, rejected parts, unlabelled variables).
    """

    path: Path
    tasks_completed: int
    tasks_total: int
    counts: Counter = field(default_factory=Counter)
    reasons: Counter = field(default_factory=Counter)
    notes: list[str] = field(default_factory=list)

    @property
    def failed(self) -> int:
        """Tasks with status failed."""
        return self.counts.get(STATUS_FAILED, 0)

    def summary(self) -> str:
        """``"9 / 9 tasks: 4 ok, 5 not converged (5: reached max_points = 40 ...), 0 failed"``."""
        return f"{self.tasks_completed} / {self.tasks_total} tasks: " + summarize(self.counts, self.reasons)


def _grid_coords(job: Job, keep_subtask: bool) -> dict:
    layout = job.layout
    coords = {d: (d, values, {"units": GRID_KEYS[d][0], "long_name": GRID_KEYS[d][1]})
              for d, values in zip(layout.dims, layout.values)}
    if keep_subtask:
        coords["subtask"] = ("subtask", np.arange(layout.n_subtasks),
                             {"units": "1", "long_name": "subtask index within a grid point"})
    coords.update(job.analysis.coords(job.options))
    return coords


_STATUS_ATTRS = {"units": "1", "long_name": "task status", "flag_values": STATUS_FLAG_VALUES,
                 "flag_meanings": STATUS_FLAG_MEANINGS}
_MESSAGE_ATTRS = {"long_name": "why a task is not ok (empty when ok)"}


def merge(job: Job, parts: Path, logs: partlog.Logs | None = None) -> tuple[xr.Dataset, int]:
    """Merge the part logs into the raw Dataset, in memory.

    Returns
    -------
    raw : xarray.Dataset
        Dims ``(*grid_dims, "subtask", *variable_dims)``; tasks without a part hold the
        variables' fill values and ``status`` -1 (missing); ``message`` per task.
    tasks_completed : int
        Number of tasks found.
    """
    layout, analysis = job.layout, job.analysis
    variables = analysis.variables(job.options)
    logs = part_logs(job, parts) if logs is None else logs
    flat = {v.name: np.full((layout.n_tasks, *v.shape), v.fill, dtype=v.dtype) for v in variables}
    status = np.full(layout.n_tasks, STATUS_MISSING, dtype=np.int8)
    message = np.full(layout.n_tasks, "", dtype=object)
    with partlog.Reader(variables) as reader:
        for rec in logs:
            st, arrays, messages = reader.read(rec)
            sl = slice(rec.task_start, rec.task_start + rec.task_count)
            status[sl] = st
            for name, values in arrays.items():
                flat[name][sl] = values
            for i, m in messages.items():
                message[rec.task_start + i] = m
    grid_dims, grid_shape = layout.dims + ("subtask",), layout.shape + (layout.n_subtasks,)
    data = {v.name: ((*grid_dims, *v.dims), flat[v.name].reshape(*grid_shape, *v.shape),
                     {"units": v.units, "long_name": v.long_name, **v.attrs})
            for v in variables}
    data["status"] = (grid_dims, status.reshape(grid_shape), dict(_STATUS_ATTRS))
    data["message"] = (grid_dims, message.reshape(grid_shape), dict(_MESSAGE_ATTRS))
    return xr.Dataset(data, _grid_coords(job, keep_subtask=True)), logs.tasks


def flat_boxes(start: int, stop: int, shape: tuple[int, ...]) -> list[tuple[tuple[int, ...], tuple[int, ...]]]:
    """Split the C-order flat index range ``[start, stop)`` of an array of ``shape`` into boxes.

    Returns
    -------
    list of (corner, extent)
        Rectangular blocks, in increasing flat order, each a contiguous flat range (at most
        ``2 len(shape) - 1`` of them).
    """
    if start >= stop:
        return []
    if len(shape) == 1:
        return [((start,), (stop - start,))]
    inner = math.prod(shape[1:])
    i0, r0 = divmod(start, inner)
    i1, r1 = divmod(stop, inner)
    if i0 == i1:
        return [((i0, *c), (1, *e)) for c, e in flat_boxes(r0, r1, shape[1:])]
    out = []
    if r0:
        out += [((i0, *c), (1, *e)) for c, e in flat_boxes(r0, inner, shape[1:])]
        i0 += 1
    if i1 > i0:
        out.append(((i0, *(0,) * (len(shape) - 1)), (i1 - i0, *shape[1:])))
    if r1:
        out += [((i1, *c), (1, *e)) for c, e in flat_boxes(0, r1, shape[1:])]
    return out


def c_order_chunks(shape: tuple[int, ...], itemsize: int, target: int = 2**20) -> tuple[int, ...]:
    """HDF5 chunk shape of about ``target`` bytes that is a contiguous run of C order: the
    trailing dimensions whole, a part of the next one, ones before it.  Written in task
    order, such chunks are completed one after the other, so the chunk cache holds only
    the one being filled."""
    chunks = [1] * len(shape)
    size = itemsize
    for i in range(len(shape) - 1, -1, -1):
        if size * shape[i] <= target:
            chunks[i] = shape[i]
            size *= shape[i]
        else:
            chunks[i] = max(1, target // size)
            break
    return tuple(chunks)


def _stream(tmp: Path, job: Job, logs: partlog.Logs, attrs: dict, report: CollectReport) -> None:
    """Write the result of a raw-layout analysis window by window (bounded memory); sets
    ``report.tasks_completed``."""
    import netCDF4

    layout, analysis = job.layout, job.analysis
    variables = analysis.variables(job.options)
    keep_subtask = layout.n_subtasks > 1
    dims = layout.dims + (("subtask",) if keep_subtask else ())
    shape = layout.shape + ((layout.n_subtasks,) if keep_subtask else ())
    skeleton = xr.Dataset(coords=_grid_coords(job, keep_subtask), attrs=attrs)
    skeleton.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(skeleton))
    non_dim = [c for c in skeleton.coords if c not in skeleton.dims]
    as_coords = set(analysis.coordinate_variables(job.options))
    per_task = 1 + 8 + sum(np.dtype(v.dtype).itemsize * math.prod(v.shape) for v in variables)  # status, message
    window = layout.chunk * max(1, WINDOW_BYTES // (per_task * layout.chunk))
    with netCDF4.Dataset(tmp, "a") as nc:
        for v in variables:
            for d, n in zip(v.dims, v.shape):
                if d not in nc.dimensions:
                    nc.createDimension(d, n)
        out = {}
        for v in variables:
            floating = np.dtype(v.dtype).kind == "f"
            chunks = c_order_chunks(shape + v.shape, np.dtype(v.dtype).itemsize)
            var = nc.createVariable(v.name, v.dtype, dims + v.dims, zlib=True, complevel=4,
                                    fill_value=np.nan if floating else False, chunksizes=chunks)
            # room for the chunk being filled: written in order, a chunk is never revisited
            var.set_var_chunk_cache(size=2 * np.dtype(v.dtype).itemsize * math.prod(chunks), nelems=11,
                                    preemption=1.0)
            var.setncatts({"units": v.units, "long_name": v.long_name, **v.attrs})
            linked = [c for c in non_dim if set(skeleton[c].dims) <= set(dims + v.dims)]
            linked += [c.name for c in variables if c.name in as_coords and c.name != v.name
                       and set(c.dims) <= set(v.dims)]
            if linked:
                var.setncattr("coordinates", " ".join(linked))
            out[v.name] = var
        out["status"] = nc.createVariable("status", "i1", dims, zlib=True, complevel=4, fill_value=False,
                                          chunksizes=c_order_chunks(shape, 1))
        out["status"].setncatts(_STATUS_ATTRS)
        out["message"] = nc.createVariable("message", str, dims, chunksizes=c_order_chunks(shape, 16))
        out["message"].setncatts(_MESSAGE_ATTRS)
        records = iter(logs)
        rec = next(records, None)
        with partlog.Reader(variables) as reader:
            for w0 in range(0, layout.n_tasks, window):
                w1 = min(w0 + window, layout.n_tasks)
                buf = {v.name: np.full((w1 - w0, *v.shape), v.fill, dtype=v.dtype) for v in variables}
                buf["status"] = np.full(w1 - w0, STATUS_MISSING, np.int8)
                buf["message"] = np.full(w1 - w0, "", dtype=object)
                while rec is not None and rec.task_start < w1:
                    st, arrays, messages = reader.read(rec)
                    sl = slice(rec.task_start - w0, rec.task_start - w0 + rec.task_count)
                    buf["status"][sl] = st
                    for name, values in arrays.items():
                        buf[name][sl] = values
                    for i, m in messages.items():
                        buf["message"][sl.start + i] = m
                    rec = next(records, None)
                _count(report, buf["status"], buf["message"])
                # Messages are rare: unwritten strings read as "", so a window with few of
                # them writes those alone (HDF5 keeps every written string in its heap).
                said = np.flatnonzero(buf["message"] != "")
                few = said.size <= 64
                for i in said if few else ():
                    out["message"][np.unravel_index(w0 + i, shape)] = buf["message"][i]
                for corner, extent in flat_boxes(w0, w1, shape):
                    lo = int(np.ravel_multi_index(corner, shape)) - w0
                    size = math.prod(extent)
                    box = tuple(slice(c, c + e) for c, e in zip(corner, extent))
                    for name, var in out.items():
                        if name == "message" and few:
                            continue
                        values = buf[name][lo:lo + size]
                        var[box] = values.reshape(*extent, *values.shape[1:])
        report.tasks_completed = logs.tasks


def collect(out: Path, *, lock_held: bool = False, break_lock: bool = False) -> CollectReport:
    """Merge the parts of ``OUT.nc.parts/`` into ``out`` (idempotent).

    Written under a temporary name then renamed; temporary files of an interrupted merge
    are removed first.

    Parameters
    ----------
    out : pathlib.Path
        Output NetCDF path.
    lock_held : bool
        The caller holds the parts directory's lock (a run's final collect).
    break_lock : bool
        As for :meth:`Lock.acquire`.

    Returns
    -------
    CollectReport

    Raises
    ------
    RunError
        If there is no parts directory, it is in use, or the file cannot be written.
    """
    parts = parts_dir(out)
    if not parts.is_dir():
        read_manifest(parts)  # says that there is nothing to collect
    lock = None if lock_held else Lock(parts, "collect").acquire(break_lock=break_lock)
    try:
        return _collect(out, parts, read_manifest(parts))
    finally:
        if lock is not None:
            lock.release()


def _collect(out: Path, parts: Path, manifest: dict) -> CollectReport:
    job = parse_job(manifest["job_text"], str(parts / MANIFEST))
    check_layout(job, manifest, parts)
    temporary = re.compile(re.escape(f".{out.name}.") + r"\d+\.tmp")
    for stale in out.parent.glob(f".{out.name}.*.tmp"):
        if temporary.fullmatch(stale.name):
            stale.unlink(missing_ok=True)
    logs = part_logs(job, parts)
    report = CollectReport(out, 0, job.layout.n_tasks)
    attrs, run_attrs = _attributes(job, parts)

    def write(tmp: Path) -> None:
        if job.analysis.assemble is None:
            _stream(tmp, job, logs, attrs, report)
            with xr.open_dataset(tmp, engine="netcdf4") as ds:
                derived = {k: v.load() for k, v in job.analysis.derived(ds, job.options).items()}
            if derived:
                extra = xr.Dataset(derived)
                encoding = {k: v for k, v in _encoding(extra).items() if k in derived}
                extra.to_netcdf(tmp, mode="a", engine="netcdf4", encoding=encoding)
            _write_run_group(tmp, {**run_attrs, "tasks_completed": report.tasks_completed})
            return
        raw, report.tasks_completed = merge(job, parts, logs)
        _count(report, raw["status"].values.ravel(), raw["message"].values.ravel())
        ds = job.analysis.assemble(raw, job.options).set_coords(
            [c for c in job.analysis.coordinate_variables(job.options) if c in raw])
        ds.attrs.update(attrs)
        for name, var in ds.variables.items():
            lacking = [a for a in ("units", "long_name") if a not in var.attrs and name != "message"]
            if lacking:
                report.notes.append(f"analysis {job.analysis_name!r}: variable {name!r} has no "
                                    + " or ".join(lacking))
        ds.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(ds))
        _write_run_group(tmp, {**run_attrs, "tasks_completed": report.tasks_completed})

    try:
        replace_atomically(out, write)
    except RunError:
        raise
    except OSError as exc:
        raise file_error(exc, f"writing {out}") from None
    except RuntimeError as exc:  # netCDF4 reports a full disk as "NetCDF: HDF error"
        raise RunError(f"writing {out} failed ({exc}); check the free space and the permissions of "
                       f"{out.parent}, then run collect again (the parts are kept)") from None
    report.notes[:0] = logs.problems()
    missing = report.tasks_total - report.tasks_completed
    if missing:
        report.notes.append(f"{missing} of {report.tasks_total} tasks are missing (status "
                            f"{STATUS_MISSING}); run --resume to compute them")
    return report


def _count(report: CollectReport, status: np.ndarray, message: np.ndarray) -> None:
    """Add tasks to the counts per status and the reasons of those not ok."""
    report.counts.update(Counter(status.tolist()))
    for i in np.flatnonzero((status != STATUS_OK) & (status != STATUS_MISSING) & (status != STATUS_SKIPPED)):
        report.reasons[(int(status[i]), str(message[i]))] += 1


#: The netCDF group holding the attributes of the run(s) that wrote a result.
RUN_GROUP = "run"


def _attributes(job: Job, parts: Path) -> tuple[dict, dict]:
    """The global attributes of a result, and those of its ``run`` group.

    The global ones are what results of one analysis computed by the same code on the same
    membrane share (so that ``xarray.combine_by_coords`` and ``open_mfdataset`` combine runs
    over different grid values with their defaults): CF conventions, the analysis and its
    attributes, the package version and source hash, the membrane constants, the model
    kind, the damping law and the constants its ``[damping]`` table gives.  What is
    particular to a run (job file, history, dates, task counts, git commit, library
    versions) goes to the group ``run`` (:func:`run_attributes`; ``tasks_completed`` is
    added when the parts have been read).
    """
    runs = read_runs(parts)
    last = runs[-1]["provenance"] if runs else provenance.provenance(job.analysis)
    history = [f"{r['started']}: run {r['run']} ({'chunks ' + r['chunks'] if r.get('chunks', 'all') != 'all' else 'all chunks'})"
               f" on {r['ranks']} rank(s) at {r['host']} with "
               f"{provenance.describe(r['provenance'])}"
               + (f"; resumed with different code: {'; '.join(r['code_changed'])}" if r.get("code_changed") else "")
               for r in runs]
    shared = {
        "Conventions": "CF-1.8",
        "title": f"membrane-sweep results of the {job.analysis_name} analysis",
        "source": f"membrane-sweep {last['package_version']}, source sha256 {last['source_sha256'][:12]}",
        "analysis": job.analysis_name,
        "software": "membrane-sweep",
        "software_version": last["package_version"],
        "source_sha256": last["source_sha256"],
        **membrane_attributes(job.membrane, job.layout.dims),
        "model": job.model.kind,
        **model_attributes(job.model),
        "damping_law": job.damping.law.name,
        **damping_attributes(job.damping),
        **job.analysis.attributes(job.options),
    }
    run = {
        "job_name": job.name,
        "job_file": job.text,
        "job_sha256": job.sha256,
        "history": "\n".join(history),
        "provenance": provenance.describe(last),
        "git_commit": last.get("git_commit") or "unknown",
        "library_versions": json.dumps(last["versions"]),
        "code_changed_during_run": int(any(r.get("code_changed") for r in runs)),
        "tasks_total": job.layout.n_tasks,
        "date_created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
    }
    return shared, run


def _write_run_group(path: Path, attrs: dict) -> None:
    import netCDF4

    with netCDF4.Dataset(path, "a") as nc:
        nc.createGroup(RUN_GROUP).setncatts(attrs)


def model_attributes(model) -> dict:
    """``model_<key>`` for each option of the job's ``[model]`` table (the fields of the
    model's parsed options, a dataclass; none for a model without options); a true/false
    option as 1/0 (netCDF attributes have no boolean type)."""
    options = model.options
    if options is None or not dataclasses.is_dataclass(options):
        return {}
    values = {f"model_{f.name}": getattr(options, f.name) for f in dataclasses.fields(options)}
    return {key: int(v) if isinstance(v, bool) else v for key, v in values.items()}


def damping_attributes(damping) -> dict:
    """Global attributes of the constants a job's ``[damping]`` table gives (those of the
    grid are coordinates with units): ``damping_<name>`` and ``damping_<name>_units``."""
    out = {}
    for name in sorted(damping.given):
        out[f"damping_{name}"] = np.asarray(getattr(damping.law, name), dtype=float)
        out[f"damping_{name}_units"] = parameter_record(name)[1]
    return out


def run_attributes(path: Path) -> dict:
    """The attributes of the run(s) that wrote the result ``path`` (its ``run`` group):
    ``job_name``, ``job_file``, ``job_sha256``, ``history``, ``date_created``,
    ``tasks_total``, ``tasks_completed``, ``git_commit``, ``library_versions``, ...

    Raises
    ------
    RunError
        If ``path`` is not a readable result of this package.
    """
    import netCDF4

    try:
        with netCDF4.Dataset(path) as nc:
            if RUN_GROUP not in nc.groups:
                raise RunError(f"{path} is not a membrane-sweep result (no '{RUN_GROUP}' group)")
            group = nc.groups[RUN_GROUP]
            return {a: group.getncattr(a) for a in group.ncattrs()}
    except OSError as exc:
        raise RunError(f"{path} is not a readable NetCDF result ({type(exc).__name__}); give the "
                       "output file of a run (OUT.nc), not a job file") from None


def _encoding(ds: xr.Dataset) -> dict[str, dict]:
    """zlib on numeric variables; no fill value on integers and coordinates."""
    encoding = {}
    for name, var in ds.variables.items():
        enc = {"zlib": True, "complevel": 4} if var.dtype.kind in "biuf" else {}
        if var.dtype.kind in "biu" or name in ds.coords:
            enc["_FillValue"] = None
        encoding[name] = enc
    return encoding
