"""Storage that week-long sweeps can trust: verified part logs, one writer per output,
code provenance, failures as data, and one line for every file-system mistake.

The behaviours of several processes (a concurrent run, a killed run, a code change
between a run and its resume) are tested through ``mpiexec -n 2`` in subprocesses; the
rest in-process on one rank.
"""

import json
import os
import shutil
import subprocess
import sys
import time
import zlib

import numpy as np
import pytest
import xarray as xr
from jobfiles import GOOD, MPI_JOB, TESTS, TIMEOUT, data, sweep, sweep_env

from sweep import cli, partlog
from sweep.storage.netcdf import flat_boxes, run_attributes
from sweep.storage.parts import read_runs
from sweep.storage.resume import ChunkSet
from sweep.launch import find_mpiexec

def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def job(tmp_path):
    path = tmp_path / "job.toml"
    path.write_text(GOOD.replace('analysis = "fake"', 'analysis = "fake"\nchunk = 2'))
    return path


# -- the part log format ------------------------------------------------------------


def test_flat_ranges_split_into_contiguous_boxes():
    shape = (3, 4, 5)
    full = np.arange(60).reshape(shape)
    for start, stop in [(0, 60), (7, 8), (3, 47), (20, 40), (19, 41), (59, 60), (0, 1), (5, 25)]:
        boxes = flat_boxes(start, stop, shape)
        assert len(boxes) <= 2 * len(shape) - 1
        got = np.concatenate([full[tuple(slice(c, c + e) for c, e in zip(corner, extent))].ravel()
                              for corner, extent in boxes])
        assert np.array_equal(got, np.arange(start, stop))


def test_a_record_round_trips_and_every_kind_of_damage_is_caught(tmp_path):
    from sweep.analyses.base import Variable

    variables = [Variable("x", ("r",), (2,), "f8", "m", "x"), Variable("n", (), (), "i4", "1", "n", -1)]
    log = tmp_path / "a.log"
    w = partlog.Writer(log, variables)
    for k in range(3):
        tasks = range(2 * k, 2 * k + 2)
        w.append(k, tasks, np.array([0, 2], np.int8), {"x": np.full((2, 2), k + 0.5), "n": np.array([k, -1])},
                 {1: f"failed {k}"})
    w.close()
    logs = partlog.Logs([log], 2, 6)
    records = list(logs)
    assert logs.problems() == [] and [r.chunk for r in records] == [0, 1, 2] and logs.tasks == 6
    with partlog.Reader(variables) as reader:
        status, arrays, messages = reader.read(records[1])
    assert list(status) == [0, 2] and np.all(arrays["x"] == 1.5) and messages == {1: "failed 1"}

    raw = bytearray(log.read_bytes())
    size = len(raw) // 3
    flipped = bytearray(raw)
    flipped[size + 40] ^= 1                                          # chunk 1's payload
    (tmp_path / "b.log").write_bytes(flipped)
    chunks, problems = _chunks_and_problems(tmp_path / "b.log")
    assert chunks == [0, 2] and "chunk 1 at byte" in problems[0] and "checksum" in problems[0]

    (tmp_path / "c.log").write_bytes(raw[:-5])                       # a torn tail
    chunks, problems = _chunks_and_problems(tmp_path / "c.log")
    assert chunks == [0, 1] and "chunk 2 truncated" in problems[0]

    # chunk 0's record relabelled as chunk 2 with a valid checksum: its tasks are not chunk 2's
    head = partlog._HEADER.unpack(raw[:partlog._HEADER.size])
    payload = bytes(raw[partlog._HEADER.size:size])
    zero = partlog._HEADER.pack(*head[:3], 2, *head[4:7], 0)
    crc = zlib.crc32(payload, zlib.crc32(zero))
    (tmp_path / "d.log").write_bytes(partlog._HEADER.pack(*head[:3], 2, *head[4:7], crc) + payload)
    chunks, problems = _chunks_and_problems(tmp_path / "d.log")
    assert chunks == [] and "claims chunk 2 with tasks 0..1" in problems[0]
    # the same log twice (a copied file): every chunk once, nothing to report
    logs = partlog.Logs([log, tmp_path / "copy.log"], 2, 6)
    (tmp_path / "copy.log").write_bytes(raw)
    assert [r.chunk for r in logs] == [0, 1, 2] and logs.problems() == [] and logs.tasks == 6


def test_every_record_is_on_disk_before_the_next_chunk(tmp_path, monkeypatch):
    from sweep.analyses.base import Variable

    synced = []
    real_fsync = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (synced.append(os.fstat(fd).st_size), real_fsync(fd)))
    variables = [Variable("x", (), (), "f8", "m", "x")]
    log = tmp_path / "a.log"
    w = partlog.Writer(log, variables)
    for k in range(3):
        w.append(k, range(2 * k, 2 * k + 2), np.zeros(2, np.int8), {"x": np.full(2, k + 0.5)}, {})
        # synced after this record was written, before the next one (the directory entry first)
        assert synced[-1] == log.stat().st_size and len(synced) == k + 2
        logs = partlog.Logs([log], 2, 6)  # another reader, before close
        with partlog.Reader(variables) as reader:
            assert [reader.read(r)[1]["x"][0] for r in logs] == [j + 0.5 for j in range(k + 1)]
    w.close()
    assert len(synced) == 4


def _chunks_and_problems(path):
    logs = partlog.Logs([path], 2, 6)
    return [r.chunk for r in logs], logs.problems()


def test_chunk_set_is_a_bitmap():
    flags = np.zeros(11, bool)
    flags[[0, 3, 10]] = True
    done = ChunkSet(11, np.packbits(flags))
    assert [k for k in range(11) if k in done] == [0, 3, 10] and done.count() == 3
    assert done.bits.nbytes == 2 and done.tasks(4, 42) == 4 + 4 + 2


# -- one writer per output ----------------------------------------------------------


def test_a_second_run_on_a_locked_output_is_refused(capsys, job, tmp_path):
    parts = tmp_path / "r.nc.parts"
    parts.mkdir()
    holder = {"host": "node17", "pid": 4242, "what": "run", "started": "2026-11-30T10:00:00+00:00"}
    (parts / "lock").write_text(json.dumps(holder))
    (parts / "manifest.json").write_text("{}")
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "r.nc", "--resume")
    assert code == 1 and err.count("\n") == 1
    assert (f"error: {parts}/ is in use by a run on host node17, process 4242, since "
            "2026-11-30T10:00:00+00:00: wait for it to finish") in err
    code, _, err = run(capsys, "collect", tmp_path / "r.nc")
    assert code == 1 and "is in use by a run on host node17" in err
    code, _, err = run(capsys, "run", job, "-o", tmp_path / "r.nc", "--resume", "--break-lock")
    assert code == 1 and f"error: {parts}/manifest.json is corrupt" in err
    assert not (parts / "lock").exists()


def test_a_stale_lock_of_this_host_is_taken_over(capsys, job, tmp_path):
    assert run(capsys, "run", job, "-o", tmp_path / "r.nc")[0] == 0
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True, check=True).stdout.strip()
    holder = {"host": os.uname().nodename, "pid": int(dead), "what": "run", "started": "then"}
    (tmp_path / "r.nc.parts" / "lock").write_text(json.dumps(holder))
    code, out, _ = run(capsys, "run", job, "-o", tmp_path / "r.nc", "--resume")
    assert code == 0 and "0 computed by this run" in out
    assert not (tmp_path / "r.nc.parts" / "lock").exists()


@pytest.mark.mpi
def test_a_concurrent_run_is_refused_while_the_first_finishes(tmp_path):
    job = tmp_path / "job.toml"
    job.write_text(MPI_JOB.format(sleep=0.1))
    reference = sweep("run", job, "-o", "ref.nc", ranks=0, cwd=tmp_path)
    assert reference.returncode == 0, reference.stderr
    launch = [find_mpiexec(), "-n", "2", sys.executable, "-m", "mpi4py", "-m", "sweep", "run", str(job),
              "-o", "mpi.nc", "--resume"]
    first = subprocess.Popen(launch, cwd=tmp_path, env=sweep_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    lock = tmp_path / "mpi.nc.parts" / "lock"
    deadline = time.monotonic() + 60
    while not lock.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    second = sweep("run", job, "-o", "mpi.nc", "--resume", ranks=0, cwd=tmp_path)
    out, err = first.communicate(timeout=TIMEOUT)
    assert first.returncode == 0, err
    assert second.returncode == 1
    assert f"mpi.nc.parts/ is in use by a run on host {os.uname().nodename}, process " in second.stderr
    assert "Traceback" not in second.stderr
    assert data(tmp_path / "mpi.nc").identical(data(tmp_path / "ref.nc"))


# -- verified parts -----------------------------------------------------------------


@pytest.mark.mpi
def test_corrupted_and_misplaced_parts_are_reported_and_recomputed(tmp_path):
    job = tmp_path / "job.toml"
    job.write_text(MPI_JOB.format(sleep=0.0))
    assert sweep("run", job, "-o", "ref.nc", ranks=2, cwd=tmp_path).returncode == 0
    shutil.copytree(tmp_path / "ref.nc.parts", tmp_path / "out.nc.parts")
    parts = tmp_path / "out.nc.parts"
    layout_chunk, n_tasks = 3, 48
    log = sorted(parts.glob("run-*.log"))[0]
    records = list(partlog.Logs([log], layout_chunk, n_tasks))
    victim = records[0]
    raw = bytearray(log.read_bytes())
    raw[victim.offset + 3] ^= 0xFF                                   # one flipped byte
    log.write_bytes(raw)
    # A misplaced part: another chunk's record relabelled as the victim's neighbour, checksum valid.
    other = records[1]
    head = list(partlog._HEADER.unpack(raw[other.offset - partlog._HEADER.size:other.offset]))
    payload = bytes(raw[other.offset:other.offset + other.length])
    head[3], head[7] = victim.chunk, 0
    head[7] = zlib.crc32(payload, zlib.crc32(partlog._HEADER.pack(*head)))
    (parts / "run-0009-rank-00000.log").write_bytes(partlog._HEADER.pack(*head) + payload)

    status = sweep("status", "out.nc", ranks=0, cwd=tmp_path)
    assert (f"rejected part: out.nc.parts/{log.name}: chunk {victim.chunk} at byte "
            f"{victim.offset - partlog._HEADER.size} fails its checksum") in status.stdout
    assert f"out.nc.parts/run-0009-rank-00000.log: record at byte 0 claims chunk {victim.chunk}" in status.stdout
    resumed = sweep("run", job, "-o", "out.nc", "--resume", ranks=2, cwd=tmp_path,
                    FAKE_SWEEP_LOG=str(tmp_path / "recomputed.log"))
    assert resumed.returncode == 0, resumed.stderr
    assert "fails its checksum (corrupted); it is not merged and will be recomputed" in resumed.stderr
    assert resumed.stderr.count("fails its checksum") == 1  # reported once, by the resume
    assert len((tmp_path / "recomputed.log").read_text().splitlines()) == victim.task_count
    assert data(tmp_path / "out.nc").identical(data(tmp_path / "ref.nc"))


# -- provenance ---------------------------------------------------------------------


@pytest.mark.mpi
def test_resume_after_a_code_change_is_refused_unless_allowed(tmp_path):
    code_dir = tmp_path / "code"
    code_dir.mkdir()
    shutil.copy(TESTS / "fake_analysis.py", code_dir)
    job = tmp_path / "job.toml"
    job.write_text(MPI_JOB.format(sleep=0.03))
    killed = sweep("run", job, "-o", "out.nc", ranks=2, cwd=tmp_path, pythonpath=code_dir,
                   FAKE_SWEEP_LOG=str(tmp_path / "first.log"), FAKE_SWEEP_KILL_AFTER="12")
    assert killed.returncode != 0
    with open(code_dir / "fake_analysis.py", "a") as f:
        f.write("\n# an edit between the run and its resume\n")
    refused = sweep("run", job, "-o", "out.nc", "--resume", ranks=2, cwd=tmp_path, pythonpath=code_dir)
    assert refused.returncode == 1 and refused.stderr.count("error: ") == 1
    assert "error: cannot resume: the code differs from the run that wrote out.nc.parts/ (source sha256 " in \
        refused.stderr
    assert "pass --allow-code-change to resume anyway" in refused.stderr
    allowed = sweep("run", job, "-o", "out.nc", "--resume", "--allow-code-change", ranks=2, cwd=tmp_path,
                    pythonpath=code_dir)
    assert allowed.returncode == 0, allowed.stderr
    assert "note: resumed with different code (--allow-code-change, recorded): source sha256" in allowed.stderr
    run_attrs = run_attributes(tmp_path / "out.nc")
    assert run_attrs["code_changed_during_run"] == 1
    assert "resumed with different code: source sha256" in run_attrs["history"]
    with xr.open_dataset(tmp_path / "out.nc") as ds:
        assert ds.attrs["source"].startswith("membrane-sweep ")
    runs = read_runs(tmp_path / "out.nc.parts")
    assert [r["run"] for r in runs] == [1, 2]  # the refused attempt is no run
    first, last = runs[0]["provenance"], runs[-1]["provenance"]
    assert first["source_sha256"] != last["source_sha256"] and set(first["versions"]) >= {"numpy", "numba", "MPI"}


# -- failures are data, wrong numbers are not ok ------------------------------------


def test_a_numerical_exception_in_one_continuation_task_is_data(capsys, tmp_path):
    path = tmp_path / "cont.toml"
    path.write_text("""[job]
name = "cont"
analysis = "continuation"
[grid]
delta = 1.1
delta_o = 0.2
Omega = [33.5, 0.1, 46.0]
c = 0.05
[continuation]
parameter = "P0"
start = 0.0
stop = 2.0
max_points = 40
prestretch = "analytic"
""")
    code, out, err = run(capsys, "run", path, "-o", tmp_path / "cont.nc")
    assert code == cli.EXIT_TASKS_FAILED, err
    with xr.open_dataset(tmp_path / "cont.nc") as ds:
        status = ds["status"].squeeze().values
        message = ds["message"].squeeze().values
    assert status[1] == 2 and message[1].startswith("LinAlgError: ")
    assert status[0] in (0, 1) and status[2] in (0, 1)
    assert "1 failed (1: LinAlgError: " in out


def test_the_fig14a_branch_covers_its_range_with_the_default_max_points(capsys, tmp_path):
    # The paper's job without its max_points = 1000 and ds_max = 0.3: at the default step the
    # branch has 885 points, more than the 400 that used to be the default.
    text = (TESTS.parent / "jobs" / "fig14-bifurcation-omega.toml").read_text()
    path = tmp_path / "fig14a.toml"
    path.write_text(text.replace("delta = [1.1, 1.5, 2.0]", "delta = [1.1]").replace("ds_max = 0.3\n", "")
                    .replace("max_points = 1000\n", ""))
    code, out, err = run(capsys, "run", path, "-o", tmp_path / "fig14a.nc")
    assert code == 0, err
    with xr.open_dataset(tmp_path / "fig14a.nc") as ds:
        assert ds.sizes["point"] == 4000 and int(ds["status"].item()) == 0 and ds["message"].item() == ""
        n = int(ds["n_points"].item())
        assert 400 < n < 4000 and ds["Omega"].squeeze().values[n - 1] == 55.0


@pytest.mark.slow
def test_linear_above_the_eq29_bound_is_not_ok(capsys, tmp_path):
    # At n = 31 (delta 1.5, analytic pre-stretch) the Bessel-basis Galerkin solution is not
    # reliable: its value exceeds the Eq. 29 bound, which every frequency respects.
    path = tmp_path / "lin.toml"
    path.write_text("""[job]
name = "lin"
analysis = "linear"
[grid]
delta = 1.5
delta_o = 0.2
[linear]
prestretch = "analytic"
modes = [[1, 2], [1, 31]]
""")
    code, out, err = run(capsys, "run", path, "-o", tmp_path / "lin.nc")
    with xr.open_dataset(tmp_path / "lin.nc") as ds:
        omega, bound = ds["omega"].squeeze().values, ds["omega_bound"].squeeze().values
        status, message = ds["status"].values.item(), ds["message"].values.item()
    assert omega[0] < bound[0] and omega[1] > bound[1]
    assert status == 2 and code == cli.EXIT_TASKS_FAILED
    assert message.startswith("n = 31: basis not converged at 256 functions (last relative change ")
    assert message.endswith(f"; mode (1, 31): omega = {omega[1]:.6g} rad/s is not in (0, Eq. 29 bound = "
                            f"{bound[1]:.6g})")


# -- one line for every file-system mistake -----------------------------------------


@pytest.mark.parametrize("damage, expected", [
    ("truncate", "manifest.json is corrupt (JSONDecodeError"),
    ("garbage", "manifest.json is corrupt (JSONDecodeError"),
    ("empty object", "manifest.json is corrupt (KeyError"),
])
def test_a_corrupt_manifest_is_one_line(capsys, job, tmp_path, damage, expected):
    assert run(capsys, "run", job, "-o", tmp_path / "r.nc")[0] == 0
    manifest = tmp_path / "r.nc.parts" / "manifest.json"
    text = manifest.read_text()
    manifest.write_text({"truncate": text[:len(text) // 2], "garbage": "\x00\x01", "empty object": "{}"}[damage])
    for command in (["run", job, "-o", tmp_path / "r.nc", "--resume"], ["collect", tmp_path / "r.nc"],
                    ["status", tmp_path / "r.nc"]):
        code, _, err = run(capsys, *command)
        assert code == 1 and err.count("\n") == 1 and expected in err and "Traceback" not in err


def test_a_read_only_directory_is_one_line(capsys, job, tmp_path):
    if os.geteuid() == 0:
        # root ignores permissions: the same path through a file where a directory is expected
        target = tmp_path / "file"
        target.write_text("")
        out, expected = target / "r.nc", "Not a directory"
    else:
        target = tmp_path / "ro"
        target.mkdir(mode=0o555)
        out, expected = target / "r.nc", "Permission denied"
    code, _, err = run(capsys, "run", job, "-o", out)
    assert code == 1 and err.count("\n") == 1 and expected in err


def test_a_long_job_name_is_a_job_error(capsys, tmp_path):
    path = tmp_path / "long.toml"
    path.write_text(GOOD.replace('name = "good"', f'name = "{"x" * 300}"'))
    code, _, err = run(capsys, "run", path)
    assert code == 2 and err.count("\n") == 1 and "at most 200 characters" in err


def test_a_parts_directory_left_empty_by_a_failed_start_is_reused(capsys, job, tmp_path):
    (tmp_path / "r.nc.parts").mkdir()
    code, out, _ = run(capsys, "run", job, "-o", tmp_path / "r.nc")
    assert code == 0 and "6 computed" in out


def test_an_interrupted_merge_leaves_nothing_behind(capsys, job, tmp_path):
    assert run(capsys, "run", job, "-o", tmp_path / "r.nc")[0] == 0
    stale = tmp_path / ".r.nc.12345.tmp"
    stale.write_bytes(b"x" * 1000)
    assert run(capsys, "collect", tmp_path / "r.nc")[0] == 0
    assert not stale.exists()


def test_status_of_a_job_file_is_one_line(capsys, job):
    code, _, err = run(capsys, "status", job)
    assert code == 1 and err.count("\n") == 1 and "not a readable NetCDF result" in err


# -- a job split into pieces (Slurm arrays) -----------------------------------------


def test_two_pieces_collect_into_the_file_of_one_run(capsys, job, tmp_path):
    assert run(capsys, "run", job, "-o", tmp_path / "one.nc")[0] == 0
    for i in (2, 1):
        code, out, err = run(capsys, "run", job, "-o", tmp_path / "two.nc", "--chunks", f"{i}/2")
        assert code == 0, err
        assert f"piece {i}/2 of {tmp_path}/two.nc: " in out and "(0 failed)" in out and "python -m sweep collect" in out
        assert not (tmp_path / "two.nc").exists()
    code, out, _ = run(capsys, "status", tmp_path / "two.nc")
    assert "6 / 6 tasks completed, 3 / 3 chunks" in out
    assert run(capsys, "collect", tmp_path / "two.nc")[0] == 0
    assert data(tmp_path / "two.nc").identical(data(tmp_path / "one.nc"))
    assert "chunks 2/2" in run_attributes(tmp_path / "two.nc")["history"]
    failing = tmp_path / "failing.toml"
    failing.write_text(job.read_text().replace("scale = 1.0", "scale = 1.0\nfail_delta = 1.1"))
    code, out, _ = run(capsys, "run", failing, "-o", tmp_path / "f.nc", "--chunks", "1/2")
    assert code == cli.EXIT_TASKS_FAILED and "(2 failed)" in out  # an afterok collect waits
    with pytest.raises(SystemExit) as info:
        cli.main(["run", str(job), "--chunks", "3/2"])
    assert info.value.code == 2 and "'3/2' is invalid: need 1 <= I <= N" in capsys.readouterr().err


def test_a_merge_of_more_logs_than_it_keeps_open_is_the_same(capsys, job, tmp_path, monkeypatch):
    import io

    job.write_text(job.read_text().replace("chunk = 2", "chunk = 1"))  # two records per log
    assert run(capsys, "run", job, "-o", tmp_path / "one.nc")[0] == 0
    for i in range(1, 4):
        assert run(capsys, "run", job, "-o", tmp_path / "pieces.nc", "--chunks", f"{i}/3")[0] == 0
    assert len(list((tmp_path / "pieces.nc.parts").glob("run-*.log"))) == 3
    live, peak = set(), [0]

    class Counted(io.BufferedReader):
        def __init__(self, path, mode="rb"):
            super().__init__(io.FileIO(path, "r"))
            live.add(id(self))
            peak[0] = max(peak[0], len(live))

        def close(self):
            live.discard(id(self))
            super().close()

    monkeypatch.setattr(partlog, "open", Counted, raising=False)
    monkeypatch.setattr(partlog, "MAX_OPEN", 1)
    monkeypatch.setattr(partlog, "SCAN_BATCH", 1)
    assert run(capsys, "collect", tmp_path / "pieces.nc")[0] == 0
    assert peak[0] == 2 and not live  # the reader's one log and the one being scanned again
    assert data(tmp_path / "pieces.nc").identical(data(tmp_path / "one.nc"))


def test_pieces_run_side_by_side_and_a_whole_run_waits_for_them(tmp_path):
    job = tmp_path / "job.toml"
    # each piece runs 16 tasks of 0.25 s: longer than a second run takes to start and find its lock
    job.write_text(MPI_JOB.format(sleep=0.25))
    fast = tmp_path / "fast.toml"
    fast.write_text(MPI_JOB.format(sleep=0.0))  # the same results without the waits
    reference = sweep("run", fast, "-o", "ref.nc", ranks=0, cwd=tmp_path)
    assert reference.returncode == 0, reference.stderr
    launch = [sys.executable, "-m", "sweep", "run", str(job), "-o", "mpi.nc", "--progress", "none"]
    pieces = [subprocess.Popen([*launch, "--chunks", f"{i}/3"], cwd=tmp_path, env=sweep_env(),
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for i in (1, 2, 3)]
    parts = tmp_path / "mpi.nc.parts"
    deadline = time.monotonic() + 60
    while not list(parts.glob("lock-piece-*")) and time.monotonic() < deadline:
        time.sleep(0.02)
    whole = sweep("run", job, "-o", "mpi.nc", "--resume", ranks=0, cwd=tmp_path)
    results = [p.communicate(timeout=TIMEOUT) for p in pieces]
    assert all(p.returncode == 0 for p in pieces), [err for _, err in results]
    assert whole.returncode == 1 and "(piece-" in whole.stderr and "is in use by a run" in whole.stderr
    assert sorted(r["chunks"] for r in read_runs(parts)) == ["1/3", "2/3", "3/3"]
    assert len({r["run"] for r in read_runs(parts)}) == 3
    assert sweep("collect", "mpi.nc", ranks=0, cwd=tmp_path).returncode == 0
    assert data(tmp_path / "mpi.nc").identical(data(tmp_path / "ref.nc"))


def test_a_damaged_length_and_foreign_layouts_are_reported_not_crashed(capsys, job, tmp_path):
    from sweep.analyses.base import Variable

    variables = [Variable("x", (), (), "f8", "m", "x")]
    log = tmp_path / "a.log"
    w = partlog.Writer(log, variables)
    w.append(0, range(0, 2), np.zeros(2, np.int8), {"x": np.ones(2)}, {})
    w.close()
    raw = bytearray(log.read_bytes())
    head = list(partlog._HEADER.unpack(raw[:partlog._HEADER.size]))
    head[6] = 2**40                                                  # a flipped high bit of the length
    (tmp_path / "b.log").write_bytes(partlog._HEADER.pack(*head) + raw[partlog._HEADER.size:])
    chunks, problems = _chunks_and_problems(tmp_path / "b.log")
    assert chunks == [] and "damaged length" in problems[0]

    assert run(capsys, "run", job, "-o", tmp_path / "r.nc")[0] == 0
    manifest = tmp_path / "r.nc.parts" / "manifest.json"
    m = json.loads(manifest.read_text())
    m["variables"][0][2] = [7]
    manifest.write_text(json.dumps(m))
    code, _, err = run(capsys, "collect", tmp_path / "r.nc")
    assert code == 1 and "written by code that stores other variables" in err and err.count("\n") == 1


def test_a_terminal_that_goes_away_does_not_stop_the_progress_or_the_run():
    from sweep.progress import Progress

    class Gone:
        def write(self, text):
            raise OSError(5, "Input/output error")

        def flush(self):
            pass

        def isatty(self):
            return True

    progress = Progress(10, 0, Gone())
    progress.last -= 10
    progress.update(3)
    progress.finish(10)
    assert progress.stream is None
