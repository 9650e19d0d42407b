"""The ``status`` command: how far the run writing an output has got."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import numpy as np
import xarray as xr

from sweep import partlog
from sweep.analyses.base import STATUS_OK, STATUS_SKIPPED
from sweep.errors import RunError
from sweep.jobspec import parse_job
from sweep.storage.lock import LOCK, Lock
from sweep.storage.netcdf import run_attributes
from sweep.storage.parts import MANIFEST, check_layout, part_logs, parts_dir, read_manifest
from sweep.storage.tally import STATUS_MISSING, summarize


def describe_status(out: Path) -> str:
    """Completed / total tasks of the run writing ``out``, finished or not, with the
    counts per status, the commonest reasons and any part that failed verification.

    Read from ``OUT.nc.parts/`` when it exists, else from ``out``.

    Raises
    ------
    RunError
        If neither exists, or ``out`` is not a sweep result.
    """
    parts = parts_dir(out)
    if parts.exists():
        m = read_manifest(parts)
        job = parse_job(m["job_text"], str(parts / MANIFEST))
        check_layout(job, m, parts)
        logs = part_logs(job, parts)
        counts: Counter[int] = Counter()
        reasons: Counter = Counter()
        chunks = 0
        with partlog.Reader(job.analysis.variables(job.options)) as reader:
            for rec in logs:
                chunks += 1
                st = reader.read(rec, only_status=True)[0]
                counts.update(Counter(st.tolist()))
                if np.any((st != STATUS_OK) & (st != STATUS_SKIPPED)):
                    messages = reader.read(rec)[2]
                    for i in np.flatnonzero((st != STATUS_OK) & (st != STATUS_SKIPPED)):
                        reasons[(int(st[i]), messages.get(int(i), ""))] += 1
        written = "written" if out.exists() else "not collected yet"
        lines = [f"{m['job_name']} ({m['analysis']}): {logs.tasks} / {m['n_tasks']} tasks "
                 f"completed, {chunks} / {m['n_chunks']} chunks ({summarize(counts, reasons)}); "
                 f"{out}: {written}"]
        for path in sorted(parts.glob(f"{LOCK}*")):
            h = Lock.holder(path)
            lines.append(f"in use ({path.name}) by a {h.get('what')} on host {h.get('host')}, process "
                         f"{h.get('pid')}, since {h.get('started')}")
        return "\n".join(lines + [f"rejected part: {p}" for p in logs.problems()])
    if not out.exists():
        raise RunError(f"no run at {out}: neither {out} nor {parts}/ exists")
    run = run_attributes(out)
    try:
        with xr.open_dataset(out, engine="netcdf4") as ds:
            counts = Counter(ds["status"].values.ravel().tolist()) if "status" in ds else Counter()
            reasons = Counter()
            if "message" in ds:
                for s, msg in zip(ds["status"].values.ravel(), ds["message"].values.ravel()):
                    if s not in (STATUS_OK, STATUS_MISSING, STATUS_SKIPPED):
                        reasons[(int(s), str(msg))] += 1
            return (f"{run['job_name']} ({ds.attrs['analysis']}): {run['tasks_completed']} / "
                    f"{run['tasks_total']} tasks completed ({summarize(counts, reasons)}); "
                    f"{parts}/ deleted")
    except (OSError, ValueError) as exc:
        raise RunError(f"{out} is not a readable NetCDF result ({type(exc).__name__}); give the "
                       "output file of a run (OUT.nc), not a job file") from None
