"""The full model's force, Hessian and RK4 free motion on circumferential harmonics
(model/full/harmonic_kernels.py): the numba kernels against a C program of the same algorithms
(the hardware reference), numpy (what a user would write for the force and the Hessian) and
scipy's ``solve_ivp`` (for the motion).

delta = 1.1, delta_o = 0.2, ``--order`` radial functions per field (default 8, the order of the
validation jobs on harmonics), the harmonics 0, 1, 2 (8 blocks: the check of the family n = 1
and its standing waves), 12 angular points (the default ``4 max k + 4``), the full model's
radial quadrature (2 order + 24 points).  The force is evaluated on ``--states`` random states
(transverse coefficients up to 0.05, in-plane ones up to 0.005, the harmonic 2 a tenth of
those) ``--repeats`` times per round, the Hessian (the variational equations of every shooting
and continuation on the harmonics) on the same states; the free motion runs ``--steps`` RK4
steps of ``1 / omega_max`` (``omega_max`` the highest frequency of the families n = 1, 2 and of
the axisymmetric model) from rest on the first transverse mode, 5 cm at ``rho = 0.5 Re``, with its
quasi-static radial displacement, plus 1 cm of the family n = 1's lowest mode, and ``solve_ivp``
(RK45, numpy force, rtol 1e-8) covers the same time.  The numba force and Hessian are driven by compiled loops;
the C program, ``benchmarks/c/full_harmonic.c``, is compiled here with ``cc -O3 -march=native
-ffast-math`` (the numba kernels use fastmath too; skipped with a message without a compiler)
and times its own loops.  Variants are interleaved in each of ``--rounds`` rounds (medians
printed, compilation excluded); forces and Hessians are compared with the numba kernels', final
states with the numba RK4 (relative difference printed).
Run: ``python benchmarks/bench_full_harmonic.py [--rounds 7] [--smoke]``.
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
from scipy.linalg import eigh

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from benchmarks.full_states import first_mode_coordinates  # noqa: E402
from benchmarks.kernel_report import print_kernel, print_rk4  # noqa: E402
from model.full.axisymmetric import AxisymmetricFull  # noqa: E402
from model.full.families import FullFamily  # noqa: E402
from model.full.harmonic import HarmonicFull  # noqa: E402
from model.full.harmonic_kernels import harmonic_gradient, harmonic_hessian  # noqa: E402
from model.full.static import solve_full_prestretch  # noqa: E402
from model.params import Membrane  # noqa: E402


@nb.njit(cache=True)
def _forces(Q, repeats, law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, G):
    B = fields.size
    work = np.empty((4, B))
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            harmonic_gradient(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, Q[m], G[m],
                              work[0], work[1], work[2], work[3])


@nb.njit(cache=True)
def _hessians(Q, repeats, law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, var_index,
              var_value, H):
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            harmonic_hessian(law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight, var_index,
                             var_value, Q[m], H[m])


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def _states(h: HarmonicFull, count: int, rng) -> np.ndarray:
    size = {"U": 0.005, "V": 0.005, "W": 0.05}
    scale = np.concatenate([np.full(h.order, size[f] * (0.1 if k == 2 else 1.0)) for k, f, _ in h.blocks])
    return rng.uniform(-1.0, 1.0, (count, h.dof)) * scale


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--order", type=int, default=8)
    ap.add_argument("--states", type=int, default=16)
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    order, states, repeats, steps, rounds = ((6, 4, 1, 20, 1) if args.smoke else
                                             (args.order, args.states, args.repeats, args.steps, args.rounds))
    model = AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), order))
    h = HarmonicFull(model, (0, 1, 2))
    tables = h._tables()
    law, phi, dphi, s, sw, w, r0, dr0, fields, wave, even_t, odd_t, theta_weight = tables
    P, N = phi.shape
    Q = _states(h, states, np.random.default_rng(0))
    families = [FullFamily.build(model, n) for n in (1, 2)]
    dt = 1.0 / max(model.highest_frequency(), *(f.omega_max for f in families))
    # the motion from rest on the first transverse mode, 5 cm at 0.5 Re, with its quasi-static
    # radial displacement, and 1 cm of the family n = 1's lowest mode (smooth states: a random
    # one puts its energy in the fastest modes, where RK4 at omega_max dt = 1 and RK45 part)
    Q[0] = 0.0
    axisymmetric = first_mode_coordinates(model, -0.05)
    Q[0][h.block(0, "U")], Q[0][h.block(0, "W")] = axisymmetric[:N], axisymmetric[N:]
    mass, stiffness = families[0].linear_system()
    lowest = eigh(stiffness, mass)[1][:, 0]
    Q[0][h.block(1, "U").start:h.block(1, "W").stop] = 0.01 / model.membrane.Re * lowest / np.abs(lowest).max()
    y0 = np.concatenate([Q[0], np.zeros(h.dof)])  # the C program starts its motion from the first state at rest
    G = np.empty_like(Q)
    H = np.empty((states, h.dof, h.dof))
    _forces(Q[:1], 1, *tables, G)  # compile
    _hessians(Q[:1], 1, *tables, h._var_index, h._var_value, H)
    h.motion(y0, dt, 1)
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("full_harmonic", work, ("-ffast-math",))
    np.concatenate([phi.ravel(), dphi.ravel(), s, sw, w, r0, dr0, model.inverse_mass.ravel(), h.inverse_scale,
                    fields.astype(float), wave, even_t.ravel(), odd_t.ravel(), theta_weight,
                    h._var_index.ravel().astype(float), h._var_value.ravel(),
                    [model.omega0_2, 0.0]]).tofile(work / "tables.bin")
    Q.tofile(work / "q.bin")
    names = ["numba force", "numpy force", "C force", "numba Hessian", "numpy Hessian", "C Hessian", "numba RK4",
             "C RK4"]
    times = {name: [] for name in names}
    scipy_times = []

    def rhs(t, y):
        g = h.gradient(y[:h.dof])
        acc = np.concatenate([h.inverse_scale[b] * (model.inverse_mass @ g[b * N:(b + 1) * N])
                              for b in range(len(h.blocks))])
        return np.concatenate([y[h.dof:], h.bias - model.omega0_2 * acc])

    def timed(name, calls, run):  # ns per call of run(), which makes `calls` calls
        t0 = time.perf_counter()
        result = run()
        times[name].append((time.perf_counter() - t0) / calls * 1e9)
        return result

    for _ in range(rounds):
        timed("numba force", states * repeats, lambda: _forces(Q, repeats, *tables, G))
        numpy_g = timed("numpy force", states, lambda: np.array([h.gradient(q) for q in Q]))
        timed("numba Hessian", states * repeats, lambda: _hessians(Q, repeats, *tables, h._var_index, h._var_value, H))
        numpy_h = timed("numpy Hessian", states, lambda: np.array([h.hessian(q) for q in Q]))
        t0 = time.perf_counter()
        end = h.motion(y0, dt, steps, every=steps)[-1]
        times["numba RK4"].append((time.perf_counter() - t0) / steps * 1e9)
        t0 = time.perf_counter()
        ivp = solve_ivp(rhs, (0.0, steps * dt), y0, method="RK45", rtol=1e-8, atol=1e-12)
        scipy_times.append(time.perf_counter() - t0)
        if exe is not None:
            out = subprocess.run([str(exe), str(work / "tables.bin"), str(N), str(P), str(theta_weight.size),
                                  str(len(h.blocks)), str(work / "q.bin"), str(repeats), str(steps), repr(dt),
                                  str(work / "out.bin")], capture_output=True, text=True, check=True)
            force_ns, step_ns, hessian_ns = out.stdout.split()
            times["C force"].append(float(force_ns))
            times["C RK4"].append(float(step_ns))
            times["C Hessian"].append(float(hessian_ns))
    err = {"numba force": 0.0, "numpy force": _rel(numpy_g, G), "numba Hessian": 0.0,
           "numpy Hessian": _rel(numpy_h, H), "numba RK4": 0.0}
    if exe is not None:
        c = np.fromfile(work / "out.bin")
        n = states * h.dof
        err["C force"] = _rel(c[:n].reshape(states, h.dof), G)
        err["C RK4"] = _rel(c[n:n + 2 * h.dof], end)
        err["C Hessian"] = _rel(c[n + 2 * h.dof:].reshape(H.shape), H)
    med = {k: statistics.median(v) for k, v in times.items() if v}
    print(f"full-model force on the harmonics 0, 1, 2, order {N} ({h.dof} coordinates), {P} x {theta_weight.size} "
          f"quadrature points, {states} states x {repeats} repeats; medians of {rounds} interleaved rounds")
    for kernel in ("force", "Hessian"):
        if kernel == "Hessian":
            print(f"full-model Hessian on the harmonics ({h.dof} x {h.dof}), the same states")
        print_kernel(med, err, kernel)
    print(f"full-model RK4 on the harmonics, {steps} steps of 1/omega_max = {dt:.3e} s")
    print_rk4(med, err, steps, dt, statistics.median(scipy_times), ivp.nfev, _rel(ivp.y[:, -1], end))


if __name__ == "__main__":
    main()
