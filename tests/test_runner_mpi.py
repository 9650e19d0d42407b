"""The runner under ``mpiexec -n 2`` in a subprocess, compared with 1 rank.

Every test here launches real MPI jobs (marker ``mpi``); they run in CI.  A missing
``mpiexec`` is a failure, not a skip.
"""

from pathlib import Path

import numpy as np
import pytest

from sweep import partlog
from sweep.jobspec import parse_job
from jobfiles import BAD, MPI_JOB, data, job_text, sweep

JOB = MPI_JOB

pytestmark = pytest.mark.mpi


@pytest.fixture
def job(tmp_path):
    path = tmp_path / "job.toml"
    path.write_text(JOB.format(sleep=0.0))
    return path


def test_two_ranks_identical_to_one_rank_and_to_serial(job, tmp_path):
    runs = {"serial": sweep("run", job, "-o", "serial.nc", ranks=0, cwd=tmp_path),
            "one": sweep("run", job, "-o", "one.nc", ranks=1, cwd=tmp_path),
            "two": sweep("run", job, "-o", "two.nc", ranks=2, cwd=tmp_path)}
    for name, proc in runs.items():
        assert proc.returncode == 0, proc.stderr
    assert "on 2 rank(s)" in runs["two"].stdout
    one = data(tmp_path / "one.nc")
    assert one.sizes == {"delta": 6, "delta_o": 4, "Omega": 1, "subtask": 2, "rho": 4}
    assert set(one["status"].values.ravel()) <= {0, 1}
    for name in ("serial", "two"):
        other = data(tmp_path / f"{name}.nc")
        assert other.identical(one)
        for var in one.variables:
            np.testing.assert_array_equal(other[var].values, one[var].values, strict=True)


def _done_chunks(parts: Path, layout) -> set[int]:
    return {rec.chunk for rec in partlog.Logs(sorted(parts.glob("run-*.log")), layout.chunk, layout.n_tasks)}


def _logs(parts: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in parts.glob("run-*.log")}


def test_killed_run_resumes_to_the_same_file_without_recomputing(tmp_path):
    job = tmp_path / "job.toml"
    job.write_text(JOB.format(sleep=0.03))
    reference = sweep("run", job, "-o", "ref.nc", ranks=1, cwd=tmp_path)
    assert reference.returncode == 0, reference.stderr

    killed = sweep("run", job, "-o", "out.nc", ranks=2, cwd=tmp_path,
                   FAKE_SWEEP_LOG=str(tmp_path / "first.log"), FAKE_SWEEP_KILL_AFTER="20")
    assert killed.returncode != 0
    parts = tmp_path / "out.nc.parts"
    layout = parse_job(job.read_text()).layout
    before = _done_chunks(parts, layout)
    old_logs = _logs(parts)
    assert 0 < len(before) < layout.n_chunks and len(old_logs) <= 2
    assert not (tmp_path / "out.nc").exists()
    status = sweep("status", "out.nc", ranks=0, cwd=tmp_path)
    assert f"{3 * len(before)} / 48 tasks completed, {len(before)} / 16 chunks" in status.stdout

    # The killed run's lock is stale (its processes are gone): the resume takes it over.
    resumed = sweep("run", job, "-o", "out.nc", "--resume", ranks=2, cwd=tmp_path,
                    FAKE_SWEEP_LOG=str(tmp_path / "second.log"))
    assert resumed.returncode == 0, resumed.stderr
    assert {name: data for name, data in _logs(parts).items() if name in old_logs} == old_logs
    assert _done_chunks(parts, layout) == set(range(layout.n_chunks))
    assert len(list(parts.iterdir())) <= 1 + 2 * (1 + 2)  # manifest, per run a record and a log per rank

    def task_line(t):
        point, subtask = layout.task(t)
        return f"{point['delta']!r} {point['delta_o']!r} {point['Omega']!r} {subtask}"

    done_before = {task_line(t) for k in before for t in layout.chunk_tasks(k)}
    recomputed = (tmp_path / "second.log").read_text().splitlines()
    assert len(recomputed) == len(set(recomputed)) == layout.n_tasks - len(done_before)
    assert not done_before & set(recomputed)
    assert data(tmp_path / "out.nc").identical(data(tmp_path / "ref.nc"))


def test_failing_tasks_are_stored_and_every_rank_goes_on(tmp_path):
    job = tmp_path / "job.toml"
    job.write_text(JOB.format(sleep=0.01).replace("n_sub = 2", "n_sub = 2\nfail_delta = 1.4"))
    proc = sweep("run", job, ranks=2, cwd=tmp_path)
    assert proc.returncode == 3, proc.stderr
    assert "error" not in proc.stderr and "Traceback" not in proc.stderr
    assert "8 failed (8: ZeroDivisionError: the fake analysis fails here on purpose); 48 computed" in proc.stdout
    ds = data(tmp_path / "mpi.nc")
    assert (ds["status"].sel(delta=1.4) == 2).all() and (ds["status"].sel(delta=1.5) < 2).all()
    assert (ds["message"].sel(delta=1.4) == "ZeroDivisionError: the fake analysis fails here on purpose").all()


@pytest.mark.parametrize("kind", ["delta <= 1", "unknown table", "malformed TOML",
                                  "missing analysis table"])
def test_bad_job_exits_non_zero_on_two_ranks(tmp_path, kind):
    (old, new), expected = BAD[kind]
    path = tmp_path / "bad.toml"
    path.write_text(job_text(a=(old, new)))
    proc = sweep("run", path, ranks=2, cwd=tmp_path)
    assert proc.returncode != 0
    assert proc.stderr.count(f"error: {path}: ") == 1
    for text in expected[1:] if kind == "malformed TOML" else expected:
        assert text in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_missing_job_file_and_refused_resume_on_two_ranks(job, tmp_path):
    proc = sweep("run", "nope.toml", ranks=2, cwd=tmp_path)
    assert proc.returncode != 0
    assert "error: nope.toml: job file = 'nope.toml' is invalid: an existing file" in proc.stderr
    assert sweep("run", job, ranks=2, cwd=tmp_path).returncode == 0
    job.write_text(JOB.format(sleep=0.001))
    proc = sweep("run", job, "--resume", ranks=2, cwd=tmp_path)
    assert proc.returncode != 0
    assert proc.stderr.count("error: cannot resume: mpi.nc.parts/ was written by a "
                             "different job file") == 1
