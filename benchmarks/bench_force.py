"""The quadrature force and force + Jacobian of a ROM: the project's kernels against a C
program of the same algorithm (the hardware reference) and numpy (what a user would write).

Two cases at delta = 1.1, delta_o = 0.2 (numeric pre-stretch), ``--states`` random modal
coordinates (|q_1| < 0.3 m, the others < 0.03 m) evaluated ``--repeats`` times per round:

* three axisymmetric modes (1, 0), (2, 0), (3, 0), 160 radial quadrature points: the numba
  kernels ``model.rom.axisymmetric_force`` and ``axisymmetric_force_jacobian`` (what the RK4
  stages and the variational equations call);
* the mixed set (1, 0), (1, 1), (1, 2) on its default 2-D rule, 80 radial points x 96
  angular points folded onto [0, pi] (49; no sine companions, so the integrands are even
  in theta, docs/model.md): ``model.rom.general_force`` and ``general_force_jacobian``;
  the numba force on the unfolded rule
  (96 angular points on [0, 2 pi)) gives the gain of the fold.

The numba kernels are driven by a compiled loop; the C program of the same algorithms,
``benchmarks/c/force_jacobian.c``, is compiled here with
``cc -O3 -march=native -ffast-math`` (the numba kernels use fastmath too: sums may be
reassociated and vectorised; skipped with a message without a compiler) and times its
own loops; numpy evaluates the same formulas on whole arrays, one state at a time.
Variants are interleaved in each of ``--rounds`` rounds (medians printed, compilation
excluded); every variant's forces and Jacobians are compared with the numba force +
Jacobian (relative difference printed).
Run: ``python benchmarks/bench_force.py [--rounds 7] [--smoke]``.
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
from model.rom import (axisymmetric_force, axisymmetric_force_jacobian, build_rom, general_force,  # noqa: E402
                       general_force_jacobian)



@nb.njit(cache=True)
def _axisymmetric_force(Q, repeats, law, weight, inv_rho2, hoop2, radial2, b_rho, G):
    a = np.empty(weight.size)
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            axisymmetric_force(Q[m], law, weight, inv_rho2, hoop2, radial2, b_rho, G[m], a)


@nb.njit(cache=True)
def _axisymmetric_force_jacobian(Q, repeats, law, weight, inv_rho2, hoop2, radial2, b_rho, G, J):
    work = np.empty((7, weight.size))
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            axisymmetric_force_jacobian(Q[m], law, weight, inv_rho2, hoop2, radial2, b_rho, G[m], J[m], work)


@nb.njit(cache=True)
def _general_force(Q, repeats, law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, G):
    a = np.empty(weight.size)
    b = np.empty(weight.size)
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            general_force(Q[m], law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, G[m], a, b)


@nb.njit(cache=True)
def _general_force_jacobian(Q, repeats, law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, G, J):
    work = np.empty((7, weight.size))
    for _ in range(repeats):
        for m in range(Q.shape[0]):
            general_force_jacobian(Q[m], law, weight, inv_rho2, hoop2, radial2, b_rho, b_theta, G[m], J[m], work)


def _numpy_force_jacobian(q, t, axisymmetric):
    """Force and Jacobian, the formulas of ``benchmarks/c/force_jacobian.c`` on whole
    arrays, without the ``w_theta`` terms for an axisymmetric set (as a user would write it:
    the neo-Hookean law in the determinant ``delta`` of the in-plane metric)."""
    a = q @ t.b_rho
    if axisymmetric:
        e = 1 / (t.hoop2 * (t.radial2 + a * a))
        g = t.b_rho @ (2 * a * (1 - e**2 * t.hoop2) * t.weight)
        jac = (t.b_rho * ((2 - 2 * e**2 * t.hoop2 + 8 * e**3 * t.hoop2**2 * a**2) * t.weight)) @ t.b_rho.T
        return g, jac
    b = q @ t.b_theta
    bt = b * t.inv_rho2
    e = 1 / (t.hoop2 * (t.radial2 + a * a) + t.radial2 * b * bt)
    g = t.b_rho @ (2 * a * (1 - e**2 * t.hoop2) * t.weight) + t.b_theta @ (2 * bt * (1 - e**2 * t.radial2) * t.weight)
    iaa = (2 - 2 * e**2 * t.hoop2 + 8 * e**3 * t.hoop2**2 * a * a) * t.weight
    iab = 8 * e**3 * t.hoop2 * t.radial2 * a * bt * t.weight
    ibb = (2 * t.inv_rho2 * (1 - e**2 * t.radial2) + 8 * e**3 * t.radial2**2 * bt * bt) * t.weight
    cross = (t.b_rho * iab) @ t.b_theta.T
    jac = (t.b_rho * iaa) @ t.b_rho.T + cross + cross.T + (t.b_theta * ibb) @ t.b_theta.T
    return g, jac


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def _case(title, tables, axisymmetric, states, repeats, rounds, unfolded=None):
    """Time one case and print its block; ``unfolded``: the same ROM's tables on the full
    angular rule, for the row of the force without the fold."""
    t = tables
    K, P = t.b_rho.shape
    rng = np.random.default_rng(0)
    Q = np.column_stack([rng.uniform(-0.3, 0.3, states), rng.uniform(-0.03, 0.03, (states, K - 1))])
    # the C program takes the general kernels when the tables carry b_theta
    if axisymmetric:
        arrays, force, fused = (t.weight, t.inv_rho2, t.hoop2, t.radial2, t.b_rho), _axisymmetric_force, _axisymmetric_force_jacobian
    else:
        arrays, force, fused = (t.weight, t.inv_rho2, t.hoop2, t.radial2, t.b_rho, t.b_theta), _general_force, _general_force_jacobian
    G, G2, Gu, J = np.empty((states, K)), np.empty((states, K)), np.empty((states, K)), np.empty((states, K, K))
    force(Q[:1], 1, t.law, *arrays, G)
    fused(Q[:1], 1, t.law, *arrays, G2, J)
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("force_jacobian", work, ("-ffast-math",))
    np.concatenate([a.ravel() for a in arrays]).tofile(work / "tables.bin")
    Q.tofile(work / "q.bin")
    names = ["numba force", "numba force + Jacobian", "numpy force + Jacobian", "C force", "C force + Jacobian"]
    if unfolded is not None:
        names.insert(2, "numba force, unfolded rule")
    times = {name: [] for name in names}
    if unfolded is not None:
        u = unfolded
        u_arrays = (u.weight, u.inv_rho2, u.hoop2, u.radial2, u.b_rho, u.b_theta)
        force(Q[:1], 1, t.law, *u_arrays, Gu)
    calls = states * repeats
    for _ in range(rounds):
        t0 = time.perf_counter()
        force(Q, repeats, t.law, *arrays, G)
        times["numba force"].append((time.perf_counter() - t0) / calls * 1e9)
        t0 = time.perf_counter()
        fused(Q, repeats, t.law, *arrays, G2, J)
        times["numba force + Jacobian"].append((time.perf_counter() - t0) / calls * 1e9)
        if unfolded is not None:
            t0 = time.perf_counter()
            force(Q, repeats, t.law, *u_arrays, Gu)
            times["numba force, unfolded rule"].append((time.perf_counter() - t0) / calls * 1e9)
        t0 = time.perf_counter()
        numpy_out = [_numpy_force_jacobian(q, t, axisymmetric) for q in Q]
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
    if unfolded is not None:
        err["numba force, unfolded rule"] = _rel(Gu, G2)
    if exe is not None:
        c = np.fromfile(work / "out.bin")
        err["C force"] = err["C force + Jacobian"] = max(_rel(c[:states * K].reshape(states, K), G2),
                                                         _rel(c[states * K:].reshape(states, K, K), J))
    med = {k: statistics.median(v) for k, v in times.items() if v}
    print(f"{title}, {P} quadrature points, {states} states x {repeats} repeats; medians of {rounds} "
          "interleaved rounds")
    for name, ns in med.items():
        print(f"  {name:28s} {ns:9.1f} ns per call   (vs numba force + Jacobian: {err[name]:.1e} relative)")
    if exe is not None:
        print(f"  ratio numba / C, force: {med['numba force'] / med['C force']:.2f}; force + Jacobian: "
              f"{med['numba force + Jacobian'] / med['C force + Jacobian']:.2f} (target <= 1.5)")
    print(f"  ratio numpy / numba, force + Jacobian: {med['numpy force + Jacobian'] / med['numba force + Jacobian']:.1f}")
    if unfolded is not None:
        print(f"  ratio unfolded / folded rule, numba force: "
              f"{med['numba force, unfolded rule'] / med['numba force']:.2f} "
              f"({unfolded.weight.size} / {P} points)")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--states", type=int, default=256)
    ap.add_argument("--repeats", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    states, repeats, rounds = (16, 2, 1) if args.smoke else (args.states, args.repeats, args.rounds)
    ps = solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")
    axi = build_rom(ps, [(1, 0), (2, 0), (3, 0)])
    _case("three-mode force", axi.tables, True, states, repeats, rounds)
    mixed = [(1, 0), (1, 1), (1, 2)]
    folded = build_rom(ps, mixed)
    # the full rule on [0, 2 pi): the set with a sine companion, whose coordinate stays 0
    full = build_rom(ps, mixed + [(1, -1)]).tables
    K = len(mixed)
    unfolded = full._replace(b_rho=np.ascontiguousarray(full.b_rho[:K]), b_theta=np.ascontiguousarray(full.b_theta[:K]))
    _case("mixed-set force (1,0), (1,1), (1,2)", folded.tables, False, max(4, states // 8), repeats, rounds, unfolded)


if __name__ == "__main__":
    main()
