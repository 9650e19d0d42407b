"""Time integration of the ROM: the project's DOP853 kernel against scipy's solve_ivp
(what a user would write) and a C program of the same algorithm (the hardware reference).

Same model (the exact neo-Hookean ROM of Eq. 31, delta = 1.1, delta_o = 0.2, forced and
damped: P0 = 1 Pa, Omega = 33.5 rad/s, c = 0.05 N s/m^3), same trajectories (N initial
states), same method (DOP853, the tableau of :mod:`model.dopri`) and tolerances:

* project: :func:`model.dopri.solve` (one trajectory at a time, compiled, one thread),
  timed around the call (its Python checks, about 60 us, included);
* C: ``benchmarks/c/dop853.c``, compiled here with ``cc -O3 -march=native -ffast-math``
  (skipped with a message without a compiler), the same step-size controller and force
  (the one-mode force table in its range, else the quadrature); it times its own loop
  (reading and writing its files excluded);
* solve_ivp: ``scipy.integrate.solve_ivp(method="DOP853")`` with the right-hand side
  written plainly in numpy.

Prints medians of interleaved repeats, the evaluations each made, the ratios, the largest
difference of the final states from the project's, and evaluations per second.  Run:

    python benchmarks/bench_integrators.py [--repeats 3] [--trajectories 4] [--periods 20] [--smoke]

``--smoke`` (the test suite): one trajectory, one period, one repeat.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from model import dopri  # noqa: E402
from model.params import Membrane  # noqa: E402
from model.prestretch import solve_prestretch  # noqa: E402
from model.rom import build_rom  # noqa: E402

C, P0, OMEGA = 0.05, 1.0, 33.5


def numpy_rhs(rom):
    """``y' = F(t, y)`` of the ROM in plain numpy."""
    t, K = rom.tables, rom.dof
    c_damp = rom.membrane.damping_rate(C)

    def f(time_, y):
        q, v = y[:K], y[K:]
        a, b = q @ t.b_rho, q @ t.b_theta
        delta = t.hoop2 * (t.radial2 + a * a) + t.radial2 * b * b * t.inv_rho2  # det of the metric
        g = (t.b_rho @ (2 * a * (1 - t.hoop2 / delta**2) * t.weight)
             + t.b_theta @ (2 * b * t.inv_rho2 * (1 - t.radial2 / delta**2) * t.weight))
        return np.concatenate([v, -c_damp * v - t.k_force * g + P0 * np.cos(OMEGA * time_) * t.load])

    return f


def c_inputs(rom, work: Path) -> list[str]:
    """Write the tableau and tables for ``benchmarks/c/dop853.c``; its TABLES ... Q_MAX arguments."""
    t = rom.tables
    assert t.axisymmetric, "the C force is the axisymmetric one"
    coef = dopri._COEF
    np.concatenate([coef.A.ravel(), coef.B, coef.C, coef.E3, coef.E5]).tofile(work / "coef.bin")
    pieces = t.stiffness_table.shape[0] if t.table_max > 0 else 0
    np.concatenate([t.weight, t.inv_rho2, t.hoop2, t.radial2, t.b_rho.ravel(), t.k_force, t.load,
                    t.stiffness_table.ravel() if pieces else []]).tofile(work / "tables.bin")
    return [str(work / "coef.bin"), str(work / "tables.bin"), str(rom.dof), str(t.weight.size), str(pieces),
            _number(t.table_max)]


def _number(x) -> str:
    """``x`` as a C program's argument: all 17 digits, no numpy repr."""
    return f"{float(x):.17g}"


def run(modes, n_traj, periods, repeats, rtol, atol, exe, work):
    rom = build_rom(solve_prestretch(Membrane(1.1, 0.2)), modes)
    K = rom.dof
    rng = np.random.default_rng(0)
    y0 = np.zeros((n_traj, 2 * K))
    y0[:, 0] = rng.uniform(0.05, 0.6, n_traj)
    y0[:, 1:K] = rng.uniform(-0.01, 0.01, (n_traj, K - 1))
    t_end = periods * 2 * np.pi / OMEGA
    dopri.solve(rom, y0[:1], [1e-3], c=C, P0=P0, Omega=OMEGA)        # compile
    f = numpy_rhs(rom)
    c_args = c_inputs(rom, work) if exe is not None else []
    y0.tofile(work / "states.bin")
    times = {"project": [], "C": [], "solve_ivp": []}
    c_evals = 0
    for _ in range(repeats):
        t0 = time.perf_counter()
        Y, nfev = dopri.solve(rom, y0, [t_end], c=C, P0=P0, Omega=OMEGA, rtol=rtol, atol=atol)
        times["project"].append(time.perf_counter() - t0)
        if exe is not None:
            numbers = (t_end, rtol, atol, rom.membrane.damping_rate(C), P0, OMEGA)
            out = subprocess.run([str(exe), *c_args, str(work / "states.bin"), *map(_number, numbers),
                                  str(work / "out.bin")],
                                 capture_output=True, text=True, check=True)
            ns, c_evals = out.stdout.split()
            c_evals = int(c_evals)
            times["C"].append(float(ns) * 1e-9 * c_evals)
        t0 = time.perf_counter()
        sols = [solve_ivp(f, (0, t_end), y, method="DOP853", rtol=rtol, atol=atol) for y in y0]
        times["solve_ivp"].append(time.perf_counter() - t0)
    med = {k: statistics.median(v) for k, v in times.items() if v}
    evals = {"project": int(nfev.sum()), "C": c_evals, "solve_ivp": sum(s.nfev for s in sols)}
    diff = {"solve_ivp": max(np.abs(s.y[:, -1] - Y[i, -1]).max() for i, s in enumerate(sols))}
    if exe is not None:
        diff["C"] = np.abs(np.fromfile(work / "out.bin").reshape(n_traj, 2 * K) - Y[:, -1]).max()
    print(f"{K} mode(s), {rom.tables.weight.size} quadrature points, {n_traj} trajectories x {periods} periods, "
          f"rtol={rtol:g}; medians of {repeats} interleaved rounds")
    for name, seconds in med.items():
        compared = f"max |difference| from project {diff[name]:.1e}" if name in diff else "the reference"
        print(f"  {name:9s} {seconds * 1e3:8.1f} ms  {evals[name]:7d} evals  "
              f"{evals[name] / seconds / 1e6:6.2f} M evals/s  ({compared})")
    print(f"  speed-up over solve_ivp {med['solve_ivp'] / med['project']:.0f}x (target >= 100x)"
          + (f"; ratio project / C {med['project'] / med['C']:.2f}" if "C" in med else ""))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--trajectories", type=int, default=4)
    ap.add_argument("--periods", type=int, default=20)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    trajectories, periods, repeats = (1, 1, 1) if args.smoke else (args.trajectories, args.periods, args.repeats)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        exe = compile_reference("dop853", work, ("-ffast-math",))
        for modes in ([(1, 0)], [(1, 0), (2, 0), (3, 0)]):
            for rtol in (1e-8, 1e-11):
                run(modes, trajectories, periods, repeats, rtol, 1e-12 * rtol / 1e-8, exe, work)


if __name__ == "__main__":
    main()
