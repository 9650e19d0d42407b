"""Job file validation, task layout and the analysis registry (in-process, no MPI)."""

import importlib.util
import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from sweep import analyses
from sweep.analyses.base import JobError
from sweep.grid import MAX_DEFAULT_CHUNKS, default_chunk
from sweep.jobspec import MEMBRANE_DEFAULTS, load_job, parse_job

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


@pytest.fixture(autouse=True)
def fake_registered(monkeypatch):
    monkeypatch.setenv(analyses.EXTRA_ENV, EXTRA)


def job_text(**replace: str) -> str:
    """GOOD with some lines replaced: ``{old line: new text}`` given as keyword pairs."""
    text = GOOD
    for old, new in replace.values():
        assert old in text
        text = text.replace(old, new)
    return textwrap.dedent(text)


def test_layout_is_canonical_c_order_with_membrane_defaults():
    job = parse_job(GOOD)
    layout = job.layout
    assert layout.dims == ("delta", "delta_o", "Omega")
    assert layout.shape == (3, 2, 1)
    assert layout.n_tasks == 6 and layout.n_subtasks == 1
    np.testing.assert_array_equal(layout.values[0], [1.1, 1.3, 1.5])
    point, subtask = job.point(1)
    assert point == {"delta": 1.1, "delta_o": 0.3, "Omega": 2.0, **MEMBRANE_DEFAULTS}
    assert subtask == 0
    assert job.point(2)[0]["delta"] == 1.3
    assert layout.describe(5) == "task 5 of 6 (delta=1.5, delta_o=0.3, Omega=2.0, subtask 0)"


def test_subtasks_vary_fastest_and_chunks_cover_all_tasks():
    job = parse_job(job_text(a=("scale = 1.0", "scale = 1.0\nn_sub = 3"),
                             b=('analysis = "fake"', 'analysis = "fake"\nchunk = 4')))
    layout = job.layout
    assert layout.n_tasks == 18 and layout.n_chunks == 5
    assert job.point(4) == (job.point(3)[0], 1)
    assert [t for k in range(layout.n_chunks) for t in layout.chunk_tasks(k)] == list(range(18))


def test_membrane_table_and_single_numbers():
    job = parse_job(job_text(a=("[grid]", "[membrane]\nh = 2e-3\nC1 = 1\n\n[grid]")))
    assert job.membrane == {**MEMBRANE_DEFAULTS, "h": 2e-3, "C1": 1.0}
    assert isinstance(job.membrane["C1"], float)


def test_default_chunk_bounds_the_number_of_part_files():
    assert default_chunk(1) == 1
    assert default_chunk(MAX_DEFAULT_CHUNKS) == 1
    assert default_chunk(MAX_DEFAULT_CHUNKS + 1) == 2


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
                             ["grid.delta_o[1] = 1.0", "in (0, 1)"]),
    "Omega <= 0": (("Omega = 2.0", "Omega = 0"), ["grid.Omega = 0", "> 0 (rad s-1)"]),
    "c < 0": (("Omega = 2.0", "c = -1e-3"), ["grid.c = -0.001", ">= 0 (N s m-3)"]),
    "P0 not finite": (("Omega = 2.0", "P0 = inf"), ["grid.P0 = inf", "finite number >= 0"]),
    "NaN": (("Omega = 2.0", "Omega = nan"), ["grid.Omega = nan", "finite number > 0"]),
    "bool for a number": (("Omega = 2.0", "Omega = true"), ["grid.Omega = True", "a number"]),
    "string in a list": (("delta_o = [0.2, 0.3]", 'delta_o = [0.2, "0.3"]'),
                         ["grid.delta_o[1] = '0.3'", "finite number in (0, 1)"]),
    "empty list": (("delta_o = [0.2, 0.3]", "delta_o = []"),
                   ["grid.delta_o = []", "non-empty list", "empty grid"]),
    "empty grid table": (("delta_o = [0.2, 0.3]\ndelta = {start = 1.1, stop = 1.5, num = 3}\n"
                          "Omega = 2.0", ""), ["grid = {}", "at least one of the keys delta"]),
    "num = 0": (("num = 3", "num = 0"), ["grid.delta.num = 0", "integer >= 1"]),
    "num float": (("num = 3", "num = 3.0"), ["grid.delta.num = 3.0", "integer >= 1"]),
    "range key missing": (("stop = 1.5, ", ""), ["grid.delta.stop = <missing>", "required"]),
    "range unknown key": (("num = 3", "num = 3, step = 1"), ["grid.delta.step", "unknown key"]),
    "duplicates": (("delta_o = [0.2, 0.3]", "delta_o = [0.2, 0.2]"),
                   ["grid.delta_o = [0.2, 0.2]", "distinct values (0.2 repeats)"]),
    "unknown grid key": (("Omega = 2.0", "omega = 2.0"),
                         ["grid.omega = 2.0", "unknown key", "delta, delta_o, Omega, P0, c"]),
    "unknown table": (("[fake]", "[fak]\nscale = 1\n[fake]"),
                      ["fak = {'scale': 1}", "unknown table", "[job], [membrane], [grid], [fake]"]),
    "table is a value": (("[job]", "membrane = 3\n[job]"),
                         ["membrane = 3", "a [membrane] table"]),
    "membrane h <= 0": (("[grid]", "[membrane]\nh = 0.0\n[grid]"),
                        ["membrane.h = 0.0", "> 0 (m)"]),
    "membrane unknown key": (("[grid]", "[membrane]\nE = 1.0\n[grid]"),
                             ["membrane.E = 1.0", "C1, h, Gamma, Re"]),
    "required grid key": (("delta = {start = 1.1, stop = 1.5, num = 3}", ""),
                          ["grid.delta = <missing>", "analysis 'fake' needs grid keys delta"]),
    "missing analysis table": (("[fake]\nscale = 1.0", ""),
                               ["fake.scale = <missing>", "a number > 0 is required"]),
    "chunk = 0": (('analysis = "fake"', 'analysis = "fake"\nchunk = 0'),
                  ["job.chunk = 0", "integer > 0"]),
    "negative seed": (('analysis = "fake"', 'analysis = "fake"\nseed = -1'),
                      ["job.seed = -1", "integer >= 0"]),
    "malformed TOML": (("Omega = 2.0", "Omega = = 2"), ["job file = 'bad.toml'", "TOML syntax",
                                                         "line"]),
}


@pytest.mark.parametrize("kind", sorted(BAD))
def test_bad_job_message_names_key_value_and_allowed(kind):
    (old, new), expected = BAD[kind]
    with pytest.raises(JobError) as info:
        parse_job(job_text(a=(old, new)), "bad.toml")
    for text in expected:
        assert text in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(JobError, match=r"job file = '.*nope.toml' is invalid: an existing "
                                       r"file \(no such file\)"):
        load_job(tmp_path / "nope.toml")


def test_registry_lists_existing_modules_without_importing_them():
    code = ("import json, sys, sweep.cli; from sweep import analyses; "
            "print(json.dumps([sorted(analyses.registry()), sorted(m for m in sys.modules if m in "
            "('numba', 'mpi4py.MPI', 'xarray') or m.startswith(('model', 'sweep.analyses.')))]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60, check=True).stdout
    listed, imported = json.loads(out)
    assert {"fake", "fake_nofig"} <= set(listed)
    for name in ("static", "linear", "backbone", "response", "continuation", "basins"):
        module = f"sweep.analyses.{name}"
        assert (name in listed) == (importlib.util.find_spec(module) is not None)
    assert imported == ["sweep.analyses.base"]


def test_malformed_extra_registry_entry(monkeypatch):
    monkeypatch.setenv(analyses.EXTRA_ENV, "fake")
    with pytest.raises(JobError, match="SWEEP_EXTRA_ANALYSES = 'fake' is invalid: "
                                       "comma-separated name=module:attribute items"):
        analyses.registry()


def test_registry_entry_that_is_not_an_analysis(monkeypatch):
    monkeypatch.setenv(analyses.EXTRA_ENV, "odd=fake_analysis:FakeOptions")
    with pytest.raises(TypeError, match="fake_analysis:FakeOptions is a type, not an Analysis"):
        analyses.get("odd")


def test_job_file_not_utf8(tmp_path):
    path = tmp_path / "latin.toml"
    path.write_bytes(b"# \xe9\n")
    with pytest.raises(JobError, match=r"latin.toml' is invalid: a readable UTF-8 text file"):
        load_job(path)
