"""Bookkeeping at scale: a cheap sweep of many tasks, one task per chunk, on MPI ranks.

Job: ``static`` with the analytic pre-stretch and two ``rho`` points, a ``delta x delta_o``
grid of ``--tasks`` points, ``chunk = 1`` (the worst case for part files).  For each task
count the benchmark reports, from one run each:

* files in the parts directory after the run;
* wall time of ``mpiexec -n RANKS ... sweep run`` (includes the final collect) and of a
  separate ``sweep collect`` and ``sweep status``;
* peak resident memory of the ``sweep collect`` process (it is rank 0's collect);
* the ratios of the largest task count to the smallest.

Usage::

    python benchmarks/bench_bookkeeping.py                     # 20,000 and 200,000 tasks
    python benchmarks/bench_bookkeeping.py --tasks 200 2000    # smoke mode (the tests)

Only the command line is used, so the same script measures any version of the package.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from sweep.launch import find_mpiexec  # noqa: E402

JOB = """[job]
name = "bookkeeping"
analysis = "static"
chunk = 1

[grid]
delta = {{start = 1.05, stop = 3.0, num = {n1}}}
delta_o = {{start = 0.1, stop = 0.8, num = {n2}}}

[static]
prestretch = "analytic"
rho = {{start = 0.85, stop = 1.0, num = 2}}
"""

#: Prints the peak RSS (MiB) of the collect it runs, as the last line.
_COLLECT = ("import resource, sys; from sweep import cli; code = cli.main(['collect', sys.argv[1]]); "
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024); sys.exit(code)")


def _timed(cmd, env) -> tuple[float, str]:
    start = time.perf_counter()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=3600)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stdout}\n{done.stderr}")
    return seconds, done.stdout


def measure(tasks: int, ranks: int, workdir: Path) -> dict:
    """Run, collect and status of a ``tasks``-task static sweep; returns the measurements."""
    n1 = int(math.sqrt(tasks))
    n2 = tasks // n1
    job = workdir / f"job-{tasks}.toml"
    job.write_text(JOB.format(n1=n1, n2=n2))
    out = workdir / f"out-{tasks}.nc"
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    run = [find_mpiexec(), "-n", str(ranks), sys.executable, "-m", "mpi4py", "-m", "sweep", "run",
           str(job), "-o", str(out)]
    t_run, _ = _timed(run, env)
    parts = out.with_name(out.name + ".parts")
    files = sum(1 for p in parts.iterdir()) if parts.exists() else 0
    t_collect, text = _timed([sys.executable, "-c", _COLLECT, str(out)], env)
    rss = float(text.strip().splitlines()[-1])
    t_status, _ = _timed([sys.executable, "-m", "sweep", "status", str(out)], env)
    return {"tasks": n1 * n2, "files": files, "run_s": t_run, "collect_s": t_collect,
            "collect_rss_mib": rss, "status_s": t_status, "nc_mib": out.stat().st_size / 2**20}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tasks", type=int, nargs="+", default=[20_000, 200_000])
    ap.add_argument("--ranks", type=int, default=2)
    args = ap.parse_args(argv)
    if find_mpiexec() is None:
        raise SystemExit("mpiexec not found: install the project (pip install -e .)")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for tasks in args.tasks:
            rows.append(measure(tasks, args.ranks, Path(tmp)))
            r = rows[-1]
            print(f"{r['tasks']:>8} tasks: {r['files']:>7} files in the parts directory, run {r['run_s']:.1f} s, "
                  f"collect {r['collect_s']:.1f} s (peak RSS {r['collect_rss_mib']:.0f} MiB), "
                  f"status {r['status_s']:.2f} s, result {r['nc_mib']:.1f} MiB", flush=True)
    lo, hi = rows[0], rows[-1]
    print(f"ratios {hi['tasks']} / {lo['tasks']} tasks: files {hi['files'] / max(lo['files'], 1):.2f}, "
          f"run {hi['run_s'] / lo['run_s']:.2f}, collect {hi['collect_s'] / lo['collect_s']:.2f}, "
          f"collect peak RSS {hi['collect_rss_mib'] / lo['collect_rss_mib']:.3f}, "
          f"status {hi['status_s'] / lo['status_s']:.2f}")


if __name__ == "__main__":
    main()
