"""Basins of attraction of the paper's Fig. 19a case: wall time, rank independence,
agreement with converged brute force, memory.

Case: delta = 1.1, delta_o = 0.2, Omega = 33.5 rad/s, P0 = 1 Pa, c = 0.05 N s/m^3, one
mode, lattice ic_x = -0.3..0.3 m, ic_y = -10..10 m/s, ``--size`` x ``--size`` (200).
Printed:

* (a) wall time of the whole command ``mpiexec -n 2 python -m mpi4py -m sweep run`` with an
  empty ``NUMBA_CACHE_DIR`` (compilation included: "cold"), median over ``--repeats``, and
  ``--warm-repeats`` runs with the cache filled by the first run ("warm", median: the
  machine's noise is about 0.1 s); targets <= 15 s cold, <= 5 s warm;
* (b) the same on 1 rank, alternating with 2 ranks, and whether the ``label`` arrays of
  all runs are identical;
* (c) agreement of the labels with brute force (long integration to the capture disc of
  an attractor, no cells, no discovery) at 192 RK4 steps per period, converged (96 and
  192 steps agree on 100 % of a sample), on random samples of 400 and 1000 lattice points
  (the 400 are the first 400 of the 1000); target >= 99 %;
* (d) peak resident memory per rank (``run --report-memory``) for the ``--size`` lattice
  and for an ``--memory-size`` lattice (800); the latter with ``max_periods`` capped at
  ``--memory-periods`` (memory only: the labels are then mostly -1);
* (e) the quickstart job, ``jobs/quickstart.toml`` (120 x 120), on 2 ranks: cold once,
  then warm (``--warm-repeats``, median), and the ratio (target <= 1.3).

With ``--modes K`` (K > 1) the ROM has the axisymmetric modes (1..K, 0) (the lattice on
mode (1, 0), steps per period from the mode set, ``steps = "auto"``), and only (a) on 2
ranks (cold) and (c) run; brute force then uses twice the set's steps (264 and 528 steps
agree on 200 of 200 random points of the 3-mode lattice).

Run from the repository root:  ``python benchmarks/bench_basins.py``; ``--smoke`` (the test
suite): a 10 x 10 lattice, one repeat, 20 brute-force points, a 12 x 12 memory run of 5 periods,
the quickstart job on a 10 x 10 lattice once cold and once warm.
Other processes on the machine distort the timings: the load average is printed too.
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from model import attractors as ma  # noqa: E402
from model import basins as mb  # noqa: E402
from model import lattice as ml  # noqa: E402
from model.forced import ForcedMap, steps_per_period  # noqa: E402
from model.params import Loading, Membrane  # noqa: E402
from model.prestretch import solve_prestretch  # noqa: E402
from model.rom import build_rom  # noqa: E402
from sweep.launch import find_mpiexec  # noqa: E402

TIMEOUT = 1800  # seconds per sweep
CASE = dict(delta=1.1, delta_o=0.2, Omega=33.5, P0=1.0, c=0.05)
BRUTE_STEPS = 192

JOB = """
[job]
name = "bench-basins"
analysis = "basins"

[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
P0 = 1.0
c = 0.05

[basins]
modes = {modes}
ic_x = {{start = -0.3, stop = 0.3, num = {n}}}
ic_y = {{start = -10.0, stop = 10.0, num = {n}}}
{extra}
"""


def mpiexec() -> str:
    path = find_mpiexec()
    if path is None:
        sys.exit("mpiexec not found next to the Python executable nor on PATH")
    return path


def sweep(job: Path, ranks: int, out: Path, cache: Path) -> tuple[float, float, list, str]:
    """One run; returns (wall s, compute s, peak RSS per rank after compute MiB, stderr)."""
    env = {**os.environ, "MPIEXEC_TIMEOUT": str(TIMEOUT), "NUMBA_CACHE_DIR": str(cache)}
    command = [mpiexec(), "-n", str(ranks), sys.executable, "-m", "mpi4py", "-m", "sweep",
               "run", str(job), "-o", str(out), "--overwrite", "--report-memory"]
    start = time.perf_counter()
    proc = subprocess.run(command, env=env, capture_output=True, text=True, timeout=TIMEOUT,
                          cwd=Path(__file__).resolve().parents[1])
    wall = time.perf_counter() - start
    if proc.returncode:
        sys.exit(f"sweep failed:\n{proc.stderr}")
    compute = float(re.search(r"rank\(s\) in ([0-9.]+) s", proc.stdout).group(1))
    rss = re.search(r"after compute \(MiB\): ([0-9., ]+); rank 0 after collect: ([0-9.]+)",
                    proc.stderr)
    per_rank = [float(x) for x in rss.group(1).split(",")] + [float(rss.group(2))]
    return wall, compute, per_rank, proc.stderr


def labels(path: Path) -> np.ndarray:
    with xr.open_dataset(path) as ds:
        return ds["label"].squeeze().values.copy()


def agreement(path: Path, samples: int, K: int) -> None:
    """(c): labels of ``path`` versus converged brute force on ``samples`` random points."""
    with xr.open_dataset(path) as ds:
        ds = ds.isel({d: 0 for d in CASE})  # the one grid point; the mode dimension stays
        lab = ds["label"].values
        x, y = ds["ic_x"].values, ds["ic_y"].values
        per = ds["attractor_period"].values
        pts = np.concatenate([ds["attractor_coordinate"].values, ds["attractor_velocity"].values], axis=-1)
        steps = int(ds["rk4_steps"])
    rom = build_rom(solve_prestretch(Membrane(CASE["delta"], CASE["delta_o"]), "numeric"),
                    [(m, 0) for m in range(1, K + 1)])
    brute_steps = BRUTE_STEPS if K == 1 else 2 * steps
    fmap = ForcedMap.from_loading(rom, Loading(CASE["Omega"], CASE["P0"], CASE["c"]), brute_steps)
    lattice = ml.Lattice(x, y, 0, K)
    scale = ml.lattice_scale(lattice, 2 * K)
    # The attractors again, at the brute-force step count (Newton from the stored points).
    atts = [ma.find_periodic_orbit(pts[a, 0], int(per[a]), fmap, scale, 1e-11)
            for a in range(per.size) if per[a] > 0]
    rng = np.random.default_rng(0)
    idx = rng.choice(lab.size, samples, replace=False)
    ii, jj = np.unravel_index(idx, lab.shape)
    states = np.zeros((samples, 2 * K))
    states[:, 0], states[:, K] = x[ii], y[jj]
    start = time.perf_counter()
    brute, _, periods = mb.classify_lattice(states, lattice, fmap, mb.Settings(), atts, use_cells=False,
                                            discover=False)
    seconds = time.perf_counter() - start
    same = brute == lab[ii, jj]
    print(f"(c) brute force at {brute_steps} steps/period (fast: {steps}): {seconds:.1f} s for {samples} points, "
          f"mean {periods.mean():.0f} periods, unclassified {np.count_nonzero(brute < 0)}")
    for n in sorted({min(400, samples), samples}):
        print(f"    agreement on {n} random points: {same[:n].mean():.4f} "
              f"({np.count_nonzero(~same[:n])} differ; target >= 0.99)")
    fractions = [float(np.mean(lab == a)) for a in range(len(atts))]
    print(f"    basin fractions of the lattice: {', '.join(f'{f:.4f}' for f in fractions)}, "
          f"unclassified {np.mean(lab < 0):.4f}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--warm-repeats", type=int, default=5, help="warm runs on 2 ranks (median printed)")
    parser.add_argument("--memory-size", type=int, default=800)
    parser.add_argument("--memory-periods", type=int, default=0,
                        help="max_periods of the memory run (0: the default, a full run)")
    parser.add_argument("--modes", type=int, default=1,
                        help="axisymmetric modes (1..K, 0); K > 1: (a) on 2 ranks and (c) only")
    parser.add_argument("--tiles", type=int, default=0, help="the job's tiles (0: its default)")
    parser.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = parser.parse_args(argv)
    if args.smoke:
        args.size, args.repeats, args.samples, args.memory_size, args.memory_periods = 10, 1, 20, 12, 5
        args.warm_repeats = 1
    if args.modes > 1:
        several_modes(args)
        return

    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        job = work / "fig19a.toml"
        job.write_text(JOB.format(n=args.size, modes="[[1, 0]]", extra=f"tiles = {args.tiles}" if args.tiles else ""))
        runs = {2: [], 1: []}
        arrays = []
        for r in range(args.repeats):
            for ranks in runs:
                cache = work / f"cache-{ranks}-{r}"
                out = work / f"out-{ranks}-{r}.nc"
                runs[ranks].append(sweep(job, ranks, out, cache))
                arrays.append(labels(out))
                print(f"  run {r}, {ranks} rank(s), cold: wall {runs[ranks][-1][0]:.1f} s, "
                      f"compute {runs[ranks][-1][1]:.1f} s", flush=True)
        warm = [sweep(job, 2, work / "warm.nc", work / "cache-2-0") for _ in range(args.warm_repeats)]
        arrays.append(labels(work / "warm.nc"))
        for ranks, label in ((2, "(a)"), (1, "(b)")):
            wall = statistics.median(run[0] for run in runs[ranks])
            compute = statistics.median(run[1] for run in runs[ranks])
            print(f"{label} {args.size} x {args.size} on {ranks} rank(s), cold numba cache: wall "
                  f"{wall:.1f} s, compute {compute:.1f} s (medians of {args.repeats}"
                  f"{'' if ranks == 1 else '; target wall <= 15 s'})")
        print(f"    2 ranks, warm cache: wall {statistics.median(w[0] for w in warm):.2f} s, compute "
              f"{statistics.median(w[1] for w in warm):.2f} s (medians of {len(warm)}; target wall <= 5 s; "
              f"walls {', '.join(f'{w[0]:.2f}' for w in warm)})")
        ratio = [statistics.median(r[i] for r in runs[1]) / statistics.median(r[i] for r in runs[2])
                 for i in (0, 1)]
        print(f"    speed-up 2 ranks / 1 rank: wall {ratio[0]:.2f}, compute {ratio[1]:.2f}")
        identical = all(np.array_equal(arrays[0], a) for a in arrays[1:])
        print(f"    label arrays of all {len(arrays)} runs (1 and 2 ranks) identical: {identical}")
        agreement(work / "out-2-0.nc", args.samples, 1)
        print(f"(d) {args.size} x {args.size}: peak RSS per rank after compute "
              f"{', '.join(f'{m:.1f}' for m in runs[2][0][2][:-1])} MiB, rank 0 after collect "
              f"{runs[2][0][2][-1]:.1f} MiB")
        big = work / "big.toml"
        extra = f"max_periods = {args.memory_periods}" if args.memory_periods else ""
        big.write_text(JOB.format(n=args.memory_size, modes="[[1, 0]]", extra=extra))
        wall, compute, rss, _ = sweep(big, 2, work / "big.nc", work / "cache-2-0")
        note = (f"max_periods = {args.memory_periods}, memory only"
                if args.memory_periods else "full run")
        print(f"(d) {args.memory_size} x {args.memory_size} ({note}; wall {wall:.1f} s): peak "
              f"RSS per rank after compute {', '.join(f'{m:.1f}' for m in rss[:-1])} MiB, "
              f"rank 0 after collect {rss[-1]:.1f} MiB; unclassified "
              f"{np.mean(labels(work / 'big.nc') < 0):.3f}")
        quickstart(work, args.warm_repeats, args.size if args.smoke else 0)
    print(f"load average after: {os.getloadavg()[0]:.2f}")


def quickstart(work: Path, warm_repeats: int, lattice: int = 0) -> None:
    """(e): ``jobs/quickstart.toml`` on 2 ranks, cold (empty numba cache) then warm; on a
    ``lattice x lattice`` copy of its initial conditions when ``lattice`` > 0 (the smoke run)."""
    job = Path(__file__).resolve().parents[1] / "jobs" / "quickstart.toml"
    name = job.name
    if lattice:
        text = job.read_text()
        assert text.count("num = 120") == 2, "jobs/quickstart.toml's lattice changed: update quickstart()"
        job = work / "quickstart.toml"
        job.write_text(text.replace("num = 120", f"num = {lattice}"))
        name += f" on {lattice} x {lattice}"
    cache = work / "cache-quickstart"
    cold = sweep(job, 2, work / "quickstart.nc", cache)[0]
    warm = statistics.median(sweep(job, 2, work / "quickstart.nc", cache)[0] for _ in range(warm_repeats))
    print(f"(e) jobs/{name} on 2 ranks: cold {cold:.2f} s, warm {warm:.2f} s (median of {warm_repeats}); "
          f"cold / warm {cold / warm:.2f} (target <= 1.3)")


def several_modes(args) -> None:
    """(a) on 2 ranks, cold, and (c) for the modes (1..K, 0)."""
    K = args.modes
    rom = build_rom(solve_prestretch(Membrane(CASE["delta"], CASE["delta_o"]), "numeric"),
                    [(m, 0) for m in range(1, K + 1)])
    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print(f"modes (1..{K}, 0): {steps_per_period(rom, mb.DEFAULT_STEPS)} RK4 steps per period")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        job = work / "fig19a.toml"
        modes = "[" + ", ".join(f"[{m}, 0]" for m in range(1, K + 1)) + "]"
        job.write_text(JOB.format(n=args.size, modes=modes, extra=f"tiles = {args.tiles}" if args.tiles else ""))
        wall, compute, rss, _ = sweep(job, 2, work / "out.nc", work / "cache")
        print(f"(a) {args.size} x {args.size}, {K} modes, {args.tiles or 'default'} tiles, 2 ranks, cold numba "
              f"cache: wall {wall:.1f} s, "
              f"compute {compute:.1f} s (one run; target wall <= 300 s); peak RSS per rank after "
              f"compute {', '.join(f'{m:.1f}' for m in rss[:-1])} MiB")
        with xr.open_dataset(work / "out.nc") as ds:
            print(f"    unclassified {float(ds['unclassified_fraction'].squeeze()):.4f}")
        agreement(work / "out.nc", args.samples, K)
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
