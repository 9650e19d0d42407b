"""Analysis ``response``: brute-force steady states stepped up and down (Figs. 13, 18).

Per grid point, :func:`model.response.stepped_sweep` steps one parameter through
``values`` upwards, then downwards, each value starting from the previous steady state and
integrated until the stroboscopic map has settled (criterion in :mod:`model.response`).

Options: :attr:`ResponseAnalysis.OPTIONS` (``docs/options.md``).

Outputs over (``<parameter>``, ``direction`` = up, down): ``amplitude`` (m, max over one
period of ``|w(0.5 Re, 0, t)|``), ``converged`` (int8 1/0, flags declared), ``periods``
(integrated per value) and, over ``mode`` too, ``modal_coordinate`` and ``modal_velocity``: the
steady state on the stroboscopic section (the paper's ``A_mn`` axes); ``jump_value`` over (``direction``, ``jump``): the located jumps, NaN padded (all NaN
unless ``refine_jumps``).  The task status is ``not_converged`` if any value did not settle.

With ``poincare_points`` > 0 the sweep is a brute-force bifurcation diagram
(:mod:`model.lyapunov`): after the settling (the transient), over (``<parameter>``,
``direction``) ``poincare_coordinate`` and ``poincare_velocity`` (with ``sample`` and
``mode``: the Poincare points), ``lyapunov_exponent`` and ``lyapunov_error`` (with
``exponent``; s-1), ``response_kind`` (flags periodic, quasi_periodic, chaotic, diverged,
unsettled), ``response_period`` and ``rotation_number``.  A value that does not settle is
then data (its kind says what it is), and the status is ``not_converged`` only if a value
is ``unsettled``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np

from model.forced import DEFAULT_STEPS, ForcedMap
from model.lyapunov import KIND_NAMES, UNSETTLED
from model.params import Loading, Membrane
from model.protocol import modal_section
from model.response import LYAPUNOV_BLOCKS, refine_jumps, stepped_sweep

from sweep.models.rom import rom_for

from . import options as opt
from .base import (DEFAULT_CONTEXT, GRID_KEYS, STATUS_NOT_CONVERGED, STATUS_OK, Analysis, JobError, Variable,
                   check_keys)


def response_kind_attrs() -> dict:
    """The CF flag attributes of a variable holding :data:`model.lyapunov.KIND_NAMES` indices
    (-1: not computed)."""
    return {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
            "flag_meanings": " ".join(("not_computed",) + KIND_NAMES)}


@dataclass(frozen=True)
class ResponseOptions:
    parameter: str
    values: tuple[float, float, int]
    modes: tuple[tuple[int, int], ...]
    prestretch: str
    steps: int | None
    tol: float
    consecutive: int
    max_periods: int
    refine_jumps: bool
    #: Poincare points per value of the bifurcation diagram (0: none) and the longest period
    #: its classification looks for
    poincare_points: int = 0
    max_period: int = 16
    perturbation: float = 0.0
    #: the job's material law (``[membrane] law``): the warmups compile its kernels
    material: str = "neo-hookean"

    @property
    def swept_values(self) -> np.ndarray:
        """The swept values in increasing order."""
        return np.sort(np.linspace(*self.values))


#: Jumps located per sweep direction.
MAX_JUMPS = 2


class ResponseAnalysis(Analysis):
    """Brute-force stepped sweeps of the forced ROM, up and down."""

    name = "response"
    model_needs = ("forced_map",)
    #: The option table ``[response]``: key -> description (docs/options.md).
    OPTIONS = {
        "parameter": "Omega | P0 (required): the swept forcing parameter, not a grid key; the other "
                     "forcing keys (P0 or Omega, and c) must be grid keys",
        "values": "{start, stop, num} (required): the swept values (rad/s or Pa)",
        "modes": opt.MODES_HELP,
        "prestretch": "analytic (Eq. 21) | numeric (Eq. 15, default) | fit (Eq. 18)",
        "steps": opt.steps_help(DEFAULT_STEPS),
        "tol": "relative stroboscopic residual that counts as settled (default 1e-6)",
        "consecutive": "periods in a row below tol to accept a steady state (default 20)",
        "max_periods": "periods before a value is declared not converged (default 30000)",
        "refine_jumps": "true: locate each jump to 0.1 % by an adaptive brute-force march (default false)",
        "poincare_points": f"Poincare points per value after the transient (the settling, at most max_periods), "
                           f"with Lyapunov exponents and the kind of response: a bifurcation diagram; a multiple "
                           f"of {LYAPUNOV_BLOCKS} (default 0: none)",
        "max_period": "longest period (forcing periods) the diagram's classification looks for (default 16)",
        "perturbation": "added to every modal coordinate (m) at the start of each value, so that a "
                        "symmetry-breaking instability of a symmetric response can be seen (default 0)",
    }

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        s = self.name
        check_keys(table, s, tuple(self.OPTIONS))
        parameter = opt.forcing_parameter(table, s, grid, "is swept by the analysis", context.damping)
        values = opt.linspace(table, s, "values", low=0.0, low_open=parameter == "Omega", max_num=10_000)
        modes = opt.modes(table, s)
        opt.model_modes(s, context.model, modes, table, ("poincare_points",))
        opt.damping_modes(context.damping, s, modes, None)
        max_period = opt.number(table, s, "max_period", 16, low=1, high=1000, integer=True)
        points = opt.number(table, s, "poincare_points", 0, low=0, high=100_000, integer=True)
        if points % LYAPUNOV_BLOCKS or 0 < points < 2 * max_period:
            raise JobError(f"{s}.poincare_points", points,
                           f"0 or a multiple of {LYAPUNOV_BLOCKS} of at least 2 max_period = {2 * max_period}")
        return ResponseOptions(
            parameter, values, modes, opt.prestretch(table, s, context),
            opt.steps(table, s, DEFAULT_STEPS, low=16),
            opt.number(table, s, "tol", 1e-6, low=0.0, low_open=True, high=1e-2),
            opt.number(table, s, "consecutive", 20, low=1, high=10_000, integer=True),
            opt.number(table, s, "max_periods", 30_000, low=1, high=10_000_000, integer=True),
            opt.flag(table, s, "refine_jumps", False), points, max_period,
            opt.number(table, s, "perturbation", 0.0, low=0.0, high=1.0), membrane.law)

    def variables(self, options):
        dims = (options.parameter, "direction")
        shape = (options.values[2], 2)
        K = len(options.modes)
        return [
            Variable("amplitude", dims, shape, "f8", "m",
                     "steady-state max over one period of |w(0.5 Re, 0, t)|"),
            Variable("converged", dims, shape, "i1", "1", "whether the steady-state criterion was met", -1,
                     {"flag_values": np.array([-1, 0, 1], np.int8),
                      "flag_meanings": "not_computed not_settled settled"}),
            Variable("modal_coordinate", (*dims, "mode"), (*shape, K), "f8", "m",
                     "modal coordinate q_mn of the steady state on the stroboscopic section t = 0 mod 2 pi / Omega"),
            Variable("modal_velocity", (*dims, "mode"), (*shape, K), "f8", "m s-1",
                     "modal velocity dq_mn/dt of the steady state on the stroboscopic section"),
            Variable("periods", dims, shape, "i4", "1", "forcing periods integrated at this value", -1),
            Variable("jump_value", ("direction", "jump"), (2, MAX_JUMPS), "f8", GRID_KEYS[options.parameter][0],
                     f"{options.parameter} at which the sweep jumps to another branch (adaptive brute force)"),
            Variable("rk4_steps", (), (), "i4", "1", "RK4 steps per forcing period", 0),
            *self._diagram_variables(options, dims, shape, K),
        ]

    @staticmethod
    def _diagram_variables(options, dims, shape, K):
        P = options.poincare_points
        if not P:
            return []
        return [
            Variable("poincare_coordinate", (*dims, "sample", "mode"), (*shape, P, K), "f8", "m",
                     "modal coordinate q_mn at successive stroboscopic sections after the transient"),
            Variable("poincare_velocity", (*dims, "sample", "mode"), (*shape, P, K), "f8", "m s-1",
                     "modal velocity dq_mn/dt at successive stroboscopic sections after the transient"),
            Variable("lyapunov_exponent", (*dims, "exponent"), (*shape, 2 * K), "f8", "s-1",
                     "Lyapunov exponents of the stroboscopic map along the Poincare points, decreasing"),
            Variable("lyapunov_error", (*dims, "exponent"), (*shape, 2 * K), "f8", "s-1",
                     f"statistical error of the Lyapunov exponents ({LYAPUNOV_BLOCKS} block means)"),
            Variable("response_kind", dims, shape, "i1", "1", "kind of the response after the transient", -1,
                     response_kind_attrs()),
            Variable("response_period", dims, shape, "i4", "1",
                     "least period of a periodic response in forcing periods (0: not periodic)", -1),
            Variable("rotation_number", dims, shape, "f8", "1",
                     "rotation number of a quasi-periodic response on its invariant circle, in [0, 1/2]"),
        ]

    def coords(self, options):
        units, what = GRID_KEYS[options.parameter]
        return {
            **opt.mode_coords(options.modes),
            options.parameter: ((options.parameter,), options.swept_values, {"units": units, "long_name": what}),
            **({"sample": (("sample",), np.arange(options.poincare_points),
                           {"units": "1", "long_name": "forcing periods after the transient, less one"}),
                "exponent": (("exponent",), np.arange(2 * len(options.modes)),
                             {"units": "1", "long_name": "index of the Lyapunov exponent, largest first"})}
               if options.poincare_points else {}),
            "direction": (("direction",), np.array(["up", "down"]),
                          {"units": "1", "long_name": "sweep direction of the parameter"}),
        }

    def compute(self, point, options, subtask):
        values = options.swept_values
        fmap = point.model.forced_map(point, options, default_steps=DEFAULT_STEPS).varied(options.parameter, values[0])
        steps = getattr(fmap, "steps", 0)
        res = stepped_sweep(fmap, options.parameter, values, tol=options.tol, consecutive=options.consecutive,
                            max_periods=options.max_periods,
                            min_periods=min(options.consecutive, options.max_periods),
                            poincare=options.poincare_points, max_period=options.max_period,
                            perturbation=options.perturbation)
        conv = res.converged.T
        jumps = np.full((2, MAX_JUMPS), np.nan)
        if options.refine_jumps:
            jumps = refine_jumps(fmap, options.parameter, res, max_jumps=MAX_JUMPS, tol=options.tol,
                                 consecutive=options.consecutive, max_periods=options.max_periods)
        K = len(options.modes)
        state = modal_section(fmap, res.state.transpose(1, 0, 2))  # (value, direction, 2K)
        out = {"amplitude": res.amplitude.T.copy(), "converged": conv.astype(np.int8),
               "modal_coordinate": state[..., :K].copy(), "modal_velocity": state[..., K:].copy(),
               "periods": res.periods.T.astype(np.int32), "jump_value": jumps, "rk4_steps": steps,
               "status": STATUS_OK if conv.all() else STATUS_NOT_CONVERGED}
        if res.poincare is not None:
            return out | _diagram_outputs(res.poincare, K)
        if not conv.all():
            out["message"] = (f"{np.count_nonzero(~conv)} of {conv.size} steady states did not settle within "
                              f"max_periods = {options.max_periods} (raise max_periods or tol)")
        return out

    def warmups(self, options):
        return [partial(_compile_stepped_sweep, options.modes, options.material)]

    def attributes(self, options):
        return {"swept_parameter": options.parameter}


RESPONSE = ResponseAnalysis()


def _diagram_outputs(diagram, K: int) -> dict:
    # The bifurcation diagram's variables (value, direction first) and the status: a value
    # that is not periodic is data, an unsettled one is not converged.
    def by_value(a):
        return np.ascontiguousarray(np.swapaxes(a, 0, 1))

    unsettled = np.count_nonzero(diagram.kind == UNSETTLED)
    out = {"poincare_coordinate": by_value(diagram.points[..., :K]),
           "poincare_velocity": by_value(diagram.points[..., K:]),
           "lyapunov_exponent": by_value(diagram.exponents), "lyapunov_error": by_value(diagram.error),
           "response_kind": by_value(diagram.kind), "response_period": by_value(diagram.least_period).astype(np.int32),
           "rotation_number": by_value(diagram.rotation_number),
           "status": STATUS_NOT_CONVERGED if unsettled else STATUS_OK}
    if unsettled:
        out["message"] = (f"{unsettled} of {diagram.kind.size} responses are still transient after the "
                          "transient (max_periods) and the Poincare points: raise max_periods")
    return out


def _compile_stepped_sweep(modes, material: str) -> None:
    # Response.warmups: the stepped sweep of a ROM of these modes and this material law
    rom = rom_for(Membrane(law=material), "analytic", modes)
    stepped_sweep(ForcedMap.from_loading(rom, Loading(30.0, 0.1, 1.0), steps=16), "P0", [0.1],
                  max_periods=2, min_periods=1)
