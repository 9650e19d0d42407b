"""The printed rows of the kernel benchmarks of the full model (force, Hessian, RK4 step):
numba against numpy and the C program of the same algorithm, and the RK4 step against
``solve_ivp``, in the format ``docs/performance.md`` and ``tests/test_benchmarks.py`` read."""

from __future__ import annotations


def print_kernel(med: dict, err: dict, kernel: str) -> None:
    """The rows ``numba <kernel>``, ``numpy <kernel>``, ``C <kernel>`` (medians ``med`` in ns per
    call, relative differences ``err`` from numba's) and the ratios."""
    for name in (f"numba {kernel}", f"numpy {kernel}", f"C {kernel}"):
        if name in med:
            print(f"  {name:13s} {med[name]:10.1f} ns per call   (vs numba {kernel}: {err[name]:.1e} relative)")
    if f"C {kernel}" in med:
        print(f"  ratio numba / C, {kernel}: {med[f'numba {kernel}'] / med[f'C {kernel}']:.2f} (target <= 1.5)")
    print(f"  ratio numpy / numba, {kernel}: {med[f'numpy {kernel}'] / med[f'numba {kernel}']:.1f}")


def print_rk4(med: dict, err: dict, steps: int, dt: float, scipy_s: float, evaluations: int, ivp_err: float) -> None:
    """The rows ``numba RK4``, ``C RK4`` (ns per step), their ratio and ``solve_ivp``'s time
    ``scipy_s`` (s) over the same ``steps`` steps of ``dt`` (s), with its ``evaluations`` and the
    relative difference ``ivp_err`` of its final state."""
    for name in ("numba RK4", "C RK4"):
        if name in med:
            print(f"  {name:12s} {med[name]:9.1f} ns per step   (vs numba RK4: {err[name]:.1e} relative)")
    if "C RK4" in med:
        print(f"  ratio numba / C, RK4 step: {med['numba RK4'] / med['C RK4']:.2f} (target <= 1.5)")
    print(f"  solve_ivp (RK45, numpy force, rtol 1e-8) over the same {steps * dt:.3e} s: {scipy_s * 1e3:.1f} ms, "
          f"{evaluations} evaluations; speed-up of numba RK4: {scipy_s / (med['numba RK4'] * 1e-9 * steps):.0f}x "
          f"(final states differ by {ivp_err:.1e} relative)")
