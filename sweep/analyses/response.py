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
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np

from model.forced import DEFAULT_STEPS, ForcedMap
from model.params import Loading, Membrane
from model.response import refine_jumps, stepped_sweep

from sweep.models.rom import rom_for

from . import options as opt
from .base import DEFAULT_CONTEXT, GRID_KEYS, STATUS_NOT_CONVERGED, STATUS_OK, Analysis, Variable, check_keys


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
    }

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        s = self.name
        check_keys(table, s, tuple(self.OPTIONS))
        parameter = opt.forcing_parameter(table, s, grid, "is swept by the analysis", context.damping)
        values = opt.linspace(table, s, "values", low=0.0, low_open=parameter == "Omega", max_num=10_000)
        modes = opt.modes(table, s)
        opt.damping_modes(context.damping, s, modes, None)
        return ResponseOptions(
            parameter, values, modes, opt.prestretch(table, s, context),
            opt.steps(table, s, DEFAULT_STEPS, low=16),
            opt.number(table, s, "tol", 1e-6, low=0.0, low_open=True, high=1e-2),
            opt.number(table, s, "consecutive", 20, low=1, high=10_000, integer=True),
            opt.number(table, s, "max_periods", 30_000, low=1, high=10_000_000, integer=True),
            opt.flag(table, s, "refine_jumps", False), membrane.law)

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
        ]

    def coords(self, options):
        units, what = GRID_KEYS[options.parameter]
        return {
            **opt.mode_coords(options.modes),
            options.parameter: ((options.parameter,), options.swept_values, {"units": units, "long_name": what}),
            "direction": (("direction",), np.array(["up", "down"]),
                          {"units": "1", "long_name": "sweep direction of the parameter"}),
        }

    def compute(self, point, options, subtask):
        values = options.swept_values
        fmap = point.model.forced_map(point, options, default_steps=DEFAULT_STEPS).varied(options.parameter, values[0])
        steps = getattr(fmap, "steps", 0)
        res = stepped_sweep(fmap, options.parameter, values, tol=options.tol, consecutive=options.consecutive,
                            max_periods=options.max_periods,
                            min_periods=min(options.consecutive, options.max_periods))
        conv = res.converged.T
        jumps = np.full((2, MAX_JUMPS), np.nan)
        if options.refine_jumps:
            jumps = refine_jumps(fmap, options.parameter, res, max_jumps=MAX_JUMPS, tol=options.tol,
                                 consecutive=options.consecutive, max_periods=options.max_periods)
        K = len(options.modes)
        state = res.state.transpose(1, 0, 2)  # (value, direction, 2K)
        out = {"amplitude": res.amplitude.T.copy(), "converged": conv.astype(np.int8),
               "modal_coordinate": state[..., :K].copy(), "modal_velocity": state[..., K:].copy(),
               "periods": res.periods.T.astype(np.int32), "jump_value": jumps, "rk4_steps": steps,
               "status": STATUS_OK if conv.all() else STATUS_NOT_CONVERGED}
        if not conv.all():
            out["message"] = (f"{np.count_nonzero(~conv)} of {conv.size} steady states did not settle within "
                              f"max_periods = {options.max_periods} (raise max_periods or tol)")
        return out

    def warmups(self, options):
        return [partial(_compile_stepped_sweep, options.modes, options.material)]

    def attributes(self, options):
        return {"swept_parameter": options.parameter}


RESPONSE = ResponseAnalysis()


def _compile_stepped_sweep(modes, material: str) -> None:
    # Response.warmups: the stepped sweep of a ROM of these modes and this material law
    rom = rom_for(Membrane(law=material), "analytic", modes)
    stepped_sweep(ForcedMap.from_loading(rom, Loading(30.0, 0.1, 1.0), steps=16), "P0", [0.1],
                  max_periods=2, min_periods=1)
