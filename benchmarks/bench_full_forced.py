"""The full model's forced monodromy (model/full/forced.py): the compiled RK4 variational flow
over one forcing period against what a user would write, ``solve_ivp`` of the variational
equations with the numpy force and Hessian.

delta = 1.1, delta_o = 0.2, ``--order`` radial functions per field (default 12; 2 x order
coordinates, a state of 4 x order), P0 = 1 Pa at Omega = 33.5 rad/s (Fig. 15a), c = 0.05
N s/m^3, from a state 2 cm along the first transverse mode with its quasi-static in-plane
displacement.  The compiled map takes the job's default steps per period (at least 128, RK4's
stable step: ``steps_per_period``) and returns ``P(y)`` and ``dP/dy``; ``solve_ivp`` (RK45, rtol
``--rtol``, atol 1e-12 on the coordinates scaled by ``Re``) integrates the state and the
``(4 order)^2`` entries of ``dP/dy`` together with ``AxisymmetricFull.acceleration`` and
``AxisymmetricFull.hessian``.  The two agree to the compiled map's RK4 error, not to rounding
(the compiled map is the exact derivative of its discrete RK4 map): the difference is printed
at the default steps and at four times as many, where RK4's error is 256 times smaller.  The
force, the Hessian and the free RK4 step have C programs of the same algorithms
(``benchmarks/c/full_axisymmetric.c``, run by ``benchmarks/bench_full_axisymmetric.py``); the
variational flow itself has none.  The plain
compiled period (``ForcedFull.advance``) is printed beside it, so that the variational flow's
cost is seen in units of the force's.
Variants are interleaved in each of ``--rounds`` rounds (medians printed, compilation
excluded).  Run: ``python benchmarks/bench_full_forced.py [--rounds 5] [--smoke]``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import block_diag

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.full_states import first_mode_coordinates  # noqa: E402
from model.damping import Viscous  # noqa: E402
from model.full.axisymmetric import AxisymmetricFull  # noqa: E402
from model.full.forced import ForcedFull, steps_per_period  # noqa: E402
from model.full.static import solve_full_prestretch  # noqa: E402
from model.params import Membrane  # noqa: E402


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--order", type=int, default=12)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    order, rounds, rtol = (6, 1, 1e-6) if args.smoke else (args.order, args.rounds, args.rtol)
    c, P0, Omega = 0.05, 1.0, 33.5
    model = AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), order))
    fmap = ForcedFull.build(model, P0, Omega, Viscous(c), steps=steps_per_period(model, 128))
    fine = ForcedFull.build(model, P0, Omega, Viscous(c), steps=4 * fmap.steps)
    re, n = model.membrane.Re, model.dof
    y0 = np.concatenate([first_mode_coordinates(model, 0.02), np.zeros(n)]) * re
    inverse_mass = block_diag(*model.inverse_masses)
    load = np.concatenate([np.zeros(order), P0 * model.load])  # on the W accelerations

    def rhs(t, z):
        # z = (q, q', dP/dy row-major) in the model's scaled coordinates
        q, v, phi = z[:n], z[n:2 * n], z[2 * n:].reshape(2 * n, 2 * n)
        a = model.acceleration(q, v, c) + np.cos(Omega * t) * load
        jac = np.block([[np.zeros((n, n)), np.eye(n)],
                        [-model.omega0_2 * inverse_mass @ model.hessian(q),
                         -(c / (model.membrane.Gamma * model.membrane.h)) * np.eye(n)]])
        return np.concatenate([v, a, (jac @ phi).ravel()])

    fmap.monodromy(y0)  # compile
    fmap.advance(y0)
    z0 = np.concatenate([y0 / re, np.eye(2 * n).ravel()])
    times = {"compiled monodromy": [], "compiled period": [], "solve_ivp monodromy": []}
    for _ in range(rounds):
        t0 = time.perf_counter()
        yT, phi = fmap.monodromy(y0)
        times["compiled monodromy"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        fmap.advance(y0)
        times["compiled period"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        ivp = solve_ivp(rhs, (0.0, fmap.period), z0, method="RK45", rtol=rtol, atol=1e-12)
        times["solve_ivp monodromy"].append(time.perf_counter() - t0)
    med = {k: statistics.median(v) for k, v in times.items()}
    end = ivp.y[:, -1]
    print(f"full-model forced monodromy, order {order} ({n} coordinates, dP/dy {2 * n} x {2 * n}), "
          f"P0 = {P0} Pa, Omega = {Omega} rad/s, {fmap.steps} RK4 steps per period; medians of {rounds} "
          "interleaved rounds")
    print(f"  compiled monodromy  {med['compiled monodromy'] * 1e3:9.2f} ms")
    print(f"  compiled period     {med['compiled period'] * 1e3:9.2f} ms   (the map alone; "
          f"monodromy / period: {med['compiled monodromy'] / med['compiled period']:.1f})")
    print(f"  solve_ivp monodromy {med['solve_ivp monodromy'] * 1e3:9.2f} ms   (RK45, rtol {rtol:g}, "
          f"{ivp.nfev} evaluations of the numpy force and Hessian)")
    print(f"  ratio solve_ivp / compiled, monodromy: {med['solve_ivp monodromy'] / med['compiled monodromy']:.0f}")
    phi_ivp = end[2 * n:].reshape(2 * n, 2 * n)
    yT4, phi4 = fine.monodromy(y0)
    print(f"  the two differ by {_rel(end[:2 * n] * re, yT):.1e} (state) and {_rel(phi_ivp, phi):.1e} (dP/dy) "
          f"relative; at {fine.steps} steps by {_rel(end[:2 * n] * re, yT4):.1e} and {_rel(phi_ivp, phi4):.1e}")


if __name__ == "__main__":
    main()
