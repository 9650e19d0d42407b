"""A cheap, deterministic analysis for the runner's tests (registered through
``SWEEP_EXTRA_ANALYSES="fake=fake_analysis:FAKE,fake_nofig=fake_analysis:FAKE_NOFIG"`` with
``tests/`` on ``PYTHONPATH``).

Job options, table ``[fake]``: ``scale`` (required, > 0), ``n_sub`` (subtasks per point,
default 1), ``sleep`` (seconds per task, default 0), ``fail_delta`` (a task at this delta
raises, default none).  Test hooks through the environment: ``FAKE_SWEEP_LOG`` (a file
to which each computed task appends one line ``delta delta_o Omega subtask``) and
``FAKE_SWEEP_KILL_AFTER`` (SIGKILL the computing process once that log has this many
lines), which leave the job file, hence its hash, unchanged between a run and its resume.
"""

from __future__ import annotations

import math
import os
import signal
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sweep import figures
from sweep.analyses.base import (DEFAULT_CONTEXT, MISSING, STATUS_NOT_CONVERGED, STATUS_OK, Analysis,
                                 JobError, Variable)


@dataclass(frozen=True)
class FakeOptions:
    scale: float
    n_sub: int = 1
    sleep: float = 0.0
    fail_delta: float | None = None


class Fake(Analysis):
    name = "fake"
    required_grid = ("delta",)

    def parse_options(self, table, grid, membrane, context=DEFAULT_CONTEXT):
        for key in table:
            if key not in ("scale", "n_sub", "sleep", "fail_delta"):
                raise JobError(f"fake.{key}", table[key], "unknown key")
        scale = table.get("scale", MISSING)
        if not isinstance(scale, (int, float)) or isinstance(scale, bool) or scale <= 0:
            raise JobError("fake.scale", scale, "a number > 0 is required")
        return FakeOptions(float(scale), int(table.get("n_sub", 1)),
                           float(table.get("sleep", 0.0)), table.get("fail_delta"))

    def variables(self, options):
        return [Variable("value", (), (), "f8", "m", "a value"),
                Variable("profile", ("rho",), (4,), "f8", "m", "a profile"),
                Variable("count", (), (), "i4", "1", "a count", -1)]

    def coords(self, options):
        return {"rho": (("rho",), np.linspace(0.2, 1.0, 4),
                        {"units": "m", "long_name": "radial coordinate"})}

    def n_subtasks(self, options):
        return options.n_sub

    def compute(self, point, options, subtask):
        log = os.environ.get("FAKE_SWEEP_LOG")
        if log:
            line = f"{point.grid['delta']!r} {point.grid.get('delta_o')!r} {point.grid.get('Omega')!r} {subtask}\n"
            with open(log, "a") as f:
                f.write(line)
            kill_after = os.environ.get("FAKE_SWEEP_KILL_AFTER")
            if kill_after and len(Path(log).read_text().splitlines()) >= int(kill_after):
                os.kill(os.getpid(), signal.SIGKILL)
        if options.fail_delta is not None and point.grid["delta"] == options.fail_delta:
            raise ZeroDivisionError("the fake analysis fails here on purpose")
        time.sleep(options.sleep)
        phase = 3 * point.grid["delta"] + 7 * point.grid.get("delta_o", 0.0) + point.grid.get("Omega", 0.0)
        value = options.scale * math.sin(phase) * point.membrane.h * 1e3 + subtask
        return {"value": value,
                "profile": value * np.linspace(0.2, 1.0, 4),
                "count": np.int32(10 * point.grid["delta"]) + subtask,
                "status": STATUS_NOT_CONVERGED if math.sin(phase) < -0.9 else STATUS_OK}

class FakeNoFigures(Fake):
    name = "fake_nofig"


def _figures(ds, outdir):
    path = Path(outdir) / "value.png"
    path.write_bytes(b"\x89PNG fake")
    return [path]


FAKE = Fake()
FAKE_NOFIG = FakeNoFigures()
figures.register(FAKE.name, _figures)
