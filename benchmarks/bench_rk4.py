"""RK4 step of the one-mode ROM per trajectory: the project's kernels against a C program
of the same algorithm (the hardware reference) and numpy (what a user would write).

Case: Fig. 19a, delta = 1.1, delta_o = 0.2 (analytic pre-stretch), Omega = 33.5 rad/s,
P0 = 1 Pa, c = 0.05 N s/m^3, 64 RK4 steps per period, ``--trajectories`` random initial
states in the basins window (-0.3..0.3 m, -10..10 m/s) advanced ``--periods`` periods.
Variants, interleaved in each of ``--repeats`` rounds (medians printed, compilation
excluded):

* numba scalar: ``ForcedMap.advance_batch`` (one trajectory at a time, the table loop of
  ``model.integrate``);
* numba lock-step: ``model.integrate.rk4_one_mode_lockstep`` in blocks of
  ``LOCKSTEP_WIDTH`` (what the basins use);
* C scalar and C lock-step: ``benchmarks/c/rk4_one_mode.c``, compiled here with
  ``cc -O3 -march=native`` (the C variants are skipped, with a message, when no compiler
  is found); the C program times its own kernel loop;
* numpy lock-step: the same RK4 on whole arrays with numpy (table lookups by fancy
  indexing), a plain vectorised implementation.

Every variant's final states are compared with numba scalar (agreement to 1e-9 relative
is printed).  Run: ``python benchmarks/bench_rk4.py [--repeats 7] [--smoke]``.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from model.forced import ForcedMap  # noqa: E402
from model.integrate import LOCKSTEP_WIDTH, lockstep_table, rk4_one_mode_lockstep  # noqa: E402
from model.params import Loading, Membrane  # noqa: E402
from model.prestretch import solve_prestretch  # noqa: E402
from model.rom import build_rom  # noqa: E402

STEPS = 64
def numpy_lockstep(states, fmap, coef_t, periods):
    """RK4 on whole arrays in numpy: the vectorised implementation a user would write."""
    tab, f = fmap.rom.tables, fmap.forcing
    pieces = coef_t.shape[1]
    q, v = states[:, 0].copy(), states[:, 1].copy()
    h = fmap.period / STEPS

    def accel(qs, vs, t):
        u = np.minimum(np.abs(qs) * (pieces / tab.table_max), pieces - 0.5)
        j = u.astype(np.intp)
        tc = 2.0 * (u - j) - 1.0
        b1, b2 = coef_t[-1, j], 0.0
        for k in range(coef_t.shape[0] - 2, 0, -1):
            b1, b2 = 2.0 * tc * b1 - b2 + coef_t[k, j], b1
        return -f.damping_rate * vs - tab.k_force[0] * qs * (tc * b1 - b2 + coef_t[0, j]) \
            + f.P0 * np.cos(f.Omega * t) * tab.load[0]

    for _ in range(periods):
        for i in range(STEPS):
            t = i * h
            a1 = accel(q, v, t)
            q2, v2 = q + 0.5 * h * v, v + 0.5 * h * a1
            a2 = accel(q2, v2, t + 0.5 * h)
            q3, v3 = q + 0.5 * h * v2, v + 0.5 * h * a2
            a3 = accel(q3, v3, t + 0.5 * h)
            q4, v4 = q + h * v3, v + h * a3
            a4 = accel(q4, v4, t + h)
            q = q + h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
            v = v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
    return np.column_stack([q, v])


def numba_lockstep(states, fmap, coef_t, periods):
    """``rk4_one_mode_lockstep`` over blocks of ``LOCKSTEP_WIDTH`` trajectories."""
    tab, f = fmap.rom.tables, fmap.forcing
    out = np.empty_like(states)
    reach = np.empty(LOCKSTEP_WIDTH)
    h = fmap.period / STEPS
    for s in range(0, states.shape[0], LOCKSTEP_WIDTH):
        q, v = states[s:s + LOCKSTEP_WIDTH, 0].copy(), states[s:s + LOCKSTEP_WIDTH, 1].copy()
        r = reach[:q.size]
        for _ in range(periods):
            rk4_one_mode_lockstep(q, v, 0.0, h, STEPS, coef_t, tab.table_max, tab.k_force[0], tab.load[0],
                                  f.damping_rate, f.P0, f.Omega, r)
        if np.any(r >= tab.table_max):
            sys.exit("a benchmark trajectory left the force table")
        out[s:s + q.size, 0], out[s:s + q.size, 1] = q, v
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trajectories", type=int, default=4096)
    ap.add_argument("--periods", type=int, default=5)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    if args.smoke:
        args.trajectories, args.periods, args.repeats = 200, 1, 1
    rom = build_rom(solve_prestretch(Membrane(1.1, 0.2), "analytic"), [(1, 0)])
    fmap = ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05), STEPS)
    tab, f = rom.tables, fmap.forcing
    coef_t = lockstep_table(tab)
    rng = np.random.default_rng(0)
    states = np.column_stack([rng.uniform(-0.3, 0.3, args.trajectories), rng.uniform(-10.0, 10.0, args.trajectories)])
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("rk4_one_mode", work)
    n_steps = args.trajectories * args.periods * STEPS

    def c_variant(mode):
        table = work / f"table{mode}.bin"
        (tab.stiffness_table if mode == 0 else coef_t).tofile(table)
        states.tofile(work / "in.bin")

        def run():
            out = subprocess.run([str(exe), str(mode), str(LOCKSTEP_WIDTH), str(table), str(coef_t.shape[1]),
                                  *(repr(float(x)) for x in (tab.table_max, tab.k_force[0], tab.load[0],
                                                             f.damping_rate, f.P0, f.Omega, fmap.period / STEPS)),
                                  str(STEPS), str(args.periods), str(work / "in.bin"), str(work / "out.bin")],
                                 capture_output=True, text=True, check=True)
            return float(out.stdout), np.fromfile(work / "out.bin").reshape(-1, 2)
        return run

    def timed(fn):
        def run():
            t0 = time.perf_counter()
            out = fn()
            return (time.perf_counter() - t0) / n_steps * 1e9, out
        return run

    variants = {
        "numba scalar": timed(lambda: fmap.advance_batch(states, args.periods)),
        "numba lock-step": timed(lambda: numba_lockstep(states, fmap, coef_t, args.periods)),
        "numpy lock-step": timed(lambda: numpy_lockstep(states, fmap, coef_t, args.periods)),
    }
    if exe is not None:
        variants["C scalar"] = c_variant(0)
        variants["C lock-step"] = c_variant(1)
    times = {name: [] for name in variants}
    finals = {}
    for r in range(args.repeats + 1):  # round 0 compiles
        for name, run in variants.items():
            ns, finals[name] = run()
            if r:
                times[name].append(ns)
    print(f"one-mode RK4, {args.trajectories} trajectories x {args.periods} periods x {STEPS} steps, "
          f"lock-step width {LOCKSTEP_WIDTH}; medians of {args.repeats} interleaved rounds")
    med = {name: statistics.median(t) for name, t in times.items()}
    ref = finals["numba scalar"]
    for name in variants:
        err = np.max(np.abs(finals[name] - ref) / (np.abs(ref) + 1e-3))
        print(f"  {name:16s} {med[name]:9.2f} ns per trajectory and step   (final states vs numba scalar: "
              f"{err:.1e} relative)")
    if exe is not None:
        print(f"  ratio numba lock-step / C lock-step: {med['numba lock-step'] / med['C lock-step']:.2f} "
              f"(target <= 1.5)")
        print(f"  ratio numba scalar / C scalar:       {med['numba scalar'] / med['C scalar']:.2f}")
    print(f"  ratio numpy lock-step / numba lock-step: {med['numpy lock-step'] / med['numba lock-step']:.1f}")
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
