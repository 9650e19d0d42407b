"""The full model's family monodromy (model/full/family_kernels.py): one forcing period of the
variational equations of an asymmetric family along an axisymmetric orbit, the numba kernel
against a C program of the same algorithm (the hardware reference) and ``solve_ivp`` (what a
user would write: the numpy tangent moduli of :mod:`model.full.surface`).

delta = 1.1, delta_o = 0.2, ``--order`` radial functions per field (default 12), the family
``n = --n`` (default 3) on all ``order`` functions of the fields U, V, W (a block of
``6 order`` x ``6 order``), along the orbit from a state 2 cm along the first transverse mode
with its quasi-static in-plane displacement under P0 = 1 Pa at Omega = 33.5 rad/s, c = 0.05
N s/m^3, at the job's default RK4 steps per period.  The orbit's stage coordinates are
recorded (:func:`model.full.axisymmetric_kernels.rk4_motion`, as before every family block;
its time is printed) and
both the numba kernel and the C program, ``benchmarks/c/full_families.c`` (compiled here with
``cc -O3 -march=native -ffast-math``; skipped with a message without a compiler; it times its
own runs and reports their median), integrate the block along them.  ``solve_ivp`` (RK45, rtol
``--rtol``) integrates the orbit and the block together with ``AxisymmetricFull.acceleration``
and a numpy stiffness; the two agree to the RK4 error of the compiled block (printed, with
the block at four times the steps).  Variants are interleaved in each of ``--rounds`` rounds
(medians printed, compilation excluded).
Run: ``python benchmarks/bench_full_families.py [--rounds 5] [--smoke]``.
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.c_reference import compile_reference  # noqa: E402
from benchmarks.full_states import first_mode_coordinates  # noqa: E402
from model.damping import Viscous  # noqa: E402
from model.full import surface  # noqa: E402
from model.full.axisymmetric import AxisymmetricFull  # noqa: E402
from model.full.axisymmetric_kernels import rk4_motion  # noqa: E402
from model.full.families import FullFamily  # noqa: E402
from model.full.family_kernels import family_monodromy  # noqa: E402
from model.full.forced import ForcedFull, steps_per_period  # noqa: E402
from model.full.static import solve_full_prestretch  # noqa: E402
from model.params import Membrane  # noqa: E402


def _rel(x, ref) -> float:
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def numpy_stiffness(model: AxisymmetricFull, n: int, q) -> np.ndarray:
    """``K_n(q)`` of the fields U, V, W as a user would write it: the surface's tangent moduli at
    the axisymmetric columns, contracted with the variations of ``F`` of each coefficient."""
    b = model.state.basis
    du, u, dw = model.fields(q)
    zero = np.zeros_like(du)
    a1 = np.stack([model.dr0 + du, zero, dw], axis=-1)
    a2 = np.stack([zero, (model.r0 + u) / b.s, zero], axis=-1)
    A = surface.hessian(model.membrane.material, a1, a2)  # (points, 6, 6)
    d, p = b.dphi, b.phi / b.s
    z = np.zeros_like(d)
    # rows: the six components of F; columns: the coefficients of U, V, W
    dF = np.array([np.concatenate(c) for c in ([d, z, z], [z, d, z], [z, z, d], [-n * p, -p, z], [p, n * p, z],
                                               [z, z, -n * p])])
    return np.einsum("ikp,pij,jlp,p->kl", dF, A, dF, b.s * b.weights)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--order", type=int, default=12)
    ap.add_argument("--n", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    order, rounds, rtol = (6, 1, 1e-6) if args.smoke else (args.order, args.rounds, args.rtol)
    wave, c, P0, Omega = args.n, 0.05, 1.0, 33.5
    model = AxisymmetricFull(solve_full_prestretch(Membrane(delta=1.1, delta_o=0.2), order))
    fmap = ForcedFull.build(model, P0, Omega, Viscous(c), steps=steps_per_period(model, 128))
    fam = FullFamily.build(model, wave, order, "UVW")
    re, dof, steps = model.membrane.Re, model.dof, fmap.steps
    dt = fmap.period / steps
    y0 = np.concatenate([first_mode_coordinates(model, 0.02), np.zeros(dof)])  # scaled by Re
    law, phi, dphi, s, sw, _, r0, dr0 = model.kernel_tables
    stages = np.empty((steps, 4, dof))

    def record():
        rk4_motion(*model.kernel_tables, model.inverse_masses, model.omega0_2, model.bias, fmap.rate, None, model.load,
                   P0, Omega, y0, dt, steps, steps, np.empty((2, 2 * dof)), stages)

    def numba_block():
        return family_monodromy(law, phi, dphi, s, sw, r0, dr0, stages, fam.phi, fam.dphi, fam.variations,
                                fam.inverse_mass, model.omega0_2, fmap.rate, None, dt)

    record()
    block = numba_block()  # compile
    np.testing.assert_allclose(block, fmap.family_monodromy(y0 * re, fam), rtol=0, atol=1e-12 * np.abs(block).max())
    work = Path(tempfile.mkdtemp())
    exe = compile_reference("full_families", work, ("-ffast-math",))
    np.concatenate([phi.ravel(), dphi.ravel(), fam.phi.ravel(), fam.dphi.ravel(), s, sw, r0, dr0, fam.variations.ravel(),
                    fam.inverse_mass.ravel(), [model.omega0_2, fmap.rate]]).tofile(work / "tables.bin")
    stages.tofile(work / "stages.bin")
    m = fam.size // 2
    mass_inv = np.linalg.inv(fam.mass())
    load = np.concatenate([np.zeros(order), P0 * model.load])

    def rhs(t, z):
        q, v, X = z[:dof], z[dof:2 * dof], z[2 * dof:].reshape(2 * m, 2 * m)
        a = model.acceleration(q, v, c) + np.cos(Omega * t) * load
        dX = np.vstack([X[m:], -model.omega0_2 * mass_inv @ numpy_stiffness(model, wave, q) @ X[:m] - fmap.rate * X[m:]])
        return np.concatenate([v, a, dX.ravel()])

    z0 = np.concatenate([y0, np.eye(2 * m).ravel()])
    times = {"numba block": [], "C block": [], "stage record": [], "solve_ivp block": []}
    for _ in range(rounds):
        t0 = time.perf_counter()
        record()
        times["stage record"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        block = numba_block()
        times["numba block"].append(time.perf_counter() - t0)
        if exe is not None:
            out = subprocess.run([str(exe), str(work / "tables.bin"), str(order), str(phi.shape[0]), str(order), "3",
                                  str(work / "stages.bin"), str(steps), repr(dt), "3", str(work / "out.bin")],
                                 capture_output=True, text=True, check=True)
            times["C block"].append(float(out.stdout) * 1e-9)
        t0 = time.perf_counter()
        ivp = solve_ivp(rhs, (0.0, fmap.period), z0, method="RK45", rtol=rtol, atol=1e-12)
        times["solve_ivp block"].append(time.perf_counter() - t0)
    med = {k: statistics.median(v) for k, v in times.items() if v}
    print(f"full-model family monodromy, order {order}, n = {wave}, fields U, V, W ({fam.size} x {fam.size} block), "
          f"{phi.shape[0]} quadrature points, {steps} RK4 steps per period; medians of {rounds} interleaved rounds")
    print(f"  numba block      {med['numba block'] * 1e3:9.2f} ms per period")
    if "C block" in med:
        c_block = np.fromfile(work / "out.bin").reshape(block.shape)
        print(f"  C block          {med['C block'] * 1e3:9.2f} ms per period   (vs numba: {_rel(c_block, block):.1e} "
              "relative)")
        print(f"  ratio numba / C, family block: {med['numba block'] / med['C block']:.2f} (target <= 1.5)")
    print(f"  stage record     {med['stage record'] * 1e3:9.2f} ms per period   (the orbit's RK4 period with its "
          "stage coordinates, before every family block)")
    print(f"  solve_ivp block  {med['solve_ivp block'] * 1e3:9.2f} ms per period   (RK45, rtol {rtol:g}, "
          f"{ivp.nfev} evaluations of the numpy force and stiffness)")
    print(f"  ratio solve_ivp / numba, family block: {med['solve_ivp block'] / med['numba block']:.0f}")
    fine = ForcedFull.build(model, P0, Omega, Viscous(c), steps=4 * steps).family_monodromy(y0 * re, fam)
    reference = ivp.y[2 * dof:, -1].reshape(block.shape)
    print(f"  solve_ivp and numba differ by {_rel(reference, block):.1e} relative; at {4 * steps} steps by "
          f"{_rel(reference, fine):.1e}")


if __name__ == "__main__":
    main()
