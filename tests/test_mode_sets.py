"""Mode sets as a sweep dimension: a job over several mode sets gives, set by set, exactly
what a job of that set alone gives, padded to the largest set along the mode dimensions."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from sweep import cli, figures
from sweep.analyses import get
from sweep.analyses.base import JobError
from sweep.analyses.mode_sets import INT_PAD, is_mode_set_list, select, set_label
from sweep.jobspec import parse_job

BACKBONE_JOB = """
[job]
name = "{name}"
analysis = "backbone"
[grid]
delta = [1.1, 1.3]
delta_o = 0.2
[backbone]
modes = {modes}
prestretch = "analytic"
amplitude = {{start = 0.001, stop = 0.1, num = 3}}
"""

BASINS_JOB = """
[job]
name = "{name}"
analysis = "basins"
[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
P0 = 1.0
c = 0.05
[basins]
modes = {modes}
tiles = 2
ic_x = {{start = -0.3, stop = 0.3, num = 5}}
ic_y = {{start = -10.0, stop = 10.0, num = 4}}
"""

CONTINUATION_JOB = """
[job]
name = "{name}"
analysis = "continuation"
[grid]
delta = 1.1
delta_o = 0.2
P0 = 1.0
c = 0.05
[continuation]
parameter = "Omega"
start = 30.0
stop = 40.0
ds_max = 0.5
max_points = 60
steps = 64
modes = {modes}
"""


def _close(made):
    """Close the figures that figures.make handed back."""
    import matplotlib.pyplot as plt

    for fig in made.values():
        plt.close(fig)


def _run(tmp_path, template, name, modes):
    job = tmp_path / f"{name}.toml"
    job.write_text(template.format(name=name, modes=modes))
    out = tmp_path / f"{name}.nc"
    assert cli.main(["run", str(job), "-o", str(out), "--progress", "none"]) == 0
    return xr.load_dataset(out)


def test_backbone_over_mode_sets_equals_the_sets_alone_and_pads(tmp_path):
    both = _run(tmp_path, BACKBONE_JOB, "both", "[[[1, 0]], [[1, 0], [2, 0]]]")
    assert list(both.mode_set.values) == ["(1,0)", "(1,0)+(2,0)"]
    assert list(both.n_modes.values) == [1, 2]
    assert both.omega_nl.dims[0] == "mode_set" and both.sizes["mode"] == 2
    for name, modes in (("one", "[[1, 0]]"), ("two", "[[1, 0], [2, 0]]")):
        alone = _run(tmp_path, BACKBONE_JOB, name, modes)
        part = select(both, set_label(tuple(map(tuple, eval(modes)))))
        for var in alone.data_vars:
            xr.testing.assert_identical(part[var], alone[var])
    padded = both.sel(mode_set="(1,0)")
    assert list(padded.m.values) == [1, INT_PAD]
    assert np.isnan(padded.modal_amplitude.isel(mode=1)).all()
    assert not np.isnan(padded.modal_amplitude.isel(mode=0)).any()


def test_continuation_over_mode_sets_cuts_every_padded_dimension_back(tmp_path):
    # multipliers (2K) are padded too, and point_family exists only for the mixed set
    both = _run(tmp_path, CONTINUATION_JOB, "both", "[[[1, 0]], [[1, 0], [1, 1]]]")
    assert list(both.multiplier_extent.values) == [2, 4] and list(both.mode_extent.values) == [1, 2]
    assert both.point_family.attrs["absent_in_mode_sets"] == "(1,0)"
    for name, modes, label in (("one", "[[1, 0]]", "(1,0)"), ("mixed", "[[1, 0], [1, 1]]", "(1,0)+(1,1)")):
        alone = _run(tmp_path, CONTINUATION_JOB, name, modes)
        part = select(both, label)
        assert set(part.data_vars) == set(alone.data_vars)
        for var in alone.data_vars:
            xr.testing.assert_identical(part[var], alone[var])
    made = figures.make(get("continuation"), both)
    assert len(made["branch_Omega_mode_sets"].axes[0].lines) == 2
    _close(made)


def test_basins_over_mode_sets_assemble_each_set_as_alone(tmp_path):
    both = _run(tmp_path, BASINS_JOB, "both", "[[[1, 0]], [[2, 0]]]")
    for name, modes, label in (("one", "[[1, 0]]", "(1,0)"), ("two", "[[2, 0]]", "(2,0)")):
        alone = _run(tmp_path, BASINS_JOB, name, modes)
        part = select(both, label)
        for var in ("label", "basin_fraction", "attractor_coordinate", "status"):
            xr.testing.assert_equal(part[var], alone[var])
            assert str(part[var].attrs) == str(alone[var].attrs)
    # the lattice axes are the mode of each set: their long names say so set by set, and
    # each set selected has its own again
    assert both["ic_x"].attrs["long_name"] == ("(1,0): initial displacement of mode (1, 0); "
                                               "(2,0): initial displacement of mode (2, 0)")
    for label, mode in (("(1,0)", "(1, 0)"), ("(2,0)", "(2, 0)")):
        assert select(both, label)["ic_x"].attrs == {"units": "m", "long_name": f"initial displacement of mode {mode}"}
    made = figures.make(get("basins"), both)
    assert len(made["basin_fraction_mode_sets"].axes[0].patches) == 2
    _close(made)


def test_figures_of_a_mode_set_result_are_drawn_set_by_set(tmp_path):
    both = _run(tmp_path, BACKBONE_JOB, "both", "[[[1, 0]], [[1, 0], [2, 0]]]")
    made = figures.make(get("backbone"), both)
    assert sorted(made) == ["backbone_mode_sets", "modes_1_0-2_0/backbone", "modes_1_0-2_0/modal_amplitudes",
                            "modes_1_0/backbone", "modes_1_0/modal_amplitudes"]
    assert len(made["backbone_mode_sets"].axes[0].lines) == 4   # one backbone per set and delta
    _close(made)
    paths = figures.draw(get("backbone"), both, tmp_path / "fig")
    assert {p.parent.name for p in paths} == {"fig", "modes_1_0", "modes_1_0-2_0"}


@pytest.mark.parametrize("modes,message", [
    ("[[[1, 0]], [[0, 0]]]", r"backbone.modes\[1\] = \[0, 0\] is invalid: each mode needs m >= 1"),
    ("[[[1, 0]], [[1, 0]]]", r"backbone.modes = .* is invalid: the mode sets must be distinct"),
    ("[[[1, 0]], [[1, 0], [1, 0]]]", r"backbone.modes\[1\] = .* is invalid: modes must be distinct"),
    ("[[[1, 0]], [{n = 1, radial = 0}]]", r"backbone.modes\[1\].radial = 0 is invalid: must be >= 1"),
])
def test_bad_mode_sets_name_the_set(modes, message):
    with pytest.raises(JobError, match=message):
        parse_job(BACKBONE_JOB.format(name="bad", modes=modes))


def test_one_mode_set_is_not_a_list_of_sets():
    assert not is_mode_set_list([[1, 0], [2, 0]])
    assert not is_mode_set_list([{"n": 1, "radial": 2}])
    assert is_mode_set_list([[[1, 0]], [{"n": 0, "radial": 2}]])
    job = parse_job(BACKBONE_JOB.format(name="plain", modes="[[1, 0], [2, 0]]"))
    assert job.analysis is get("backbone")


def test_a_set_result_not_as_declared_fails_the_run(tmp_path, monkeypatch, capsys):
    """The mode-set wrapper checks each set's result against the analysis' declarations
    before padding it (as the runner checks any result): a wrong shape is a bug of the
    analysis, which stops the run naming the task, not a failed task."""
    backbone = get("backbone")
    original = backbone.compute

    def short_amplitude(point, options, subtask):
        result = original(point, options, subtask)
        name = next(v.name for v in backbone.variables(options) if v.shape)
        return {**result, name: np.asarray(result[name])[..., :1]}

    monkeypatch.setattr(backbone, "compute", short_amplitude)
    job = tmp_path / "bad.toml"
    job.write_text(BACKBONE_JOB.format(name="bad", modes="[[[1, 0]], [[1, 0], [2, 0]]]"))
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc"), "--progress", "none"]) == 1
    err = capsys.readouterr().err
    assert "error: task " in err and "with shape" in err


#: Compiles one warmup call of a job in a fresh process (argv: job file, call index) and
#: prints the signatures it compiled of each cached kernel of model/, as JSON.
_WARMUP_CALL = """
import json, sys
from numba.core import event
compiled = {}
class Listener(event.Listener):
    def on_start(self, ev):
        pass
    def on_end(self, ev):
        d = ev.data["dispatcher"]
        f = d.py_func
        # cached kernels only: the inline overloads of model.material_kernels are compiled
        # into their callers and never written to the cache
        if f.__module__.startswith("model.") and type(d._cache).__name__ != "NullCache":
            compiled.setdefault(f"{f.__module__}.{f.__qualname__}", []).append(str(ev.data["args"]))
event.register("numba:compile", Listener())
from sweep.jobspec import load_job
job = load_job(sys.argv[1])
job.analysis.warmups(job.options)[int(sys.argv[2])]()
print(json.dumps(compiled))
"""


def test_warmup_calls_never_compile_one_kernel_with_different_types(tmp_path):
    """The runner makes an analysis' warmup calls concurrently on the ranks of a node, and
    numba's cache index is not safe against two processes adding different signatures of
    one kernel at once (Analysis.warmups).  Each call of a basins job over a one- and a
    two-mode set, in a fresh process with an empty cache: a kernel of model/ compiled by
    two calls has the same signatures, in the same order (numba numbers a kernel's cache
    files in the order its signatures arrive), in both.  (With the calls of the sets listed
    one after the other, the two sets' classifier kernels clash.)"""
    job = tmp_path / "job.toml"
    job.write_text(BASINS_JOB.format(name="warm", modes="[[[1, 0]], [[1, 0], [2, 0]]]"))
    parsed = parse_job(job.read_text(), str(job))
    n_calls = len(parsed.analysis.warmups(parsed.options))
    assert n_calls >= 2
    compiled = []
    for first in range(0, n_calls, 2):  # two at a time (the machine's cores), each in its own process and cache
        procs = [subprocess.Popen([sys.executable, "-c", _WARMUP_CALL, str(job), str(i)],
                                  env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / f"cache-{i}")},
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                 for i in range(first, min(first + 2, n_calls))]
        for proc in procs:
            out, err = proc.communicate(timeout=600)
            assert proc.returncode == 0, err
            compiled.append(json.loads(out.splitlines()[-1]))  # kernel -> signatures in compilation order
    assert all(len(c) > 3 for c in compiled)  # each call compiles kernels of its own
    clashes = {(i, j, name): (a[name], b[name]) for i, a in enumerate(compiled) for j, b in enumerate(compiled)
               if i < j for name in set(a) & set(b) if a[name] != b[name]}
    assert clashes == {}
