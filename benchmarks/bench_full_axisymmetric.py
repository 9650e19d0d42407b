"""The full model's axisymmetric force, Hessian and RK4 free motion
(model/full/axisymmetric_kernels.py): the numba kernels against a C program of the same
algorithms (the hardware reference), numpy (what a user would write for the force and the
Hessian) and scipy's ``solve_ivp`` (for the motion).

delta = 1.1, delta_o = 0.2, ``--order`` radial functions per field (default 24; 2 x order
coordinates), the full model's quadrature (2 order + 24 points).  The force is evaluated on
``--states`` random states (transverse coefficients up to 0.05, radial ones up to 0.005)
``--repeats`` times per round, the Hessian (the Newton matrices and variational equations of
every continuation on the full model) on the same states; the free motion runs ``--steps`` RK4 steps of
``1 / omega_max`` (the step the tests use; ``omega_max`` the highest frequency of the
discretisation) from rest on the first transverse mode, 5 cm at ``rho = 0.5 Re``, with its
quasi-static radial displacement, and ``solve_ivp`` (RK45, numpy force, rtol 1e-8) covers the
same time.  The numba force is driven by a compiled loop; the C program,
``benchmarks/c/full_axisymmetric.c``, is compiled here with ``cc -O3 -march=native
-ffast-math`` (the numba kernels use fastmath too; skipped with a message without a compiler)
and times its own loops.  Variants are interleaved in each of ``--rounds`` rounds (medians
printed, compilation excluded); forces and Hessians are compared with the numba kernels', final
states with the numba RK4 (relative difference printed).
Run: ``python benchmarks/bench_full_axisymmetric.py [--rounds 7] [--smoke]``.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba as nb
import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from benchmarks.full_states import first_mode_coordinates  # noqa: E402
from benchmarks.kernel_report import print_kernel, print_rk4  # noqa: E402
from model.full.axisymmetric import AxisymmetricFull  # noqa: E402
from model.full.axisymmetric_kernels import axisymmetric_gradient, axisymmetric_hessian  # noqa: E402
from model.full.static import solve_full_prestretch  # noqa: E402
from model.params import Membrane  # noqa: E402


@nb.njit(cache=True)
def _forces(Q, repeats, law, phi, dphi, s, sw, w, r0, dr0, G):
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            axisymmetric_gradient(law, phi, dphi, s, sw, w, r0, dr0, Q[m], G[m])


@nb.njit(cache=True)
def _hessians(Q, repeats, law, phi, dphi, s, sw, w, r0, dr0, H):
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            axisymmetric_hessian(law, phi, dphi, s, sw, w, r0, dr0, Q[m], H[m])


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--order", type=int, default=24)
    ap.add_argument("--states", type=int, default=64)
    ap.add_argument("--repeats", type=int, default=200)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    order, states, repeats, steps, rounds = ((12, 8, 2, 50, 1) if args.smoke else
                                             (args.order, args.states, args.repeats, args.steps, args.rounds))
    model = AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), order))
    law, phi, dphi, s, sw, w, r0, dr0 = model.kernel_tables
    P, N = phi.shape
    rng = np.random.default_rng(0)
    Q = np.column_stack([rng.uniform(-0.005, 0.005, (states, N)), rng.uniform(-0.05, 0.05, (states, N))])
    dt = 1.0 / model.highest_frequency()
    y0 = np.concatenate([first_mode_coordinates(model, -0.05), np.zeros(model.dof)])
    Q[0] = y0[:model.dof]  # the C program starts its motion from the first state at rest
    G = np.empty_like(Q)
    H = np.empty((states, model.dof, model.dof))
    _forces(Q[:1], 1, *model.kernel_tables, G)  # compile
    _hessians(Q[:1], 1, *model.kernel_tables, H)
    model.free_motion(y0, dt, 1)
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("full_axisymmetric", work, ("-ffast-math",))
    np.concatenate([phi.ravel(), dphi.ravel(), s, sw, w, r0, dr0, model.inverse_masses.ravel(),
                    [model.omega0_2, 0.0]]).tofile(work / "tables.bin")
    Q.tofile(work / "q.bin")
    names = ["numba force", "numpy force", "C force", "numba Hessian", "numpy Hessian", "C Hessian", "numba RK4",
             "C RK4"]
    times = {name: [] for name in names}
    scipy_times = []

    def rhs(t, y):
        return np.concatenate([y[model.dof:], model.acceleration(y[:model.dof], y[model.dof:])])

    def timed(name, calls, run):  # ns per call of run(), which makes `calls` calls
        t0 = time.perf_counter()
        result = run()
        times[name].append((time.perf_counter() - t0) / calls * 1e9)
        return result

    for _ in range(rounds):
        timed("numba force", states * repeats, lambda: _forces(Q, repeats, *model.kernel_tables, G))
        numpy_g = timed("numpy force", states, lambda: np.array([model.gradient(q) for q in Q]))
        timed("numba Hessian", states * repeats, lambda: _hessians(Q, repeats, *model.kernel_tables, H))
        numpy_h = timed("numpy Hessian", states, lambda: np.array([model.hessian(q) for q in Q]))
        t0 = time.perf_counter()
        end = model.free_motion(y0, steps * dt, steps, every=steps)[-1]
        times["numba RK4"].append((time.perf_counter() - t0) / steps * 1e9)
        t0 = time.perf_counter()
        ivp = solve_ivp(rhs, (0.0, steps * dt), y0, method="RK45", rtol=1e-8, atol=1e-12)
        scipy_times.append(time.perf_counter() - t0)
        if exe is not None:
            out = subprocess.run([str(exe), str(work / "tables.bin"), str(N), str(P), str(work / "q.bin"),
                                  str(repeats), str(steps), repr(dt), str(work / "out.bin")],
                                 capture_output=True, text=True, check=True)
            force_ns, step_ns, hessian_ns = out.stdout.split()
            times["C force"].append(float(force_ns))
            times["C RK4"].append(float(step_ns))
            times["C Hessian"].append(float(hessian_ns))
    err = {"numba force": 0.0, "numpy force": _rel(numpy_g, G), "numba Hessian": 0.0,
           "numpy Hessian": _rel(H, numpy_h), "numba RK4": 0.0}
    if exe is not None:
        c = np.fromfile(work / "out.bin")
        n = states * model.dof
        err["C force"] = _rel(c[:n].reshape(states, model.dof), G)
        err["C RK4"] = _rel(c[n:n + 2 * model.dof], end)
        err["C Hessian"] = _rel(c[n + 2 * model.dof:].reshape(H.shape), H)
    med = {k: statistics.median(v) for k, v in times.items() if v}
    print(f"full-model axisymmetric force, order {N} ({2 * N} coordinates), {P} quadrature points, {states} states "
          f"x {repeats} repeats; medians of {rounds} interleaved rounds")
    for kernel in ("force", "Hessian"):
        if kernel == "Hessian":
            print(f"full-model axisymmetric Hessian ({2 * N} x {2 * N}), the same states")
        print_kernel(med, err, kernel)
    print(f"full-model axisymmetric RK4, {steps} steps of 1/omega_max = {dt:.3e} s")
    print_rk4(med, err, steps, dt, statistics.median(scipy_times), ivp.nfev, _rel(ivp.y[:, -1], end))


if __name__ == "__main__":
    main()
