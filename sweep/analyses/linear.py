"""Analysis ``linear``: natural frequencies of the pre-stretched membrane (section 4.1).

Per grid point and mode (m, n): the converged Galerkin frequency of Eq. (25)
(``omega``), Eq. (28) (``omega_approx``) and the Eq. (29) bound (``omega_bound``); with a
model that has in-plane motion (``[model] kind = "full"``) also the m-th in-plane frequency
of wave number n (``omega_inplane``).
Options: :attr:`LinearAnalysis.OPTIONS` (``docs/options.md``).  A task whose frequency is
not below its Eq. 29 bound, or whose adaptive basis did not converge, is failed (the reason
in ``message``).

A list of basis sizes (``basis = [4, 8, 16]``) is a convergence study: ``omega`` gains a
leading dimension ``basis`` (its coordinate the sizes, in the job's order), one Galerkin
solution per size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from model.linear import MAX_BASIS, approximate_frequency, frequency_bound
from model.modes import bessel_roots

from . import options as opt
from .base import DEFAULT_CONTEXT, STATUS_FAILED, STATUS_OK, Analysis, JobError, Variable, check_keys


@dataclass(frozen=True)
class LinearOptions:
    modes: tuple[tuple[int, int], ...]
    prestretch: str
    #: Bessel functions per wave number: None (adaptive), or one size per ``basis`` entry
    basis: tuple[int, ...] | None
    #: whether ``basis`` was a list (a ``basis`` dimension) rather than one size
    basis_study: bool = False
    #: whether the job's model has in-plane frequencies (``omega_inplane``)
    inplane: bool = False


class LinearAnalysis(Analysis):
    """Linear frequencies omega_mn by Galerkin (Eq. 25), Eq. (28) and Eq. (29)."""

    name = "linear"
    model_needs = ("natural_frequencies",)
    #: The option table ``[linear]``: key -> description (docs/options.md).
    OPTIONS = {
        "modes": opt.MODES_HELP,
        "prestretch": "analytic (Eq. 21) | numeric (Eq. 15, default) | fit (Eq. 18)",
        "basis": "radial functions per wave number n: the ROM's Bessel functions of the Galerkin basis "
                 "(default: adaptive, doubled from 32 until the frequencies change by less than 2e-6, at most "
                 "256), the full model's Legendre functions per field (default: its [model] order), the 2-D FE "
                 "check's radial elements (default: its [model] radial); a list of sizes is a convergence "
                 "study: omega (and omega_inplane) gain a dimension basis",
    }

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        check_keys(table, self.name, tuple(self.OPTIONS))
        modes = opt.modes(table, self.name)
        value = table.get("basis")
        study = isinstance(value, list)
        if study and not value:
            raise JobError("linear.basis", value, "a basis size or a non-empty list of sizes")
        basis = None
        if study:
            basis = opt.increasing(value, "linear.basis", f"a list of distinct increasing sizes from 1 to {MAX_BASIS} "
                                   "(the last is the reference of a convergence study)", 1, MAX_BASIS)
        elif value is not None:
            basis = (opt.number(table, self.name, "basis", low=1, high=MAX_BASIS, integer=True),)
        mmax = max(m for m, _ in modes)
        if basis is not None and mmax > min(basis):
            raise JobError("linear.basis", value, f"must be >= the largest m in linear.modes ({mmax})")
        inplane = context.model.model().provides("inplane_frequencies", context.model.options)
        return LinearOptions(modes, opt.prestretch(table, self.name, context), basis, study, inplane)

    def variables(self, options):
        k = len(options.modes)
        omega_dims, omega_shape = ("mode",), (k,)
        if options.basis_study:
            omega_dims, omega_shape = ("basis", "mode"), (len(options.basis), k)
        inplane = [Variable("omega_inplane", omega_dims, omega_shape, "f8", "rad s-1",
                            "m-th in-plane natural frequency of wave number n")] if options.inplane else []
        return [
            Variable("omega", omega_dims, omega_shape, "f8", "rad s-1",
                     "transverse natural frequency, the model's solution of Eq. 25"),
            Variable("omega_approx", ("mode",), (k,), "f8", "rad s-1",
                     "approximate natural frequency, Eq. 28 (NaN for a model without a radial pre-stretch)"),
            Variable("omega_bound", ("mode",), (k,), "f8", "rad s-1",
                     "upper bound of the natural frequency, Eq. 29 (neo-Hookean law; NaN for the others)"),
        ] + inplane

    def coords(self, options):
        coords = opt.mode_coords(options.modes)
        if options.basis_study:
            coords["basis"] = (("basis",), np.array(options.basis, np.int32),
                               {"long_name": "radial resolution: functions per wave number (ROM, full model) or "
                                                "radial elements (2-D mesh)", "units": "1"})
        return coords

    def compute(self, point, options, subtask):
        m = point.membrane
        # Eq. 28 needs the pre-stretch's slope at the outer edge: NaN for a model without one
        ps = point.model.static_state(point, options) if point.model.model().provides("static_state") else None
        K = len(options.modes)
        sizes = options.basis or (None,)
        omega = np.empty((len(sizes), K))
        inplane = np.empty((len(sizes), K))
        out = {"omega_approx": np.empty(K), "omega_bound": np.empty(K)}
        problems = []
        for b, size in enumerate(sizes):
            omega[b], unconverged = point.model.natural_frequencies(point, options, size)
            problems += unconverged
            if options.inplane:
                inplane[b] = point.model.inplane_frequencies(point, options, size)
        for k, (mm, signed_n) in enumerate(options.modes):
            alpha = bessel_roots(abs(signed_n), m.delta_o, mm)[-1]
            out["omega_approx"][k] = approximate_frequency(ps, alpha) if ps is not None else np.nan
            out["omega_bound"][k] = frequency_bound(m, alpha)
            # Eq. 29 bounds every neo-Hookean frequency from above (the limit delta -> infinity);
            # the other laws have no bound (NaN)
            bound = out["omega_bound"][k] if np.isfinite(out["omega_bound"][k]) else np.inf
            for b, size in enumerate(sizes):
                w = omega[b, k]
                if not (np.isfinite(w) and 0.0 < w < bound):
                    at = f" with {size} functions" if options.basis_study else ""
                    problems.append(f"mode ({mm}, {signed_n}){at}: omega = {w:.6g} rad/s is not in "
                                    f"(0, Eq. 29 bound = {out['omega_bound'][k]:.6g})")
        out["omega"] = omega if options.basis_study else omega[0]
        if options.inplane:
            out["omega_inplane"] = inplane if options.basis_study else inplane[0]
        out["status"] = STATUS_FAILED if problems else STATUS_OK
        if problems:
            out["message"] = "; ".join(problems)
        return out


LINEAR = LinearAnalysis()
