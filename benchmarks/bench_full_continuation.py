"""The cost of the Fig. 14a branch on the full model, whole, on one core (docs/performance.md,
"The Fig. 14a branch on the full model").

The continuation analysis of ``jobs/fig14a-full.toml`` (delta = 1.1, delta_o = 0.2, P0 = 10 Pa,
a 1 % modal damping ratio, Omega from 25 to 55 rad/s, 16 radial functions per field) as a task
of the job computes it: the branch with its Floquet stability, then the same with the stability
of one asymmetric family (n = 1, (U, V, W) on all 16 functions), against the issue's targets
(the branch <= 60 s, one family <= 60 s more), and that the family leaves the branch as it
was.  The kernels these steps spend their time in have their own benchmarks against C programs
of the same algorithm (``bench_full_forced``, ``bench_full_families``); this one times the
analysis around them.

Run: ``python benchmarks/bench_full_continuation.py [--repeats 1] [--smoke]``; ``--smoke`` (the
test suite): order 8, Omega from 25 to 27 rad/s.
"""

from __future__ import annotations

import argparse
import re
import statistics
import time
from pathlib import Path

import numpy as np

from sweep.jobspec import grid_point, parse_job

JOB = Path(__file__).resolve().parents[1] / "jobs" / "fig14a-full.toml"
#: The issue's targets (s, one core, converged resolution).
BRANCH_TARGET = 60.0
FAMILY_TARGET = 60.0


def job_text(families: bool, smoke: bool) -> str:
    """``jobs/fig14a-full.toml`` with the family n = 1 alone (or none), smaller for ``smoke``."""
    text = JOB.read_text()
    text = re.sub(r"^families = .*$", "families = {n = [1], radial = 16, inplane = true}" if families else "",
                  text, flags=re.M)
    if smoke:
        text = text.replace("order = 16", "order = 8").replace("stop = 55.0", "stop = 27.0")
        text = text.replace("radial = 16", "radial = 8")
    return text


def run(text: str, repeats: int) -> tuple[float, dict]:
    """The task of the job ``text``'s one grid point, compiled first: median wall time (s) and output."""
    job = parse_job(text)
    values = {k: float(v[0]) for k, v in zip(job.layout.dims, job.layout.values)}
    point = grid_point(job.membrane, values, job.damping.law, job.model)
    job.analysis.compute(point, job.options, 0)  # compiled, the model cached
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = job.analysis.compute(point, job.options, 0)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    branch, out = run(job_text(False, args.smoke), args.repeats)
    n, steps = int(out["n_points"]), int(out["rk4_steps"])
    folds = np.sort(out["fold_value"][:int(out["n_folds"])])
    print(f"Fig. 14a branch on the full model, {'order 8 (smoke)' if args.smoke else 'order 16'}, {steps} RK4 steps "
          f"per period, one core; medians of {args.repeats}")
    print(f"  branch with Floquet stability   {branch:7.1f} s   ({n} points, folds Omega = "
          f"{np.array2string(folds, precision=3)}; target <= {BRANCH_TARGET:g} s)")
    family, with_family = run(job_text(True, args.smoke), args.repeats)
    print(f"  with the family n = 1           {family:7.1f} s   (the family adds {family - branch:.1f} s, "
          f"{(family - branch) / max(n, 1) * 1e3:.0f} ms per point; target <= {FAMILY_TARGET:g} s more)")
    same = int(with_family["n_points"]) == n
    change = np.nanmax(np.abs(with_family["amplitude"][:n] - out["amplitude"][:n])) if same else np.nan
    print(f"  the same branch with the family: {same} ({int(with_family['n_points'])} points; amplitudes differ "
          f"by {change:.1e} m)")


if __name__ == "__main__":
    main()
