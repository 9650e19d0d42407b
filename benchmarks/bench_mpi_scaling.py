"""MPI scaling and memory of the sweep runner, measured side by side in one run.

A sweep of the ``linear`` analysis (``--tasks`` grid points of comparable cost, 2048 by
default: the converged Galerkin frequency of mode (1, 0), a few milliseconds each, so that
the computation outweighs the start-up of the ranks) runs on 1 and on 2 ranks,
``--repeats`` times each, through ``mpiexec -n N python -m mpi4py -m sweep run``.  Printed:

* wall time of the whole command (start-up, compute, collect) and of the compute phase
  alone (as the runner reports it), median over the repeats, and the speed-ups (target
  >= 1.7 on 2 ranks); the CPU time of all ranks shows the parallel overhead;
* peak resident memory of each rank after the compute phase, and of rank 0 after the
  collect, for two grid sizes (``--memory-sizes``): flat per rank as the grid grows.

Run from the repository root:  ``python benchmarks/bench_mpi_scaling.py``; ``--smoke`` (the
test suite): 16 tasks, one repeat, memory at 8 and 16 tasks.
Other processes on the machine distort the timings: the load average is printed too.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from sweep.launch import find_mpiexec

TIMEOUT = 900  # seconds per sweep

JOB = """
[job]
name = "bench"
analysis = "linear"

[grid]
delta = {{start = 1.1, stop = 2.0, num = {n_delta}}}
delta_o = {{start = 0.2, stop = 0.5, num = 8}}

[linear]
modes = [[1, 0]]
prestretch = "numeric"
"""


def mpiexec() -> str:
    path = find_mpiexec()
    if path is None:
        sys.exit("mpiexec not found next to the Python executable nor on PATH")
    return path


def write_job(directory: Path, n_tasks: int) -> Path:
    """A job of ``n_tasks`` linear tasks (a multiple of 8)."""
    path = directory / f"bench_{n_tasks}.toml"
    path.write_text(JOB.format(n_delta=n_tasks // 8))
    return path


def sweep(job: Path, ranks: int, workdir: Path) -> tuple[float, float, float, str]:
    """Run one sweep; returns (wall time s, compute time s, CPU time of all ranks s, stderr)."""
    env = {**os.environ, "MPIEXEC_TIMEOUT": str(TIMEOUT)}
    command = [mpiexec(), "-n", str(ranks), sys.executable, "-m", "mpi4py", "-m", "sweep",
               "run", str(job), "-o", str(workdir / "bench.nc"), "--overwrite",
               "--report-memory"]
    cpu_before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(command, env=env, capture_output=True, text=True, timeout=TIMEOUT)
    wall = time.perf_counter() - start
    cpu_after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu_after.ru_utime + cpu_after.ru_stime) - (cpu_before.ru_utime + cpu_before.ru_stime)
    if proc.returncode:
        sys.exit(f"sweep failed:\n{proc.stderr}")
    compute = float(re.search(r"rank\(s\) in ([0-9.]+) s", proc.stdout).group(1))
    return wall, compute, cpu, proc.stderr


def memory(stderr: str) -> tuple[list[float], float]:
    """Peak RSS per rank after compute and of rank 0 after collect, MiB."""
    match = re.search(r"after compute \(MiB\): ([0-9., ]+); rank 0 after collect: ([0-9.]+)",
                      stderr)
    return [float(x) for x in match.group(1).split(",")], float(match.group(2))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tasks", type=int, default=2048,
                        help="tasks of the timed sweep (a multiple of 8)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--memory-sizes", default="64,512",
                        help="comma-separated task counts for the memory measurement")
    parser.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = parser.parse_args(argv)
    if args.smoke:
        args.tasks, args.repeats, args.memory_sizes = 16, 1, "8,16"

    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp)
        job = write_job(workdir, args.tasks)
        sweep(write_job(workdir, 8), 1, workdir)  # fills the numba cache
        # 1 and 2 ranks alternate, so that a change of the machine's load hits both.
        runs = {1: [], 2: []}
        for _ in range(args.repeats):
            for ranks in runs:
                runs[ranks].append(sweep(job, ranks, workdir)[:3])
        times = {}
        for ranks in runs:
            times[ranks] = [statistics.median(run[i] for run in runs[ranks]) for i in range(3)]
            print(f"{args.tasks} tasks on {ranks} rank(s): wall {times[ranks][0]:.2f} s, "
                  f"compute {times[ranks][1]:.2f} s, CPU of all ranks {times[ranks][2]:.2f} s "
                  f"(medians of {args.repeats})")
        print(f"speed-up 2 ranks / 1 rank: wall {times[1][0] / times[2][0]:.2f}, "
              f"compute {times[1][1] / times[2][1]:.2f} (target >= 1.7)")
        # On a machine shared with other jobs the wall times measure the share of the
        # cores each run got; the CPU times do not depend on it.
        print(f"CPU time 2 ranks / 1 rank: {times[2][2] / times[1][2]:.3f}; speed-up on "
              f"two idle cores at most {2 * times[1][2] / times[2][2]:.2f}")

        for n_tasks in (int(s) for s in args.memory_sizes.split(",")):
            n_tasks = 8 * math.ceil(n_tasks / 8)
            stderr = sweep(write_job(workdir, n_tasks), 2, workdir)[3]
            per_rank, collect = memory(stderr)
            print(f"{n_tasks} tasks on 2 ranks: peak RSS per rank after compute "
                  f"{', '.join(f'{m:.1f}' for m in per_rank)} MiB; rank 0 after collect "
                  f"{collect:.1f} MiB")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
