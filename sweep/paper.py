"""Run every paper job under MPI, draw every figure and regenerate the validation report.

Usage (from the repository root)::

    python -m sweep.paper [--quick] [-n RANKS] [-o RESULTS_DIR] [--only NAME ...]

Each job file of :data:`PAPER_JOBS` (``jobs/<name>.toml``, at the paper's parameters and
full resolution) runs as ``mpiexec -n RANKS python -m mpi4py -m sweep run``, its figures
go to ``RESULTS_DIR/figures/<name>/``; then the jobs of :data:`VALIDATION_JOBS`
(``jobs/validation/*.toml``: convergence studies and cross-checks, results in
``RESULTS_DIR/validation/``) run the same way, and at the end ``docs/validation.md`` is
regenerated from the result files alone.  ``--quick`` caps every ``num`` of a job file (grid ranges,
lattices, amplitude targets) at :data:`QUICK_NUM` for a laptop run; the full resolution
is meant for a cluster.  Runs resume: an interrupted ``python -m sweep.paper`` started
again computes only what is missing.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

from .launch import find_mpiexec

#: Job files (``jobs/<name>.toml``) that reproduce the paper's tables and figures.
PAPER_JOBS = (
    "table1", "table1-app1", "table1-app2", "table1-mooney-rivlin", "table1-gent", "table2", "tables-fe",
    "fig02-03-static", "fig04-06-frequencies",
    "fig08-inplane", "fig09-modes", "fig10-11-backbone", "fig10-full-backbone", "fig12-inner-radius",
    "fig13-resonance", "fig14-bifurcation-omega", "fig15-bifurcation-p0", "fig15-bruteforce", "fig15a-full",
    "fig14a-full",
    "fig16-17-damping", "fig17-cusp", "fig18-damping-resonance",
    "fig14-families", "stability-map-fig14a", "fig14a-bifurcation-curves", "fig14a-bruteforce-diagram",
    "fig19-basins", "fig19a-basins-modes", "fig19a-full-basins", "erosion-profile",
)
#: Job files (``jobs/validation/<name>.toml``) of the checks in ``docs/validation.md`` beyond
#: the paper: convergence in the basis, the modes and the RK4 steps, and brute-force checks.
VALIDATION_JOBS = tuple(f"validation/{name}" for name in (
    "linear-basis", "full-static", "full-linear", "full-backbone-order12", "backbone-modes", "held-backbone", "held-backbone-order24", "fe-q1-576", "fe-q1-576-lumped",
    "fe-free-vibration", "fe-free-vibration-n2", "fe-free-vibration-n4",
    "forced-modes-omega", "forced-modes-omega-fine", "forced-modes-p0", "forced-modes-p0-fine",
    "fig15a-full-order12", "fig15a-full-order12-fine", "fig15a-full-families", "fig15a-full-families-w",
    "fig15a-full-families-order12", "fig15a-full-families-fine", "fig15a-full-families-finer",
    "fig15a-full-families-order16-fine", "fig14a-full-order12", "fig14a-full-order12-fine",
    "fig14a-full-light-order8", "fig14a-full-light-order12", "fig14a-full-light-families-order8",
    "fig14a-full-light-families-order12", "full-spectrum-fig14a",
    *(f"fig14a-full-light-rayleigh-order{o}" for o in (8, 12, 16, 20)), "fig14a-held-light-rayleigh-order16",
    "families-viscous", "families-modal", "families-rayleigh",
    "families-1pct-viscous", "families-1pct-modal", "families-1pct-rayleigh", "tongues-1pct-viscous",
    "tongues-1pct-modal", "stability-map-fig14a-radial", "families-1pct-viscous-axi", "families-1pct-modal-axi",
    "families-1pct-viscous-k8", "families-1pct-modal-k4", "families-1pct-modal-k8",
    "families-viscous-axi", "families-viscous-k8", "fig14a-held-viscous-order12", "fig14a-held-viscous-order16",
    "fig14a-held-viscous-order24", *(f"fig14a-held-1pct-{law}-order{o}" for law in ("viscous", "modal", "rayleigh")
                                     for o in (16, 24)),
    "fig14a-full-1pct-rayleigh-order12", "fig14a-full-1pct-rayleigh-order16",
    "fig14a-broken-viscous-order12", "fig14a-broken-viscous-order16", "fig14a-broken-1pct-viscous-order16", "fig14a-broken-1pct-viscous-order24",
    *(f"fig14a-broken-1pct-{law}-order{o}" for law in ("modal", "rayleigh") for o in (16, 24)),
    "fig14a-broken-rom", "fig14a-broken-viscous-axi-order16", "fig14a-broken-viscous-axi-order24",
    "fig14a-bruteforce-axi",
    "family-check", "family-check-full", "family-check-full-3n-n1", "family-check-full-3n-n4",
    "family-check-full-1pct-modal", "fig14a-full-switching-order8", "fig14a-full-switching-order12",
    "fig14a-full-rotating-order8",
    "fig14a-families-m2", "waves-fig14a",
    "fig19a-basins-brute", "fig19a-full-basins-order12", "fig19a-full-basins-brute",
    "fig19a-full-basins-brute-same-steps", "fig19a-full-basins-brute-perturbed", "fig19a-basins-brute-perturbed",
))
QUICK_NUM = 41


def quick_text(text: str, cap: int = QUICK_NUM) -> str:
    """The job text with every ``num = N`` capped at ``cap``."""
    return re.sub(r"(\bnum\s*=\s*)(\d+)", lambda m: m.group(1) + str(min(int(m.group(2)), cap)), text)


def _mpiexec() -> str:
    found = find_mpiexec()
    if not found:
        raise SystemExit("mpiexec not found: install the project (pip install -e .) into this environment")
    return found


def run_job(job: Path, out: Path, ranks: int, figures: Path | None) -> int:
    """Run one job under ``mpiexec`` with resume, then draw its figures into ``figures``
    (None: none); returns the exit code."""
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [_mpiexec(), "-n", str(ranks), sys.executable, "-m", "mpi4py", "-m", "sweep", "run",
           str(job), "-o", str(out), "--resume"]
    print("+", " ".join(cmd), flush=True)
    code = subprocess.call(cmd)
    if code == 0 and figures is not None:
        code = subprocess.call([sys.executable, "-m", "sweep", "figures", str(out), "-o", str(figures)])
    return code


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sweep.paper", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=f"cap every num at {QUICK_NUM}")
    parser.add_argument("-n", "--ranks", type=int, default=2, help="MPI ranks (default 2)")
    parser.add_argument("-o", "--output", type=Path, default=Path("results"), help="results directory")
    parser.add_argument("--only", nargs="+", choices=PAPER_JOBS + VALIDATION_JOBS, metavar="NAME",
                        help="run only these jobs: " + ", ".join(PAPER_JOBS + VALIDATION_JOBS))
    parser.add_argument("--report", type=Path, default=Path("docs/validation.md"), help="validation report path")
    args = parser.parse_args(argv)
    args.output.mkdir(parents=True, exist_ok=True)
    failed = []
    for name in args.only or PAPER_JOBS + VALIDATION_JOBS:
        job = Path("jobs") / f"{name}.toml"
        if args.quick:
            quick = args.output / "jobs" / f"{name}.toml"
            quick.parent.mkdir(parents=True, exist_ok=True)
            quick.write_text(quick_text(job.read_text()))
            job = quick
        figures = args.output / "figures" / name if name in PAPER_JOBS else None
        if run_job(job, args.output / f"{name}.nc", args.ranks, figures) != 0:
            failed.append(name)
    subprocess.call([sys.executable, "-m", "sweep.validation", str(args.output), "-o", str(args.report)])
    if failed:
        print(f"failed jobs: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
