"""Cost of one task of the ``linear`` analysis and of its two parts.

One task is the numeric pre-stretch (Chebyshev collocation of Eq. 15) and the adaptive
Galerkin solution of Eq. (25) on the Bessel basis (``model.linear.galerkin_frequencies``)
for mode (1, 0); 24 grid points (delta 1.05..2.0, delta_o 0.2, 0.3, 0.5), medians of
``--repeats`` passes, one thread.  The reference is scipy's general Bessel functions
``jv``/``yv`` for the basis, measured in the same run (what the basis cost before the
dedicated order-0 and order-1 functions were used).  Run::

    python benchmarks/bench_linear.py [--repeats 5] [--smoke]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy.special import jv, yv  # noqa: E402

from model.linear import galerkin_frequencies, gauss_radial  # noqa: E402
from model.modes import bessel_roots, mode_shape  # noqa: E402
from model.params import Membrane  # noqa: E402
from model.prestretch import solve_prestretch  # noqa: E402
from sweep.analyses.linear import LINEAR  # noqa: E402
from sweep.jobspec import grid_point  # noqa: E402


def _median_ms(work, items, repeats) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for item in items:
            work(item)
        times.append((time.perf_counter() - t0) / len(items) * 1e3)
    return statistics.median(times)


def _general_basis(rho, alpha, n, Re):
    # mode_shape's four Bessel evaluations with scipy's general functions
    x = alpha[:, None] * rho / Re
    return jv(n, x), yv(n, x), jv(n + 1, x), yv(n + 1, x)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    deltas, repeats = (np.array([1.1, 1.5]), 1) if args.smoke else (np.linspace(1.05, 2.0, 8), args.repeats)
    membranes = [Membrane(delta=d, delta_o=do) for d in deltas for do in (0.2, 0.3, 0.5)]
    options = LINEAR.parse_options({}, {"delta": deltas, "delta_o": [0.2]}, Membrane())
    points = [grid_point(Membrane(), {"delta": m.delta, "delta_o": m.delta_o}) for m in membranes]
    prestretches = [solve_prestretch(m, "numeric") for m in membranes]
    LINEAR.compute(points[0], options, 0)
    task = _median_ms(lambda p: LINEAR.compute(p, options, 0), points, repeats)
    pre = _median_ms(lambda m: solve_prestretch(m, "numeric"), membranes, repeats)
    gal = _median_ms(lambda ps: galerkin_frequencies(ps, 0, 1), prestretches, repeats)
    rho, _ = gauss_radial(membranes[0], 4 * 64 + 40)
    alpha = bessel_roots(0, 0.2, 64)
    basis = _median_ms(lambda _: mode_shape(rho, alpha, 0, 1.0, 0.2), range(5), repeats)
    general = _median_ms(lambda _: _general_basis(rho, alpha, 0, 1.0), range(5), repeats)
    print(f"linear task, mode (1, 0), numeric pre-stretch, {len(points)} grid points, medians of {repeats}: "
          f"{task:.2f} ms per task (target <= 10)")
    print(f"  numeric pre-stretch {pre:.2f} ms, adaptive Galerkin (n = 0) {gal:.2f} ms")
    print(f"  basis of 64 functions at {rho.size} points: {basis:.2f} ms; scipy jv/yv for the same: "
          f"{general:.2f} ms, ratio {general / basis:.1f}")


if __name__ == "__main__":
    main()
