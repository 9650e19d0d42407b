"""RK4 step of a ROM with the quadrature force, per trajectory: the project's kernels
against C programs of the same algorithms (the hardware reference) and numpy (what a user
would write).

Case: Fig. 19a, delta = 1.1, delta_o = 0.2 (numeric pre-stretch), Omega = 33.5 rad/s,
P0 = 1 Pa, c = 0.05 N s/m^3, with the RK4 steps per period of each mode set's
``steps = "auto"``, ``--trajectories`` random initial states (|q_1| < 0.3 m,
|q_1'| < 10 m/s) advanced ``--periods`` periods:

* modes (1, 0), (2, 0), (3, 0) (the other modes at rest), with the default 160-point radial
  rule and with the 32-point rule the basins use on this window
  (:func:`model.rom.lean_radial_points`);
* the mixed set (1, 0), (1, 1), (1, 2) on its default 2-D rule (80 radial points x 49
  angular points on [0, pi], folded), |q_11|, |q_12| < 0.03 m: the general kernels, with
  the ``w_theta`` terms (the C lock-step K=3 program is for axisymmetric sets only).

Variants, interleaved in each of ``--repeats`` rounds (medians printed, compilation
excluded):

* numba scalar: ``ForcedMap.advance_batch`` (``model.integrate._rk4_quadrature``, one
  trajectory at a time; the force vectorises over the quadrature points: what shooting,
  continuation and time series use);
* numba lock-step: ``model.integrate.rk4_quadrature_lockstep`` on blocks of
  ``LOCKSTEP_WIDTH`` trajectories, one per column (what the basins use);
* C scalar and C lock-step: ``benchmarks/c/rk4_quadrature.c``, the same two algorithms,
  compiled here with ``cc -O3 -march=native -ffast-math`` (the numba kernels use fastmath
  too; skipped with a message without a compiler); the program times its own loop;
* C lock-step K=3: the same program compiled with ``-DFIXED_K=3``, the force's loops over
  the modes unrolled into one loop over the block per quadrature point (the arithmetic of
  the lock-step kernel for three modes only: a bound on what its loops can reach);
* numpy: the same RK4 with the force on whole arrays of quadrature points (one trajectory,
  one period per round: it is slow).

Final states are compared with numba scalar's (relative difference printed).  Run:
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
from model.damping_kernels import matrix_or_none  # noqa: E402
from model.integrate import LOCKSTEP_WIDTH, rk4_quadrature_lockstep  # noqa: E402
from model.params import Loading, Membrane  # noqa: E402
from model.prestretch import solve_prestretch  # noqa: E402
from model.rom import build_rom  # noqa: E402

#: (title, modes, radial rules, amplitude of the other modes' initial coordinates, m).
CASES = [("three-mode", [(1, 0), (2, 0), (3, 0)], (None, 32), 0.0),
         ("mixed-set (1,0), (1,1), (1,2)", [(1, 0), (1, 1), (1, 2)], (None,), 0.03)]


def numpy_rk4(y, fmap, periods):
    """RK4 with the force on whole numpy arrays: what a user would write."""
    t, f = fmap.rom.tables, fmap.forcing
    K = fmap.dof
    h = fmap.period / fmap.steps
    y = y.copy()

    def rhs(time_, z):
        a = z[:K] @ t.b_rho
        if t.axisymmetric:
            delta = t.hoop2 * (t.radial2 + a * a)  # det of the in-plane metric
            g = t.b_rho @ (2 * a * (1 - t.hoop2 / delta**2) * t.weight)
        else:
            b = z[:K] @ t.b_theta
            delta = t.hoop2 * (t.radial2 + a * a) + t.radial2 * b * b * t.inv_rho2
            g = (t.b_rho @ (2 * a * (1 - t.hoop2 / delta**2) * t.weight)
                 + t.b_theta @ (2 * b * t.inv_rho2 * (1 - t.radial2 / delta**2) * t.weight))
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


def lockstep_rk4(states, fmap, periods):
    """``rk4_quadrature_lockstep`` over blocks of ``LOCKSTEP_WIDTH`` trajectories."""
    t, f = fmap.rom.tables, fmap.forcing
    out = np.empty_like(states)
    h = fmap.period / fmap.steps
    for s in range(0, states.shape[0], LOCKSTEP_WIDTH):
        block = states[s:s + LOCKSTEP_WIDTH]
        columns = np.zeros((states.shape[1], LOCKSTEP_WIDTH))
        columns[:, :block.shape[0]] = block.T
        for _ in range(periods):
            rk4_quadrature_lockstep(columns, block.shape[0], 0.0, h, fmap.steps, t.weight, t.inv_rho2, t.hoop2, t.radial2,
                                    t.b_rho, t.b_theta, t.axisymmetric, t.law, t.k_force, t.load, f.damping_rate, f.P0,
                                    f.Omega, matrix_or_none(f.damping_matrix))
        out[s:s + block.shape[0]] = columns[:, :block.shape[0]].T
    return out


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trajectories", type=int, default=128)
    ap.add_argument("--periods", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    n_traj, periods, rounds = (3, 1, 1) if args.smoke else (args.trajectories, args.periods, args.repeats)
    ps = solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("rk4_quadrature", work, ("-ffast-math",))
    (work / "fixed").mkdir()
    fixed = compile_reference("rk4_quadrature", work / "fixed", ("-ffast-math", "-DFIXED_K=3"))
    for title, modes, rules, others in CASES:
        K = len(modes)
        rng = np.random.default_rng(0)
        states = np.zeros((n_traj, 2 * K))
        states[:, 0] = rng.uniform(-0.3, 0.3, n_traj)
        states[:, K] = rng.uniform(-10.0, 10.0, n_traj)
        states[:, 1:K] = rng.uniform(-others, others, (n_traj, K - 1))
        for points in rules:
            rom = build_rom(ps, modes, radial_points=points)
            _case(title, rom, states, exe, fixed if rom.tables.axisymmetric and K == 3 else None, work, periods,
                  rounds)


def _case(title, rom, states, exe, fixed, work, periods, rounds) -> None:
    """Time one ROM and print its block (``fixed``: the FIXED_K program, or None)."""
    programs = [(exe, 0, "C scalar"), (exe, 1, "C lock-step")] + ([(fixed, 1, "C lock-step K=3")] if fixed else [])
    n_traj = states.shape[0]
    steps = steps_per_period(rom, 64)
    fmap = ForcedMap.from_loading(rom, Loading(33.5, 1.0, 0.05), steps)
    t, f = rom.tables, fmap.forcing
    K, P = rom.dof, t.weight.size
    arrays = [t.weight, t.inv_rho2, t.hoop2, t.radial2, t.b_rho.ravel(), t.k_force, t.load]
    if not t.axisymmetric:
        arrays.append(t.b_theta.ravel())  # the C program takes the general branch
    np.concatenate(arrays).tofile(work / "tables.bin")
    states.tofile(work / "states.bin")
    fmap.advance_batch(states[:1], 1)
    lockstep_rk4(states[:1], fmap, 1)
    per_step = n_traj * periods * steps
    times = {"numba scalar": [], "numba lock-step": [], **{name: [] for _, _, name in programs}, "numpy": []}
    final = {}
    for _ in range(rounds):
        t0 = time.perf_counter()
        final["numba scalar"] = fmap.advance_batch(states, periods)
        times["numba scalar"].append((time.perf_counter() - t0) / per_step * 1e9)
        t0 = time.perf_counter()
        final["numba lock-step"] = lockstep_rk4(states, fmap, periods)
        times["numba lock-step"].append((time.perf_counter() - t0) / per_step * 1e9)
        for program, mode, name in programs:
            if program is None:
                continue
            out = subprocess.run([str(program), str(mode), str(LOCKSTEP_WIDTH), str(work / "tables.bin"), str(K),
                                  str(P), str(work / "states.bin"), str(steps), str(periods),
                                  repr(fmap.period / steps), repr(f.damping_rate), repr(f.P0), repr(f.Omega),
                                  str(work / "out.bin")], capture_output=True, text=True, check=True)
            times[name].append(float(out.stdout))
            final[name] = np.fromfile(work / "out.bin").reshape(states.shape)
        t0 = time.perf_counter()
        numpy_final = numpy_rk4(states[0], fmap, 1)
        times["numpy"].append((time.perf_counter() - t0) / steps * 1e9)
    ref = final["numba scalar"]
    err = {name: _rel(x, ref) for name, x in final.items() if name != "numba scalar"}
    err["numpy"] = _rel(numpy_final, fmap.advance_batch(states[:1], 1)[0])
    med = {k: statistics.median(v) for k, v in times.items() if v}
    print(f"{title} RK4, {P} quadrature points, {steps} steps per period, {n_traj} trajectories x {periods} "
          f"periods, lock-step width {LOCKSTEP_WIDTH}; medians of {rounds} interleaved rounds")
    for name, ns in med.items():
        compared = f"final states vs numba scalar: {err[name]:.1e} relative" if name in err else "the reference"
        print(f"  {name:16s} {ns:9.1f} ns per trajectory and step   ({compared})")
    if exe is not None:
        print(f"  ratio numba lock-step / C lock-step: {med['numba lock-step'] / med['C lock-step']:.2f} "
              f"(target <= 1.5)")
        print(f"  ratio numba scalar / C scalar:       {med['numba scalar'] / med['C scalar']:.2f}")
    if fixed is not None and exe is not None:
        print(f"  ratio numba lock-step / C lock-step K=3: {med['numba lock-step'] / med['C lock-step K=3']:.2f}")
    print(f"  ratio numba scalar / numba lock-step: {med['numba scalar'] / med['numba lock-step']:.2f}")
    print(f"  ratio numpy / numba lock-step: {med['numpy'] / med['numba lock-step']:.1f}")


if __name__ == "__main__":
    main()
