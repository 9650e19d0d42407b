"""Time integration of the ROM: the project's DOP853 kernel versus scipy's solve_ivp.

Same model (the exact neo-Hookean ROM of Eq. 31, delta = 1.1, delta_o = 0.2, forced and
damped: P0 = 1 Pa, Omega = 33.5 rad/s, c = 0.05 N s/m^3), same trajectories (N initial
states), same method (DOP853) and tolerances; scipy gets the right-hand side written
plainly in numpy.  Prints medians of repeats, the speed-up, the largest difference of the
final states, and force evaluations per second per core.  Run:

    python benchmarks/bench_integrators.py [--repeats 3] [--trajectories 4] [--periods 20] [--smoke]

``--smoke`` (the test suite): one trajectory, one period, one repeat.
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

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
        D = t.dr2 * t.r2 + t.dr2 * b * b + t.r2 * a * a
        s = t.rho2 / D**2
        g = t.b_rho @ (2 * a * (1 - s * t.r2) * t.weight) + t.b_theta @ (2 * b * (1 / t.rho2 - s * t.dr2) * t.weight)
        return np.concatenate([v, -c_damp * v - t.k_force * g + P0 * np.cos(OMEGA * time_) * t.load])

    return f


def run(modes, n_traj, periods, repeats, rtol, atol):
    rom = build_rom(solve_prestretch(Membrane(1.1, 0.2)), modes)
    K = rom.dof
    rng = np.random.default_rng(0)
    y0 = np.zeros((n_traj, 2 * K))
    y0[:, 0] = rng.uniform(0.05, 0.6, n_traj)
    y0[:, 1:K] = rng.uniform(-0.01, 0.01, (n_traj, K - 1))
    t_end = periods * 2 * np.pi / OMEGA
    dopri.solve(rom, y0[:1], [1e-3], c=C, P0=P0, Omega=OMEGA)        # compile
    f = numpy_rhs(rom)
    ours, theirs = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        Y, nfev = dopri.solve(rom, y0, [t_end], c=C, P0=P0, Omega=OMEGA, rtol=rtol, atol=atol)
        ours.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        sols = [solve_ivp(f, (0, t_end), y, method="DOP853", rtol=rtol, atol=atol) for y in y0]
        theirs.append(time.perf_counter() - t0)
    diff = max(np.abs(s.y[:, -1] - Y[i, -1]).max() for i, s in enumerate(sols))
    t_ours, t_theirs = np.median(ours), np.median(theirs)
    evals = int(nfev.sum())
    print(f"{K} mode(s), {rom.tables.weight.size} quadrature points, {n_traj} trajectories x {periods} periods, "
          f"rtol={rtol:g}: project {t_ours * 1e3:.1f} ms ({evals} evals, {evals / t_ours / 1e6:.2f} M evals/s/core), "
          f"solve_ivp {t_theirs * 1e3:.0f} ms ({sum(s.nfev for s in sols)} evals, "
          f"{sum(s.nfev for s in sols) / t_theirs / 1e3:.1f} k evals/s), speed-up {t_theirs / t_ours:.0f}x, "
          f"max |difference| {diff:.1e}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--trajectories", type=int, default=4)
    ap.add_argument("--periods", type=int, default=20)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    trajectories, periods, repeats = (1, 1, 1) if args.smoke else (args.trajectories, args.periods, args.repeats)
    for modes in ([(1, 0)], [(1, 0), (2, 0), (3, 0)]):
        for rtol in (1e-8, 1e-11):
            run(modes, trajectories, periods, repeats, rtol, 1e-12 * rtol / 1e-8)


if __name__ == "__main__":
    main()
