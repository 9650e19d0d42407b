"""RK4 step of a three-mode ROM (quadrature force) per trajectory: the project's kernel
against a C program of the same algorithm (the hardware reference) and numpy (what a user
would write).

Case: Fig. 19a, delta = 1.1, delta_o = 0.2 (numeric pre-stretch), Omega = 33.5 rad/s,
P0 = 1 Pa, c = 0.05 N s/m^3, modes (1, 0), (2, 0), (3, 0), 264 RK4 steps per period (the
set's ``steps = "auto"``), ``--trajectories`` random initial states (|q_1| < 0.3 m,
|q_1'| < 10 m/s, the other modes at rest) advanced ``--periods`` periods, with the default
160-point radial rule and with the 32-point rule the basins use on this window
(:func:`model.rom.lean_radial_points`).  Variants, interleaved in each of ``--repeats``
rounds (medians printed, compilation excluded):

* numba: ``ForcedMap.advance_batch`` (``model.integrate._rk4_quadrature``, one trajectory
  at a time; the force vectorises over the quadrature points);
* C: ``benchmarks/c/rk4_quadrature.c``, compiled here with ``cc -O3 -march=native
  -ffast-math`` (the numba kernels use fastmath too; skipped with a message without a
  compiler); the program times its own loop;
* numpy: the same RK4 with the force on whole arrays of quadrature points (one trajectory,
  one period per round: it is slow).

Final states are compared with numba's (relative difference printed).  Run:
``python benchmarks/bench_rk4_quadrature.py [--repeats 7] [--smoke]``.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from model.forced import ForcedMap, steps_per_period  # noqa: E402
from model.params import Loading, Membrane  # noqa: E402
from model.prestretch import solve_prestretch  # noqa: E402
from model.rom import build_rom  # noqa: E402

MODES = [(1, 0), (2, 0), (3, 0)]


def numpy_rk4(y, fmap, periods):
    """RK4 with the force on whole numpy arrays: what a user would write."""
    t, f = fmap.rom.tables, fmap.forcing
    K = fmap.dof
    h = fmap.period / fmap.steps
    y = y.copy()

    def rhs(time_, z):
        a = z[:K] @ t.b_rho
        D = t.r2 * (t.dr2 + a * a)
        g = t.b_rho @ (2 * a * (1 - t.rho2 * t.r2 / D**2) * t.weight)
        return np.concatenate([z[K:], -f.damping_rate * z[K:] - t.k_force * g
                               + f.P0 * np.cos(f.Omega * time_) * t.load])

    for _ in range(periods):
        s = 0.0
        for _ in range(fmap.steps):
            k1 = rhs(s, y)
            k2 = rhs(s + h / 2, y + h / 2 * k1)
            k3 = rhs(s + h / 2, y + h / 2 * k2)
            k4 = rhs(s + h, y + h * k3)
            y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            s += h
    return y


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trajectories", type=int, default=16)
    ap.add_argument("--periods", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    n_traj, periods, rounds = (2, 1, 1) if args.smoke else (args.trajectories, args.periods, args.repeats)
    ps = solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")
    rng = np.random.default_rng(0)
    states = np.zeros((n_traj, 2 * len(MODES)))
    states[:, 0] = rng.uniform(-0.3, 0.3, n_traj)
    states[:, len(MODES)] = rng.uniform(-10.0, 10.0, n_traj)
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("rk4_quadrature", work, ("-ffast-math",))
    for points in (None, 32):
        rom = build_rom(ps, MODES, radial_points=points)
        steps = steps_per_period(rom, 64)
        fmap = ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05), steps)
        t, f = rom.tables, fmap.forcing
        K, P = rom.dof, t.weight.size
        np.concatenate([t.weight, t.rho2, t.r2, t.dr2, t.b_rho.ravel(), t.k_force, t.load]).tofile(work / "tables.bin")
        states.tofile(work / "states.bin")
        fmap.advance_batch(states[:1], 1)
        times = {"numba": [], "C": [], "numpy": []}
        for _ in range(rounds):
            t0 = time.perf_counter()
            final = fmap.advance_batch(states, periods)
            times["numba"].append((time.perf_counter() - t0) / (n_traj * periods * steps) * 1e9)
            if exe is not None:
                out = subprocess.run([str(exe), str(work / "tables.bin"), str(K), str(P), str(work / "states.bin"),
                                      str(steps), str(periods), repr(fmap.period / steps), repr(f.damping_rate),
                                      repr(f.P0), repr(f.Omega), str(work / "out.bin")],
                                     capture_output=True, text=True, check=True)
                times["C"].append(float(out.stdout))
            t0 = time.perf_counter()
            numpy_final = numpy_rk4(states[0], fmap, 1)
            times["numpy"].append((time.perf_counter() - t0) / steps * 1e9)
        err = {"numpy": _rel(numpy_final, fmap.advance_batch(states[:1], 1)[0])}
        if exe is not None:
            err["C"] = _rel(np.fromfile(work / "out.bin").reshape(final.shape), final)
        med = {k: statistics.median(v) for k, v in times.items() if v}
        print(f"three-mode RK4, {P} radial points, {steps} steps per period, {n_traj} trajectories x {periods} "
              f"periods; medians of {rounds} interleaved rounds")
        for name, ns in med.items():
            compared = f"final states vs numba: {err[name]:.1e} relative" if name in err else "the reference"
            print(f"  {name:6s} {ns:9.1f} ns per trajectory and step   ({compared})")
        if exe is not None:
            print(f"  ratio numba / C: {med['numba'] / med['C']:.2f} (target <= 1.5)")
        print(f"  ratio numpy / numba: {med['numpy'] / med['numba']:.1f}")


if __name__ == "__main__":
    main()
