"""Analysis ``static``: the radial pre-stretch (paper section 3, Figs. 2-3).

Per grid point: the deformed radius ``r_o``, the principal stresses ``sigma_1``,
``sigma_2`` on a common radial coordinate ``rho`` (NaN where ``rho < Ro``), and the edge
traction of Eq. (16).  Options: :attr:`StaticAnalysis.OPTIONS` (``docs/options.md``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import options as opt
from .base import DEFAULT_CONTEXT, STATUS_OK, Analysis, JobError, Variable, check_keys


@dataclass(frozen=True)
class StaticOptions:
    prestretch: str
    rho: tuple[float, float, int]

    @property
    def radii(self) -> np.ndarray:
        return np.linspace(*self.rho)


class StaticAnalysis(Analysis):
    """Static pre-stretch: ``r_o(rho)``, ``sigma_1``, ``sigma_2`` and the edge traction."""

    name = "static"
    model_needs = ("static_state",)
    #: The option table ``[static]``: key -> description (docs/options.md).
    OPTIONS = {
        "prestretch": "analytic (Eq. 21) | numeric (Eq. 15, default) | fit (Eq. 18)",
        "rho": "{start, stop, num}: undeformed radii of the profiles (m; default from the smallest "
               "inner radius of the grid to Re, 201 points)",
    }

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        check_keys(table, self.name, tuple(self.OPTIONS))
        re = membrane.Re
        default = {"start": float(np.min(grid["delta_o"])) * re, "stop": re, "num": 201}
        rho = opt.linspace(table, self.name, "rho", default, low=0.0, low_open=True)
        if rho[1] > re or rho[0] > rho[1]:
            raise JobError("static.rho", table.get("rho"), f"need 0 < start <= stop <= Re = {re} m")
        return StaticOptions(opt.prestretch(table, self.name, context), rho)

    def variables(self, options):
        n = options.rho[2]
        return [
            Variable("r_o", ("rho",), (n,), "f8", "m", "deformed radius of the pre-stretched membrane"),
            Variable("sigma_1", ("rho",), (n,), "f8", "Pa", "radial principal Cauchy stress"),
            Variable("sigma_2", ("rho",), (n,), "f8", "Pa", "circumferential principal Cauchy stress"),
            Variable("traction", (), (), "f8", "N m-1", "edge traction per unit undeformed length (Eq. 16)"),
        ]

    def coords(self, options):
        return {"rho": (("rho",), options.radii, {"units": "m", "long_name": "undeformed radial coordinate"})}

    def compute(self, point, options, subtask):
        m = point.membrane
        ps = point.model.static_state(point, options)
        rho = options.radii
        inside = (rho >= m.Ro * (1 - 1e-12)) & (rho <= m.Re * (1 + 1e-12))
        r = np.full(rho.shape, np.nan)
        s1, s2 = r.copy(), r.copy()
        r[inside] = ps.radius(rho[inside])
        s1[inside], s2[inside] = ps.stresses(rho[inside])
        return {"r_o": r, "sigma_1": s1, "sigma_2": s2, "traction": np.float64(ps.traction()),
                "status": STATUS_OK}


STATIC = StaticAnalysis()
