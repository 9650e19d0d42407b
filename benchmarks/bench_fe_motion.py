"""The membrane's force and RK4 step on the two-dimensional finite-element mesh
(model/fe_kernels.py, model/fe_motion.py): the numba kernel against a C program of the same
algorithm (the hardware reference), the sparse-product force (numpy and scipy, what a user who
knows scipy would write), scikit-fem's own assembly of the residual form (what a scikit-fem
user would write), and ``solve_ivp`` for the motion.

delta = 1.5, delta_o = 0.2, ``--radial`` P2 elements across and 4 times as many around (the
finest mesh of the validation job by default: 16 x 64, 4224 nodes, 12 quadrature points per
triangle).  The force is evaluated on ``--states`` states (the pre-stretch plus random
displacements of 1 cm) ``--repeats`` times per round; the motion runs ``--steps`` RK4 steps of
the check's step (half of RK4's stability limit) from rest at 5 cm in the lowest transverse
mode's shape, and ``solve_ivp`` (RK45, the numba force, rtol 1e-8) covers the same time.  A
step is four forces and four solves with the consistent mass (SuperLU, scipy): the C program
times the force only.  It is ``benchmarks/c/fe_force.c``, compiled here with ``cc -O3
-march=native -ffast-math`` (the numba kernel uses fastmath too; skipped with a message without
a compiler).  Variants are interleaved in each of ``--rounds`` rounds (medians printed,
compilation excluded); forces are compared with the numba force (relative difference printed).
Run: ``python benchmarks/bench_fe_motion.py [--rounds 7] [--smoke]``.
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
from scipy.integrate import solve_ivp
from skfem import LinearForm

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from model.fe_annulus import AnnulusMesh, fe_modes, solve_fe_prestretch  # noqa: E402
from model.fe_motion import FeMotion  # noqa: E402
from model.full import surface  # noqa: E402
from model.params import Membrane  # noqa: E402


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def _skfem_force(motion: FeMotion):
    """The force as scikit-fem assembles the residual form on the vector basis: ``D -> f``."""
    basis = motion.state.mesh.basis(3)
    law = motion.state.mesh.membrane.material
    order = np.concatenate(basis.split_indices())  # the vector basis' dofs of components x, y, z

    @LinearForm
    def residual(v, w):
        g = w["d"].grad
        a1 = np.stack([1.0 + g[0, 0], g[1, 0], g[2, 0]], axis=-1)
        a2 = np.stack([g[0, 1], 1.0 + g[1, 1], g[2, 1]], axis=-1)
        p1, p2 = surface.gradient(law, a1, a2)
        return sum(p1[..., i] * v.grad[i, 0] + p2[..., i] * v.grad[i, 1] for i in range(3))

    def force(D):
        x = np.empty(basis.N)
        x[order] = D.ravel()
        return residual.assemble(basis, d=basis.interpolate(x))[order].reshape(3, -1)

    return force


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radial", type=int, default=16)
    ap.add_argument("--states", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    radial, states, repeats, steps, rounds = ((2, 2, 2, 20, 1) if args.smoke else
                                              (args.radial, args.states, args.repeats, args.steps, args.rounds))
    membrane = Membrane(delta=1.5, delta_o=0.2)
    state = solve_fe_prestretch(AnnulusMesh.build(membrane, radial, 4 * radial))
    motion = FeMotion.build(state)
    law, dofs, gx, gy, weights = motion.kernel_tables
    elements, points, local = gx.shape
    nodes = motion.basis.N
    rng = np.random.default_rng(0)
    Ds = np.repeat(motion.rest[None], states, axis=0)
    Ds[:, :, motion.free] += 0.01 * rng.standard_normal((states, 3, motion.free.size))
    skfem_force = _skfem_force(motion)
    shape = fe_modes(state, "W", 1, n_max=0)[0][1][:, 0]
    D0 = motion.rest.copy()
    D0[2] = 0.05 * shape / np.abs(shape).max()
    dt = motion.time_step()
    motion.compiled_force(Ds[0])  # compile

    def rhs(t, y):
        D = motion.rest.copy()
        D[:, motion.free] = y[:y.size // 2].reshape(3, -1)
        return np.concatenate([y[y.size // 2:], motion.acceleration(D).ravel()])

    y0 = np.concatenate([D0[:, motion.free].ravel(), np.zeros(3 * motion.free.size)])
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("fe_force", work, ("-ffast-math",))
    np.concatenate([dofs.ravel().astype(float), gx.ravel(), gy.ravel(), weights.ravel()]).tofile(work / "tables.bin")
    Ds.tofile(work / "d.bin")
    names = ["numba force", "sparse-product force", "scikit-fem assembly", "C force", "RK4 step"]
    times = {name: [] for name in names}
    scipy_times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        for _ in range(repeats):
            F = np.array([motion.compiled_force(D) for D in Ds])
        times["numba force"].append((time.perf_counter() - t0) / (states * repeats) * 1e9)
        t0 = time.perf_counter()
        sparse = np.array([motion.force(D) for D in Ds])
        times["sparse-product force"].append((time.perf_counter() - t0) / states * 1e9)
        t0 = time.perf_counter()
        assembled = np.array([skfem_force(D) for D in Ds])
        times["scikit-fem assembly"].append((time.perf_counter() - t0) / states * 1e9)
        end = []
        t0 = time.perf_counter()
        motion.motion(D0, dt, steps, lambda step, D, V: step == steps and end.append(D[:, motion.free].copy()))
        times["RK4 step"].append((time.perf_counter() - t0) / steps * 1e9)
        t0 = time.perf_counter()
        ivp = solve_ivp(rhs, (0.0, steps * dt), y0, method="RK45", rtol=1e-8, atol=1e-12)
        scipy_times.append(time.perf_counter() - t0)
        if exe is not None:
            out = subprocess.run([str(exe), str(work / "tables.bin"), str(elements), str(points), str(local), str(nodes),
                                  str(work / "d.bin"), str(repeats), str(work / "out.bin")],
                                 capture_output=True, text=True, check=True)
            times["C force"].append(float(out.stdout))
    err = {"numba force": 0.0, "sparse-product force": _rel(sparse, F), "scikit-fem assembly": _rel(assembled, F)}
    if exe is not None:
        err["C force"] = _rel(np.fromfile(work / "out.bin").reshape(F.shape), F)
    med = {k: statistics.median(v) for k, v in times.items() if v}
    print(f"finite-element force, {radial} x {4 * radial} P2 elements ({elements} triangles, {nodes} nodes, "
          f"{points} quadrature points each), {states} states x {repeats} repeats; medians of {rounds} interleaved "
          "rounds")
    for name in ("numba force", "sparse-product force", "scikit-fem assembly", "C force"):
        if name in med:
            print(f"  {name:20s} {med[name] / 1e3:9.1f} us per call   (vs numba force: {err[name]:.1e} relative)")
    if "C force" in med:
        print(f"  ratio numba / C, force: {med['numba force'] / med['C force']:.2f} (target <= 1.5)")
    print(f"  ratio sparse-product / numba: {med['sparse-product force'] / med['numba force']:.1f}; "
          f"scikit-fem assembly / numba: {med['scikit-fem assembly'] / med['numba force']:.0f}")
    span = steps * dt
    print(f"finite-element RK4, {steps} steps of {dt:.3e} s (half of RK4's stability limit), the consistent mass "
          "solved by SuperLU")
    print(f"  RK4 step {med['RK4 step'] / 1e3:9.1f} us per step ({med['RK4 step'] / 4 / med['numba force']:.1f} numba "
          "forces per stage)")
    scipy_s = statistics.median(scipy_times)
    print(f"  solve_ivp (RK45, numba force, rtol 1e-8) over the same {span:.3e} s: {scipy_s * 1e3:.1f} ms, "
          f"{ivp.nfev} evaluations; speed-up of RK4: {scipy_s / (med['RK4 step'] * 1e-9 * steps):.1f}x "
          f"(final states differ by {_rel(ivp.y[:ivp.y.shape[0] // 2, -1], end[0].ravel()):.1e} relative)")


if __name__ == "__main__":
    main()
