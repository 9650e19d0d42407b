"""The full model as a job's model (``[model] kind = "full"``): its static, linear and backbone
jobs end to end against the ROM's jobs on the same membranes, and what it refuses."""

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


def test_full_backbone_job_is_softer_than_the_rom_and_its_methods_agree(tmp_path):
    # 8 radial functions, 1 and 2 cm (the validation job: 16 functions, up to 0.4 m)
    text = (JOBS / "fig10-full-backbone.toml").read_text()
    text = text.replace("order = 16", "order = 8").replace("delta = [1.1, 1.5, 2.0]", "delta = [1.1]")
    full = _run(tmp_path, "full", text.replace("start = 0.001, stop = 0.4, num = 40", "start = 0.01, stop = 0.02, num = 2")).squeeze()
    rom_text = (JOBS / "fig10-11-backbone.toml").read_text().replace("delta = [1.1, 1.2, 1.5, 2.0]", "delta = [1.1]")
    rom = _run(tmp_path, "rom", rom_text.replace("start = 0.001, stop = 0.4, num = 40",
                                                "start = 0.01, stop = 0.02, num = 2")).squeeze()
    assert (full.status == 0).all() and "modal_amplitude" not in full and "mode" not in full.dims
    # transverse and in-plane motion decouple about the flat state: the linear limit is the
    # converged Galerkin frequency, which the ROM's three Bessel shapes bound from above (Ritz)
    assert float(full.omega_linear) < float(rom.omega_linear) < float(full.omega_linear) * (1 + 1e-3)
    # shooting and damped decays are independent methods (the ROM's 3-mode bound)
    np.testing.assert_allclose(full.omega_peak, full.omega_nl, rtol=1e-4)
    # u = v = 0 is a constraint, and a constraint only stiffens: the full model's hardening
    # is below the ROM's (by about a third at these amplitudes)
    assert ((full.omega_nl - full.omega_linear) < (rom.omega_nl - rom.omega_linear)).all()
    assert ((full.omega_nl - full.omega_linear) > 0).all()
    # the probe is one point of the membrane; the motion is axisymmetric (v = 0); the radial
    # displacement is driven by w'^2, of second order, so max|u| / max|w| doubles with the amplitude
    assert (full.max_abs_w >= full.amplitude).all() and (full.max_abs_w < 1.1 * full.amplitude).all()
    assert (full.max_abs_v == 0).all()
    ratio = full.max_abs_u / full.max_abs_w
    assert float(ratio[1] / ratio[0]) == pytest.approx(2.0, rel=0.05)
    assert np.isnan(full.turn_amplitude) and np.isnan(full.turn_omega)  # no internal resonance below 2 cm


@pytest.mark.parametrize("table, message", [
    ('[model]\nkind = "full"\norder = 2\n', "model.order = 2 is invalid: must be >= 4"),
    ('[model]\nkind = "full"\nmodes = 3\n', "model.modes"),
    ('[model]\nkind = "full"\ninplane = 0\n', "model.inplane = 0 is invalid"),
])
def test_full_model_options_are_checked(tmp_path, capsys, table, message):
    job = tmp_path / "bad.toml"
    job.write_text((JOBS / "table1.toml").read_text() + table)
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc")]) != 0
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("job_name, message", [
    ("table1-app2", "linear.prestretch = 'analytic' is invalid: must be one of numeric"),
    ("fig10-11-backbone", "backbone.modes = [[1, 0], [2, 0], [3, 0]] is invalid: needs the ROM's mode families"),
    ("validation/families-viscous", "continuation.tongues = True is invalid: needs the ROM's mode families"),
    ("fig08-inplane", "backbone.orbit_samples = 64 is invalid: needs a model with in-plane motion"),
    ("fig14a-full", "continuation.families.inplane = True is invalid"),
])
def test_what_the_full_model_does_not_do_is_refused(tmp_path, capsys, job_name, message):
    """Including, with u = v = 0 held (``inplane = false``), the in-plane orbit fields and
    in-plane family perturbations."""
    text = (JOBS / f"{job_name}.toml").read_text()
    if "[model]" in text:
        text = text.replace("[model]", "[model]\ninplane = false")
    else:
        text += '\n[model]\nkind = "full"\n'
    job = tmp_path / "bad.toml"
    job.write_text(text)
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc")]) != 0
    assert message in capsys.readouterr().err


def test_the_orbit_fields_of_fig08_are_those_of_the_free_orbits(tmp_path):
    """``orbit_samples`` (jobs/fig08-inplane.toml on 8 functions, two orbits): the fields vanish
    on the edges, w at 0.5 Re at rest is the target amplitude, their largest values are the
    orbits' extents (sampled differently: within 1 %), and half a period later u repeats and
    w changes sign (the orbits' symmetry q(t + T/2) = S q(t), which holds to the shooting's
    tolerance: 1e-6 of the deflection is far above it and far below a broken symmetry)."""
    text = (JOBS / "fig08-inplane.toml").read_text().replace("order = 16", "order = 8")
    text = text.replace("delta = [1.1, 2.0]", "delta = [1.1]").replace("start = 0.01, stop = 0.5, num = 50",
                                                                       "start = 0.02, stop = 0.06, num = 2")
    ds = _run(tmp_path, "fig08", text.replace("orbit_samples = 64", "orbit_samples = 32")).squeeze()
    u, w = ds.orbit_u.values, ds.orbit_w.values
    assert u.shape == (2, 32, 81) and np.isfinite(u).all()
    assert np.abs(u[:, :, [0, -1]]).max() <= 1e-12 and np.abs(w[:, :, [0, -1]]).max() <= 1e-12
    half = int(np.argmin(np.abs(ds.orbit_radius.values - 0.375)))  # rho = 0.5 Re at delta_o = 0.2
    assert np.abs(np.abs(w[:, 0, half]) - ds.amplitude.values).max() <= 1e-9
    # the same field's maximum sampled on two grids (32 instants, 81 radii; every RK4 step, 201
    # radii): a smooth maximum missed by half a sample spacing h drops by ~ (pi h / T)^2 / 2 of
    # itself in time (0.5 % at 32 samples) and less in radius, so the two agree within 1 %
    for field, extent in ((u, ds.max_abs_u.values), (w, ds.max_abs_w.values)):
        largest = np.abs(field).max(axis=(1, 2))
        assert np.all(np.abs(largest / extent - 1) <= 0.01)
    assert np.abs(u[:, 16] - u[:, 0]).max() <= 1e-6 * np.abs(w).max()
    assert np.abs(w[:, 16] + w[:, 0]).max() <= 1e-6 * np.abs(w).max()


def test_orbit_samples_need_a_model_with_inplane_motion(tmp_path, capsys):
    job = tmp_path / "bad.toml"
    job.write_text((JOBS / "fig10-11-backbone.toml").read_text().replace(
        "[backbone]", "[backbone]\norbit_samples = 16"))
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc")]) != 0
    assert "backbone.orbit_samples = 16 is invalid: needs a model with in-plane motion" in capsys.readouterr().err
