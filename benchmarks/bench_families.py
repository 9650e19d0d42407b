"""Cost of the asymmetric-family stability along an axisymmetric branch (docs/performance.md,
"Families").

Case: the Fig. 14a resonance, delta = 1.1, delta_o = 0.2, P0 = 1 Pa, c = 0.05 N s/m^3, one
axisymmetric mode, continuation in Omega from 25 to 55 rad/s (``ds_max = 0.3``).  Prints,
measured in one run with the variants interleaved (medians of ``--repeats``, compiled):

* the branch alone, and with the families n = 1..6 at M = 2 and M = 8 radial modes each:
  wall time, points, and the ratio to the branch alone (total and per family);
* one monodromy block of one family (``model.families.family_monodromy``) against one
  axisymmetric monodromy matrix (``ForcedMap.monodromy``), per call.

Run: ``python benchmarks/bench_families.py [--repeats 5] [--smoke]``; ``--smoke`` (the test
suite) narrows the range to 40..46 rad/s, 1 repeat, M = 2.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from model.continuation import continue_orbits
from model.families import build_family
from model.forced import ForcedMap
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom
from model.shooting import shoot

WAVE_NUMBERS = (1, 2, 3, 4, 5, 6)


def _per_call(fn, seconds=0.3):
    fn()
    n, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        fn()
        n += 1
    return (time.perf_counter() - t0) / n


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--smoke", action="store_true", help="tiny run for the test suite")
    args = ap.parse_args(argv)
    start, stop, repeats, radial = (40.0, 46.0, 1, (2,)) if args.smoke else (25.0, 55.0, args.repeats, (2, 8))
    ps = solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")
    rom = build_rom(ps, [(1, 0)])
    fmap = ForcedMap.from_loading(rom, Loading(Omega=start, P0=1.0, c=0.05))
    variants = {"branch alone": ()}
    for M in radial:
        variants[f"6 families, M = {M}"] = tuple(build_family(ps, rom, n, M) for n in WAVE_NUMBERS)
    times = {name: [] for name in variants}
    points = {}
    for _ in range(repeats + 1):  # the first round compiles
        for name, families in variants.items():
            t0 = time.perf_counter()
            br = continue_orbits(fmap, "Omega", start, stop, ds_max=0.3, max_points=1000, families=families)
            times[name].append(time.perf_counter() - t0)
            points[name] = br.value.size
    base = statistics.median(times["branch alone"][1:])
    for name in variants:
        t = statistics.median(times[name][1:])
        per = (t / base - 1) / len(WAVE_NUMBERS) if variants[name] else 0.0
        print(f"{name}: {points[name]} points, median {t:.3f} s, ratio to the branch alone {t / base:.2f} "
              f"(+{per:.2f} per family)")
    at = fmap.varied("Omega", 44.0)
    y = shoot(at, np.array([0.5, 0.0])).state
    t_axi = _per_call(lambda: at.monodromy(y))
    for M in radial:
        fam = build_family(ps, rom, 1, M)
        t_fam = _per_call(lambda: at.family_monodromy(y, fam))
        print(f"one family block (n = 1, M = {M}, {at.steps} RK4 steps): {t_fam * 1e6:.1f} us per call, "
              f"ratio to the axisymmetric monodromy ({t_axi * 1e6:.1f} us) {t_fam / t_axi:.2f}")


if __name__ == "__main__":
    main()
