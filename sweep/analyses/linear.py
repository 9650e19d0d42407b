"""Analysis ``linear``: natural frequencies of the pre-stretched membrane (section 4.1).

Per grid point and mode (m, n): the converged Galerkin frequency of Eq. (25)
(``omega``), Eq. (28) (``omega_approx``) and the Eq. (29) bound (``omega_bound``).
Options: :attr:`LinearAnalysis.OPTIONS` (``docs/options.md``).  A task whose frequency is
not below its Eq. 29 bound, or whose adaptive basis did not converge, is failed (the reason
in ``message``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from model.linear import CHANGE_TOL, MAX_BASIS, approximate_frequency, frequency_bound, galerkin_frequencies
from model.modes import bessel_roots
from model.prestretch import solve_prestretch

from . import options as opt
from .base import DEFAULT_CONTEXT, STATUS_FAILED, STATUS_OK, Analysis, JobError, Variable, check_keys


@dataclass(frozen=True)
class LinearOptions:
    modes: tuple[tuple[int, int], ...]
    prestretch: str
    basis: int | None


class LinearAnalysis(Analysis):
    """Linear frequencies omega_mn by Galerkin (Eq. 25), Eq. (28) and Eq. (29)."""

    name = "linear"
    #: The option table ``[linear]``: key -> description (docs/options.md).
    OPTIONS = {
        "modes": opt.MODES_HELP,
        "prestretch": "analytic (Eq. 21) | numeric (Eq. 15, default) | fit (Eq. 18)",
        "basis": "Bessel functions per wave number n in the Galerkin basis (default: adaptive, doubled "
                 "from 32 until the frequencies change by less than 2e-6, at most 256)",
    }

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        check_keys(table, self.name, tuple(self.OPTIONS))
        modes = opt.modes(table, self.name)
        basis = table.get("basis")
        if basis is not None:
            basis = opt.number(table, self.name, "basis", low=1, high=MAX_BASIS, integer=True)
        mmax = max(m for m, _ in modes)
        if basis is not None and mmax > basis:
            raise JobError("linear.basis", basis, f"must be >= the largest m in linear.modes ({mmax})")
        return LinearOptions(modes, opt.prestretch(table, self.name), basis)

    def variables(self, options):
        k = len(options.modes)
        return [
            Variable("omega", ("mode",), (k,), "f8", "rad s-1", "natural frequency, Galerkin solution of Eq. 25"),
            Variable("omega_approx", ("mode",), (k,), "f8", "rad s-1", "approximate natural frequency, Eq. 28"),
            Variable("omega_bound", ("mode",), (k,), "f8", "rad s-1",
                     "upper bound of the natural frequency, Eq. 29 (neo-Hookean law; NaN for the others)"),
        ]

    def coords(self, options):
        return opt.mode_coords(options.modes)

    def compute(self, point, options, subtask):
        m = point.membrane
        ps = solve_prestretch(m, options.prestretch)
        out = {name: np.empty(len(options.modes)) for name in ("omega", "omega_approx", "omega_bound")}
        by_n: dict[int, tuple[np.ndarray, float]] = {}
        problems = []
        for k, (mm, signed_n) in enumerate(options.modes):
            n = abs(signed_n)  # a sine companion has the frequency of its cosine mode
            if n not in by_n:
                mmax = max(a for a, b in options.modes if abs(b) == n)
                omega, _, change = galerkin_frequencies(ps, n, mmax, basis=options.basis, full_output=True)
                by_n[n] = omega, change
                if change >= CHANGE_TOL:
                    problems.append(f"n = {n}: basis not converged at {MAX_BASIS} functions "
                                    f"(last relative change {change:.1e})")
            alpha = bessel_roots(n, m.delta_o, mm)[-1]
            out["omega"][k] = by_n[n][0][mm - 1]
            out["omega_approx"][k] = approximate_frequency(ps, alpha)
            out["omega_bound"][k] = frequency_bound(m, alpha)
            # Eq. 29 bounds every neo-Hookean frequency from above (the limit delta -> infinity);
            # the other laws have no bound (NaN)
            bound = out["omega_bound"][k] if np.isfinite(out["omega_bound"][k]) else np.inf
            if not (np.isfinite(out["omega"][k]) and 0.0 < out["omega"][k] < bound):
                problems.append(f"mode ({mm}, {signed_n}): omega = {out['omega'][k]:.6g} rad/s is not in "
                                f"(0, Eq. 29 bound = {out['omega_bound'][k]:.6g})")
        out["status"] = STATUS_FAILED if problems else STATUS_OK
        if problems:
            out["message"] = "; ".join(problems)
        return out


LINEAR = LinearAnalysis()
