"""The runner under ``mpiexec -n 2`` in a subprocess, compared with 1 rank.

Every test here launches real MPI jobs (marker ``mpi``); they run in CI.  A missing
``mpiexec`` is a failure, not a skip.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sweep import analyses
from sweep.jobspec import parse_job
from sweep.launch import find_mpiexec
from jobfiles import BAD, EXTRA, job_text

TESTS = Path(__file__).parent
TIMEOUT = 120  # seconds, for mpiexec and for the subprocess

JOB = """
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

pytestmark = pytest.mark.mpi


@pytest.fixture(autouse=True)
def fake_registered(monkeypatch):
    monkeypatch.setenv(analyses.EXTRA_ENV, EXTRA)


def mpiexec() -> str:
    path = find_mpiexec()
    if path is None:
        pytest.fail("mpiexec not found next to the Python executable nor on PATH")
    return path


def env(**extra: str) -> dict[str, str]:
    path = os.pathsep.join(filter(None, [str(TESTS), os.environ.get("PYTHONPATH")]))
    return {**os.environ, "PYTHONPATH": path, analyses.EXTRA_ENV: EXTRA,
            "MPIEXEC_TIMEOUT": str(TIMEOUT), **extra}


def sweep(*args, ranks: int, cwd: Path, **extra: str) -> subprocess.CompletedProcess:
    """``python -m sweep ARGS``, under ``mpiexec -n RANKS`` when ranks > 0."""
    launch = [mpiexec(), "-n", str(ranks), sys.executable, "-m", "mpi4py"] if ranks else \
        [sys.executable]
    return subprocess.run([*launch, "-m", "sweep", *map(str, args)], cwd=cwd, env=env(**extra),
                          capture_output=True, text=True, timeout=TIMEOUT)


def data(path: Path) -> xr.Dataset:
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    del ds.attrs["date_created"]
    return ds


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


def test_killed_run_resumes_to_the_same_file_without_recomputing(tmp_path):
    job = tmp_path / "job.toml"
    job.write_text(JOB.format(sleep=0.03))
    reference = sweep("run", job, "-o", "ref.nc", ranks=1, cwd=tmp_path)
    assert reference.returncode == 0, reference.stderr

    killed = sweep("run", job, "-o", "out.nc", ranks=2, cwd=tmp_path,
                   FAKE_SWEEP_LOG=str(tmp_path / "first.log"), FAKE_SWEEP_KILL_AFTER="20")
    assert killed.returncode != 0
    parts = tmp_path / "out.nc.parts"
    before = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in parts.glob("chunk-*.h5")}
    layout = parse_job(job.read_text()).layout
    assert 0 < len(before) < layout.n_chunks
    assert not (tmp_path / "out.nc").exists()
    status = sweep("status", "out.nc", ranks=0, cwd=tmp_path)
    assert f"{3 * len(before)} / 48 tasks completed, {len(before)} / 16 chunks" in status.stdout

    resumed = sweep("run", job, "-o", "out.nc", "--resume", ranks=2, cwd=tmp_path,
                    FAKE_SWEEP_LOG=str(tmp_path / "second.log"))
    assert resumed.returncode == 0, resumed.stderr
    after = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in parts.glob("chunk-*.h5")}
    assert {name: after[name] for name in before} == before
    assert len(after) == layout.n_chunks

    def task_line(t):
        point, subtask = layout.task(t)
        return f"{point['delta']!r} {point['delta_o']!r} {point['Omega']!r} {subtask}"

    done_before = {task_line(t) for name in before
                   for t in layout.chunk_tasks(int(name[6:12]))}
    recomputed = (tmp_path / "second.log").read_text().splitlines()
    assert len(recomputed) == len(set(recomputed)) == layout.n_tasks - len(done_before)
    assert not done_before & set(recomputed)
    assert data(tmp_path / "out.nc").identical(data(tmp_path / "ref.nc"))


def test_failing_task_stops_every_rank_with_a_message(tmp_path):
    job = tmp_path / "job.toml"
    job.write_text(JOB.format(sleep=0.01).replace("n_sub = 2", "n_sub = 2\nfail_delta = 1.4"))
    proc = sweep("run", job, ranks=2, cwd=tmp_path)
    assert proc.returncode != 0
    # Every task at delta = 1.4 fails; with one-task chunks each rank may meet one, and the
    # single error line then names the first failure of each rank (joined by "; ").
    assert re.search(r"error: task 2\d of 48 \(delta=1\.4, delta_o=0\.\d, Omega=2\.0, subtask [01]\) "
                     r"failed: ZeroDivisionError: the fake analysis fails here on purpose \(on rank [01]\)",
                     proc.stderr), proc.stderr
    assert proc.stderr.count("error: ") == 1
    parts = sorted(p.name for p in (tmp_path / "mpi.nc.parts").glob("chunk-*.h5"))
    assert "chunk-000000.h5" in parts and "chunk-000008.h5" not in parts
    assert not (tmp_path / "mpi.nc").exists()


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
