"""Job file validation, task layout and the analysis registry (in-process, no MPI)."""

import json
import subprocess
import sys

import numpy as np
import pytest
from jobfiles import BAD, GOOD, job_text

from model.params import Loading, Membrane
from sweep import analyses
from sweep.analyses.base import JobError
from sweep.grid import MAX_DEFAULT_CHUNKS, default_chunk
from sweep.jobspec import load_job, parse_job

def test_layout_is_canonical_c_order_with_membrane_defaults():
    job = parse_job(GOOD)
    layout = job.layout
    assert layout.dims == ("delta", "delta_o", "Omega")
    assert layout.shape == (3, 2, 1)
    assert layout.n_tasks == 6 and layout.n_subtasks == 1
    np.testing.assert_array_equal(layout.values[0], [1.1, 1.3, 1.5])
    point, subtask = job.point(1)
    assert point.grid == {"delta": 1.1, "delta_o": 0.3, "Omega": 2.0}
    assert point.membrane == Membrane(delta=1.1, delta_o=0.3)
    assert point.loading == Loading(Omega=2.0)
    assert subtask == 0
    assert job.point(2)[0].membrane.delta == 1.3
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
    assert job.membrane == Membrane(h=2e-3, C1=1.0)
    assert isinstance(job.membrane.C1, float)


def test_default_chunk_bounds_the_number_of_part_files():
    assert default_chunk(1) == 1
    assert default_chunk(MAX_DEFAULT_CHUNKS) == 1
    assert default_chunk(MAX_DEFAULT_CHUNKS + 1) == 2


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


def test_registry_lists_the_analyses_without_importing_them():
    code = ("import json, sys, sweep.cli; from sweep import analyses; "
            "print(json.dumps([sorted(analyses.registry()), sorted(m for m in sys.modules if m in "
            "('numba', 'mpi4py.MPI', 'xarray') or m.startswith(('model', 'sweep.analyses.')))]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60, check=True).stdout
    listed, imported = json.loads(out)
    assert set(listed) == {"fake", "fake_nofig", "static", "linear", "backbone", "response",
                           "continuation", "basins"}
    # the contract, the parameter records and the mode-set wrapper (numpy only), no analysis
    # module and no kernel
    assert imported == ["model", "model.damping", "model.materials", "model.params", "sweep.analyses.base",
                        "sweep.analyses.mode_sets"]


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


def test_log_spaced_grid():
    job = parse_job(job_text(a=("Omega = 2.0", 'Omega = 2.0\nc = {start = 0.01, stop = 10.0, num = 4, scale = "log"}')))
    np.testing.assert_allclose(job.layout.values[job.layout.dims.index("c")], [0.01, 0.1, 1.0, 10.0], rtol=1e-12)
    with pytest.raises(JobError, match=r'start > 0 and stop > 0 with scale = "log"'):
        parse_job(job_text(a=("Omega = 2.0", 'Omega = 2.0\nc = {start = 0.0, stop = 1.0, num = 3, scale = "log"}')))
