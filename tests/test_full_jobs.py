"""The full model as a job's model (``[model] kind = "full"``): its static and linear jobs
end to end against the ROM's jobs on the same membranes, and what it refuses."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sweep import cli

JOBS = Path(__file__).resolve().parents[1] / "jobs"


def _run(tmp_path, name, text):
    job = tmp_path / f"{name}.toml"
    job.write_text(text)
    out = tmp_path / f"{name}.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    return xr.load_dataset(out)


def test_full_static_job_equals_the_rom_numeric_prestretch(tmp_path):
    full = _run(tmp_path, "full", (JOBS / "validation/full-static.toml").read_text().replace("num = 161", "num = 41"))
    rom = _run(tmp_path, "rom", (JOBS / "fig02-03-static.toml").read_text().replace("num = 161", "num = 41"))
    assert full.attrs["model"] == "full" and rom.attrs["model"] == "rom"
    assert (full.status == 0).all()
    np.testing.assert_allclose(full.r_o, rom.r_o, atol=1e-10, equal_nan=True)
    np.testing.assert_allclose(full.sigma_1, rom.sigma_1, rtol=1e-8, equal_nan=True)
    np.testing.assert_allclose(full.traction, rom.traction, rtol=1e-9)


def test_full_linear_job_has_the_galerkin_and_the_inplane_frequencies(tmp_path):
    text = (JOBS / "validation/full-linear.toml").read_text().replace("basis = [8, 16, 24, 32, 48, 64]",
                                                                      "basis = [8, 32]")
    full = _run(tmp_path, "full", text)
    rom = _run(tmp_path, "rom", (JOBS / "table2.toml").read_text())
    assert full.omega.dims == full.omega_inplane.dims == ("delta", "delta_o", "basis", "mode")
    assert list(full.basis.values) == [8, 32]
    fine = full.isel(basis=-1)
    for k, n in enumerate((1, 2)):  # table2: modes (1, 1), (1, 2); the ROM's adaptive basis is within 2e-6
        at = int(np.nonzero((fine.m.values == 1) & (fine.n.values == n))[0][0])
        np.testing.assert_allclose(fine.omega.isel(mode=at), rom.omega.isel(mode=k), rtol=2e-6)
    assert (fine.omega_inplane > 0).all()
    # a sine companion has the frequencies of its cosine mode
    companion = _run(tmp_path, "companion", text.replace("[1, 3]]", "[1, 3], [1, -3]]"))
    np.testing.assert_array_equal(companion.omega.isel(mode=-1), companion.omega.isel(mode=-2))
    np.testing.assert_array_equal(companion.omega_inplane.isel(mode=-1), companion.omega_inplane.isel(mode=-2))
    # the coarse order is a worse approximation, not a different problem
    change = np.abs(full.omega.isel(basis=0) / fine.omega - 1)
    assert 0 < float(change.max()) < 1e-3


@pytest.mark.parametrize("table, message", [
    ('[model]\nkind = "full"\norder = 2\n', "model.order = 2 is invalid: must be >= 4"),
    ('[model]\nkind = "full"\nmodes = 3\n', "model.modes"),
])
def test_full_model_options_are_checked(tmp_path, capsys, table, message):
    job = tmp_path / "bad.toml"
    job.write_text((JOBS / "table1.toml").read_text() + table)
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc")]) != 0
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("job_name, message", [
    ("fig13-resonance", "an analysis that model 'full' can run (this one needs its forced_map"),
    ("table1-app2", "linear.prestretch = 'analytic' is invalid: must be one of numeric"),
])
def test_what_the_full_model_does_not_do_is_refused(tmp_path, capsys, job_name, message):
    job = tmp_path / "bad.toml"
    job.write_text((JOBS / f"{job_name}.toml").read_text() + '\n[model]\nkind = "full"\n')
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc")]) != 0
    assert message in capsys.readouterr().err
