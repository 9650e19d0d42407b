"""Job-file texts and launch helpers shared by the job-file, command-line, storage and MPI
runner tests.

The ``fake`` analyses of ``fake_analysis.py`` are registered through the environment
variable ``SWEEP_EXTRA_ANALYSES`` set to :data:`EXTRA`.
"""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import xarray as xr

from sweep.launch import find_mpiexec

TESTS = Path(__file__).parent
TIMEOUT = 120  # seconds, for mpiexec and for the subprocess

EXTRA = "fake=fake_analysis:FAKE,fake_nofig=fake_analysis:FAKE_NOFIG"

GOOD = """
[job]
name = "good"
analysis = "fake"

[grid]
delta_o = [0.2, 0.3]
delta = {start = 1.1, stop = 1.5, num = 3}
Omega = 2.0

[fake]
scale = 1.0
"""


def job_text(**replace: str) -> str:
    """GOOD with some lines replaced: ``{old line: new text}`` given as keyword pairs."""
    text = GOOD
    for old, new in replace.values():
        assert old in text
        text = text.replace(old, new)
    return textwrap.dedent(text)


BAD = {
    "unknown key": (("name = ", "nme = "), ["job.nme", "unknown key", "name, analysis"]),
    "name wrong type": (('name = "good"', "name = 3"), ["job.name = 3", "a string"]),
    "name is a path": (('name = "good"', 'name = "../x"'), ["job.name = '../x'", "letters"]),
    "missing job table": (("[job]", "[jobs]"), ["job = <missing>", "[job] table is required"]),
    "unknown analysis": (('analysis = "fake"', 'analysis = "nope"'),
                         ["job.analysis = 'nope'", "'fake'", "'fake_nofig'"]),
    "delta <= 1": (("delta = {start = 1.1,", "delta = {start = 1.0,"),
                   ["grid.delta.start = 1.0", "> 1"]),
    "delta_o out of range": (("delta_o = [0.2, 0.3]", "delta_o = [0.2, 1.0]"),
                             ["grid.delta_o[1] = 1.0", "in the open interval (0, 1)"]),
    "Omega <= 0": (("Omega = 2.0", "Omega = 0"), ["grid.Omega = 0", "> 0 (rad s-1)"]),
    "c < 0": (("Omega = 2.0", "c = -1e-3"), ["grid.c = -0.001", ">= 0 (N s m-3)"]),
    "P0 not finite": (("Omega = 2.0", "P0 = inf"), ["grid.P0 = inf", "finite number >= 0"]),
    "NaN": (("Omega = 2.0", "Omega = nan"), ["grid.Omega = nan", "finite number > 0"]),
    "bool for a number": (("Omega = 2.0", "Omega = true"), ["grid.Omega = True", "a number"]),
    "string in a list": (("delta_o = [0.2, 0.3]", 'delta_o = [0.2, "0.3"]'),
                         ["grid.delta_o[1] = '0.3'", "finite number in the open interval (0, 1)"]),
    "empty list": (("delta_o = [0.2, 0.3]", "delta_o = []"),
                   ["grid.delta_o = []", "non-empty list", "empty grid"]),
    "empty grid table": (("delta_o = [0.2, 0.3]\ndelta = {start = 1.1, stop = 1.5, num = 3}\n"
                          "Omega = 2.0", ""), ["grid = {}", "at least one of the keys delta"]),
    "num = 0": (("num = 3", "num = 0"), ["grid.delta.num = 0", "integer >= 1"]),
    "num float": (("num = 3", "num = 3.0"), ["grid.delta.num = 3.0", "integer >= 1"]),
    "range key missing": (("stop = 1.5, ", ""), ["grid.delta.stop = <missing>", "required"]),
    "range unknown key": (("num = 3", "num = 3, step = 1"), ["grid.delta.step", "unknown key"]),
    "case key": (("Omega = 2.0", "Omega = 2.0\ncases = [{P1 = 1.0}]"),
                 ["grid.cases = {'P1': 1.0}", "case keys must be grid keys of this job"]),
    "case value": (("Omega = 2.0", "Omega = 2.0\ncases = [{delta = 1.2}]"),
                   ["delta = 1.2 is not a value of grid.delta"]),
    "no cases": (("Omega = 2.0", "Omega = 2.0\ncases = []"), ["grid.cases = []", "non-empty list of tables"]),
    "range bad scale": (("num = 3", 'num = 3, scale = "ln"'), ["grid.delta.scale = 'ln'", '"log"']),
    "duplicates": (("delta_o = [0.2, 0.3]", "delta_o = [0.2, 0.2]"),
                   ["grid.delta_o = [0.2, 0.2]", "distinct values (0.2 repeats)"]),
    "unknown grid key": (("Omega = 2.0", "omega = 2.0"),
                         ["grid.omega = 2.0", "unknown key", "delta, delta_o, Omega, P0, c"]),
    "unknown table": (("[fake]", "[fak]\nscale = 1\n[fake]"),
                      ["fak = {'scale': 1}", "unknown table", "[job], [model], [membrane], [damping], [grid], [fake]"]),
    "table is a value": (("[job]", "membrane = 3\n[job]"),
                         ["membrane = 3", "a [membrane] table"]),
    "membrane h <= 0": (("[grid]", "[membrane]\nh = 0.0\n[grid]"),
                        ["membrane.h = 0.0", "> 0 (m)"]),
    "membrane unknown key": (("[grid]", "[membrane]\nE = 1.0\n[grid]"),
                             ["membrane.E = 1.0", "C1, h, Gamma, Re, law, C2, Jm"]),
    "membrane law": (("[grid]", '[membrane]\nlaw = "ogden"\n[grid]'),
                     ["membrane.law = 'ogden'", '"neo-hookean", "mooney-rivlin", "gent"']),
    "constant of another law": (("[grid]", "[membrane]\nJm = 50.0\n[grid]"),
                                ["membrane.Jm = 50.0", "left at inf with law = 'neo-hookean'", '"gent"']),
    "grid constant of another law": (("Omega = 2.0", "Omega = 2.0\nC2 = [0.0, 1e4]"),
                                     ["grid.C2 = [0.0, 10000.0]", "a constant of another material law",
                                      "this job's law is 'neo-hookean'"]),
    "material constant twice": (("[grid]", '[membrane]\nlaw = "gent"\nJm = 50.0\n[grid]\nJm = [20.0, 30.0]'),
                                ["grid.Jm = [20.0, 30.0]", "set in [membrane] already"]),
    "Gent Jm <= 0": (("[grid]", '[membrane]\nlaw = "gent"\n[grid]\nJm = 0.0'),
                     ["grid.Jm = 0.0", "> 0 or inf"]),
    "law without its constant": (("[grid]", '[membrane]\nlaw = "mooney-rivlin"\n[grid]'),
                                 ["membrane.C2 = <missing>", "law = 'mooney-rivlin' needs its constant C2 (Pa)"]),
    "required grid key": (("delta = {start = 1.1, stop = 1.5, num = 3}", ""),
                          ["grid.delta = <missing>", "analysis 'fake' needs grid keys delta"]),
    "missing analysis table": (("[fake]\nscale = 1.0", ""),
                               ["fake.scale = <missing>", "a number > 0 is required"]),
    "chunk = 0": (('analysis = "fake"', 'analysis = "fake"\nchunk = 0'),
                  ["job.chunk = 0", "integer > 0"]),
    "malformed TOML": (("Omega = 2.0", "Omega = = 2"), ["job file = 'bad.toml'", "TOML syntax",
                                                         "line"]),
}

#: A 48-task job of the fake analysis (6 x 4 grid, 2 subtasks, chunks of 3 tasks).
MPI_JOB = """
[job]
name = "mpi"
analysis = "fake"
chunk = 3

[grid]
delta = [1.1, 1.2, 1.3, 1.4, 1.5, 1.6]
delta_o = [0.2, 0.4, 0.6, 0.8]
Omega = 2.0

[fake]
scale = 1.0
n_sub = 2
sleep = {sleep}
"""


def mpiexec() -> str:
    """The ``mpiexec`` of this environment (a missing one fails the test, never skips it)."""
    path = find_mpiexec()
    if path is None:
        pytest.fail("mpiexec not found next to the Python executable nor on PATH")
    return path


def sweep_env(pythonpath: Path = TESTS, **extra: str) -> dict[str, str]:
    """Environment of a ``python -m sweep`` subprocess with the fake analyses registered."""
    return {**os.environ, "PYTHONPATH": str(pythonpath), "SWEEP_EXTRA_ANALYSES": EXTRA,
            "MPIEXEC_TIMEOUT": str(TIMEOUT), **extra}


def sweep(*args, ranks: int, cwd: Path, pythonpath: Path = TESTS, **extra: str) -> subprocess.CompletedProcess:
    """``python -m sweep ARGS``, under ``mpiexec -n RANKS`` when ranks > 0."""
    launch = [mpiexec(), "-n", str(ranks), sys.executable, "-m", "mpi4py"] if ranks else [sys.executable]
    return subprocess.run([*launch, "-m", "sweep", *map(str, args)], cwd=cwd, env=sweep_env(pythonpath, **extra),
                          capture_output=True, text=True, timeout=TIMEOUT)


def data(path: Path) -> xr.Dataset:
    """A result loaded (what differs from run to run is in its ``run`` group, not loaded)."""
    with xr.open_dataset(path) as ds:
        return ds.load()
