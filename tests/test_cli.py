"""The command line in-process, on one rank: every error path checked on its message."""

import io
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sweep import analyses, cli
from sweep.storage.netcdf import run_attributes
from sweep.progress import Progress, format_duration
from jobfiles import BAD, EXTRA, GOOD, job_text

import fake_analysis

JOBS = Path(__file__).resolve().parents[1] / "jobs"

JOB = GOOD.replace('analysis = "fake"', 'analysis = "fake"\nchunk = 2')


@pytest.fixture
def job(tmp_path):
    path = tmp_path / "job.toml"
    path.write_text(JOB)
    return path


def run(capsys, *argv):
    """``cli.main(argv)`` -> (exit status, stdout, stderr)."""
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def data(path):
    with xr.open_dataset(path) as ds:
        return ds.load()


def test_plan_prints_layout_and_computes_nothing(capsys, job, tmp_path):
    code, out, _ = run(capsys, "plan", job)
    assert code == 0
    assert "grid shape (3, 2, 1) (dims delta, delta_o, Omega)" in out
    assert "tasks: 6 in 3 chunk(s) of 2 task(s) (the last holds 2)" in out
    assert "output: good.nc" in out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["job.toml"]


def test_run_status_collect(capsys, job, tmp_path):
    out_nc = tmp_path / "r.nc"
    code, out, err = run(capsys, "run", job, "-o", out_nc, "--report-memory")
    assert code == 0, err
    assert f"wrote {out_nc}: 6 / 6 tasks: " in out and ", 0 failed; 6 computed by this run on 1 rank(s)" in out
    assert "6 / 6 tasks (100%)" in err and "memory: peak RSS per rank" in err
    first = data(out_nc)
    run_attrs = run_attributes(out_nc)
    assert run_attrs["job_file"] == JOB and first.attrs["analysis"] == "fake"
    assert run_attrs["tasks_completed"] == 6 and first.attrs["software_version"]
    assert len(first.attrs["source_sha256"]) == 64 and "numpy" in run_attrs["library_versions"]
    for name, var in first.variables.items():
        assert var.attrs["long_name"] and (name == "message" or var.attrs["units"])
    assert first["status"].attrs["flag_meanings"] == "missing ok not_converged failed outside_cases"

    code, out, _ = run(capsys, "status", out_nc)
    assert code == 0
    assert "good (fake): 6 / 6 tasks completed, 3 / 3 chunks (" in out and ", 0 failed)" in out
    assert f"{out_nc}: written" in out

    code, out, _ = run(capsys, "collect", out_nc)
    assert code == 0 and "6 / 6 tasks" in out
    assert data(out_nc).identical(first)

    code, out, _ = run(capsys, "run", job, "-o", out_nc, "--resume")
    assert code == 0 and "0 computed by this run" in out
    assert data(out_nc).identical(first)


def test_rerun_refused_then_overwrite(capsys, job, tmp_path):
    out_nc = tmp_path / "r.nc"
    code, out, _ = run(capsys, "run", job, "-o", out_nc, "--resume")
    assert code == 0 and "6 computed" in out
    code, _, err = run(capsys, "run", job, "-o", out_nc)
    assert code == 1
    assert (f"error: {out_nc}.parts/ holds the parts of an earlier run: add --resume to "
            "continue it, or --overwrite (or delete the directory) to start again") in err
    code, out, _ = run(capsys, "run", job, "-o", out_nc, "--overwrite")
    assert code == 0 and "6 computed" in out


def test_output_without_parts_is_not_overwritten(capsys, job, tmp_path):
    out_nc = tmp_path / "r.nc"
    out_nc.write_text("precious")
    code, _, err = run(capsys, "run", job, "-o", out_nc)
    assert code == 1
    assert f"error: {out_nc} exists: use --overwrite to replace it, or -o" in err
    assert out_nc.read_text() == "precious"


def test_resume_with_changed_job_refused(capsys, job, tmp_path):
    out_nc = tmp_path / "r.nc"
    assert run(capsys, "run", job, "-o", out_nc)[0] == 0
    job.write_text(JOB.replace("scale = 1.0", "scale = 2.0"))
    code, _, err = run(capsys, "run", job, "-o", out_nc, "--resume")
    assert code == 1
    assert (f"error: cannot resume: {out_nc}.parts/ was written by a different job file"
            in err)
    assert "restore that file, or start again with --overwrite" in err


def test_failing_tasks_are_data_and_the_run_goes_on(capsys, tmp_path):
    path = tmp_path / "fail.toml"
    path.write_text(JOB.replace("scale = 1.0", "scale = 1.0\nfail_delta = 1.5"))
    out_nc = tmp_path / "f.nc"
    code, out, err = run(capsys, "run", path, "-o", out_nc)
    assert code == cli.EXIT_TASKS_FAILED, err
    assert ("2 failed (2: ZeroDivisionError: the fake analysis fails here on purpose)"
            "; 6 computed by this run") in out
    result = data(out_nc)
    failed = result.sel(delta=1.5)
    assert (failed["status"] == 2).all() and failed["value"].isnull().all() and (failed["count"] == -1).all()
    assert set(failed["message"].values.ravel()) == {"ZeroDivisionError: the fake analysis fails here on purpose"}
    assert (result["status"].sel(delta=1.1) < 2).all()
    code, out, _ = run(capsys, "status", out_nc)
    assert code == 0 and "2 failed (2: ZeroDivisionError: the fake analysis fails here on purpose)" in out


def test_partial_collect_marks_missing_tasks(capsys, job, tmp_path):
    out_nc = tmp_path / "r.nc"
    assert run(capsys, "run", job, "-o", out_nc)[0] == 0
    (log,) = (tmp_path / "r.nc.parts").glob("run-*.log")
    log.write_bytes(log.read_bytes()[:-10])  # the last chunk (delta = 1.5) torn, as by a kill
    code, out, err = run(capsys, "collect", out_nc)
    assert code == 0 and "4 / 6 tasks" in out
    assert f"note: {log}: chunk 2 truncated at byte" in err
    assert "note: 2 of 6 tasks are missing (status -1); run --resume" in err
    partial = data(out_nc)
    assert (partial["status"].sel(delta=1.5) == -1).all()
    assert partial["value"].sel(delta=1.5).isnull().all()
    assert (partial["count"].sel(delta=1.5) == -1).all()
    assert (partial["status"].sel(delta=1.1) >= 0).all()
    code, out, _ = run(capsys, "run", job, "-o", out_nc, "--resume")
    assert code == 0 and "2 computed by this run" in out


@pytest.mark.parametrize("result, message", [
    ({"value": 1.0, "status": 0}, "compute returned the keys ['status', 'value'], expected "
                                  "['count', 'profile', 'status', 'value'] and optionally 'message'"),
    ({"value": 1.0, "profile": [1.0], "count": 1, "status": 0},
     "compute returned 'profile' with shape (1,), the analysis declares (4,)"),
    ({"value": 1.0, "profile": [1.0] * 4, "count": 1, "status": 7},
     "compute returned status 7, expected one of (0, 1, 2)"),
    (None, "compute returned a NoneType, not a dict"),
])
def test_result_not_as_declared(capsys, monkeypatch, job, tmp_path, result, message):
    monkeypatch.setattr(fake_analysis.FAKE, "compute", lambda *args: result)
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "r.nc")
    assert code == 1
    assert f"error: task 0 of 6 (delta=1.1, delta_o=0.2, Omega=2.0, subtask 0): {message} (on rank 0)" in err


KINDS = ["unknown key", "name wrong type", "unknown analysis", "delta <= 1",
         "delta_o out of range", "NaN", "bool for a number", "empty list", "num = 0",
         "unknown table", "missing analysis table", "malformed TOML", "required grid key"]


@pytest.mark.parametrize("kind", KINDS)
def test_bad_job_run_exits_2_with_message(capsys, tmp_path, kind):
    (old, new), expected = BAD[kind]
    path = tmp_path / "bad.toml"
    path.write_text(job_text(a=(old, new)))
    code, out, err = run(capsys, "run", path, "-o", tmp_path / "bad.nc")
    assert code == 2
    assert all(line.startswith(f"error: {path}: ") for line in err.splitlines())  # no traceback
    for text in expected[1:] if kind == "malformed TOML" else expected:
        assert text in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_bad_job_plan_exits_2(capsys, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(job_text(a=BAD["delta <= 1"][0]))
    code, _, err = run(capsys, "plan", path)
    assert code == 2 and "grid.delta.start = 1.0 is invalid: a finite number > 1" in err


def test_missing_job_file(capsys, tmp_path):
    code, _, err = run(capsys, "run", tmp_path / "nope.toml")
    assert code == 2
    assert f"job file = '{tmp_path}/nope.toml' is invalid: an existing file (no such file)" in err


@pytest.mark.parametrize("command", ["status", "collect"])
def test_status_collect_without_run(capsys, tmp_path, command):
    code, _, err = run(capsys, command, tmp_path / "x.nc")
    assert code == 1
    expected = {"status": f"error: no run at {tmp_path}/x.nc: neither",
                "collect": f"error: {tmp_path}/x.nc.parts/ does not exist: nothing to collect"}
    assert expected[command] in err


def test_parts_dir_without_manifest(capsys, tmp_path):
    (tmp_path / "x.nc.parts").mkdir()
    code, _, err = run(capsys, "collect", tmp_path / "x.nc")
    assert code == 1 and "has no manifest.json: it is not the parts directory" in err


def test_figures_dispatch(capsys, job, tmp_path):
    out_nc = tmp_path / "r.nc"
    assert run(capsys, "run", job, "-o", out_nc)[0] == 0
    code, out, _ = run(capsys, "figures", out_nc, "-o", tmp_path / "figs")
    assert code == 0 and out.strip() == str(tmp_path / "figs" / "value.png")
    assert (tmp_path / "figs" / "value.png").exists()

    job.write_text(JOB.replace('"fake"', '"fake_nofig"').replace("[fake]", "[fake_nofig]"))
    assert run(capsys, "run", job, "-o", tmp_path / "n.nc")[0] == 0
    code, out, _ = run(capsys, "figures", tmp_path / "n.nc", "-o", tmp_path / "figs")
    assert code == 0 and out.strip() == "analysis 'fake_nofig' has no figures"


def test_figures_of_several_results_draw_each_and_compare(capsys, job, tmp_path):
    """Two backbone results (two mode sets of Fig. 10-11, one point): each drawn in its own
    directory, and the comparison; results of different analyses are refused in one line."""
    text = (JOBS / "fig10-11-backbone.toml").read_text().replace("delta = [1.1, 1.2, 1.5, 2.0]", "delta = [2.0]")
    text = text.replace("start = 0.001, stop = 0.4, num = 40", "start = 0.01, stop = 0.05, num = 3")
    for name, modes in (("one", "[[1, 0]]"), ("two", "[[1, 0], [2, 0]]")):
        (tmp_path / f"{name}.toml").write_text(re.sub(r"modes = \[.*\]", f"modes = {modes}", text))
        assert run(capsys, "run", tmp_path / f"{name}.toml", "-o", tmp_path / f"{name}.nc")[0] == 0
    code, out, _ = run(capsys, "figures", tmp_path / "one.nc", tmp_path / "two.nc", "-o", tmp_path / "figs")
    assert code == 0
    for path in ("one/backbone.png", "two/backbone.png", "backbone_comparison.png"):
        assert (tmp_path / "figs" / path).exists() and str(tmp_path / "figs" / path) in out
    assert run(capsys, "run", job, "-o", tmp_path / "fake.nc")[0] == 0
    code, _, err = run(capsys, "figures", tmp_path / "one.nc", tmp_path / "fake.nc")
    assert code == 1 and "results of different analyses (backbone, fake) cannot be drawn together" in err


def test_comparison_legends_name_the_model():
    """A legend tells the ROM's mode count, the full model's order and whether u is held."""
    from sweep.figures.backbone import result_label

    rom = xr.Dataset(coords={"m": ("mode", [1, 2, 3])}, attrs={"model": "rom"})
    free = xr.Dataset(attrs={"model": "full", "model_order": 16, "model_inplane": 1})
    held = xr.Dataset(attrs={"model": "full", "model_order": 24, "model_inplane": 0})
    assert [result_label(ds) for ds in (rom, free, held)] == ["rom, 3 modes", "full, order 16",
                                                             "full, u = v = 0, order 24"]


def test_forced_branches_of_two_mode_sets_are_compared(capsys, tmp_path):
    text = (JOBS / "fig15-bifurcation-p0.toml").read_text().replace("delta = [1.1, 1.5, 2.0]", "delta = [1.1]")
    text = text.replace("Omega = [33.5, 46.1, 47.35]", "Omega = [33.5]")
    for name, modes in (("one", "[[1, 0]]"), ("two", "[[1, 0], [2, 0]]")):
        (tmp_path / f"{name}.toml").write_text(text.replace("modes = [[1, 0]]", f"modes = {modes}"))
        assert run(capsys, "run", tmp_path / f"{name}.toml", "-o", tmp_path / f"{name}.nc")[0] == 0
    code, out, _ = run(capsys, "figures", tmp_path / "one.nc", tmp_path / "two.nc", "-o", tmp_path / "figs")
    assert code == 0 and (tmp_path / "figs" / "bifurcation_P0_comparison.png").exists()


def _family_branch(model: str, families, unstable_n: int) -> xr.Dataset:
    """A continuation result of one grid point whose branch is unstable to ``unstable_n`` only."""
    omega = np.linspace(30.0, 40.0, 11)
    modulus = np.full((1, 11, len(families)), 0.9)
    modulus[0, 4:7, list(families).index(unstable_n)] = 1.2
    return xr.Dataset(
        {"Omega": (("delta", "point"), omega[None]), "amplitude": (("delta", "point"), np.full((1, 11), 0.01)),
         "stable": (("delta", "point"), np.ones((1, 11), bool)), "point_type": (("delta", "point"), np.zeros((1, 11), int)),
         "family_multiplier_modulus": (("delta", "point", "family"), modulus)},
        coords={"delta": [1.1], "point": np.arange(11), "family": list(families)},
        attrs={"analysis": "continuation", "continued_parameter": "Omega", "model": model})


def test_families_of_two_results_are_compared_on_their_common_wave_numbers(tmp_path):
    """The full model's and the ROM's families: one row per wave number both have; none
    without a common one."""
    from sweep.figures.continuation import continuation_comparison

    full, rom = _family_branch("full", (1, 2, 3), 3), _family_branch("rom", (1, 3), 1)
    paths = continuation_comparison([full, rom], tmp_path / "a")
    assert [p.name for p in paths] == ["bifurcation_Omega_comparison.png", "family_stability_Omega_comparison.png"]
    paths = continuation_comparison([full.sel(family=[2]), rom], tmp_path / "b")
    assert [p.name for p in paths] == ["bifurcation_Omega_comparison.png"]
    # a grid dimension of one value that the other result lacks (the ROM's c) is no difference,
    # in either order; one of several values would merge branches: no comparison
    with_c = rom.expand_dims(c=[0.05])
    for pair in ([full, with_c], [with_c, full]):
        assert len(continuation_comparison(pair, tmp_path / "c")) == 2
    assert continuation_comparison([full, xr.concat([with_c, with_c.assign_coords(c=[0.1])], "c")], tmp_path / "d") == []


def test_figures_errors(capsys, tmp_path):
    code, _, err = run(capsys, "figures", tmp_path / "x.nc")
    assert code == 1 and f"error: {tmp_path}/x.nc does not exist" in err
    xr.Dataset({"a": ("x", [1.0])}).to_netcdf(tmp_path / "other.nc")
    code, _, err = run(capsys, "figures", tmp_path / "other.nc")
    assert code == 1 and "is not a membrane-sweep result (no analysis attribute)" in err
    code, _, err = run(capsys, "status", tmp_path / "other.nc")
    assert code == 1 and "is not a membrane-sweep result (no 'run' group)" in err


def test_resume_and_overwrite_are_exclusive(capsys, job):
    with pytest.raises(SystemExit) as info:
        cli.main(["run", str(job), "--resume", "--overwrite"])
    assert info.value.code == 2
    assert "not allowed with argument" in capsys.readouterr().err


def test_one_thread_per_rank_is_the_default():
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    code = ("import sweep.cli, os, numba; "
            "print(os.environ['OMP_NUM_THREADS'], numba.config.NUMBA_NUM_THREADS)")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=60, check=True).stdout
    assert out.split() == ["1", "1"]


class Tty(io.StringIO):
    def isatty(self):
        return True


def test_progress_lines():
    assert [format_duration(s) for s in (4.2, 185, 3720)] == ["4s", "3m05s", "1h02m"]
    pipe = io.StringIO()
    progress = Progress(10, 4, pipe)
    progress.update(1)
    assert pipe.getvalue() == ""
    progress.finish(6)
    assert pipe.getvalue().startswith("10 / 10 tasks (100%), ")
    assert "tasks/s" in pipe.getvalue() and "ETA 0s" in pipe.getvalue()
    tty = Tty()
    progress = Progress(10, 0, tty)
    progress.last -= 1
    progress.update(5)
    assert tty.getvalue().startswith("\r[###############...............] 5 / 10 tasks (50%)")


def test_collect_failure_is_reported_and_parts_kept(capsys, monkeypatch, job, tmp_path):
    def broken(raw, options):
        raise KeyError("no such variable")

    monkeypatch.setattr(fake_analysis.FAKE, "assemble", broken)
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "r.nc")
    assert code == 1
    assert (f"error: collecting {tmp_path}/r.nc failed on rank 0: KeyError: 'no such "
            "variable'") in err
    assert len(list((tmp_path / "r.nc.parts").glob("run-*.log"))) == 1
    assert not (tmp_path / "r.nc.parts" / "lock").exists()


def test_unwritable_output_is_reported(capsys, job, tmp_path):
    (tmp_path / "file").write_text("")
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "file" / "r.nc")
    assert code == 1
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"error: preparing {tmp_path}/file/r.nc.parts/: {tmp_path}/file/r.nc.parts: Not a directory" in err


def test_status_from_the_final_file_once_parts_are_deleted(capsys, job, tmp_path):
    out_nc = tmp_path / "r.nc"
    assert run(capsys, "run", job, "-o", out_nc)[0] == 0
    for part in (tmp_path / "r.nc.parts").iterdir():
        part.unlink()
    (tmp_path / "r.nc.parts").rmdir()
    code, out, _ = run(capsys, "status", out_nc)
    assert code == 0
    assert out.startswith("good (fake): 6 / 6 tasks completed (")
    assert out.strip().endswith(f"0 failed); {out_nc}.parts/ deleted")


def test_warmup_failure_is_reported(capsys, monkeypatch, job, tmp_path):
    def broken():
        raise RuntimeError("no compiler")

    monkeypatch.setattr(fake_analysis.FAKE, "warmups", lambda options: [broken])
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "r.nc")
    assert code == 1
    assert "error: warmup of analysis 'fake' failed on rank 0: RuntimeError: no compiler" in err


def test_an_analysis_with_the_old_warmup_protocol_is_refused(monkeypatch):
    """warmup(options) was replaced by warmups(options): an analysis that still defines it
    would not be compiled before its tasks, so it is refused by name."""
    monkeypatch.setattr(fake_analysis.FAKE, "warmup", lambda options: None, raising=False)
    with pytest.raises(TypeError, match=r"fake_analysis:FAKE defines warmup\(options\); the runner calls warmups"):
        analyses.get("fake")


def test_part_write_failure_is_reported(capsys, monkeypatch, job, tmp_path):
    from sweep import partlog

    def full(*args):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(partlog.Writer, "append", full)
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "r.nc")
    assert code == 1
    log = tmp_path / "r.nc.parts" / "run-0001-rank-00000.log"
    assert (f"error: writing {log}: No space left on device; free some space, then run again (with "
            "--resume to keep what is done) (on rank 0)") in err


def test_version(capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["--version"])
    assert info.value.code == 0 and capsys.readouterr().out.startswith("membrane-sweep ")


@pytest.mark.parametrize("fmt", ["pdf", "svg"])
def test_figures_in_vector_formats_leave_rcparams_alone(capsys, tmp_path, fmt):
    import matplotlib

    from sweep import figures

    job = tmp_path / "static.toml"
    job.write_text('[job]\nname = "s"\nanalysis = "static"\n[grid]\ndelta = [1.1, 1.5]\ndelta_o = 0.2\n'
                   '[static]\nprestretch = "analytic"\nrho = {start = 0.2, stop = 1.0, num = 9}\n')
    assert run(capsys, "run", job, "-o", tmp_path / "s.nc")[0] == 0
    before = dict(matplotlib.rcParams)
    code, out, err = run(capsys, "figures", tmp_path / "s.nc", "-o", tmp_path / "figs", "--format", fmt,
                         "--dpi", "300")
    assert code == 0, err
    written = [tmp_path / "figs" / f"fig02_radius.{fmt}", tmp_path / "figs" / f"fig03_stresses.{fmt}"]
    assert out.split() == [str(p) for p in written] and all(p.stat().st_size > 1000 for p in written)
    paths = figures.draw(analyses.get("linear"), _linear_result(), tmp_path / "api", fmt=fmt)
    assert paths and all(p.suffix == f".{fmt}" and p.stat().st_size > 1000 for p in paths)
    made = figures.make(analyses.get("linear"), _linear_result())
    assert sorted(made) == sorted(p.stem for p in paths)
    assert all(isinstance(f, matplotlib.figure.Figure) for f in made.values())
    assert dict(matplotlib.rcParams) == before


def _linear_result():
    """A small linear result, computed in-process (the frequencies of three modes)."""
    import numpy as np

    from model.params import Membrane
    from sweep.jobspec import grid_point

    linear = analyses.get("linear")
    options = linear.parse_options({"prestretch": "analytic", "modes": [[1, 0], [2, 0], [1, 1]]},
                                   {"delta": np.array([1.1, 1.5]), "delta_o": np.array([0.2])}, Membrane())
    rows = [linear.compute(grid_point(Membrane(), {"delta": d, "delta_o": 0.2}), options, 0) for d in (1.1, 1.5)]
    data = {v.name: (("delta", "delta_o", "mode"), np.stack([r[v.name] for r in rows])[:, None, :],
                     {"units": v.units, "long_name": v.long_name}) for v in linear.variables(options)}
    coords = {"delta": [1.1, 1.5], "delta_o": [0.2],
              **{k: (d, val, a) for k, (d, val, a) in linear.coords(options).items()}}
    return xr.Dataset(data, coords, attrs={"analysis": "linear", "job_file": ""})


@pytest.mark.parametrize("mode, shown", [("none", False), ("lines", True)])
def test_progress_switch(capsys, job, tmp_path, mode, shown):
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "r.nc", "--progress", mode)
    assert code == 0 and ("6 / 6 tasks (100%)" in err) == shown


def test_ctrl_c_is_one_line_with_the_way_to_continue(tmp_path):
    import signal
    import time

    job = tmp_path / "slow.toml"
    job.write_text(JOB.replace("scale = 1.0", "scale = 1.0\nsleep = 1.0"))
    env = {**os.environ, "PYTHONPATH": str(os.path.dirname(__file__)), analyses.EXTRA_ENV: EXTRA}
    # SIGINT at its default in the child: a test run started in the background by a shell
    # without job control inherits it ignored, and so would the child (then no Ctrl-C at all)
    proc = subprocess.Popen([sys.executable, "-m", "sweep", "run", str(job), "-o", str(tmp_path / "s.nc")],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    lock = tmp_path / "s.nc.parts" / "lock"
    deadline = time.monotonic() + 60
    while not lock.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(0.5)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130
    assert "Traceback" not in err and "MPI_Abort" not in err
    assert "interrupted: the finished chunks are kept" in err and "--resume to continue" in err
    assert not lock.exists()


def test_cases_compute_only_the_chosen_grid_points(capsys, tmp_path, monkeypatch):
    path = tmp_path / "cases.toml"
    path.write_text(JOB.replace("Omega = 2.0", "Omega = 2.0\ncases = [{delta = 1.1, delta_o = 0.3}, {delta = 1.5}]"))
    log = tmp_path / "computed.log"
    monkeypatch.setenv("FAKE_SWEEP_LOG", str(log))
    code, out, _ = run(capsys, "run", path, "-o", tmp_path / "c.nc")
    assert code == 0 and "3 outside the cases" in out
    assert sorted(line.split()[:2] for line in log.read_text().splitlines()) == [
        ["1.1", "0.3"], ["1.5", "0.2"], ["1.5", "0.3"]]
    ds = data(tmp_path / "c.nc")
    skipped = ds["status"] == 3
    assert int(skipped.sum()) == 3 and bool(ds["value"].where(skipped).isnull().all())
    assert bool(skipped.sel(delta=1.3).all()) and not bool(skipped.sel(delta=1.5).any())
    assert ds["status"].attrs["flag_meanings"] == "missing ok not_converged failed outside_cases"


def test_every_job_file_error_is_reported_at_once(capsys, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(JOB.replace('name = "good"', 'name = "good"\nnme = 1')
                       .replace("delta_o = [0.2, 0.3]", "delta_o = [0.2, 1.3]")
                       .replace("[fake]", "[membrane]\nh = -1.0\n\n[fake]"))
    code, _, err = run(capsys, "run", path, "-o", tmp_path / "b.nc")
    assert code == 2
    lines = err.splitlines()
    assert len(lines) == 3 and all(line.startswith(f"error: {path}: ") for line in lines)
    for text in ("job.nme = 1 is invalid", "membrane.h = -1.0 is invalid", "grid.delta_o[1] = 1.3 is invalid"):
        assert sum(text in line for line in lines) == 1


def test_runs_over_disjoint_grid_values_combine_by_coordinates(capsys, tmp_path):
    parts = []
    for i, deltas in enumerate(("[1.1, 1.3]", "[1.5, 1.7]")):
        path = tmp_path / f"part{i}.toml"
        path.write_text(JOB.replace("delta = {start = 1.1, stop = 1.5, num = 3}", f"delta = {deltas}")
                           .replace('name = "good"', f'name = "part{i}"'))
        assert run(capsys, "run", path, "-o", tmp_path / f"part{i}.nc")[0] == 0
        parts.append(data(tmp_path / f"part{i}.nc"))
    combined = xr.combine_by_coords(parts)
    assert list(combined.delta.values) == [1.1, 1.3, 1.5, 1.7]
    assert combined.attrs == parts[0].attrs
    xr.testing.assert_equal(combined.value.sel(delta=[1.5, 1.7]), parts[1].value)
