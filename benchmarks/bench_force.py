"""The quadrature force and force + Jacobian of a three-mode ROM: the project's kernels
against a C program of the same algorithm (the hardware reference) and numpy (what a user
would write).

Case: modes (1, 0), (2, 0), (3, 0) at delta = 1.1, delta_o = 0.2 (numeric pre-stretch),
160 radial quadrature points; ``--states`` random modal coordinates (|q_1| < 0.3 m,
|q_2|, |q_3| < 0.03 m) evaluated ``--repeats`` times per round.  Variants, interleaved in
each of ``--rounds`` rounds (medians printed, compilation excluded):

* numba: ``model.rom.axisymmetric_force`` and ``axisymmetric_force_jacobian`` (what the
  RK4 stages and the variational equations call), driven by a compiled loop;
* C: ``benchmarks/c/force_jacobian.c``, compiled here with ``cc -O3 -march=native
  -ffast-math`` (the numba kernels use fastmath too: sums may be reassociated and
  vectorised; skipped with a message without a compiler); the program times its own loop;
* numpy: the same formulas on whole arrays, one state at a time.

Every variant's forces and Jacobians are compared with numba's (relative difference
printed).  Run: ``python benchmarks/bench_force.py [--rounds 7] [--smoke]``.
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from model.params import Membrane  # noqa: E402
from model.prestretch import solve_prestretch  # noqa: E402
from model.rom import axisymmetric_force, axisymmetric_force_jacobian, build_rom  # noqa: E402


@nb.njit(cache=True)
def _numba_force(Q, repeats, weight, rho2, r2, dr2, b_rho, G):
    a = np.empty(weight.size)
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            axisymmetric_force(Q[m], weight, rho2, r2, dr2, b_rho, G[m], a)


@nb.njit(cache=True)
def _numba_force_jacobian(Q, repeats, weight, rho2, r2, dr2, b_rho, G, J):
    work = np.empty((7, weight.size))
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            axisymmetric_force_jacobian(Q[m], weight, rho2, r2, dr2, b_rho, G[m], J[m], work)


def _numpy_force_jacobian(q, t):
    a = q @ t.b_rho
    D = t.r2 * (t.dr2 + a * a)
    s = t.rho2 / D**2
    g = t.b_rho @ (2 * a * (1 - s * t.r2) * t.weight)
    jac = (t.b_rho * ((2 - 2 * s * t.r2 + 8 * s / D * t.r2**2 * a**2) * t.weight)) @ t.b_rho.T
    return g, jac


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--states", type=int, default=256)
    ap.add_argument("--repeats", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    states, repeats, rounds = (16, 2, 1) if args.smoke else (args.states, args.repeats, args.rounds)
    rom = build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0), (2, 0), (3, 0)])
    t = rom.tables
    K, P = rom.dof, t.weight.size
    rng = np.random.default_rng(0)
    Q = np.column_stack([rng.uniform(-0.3, 0.3, states), rng.uniform(-0.03, 0.03, (states, K - 1))])
    arrays = (t.weight, t.rho2, t.r2, t.dr2, t.b_rho)
    G, G2, J = np.empty((states, K)), np.empty((states, K)), np.empty((states, K, K))
    _numba_force(Q[:1], 1, *arrays, G)
    _numba_force_jacobian(Q[:1], 1, *arrays, G2, J)
    work = Path(tempfile.mkdtemp())
    # the numba kernels are compiled with fastmath (reassociated, vectorised sums): the C
    # program gets the same freedom
    exe = compile_reference("force_jacobian", work, ("-ffast-math",))
    np.concatenate([t.weight, t.rho2, t.r2, t.dr2, t.b_rho.ravel()]).tofile(work / "tables.bin")
    Q.tofile(work / "q.bin")
    times = {"numba force": [], "numba force + Jacobian": [], "numpy force + Jacobian": [],
             "C force": [], "C force + Jacobian": []}
    calls = states * repeats
    for _ in range(rounds):
        t0 = time.perf_counter()
        _numba_force(Q, repeats, *arrays, G)
        times["numba force"].append((time.perf_counter() - t0) / calls * 1e9)
        t0 = time.perf_counter()
        _numba_force_jacobian(Q, repeats, *arrays, G2, J)
        times["numba force + Jacobian"].append((time.perf_counter() - t0) / calls * 1e9)
        t0 = time.perf_counter()
        numpy_out = [_numpy_force_jacobian(q, t) for q in Q]
        times["numpy force + Jacobian"].append((time.perf_counter() - t0) / states * 1e9)
        if exe is not None:
            out = subprocess.run([str(exe), str(work / "tables.bin"), str(K), str(P), str(work / "q.bin"),
                                  str(repeats), str(work / "out.bin")], capture_output=True, text=True, check=True)
            force_ns, fused_ns, _ = out.stdout.split()
            times["C force"].append(float(force_ns))
            times["C force + Jacobian"].append(float(fused_ns))
    err = {"numba force": _rel(G, G2), "numba force + Jacobian": 0.0,
           "numpy force + Jacobian": max(_rel(np.array([g for g, _ in numpy_out]), G2),
                                         _rel(np.array([j for _, j in numpy_out]), J))}
    if exe is not None:
        c = np.fromfile(work / "out.bin")
        err["C force"] = err["C force + Jacobian"] = max(_rel(c[:states * K].reshape(states, K), G2),
                                                         _rel(c[states * K:].reshape(states, K, K), J))
    med = {k: statistics.median(v) for k, v in times.items() if v}
    print(f"three-mode force, {P} quadrature points, {states} states x {repeats} repeats; medians of {rounds} "
          "interleaved rounds")
    for name, ns in med.items():
        print(f"  {name:24s} {ns:9.1f} ns per call   (vs numba force + Jacobian: {err[name]:.1e} relative)")
    if exe is not None:
        print(f"  ratio numba / C, force: {med['numba force'] / med['C force']:.2f}; force + Jacobian: "
              f"{med['numba force + Jacobian'] / med['C force + Jacobian']:.2f} (target <= 1.5)")
    print(f"  ratio numpy / numba, force + Jacobian: {med['numpy force + Jacobian'] / med['numba force + Jacobian']:.1f}")


if __name__ == "__main__":
    main()
