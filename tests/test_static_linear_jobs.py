"""The paper's static and linear jobs end to end: job file -> NetCDF -> figures."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sweep import cli
from sweep.reference import TABLE1, TABLE2, TOL_AN, TOL_FEM

JOBS = Path(__file__).resolve().parents[1] / "jobs"


def run_job(tmp_path, name, **replace):
    text = (JOBS / f"{name}.toml").read_text()
    for old, new in replace.items():
        text = text.replace(old, new)
    job = tmp_path / f"{name}.toml"
    job.write_text(text)
    out = tmp_path / f"{name}.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    return out, xr.load_dataset(out)


def test_table1_job(tmp_path):
    out, ds = run_job(tmp_path, "table1")
    assert ds.omega.dims == ("delta", "delta_o", "mode")
    assert ds.omega.attrs["units"] == "rad s-1" and ds.delta.attrs["long_name"]
    assert (ds.status == 0).all()
    for (d, do), (fem, an, _, _) in TABLE1.items():
        pt = ds.sel(delta=d, delta_o=do, method="nearest").isel(mode=0)
        assert float(pt.omega) == pytest.approx(fem, rel=TOL_FEM)
        assert float(pt.omega_bound) > float(pt.omega)
    paths = [Path(p) for p in cli_figures(out, tmp_path / "fig")]
    assert paths and all(p.stat().st_size > 10_000 for p in paths)


def cli_figures(out, outdir):
    assert cli.main(["figures", str(out), "-o", str(outdir)]) == 0
    return sorted(outdir.glob("*.png"))


def test_table2_job(tmp_path):
    _, ds = run_job(tmp_path, "table2")
    assert list(ds.n.values) == [1, 2] and list(ds.m.values) == [1, 1]
    for (do, n, d), (an, fem) in TABLE2.items():
        pt = ds.sel(delta=d, delta_o=do, method="nearest").isel(mode=n - 1)
        assert float(pt.omega) == pytest.approx(fem, rel=TOL_FEM)
        assert float(pt.omega_approx) == pytest.approx(an, rel=TOL_AN)


def test_static_job_and_figures(tmp_path):
    out, ds = run_job(tmp_path, "fig02-03-static", **{"num = 161": "num = 33"})
    assert ds.r_o.dims == ("delta", "delta_o", "rho")
    assert ds.r_o.attrs["units"] == "m" and ds.sigma_1.attrs["units"] == "Pa"
    # Fixed edges: r_o(Ro) = Ro, r_o(Re) = Rf; NaN inside the hole of the larger delta_o.
    np.testing.assert_allclose(ds.r_o.sel(delta_o=0.2).isel(rho=0), 0.2, atol=1e-12)
    np.testing.assert_allclose(ds.r_o.isel(rho=-1), ds.delta.broadcast_like(ds.traction), atol=1e-12)
    assert np.isnan(ds.r_o.sel(delta_o=0.3).isel(rho=0)).all()
    assert (ds.traction > 0).all() and (ds.traction.diff("delta") > 0).all()
    names = [p.name for p in cli_figures(out, tmp_path / "fig")]
    assert names == ["fig02_radius.png", "fig03_stresses.png"]


def test_frequency_figures(tmp_path):
    text = ("[job]\nname = 'freq'\nanalysis = 'linear'\n[grid]\ndelta = {start = 1.05, stop = 2.0, num = 4}\n"
            "delta_o = [0.2, 0.3]\n[linear]\nmodes = [[1, 0], [2, 0], [1, 1]]\nprestretch = 'analytic'\n")
    job = tmp_path / "freq.toml"
    job.write_text(text)
    out = tmp_path / "freq.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    names = [p.name for p in cli_figures(out, tmp_path / "fig")]
    assert names == ["fig04_spectrum.png", "fig05_frequency_vs_delta.png",
                     "fig06_frequency_vs_delta_o.png", "fig07_modes.png"]


@pytest.mark.parametrize("table,message", [
    ("[linear]\nmodes = [[0, 0]]\n", "linear.modes = [0, 0] is invalid: each mode needs m >= 1 (n >= 0, or n < 0 for a sine companion)"),
    ("[linear]\nmodes = [[1, 0], [1, 0]]\n", "linear.modes = [[1, 0], [1, 0]] is invalid: modes must be distinct"),
    ("[linear]\nprestretch = 'exact'\n", "linear.prestretch = 'exact' is invalid: must be one of analytic, numeric, fit"),
    ("[linear]\nbasis = 2\nmodes = [[3, 0]]\n", "linear.basis = 2 is invalid: must be >= the largest m in linear.modes (3)"),
    ("[linear]\nbasis = [2, 8]\nmodes = [[3, 0]]\n", "linear.basis = [2, 8] is invalid: must be >= the largest m in linear.modes (3)"),
    ("[linear]\nbasis = [16, 8]\n", "linear.basis = [16, 8] is invalid: a list of distinct increasing sizes"),
    ("[linear]\nbasis = []\n", "linear.basis = [] is invalid: a basis size or a non-empty list of sizes"),
    ("[linear]\nbasis = [8, 'x']\n", "linear.basis = [8, 'x'] is invalid: a list of distinct increasing sizes"),
    ("[linear]\nspeed = 1\n", "linear.speed = 1 is invalid: unknown key; the keys of [linear] are modes, prestretch, basis"),
    ("[linear]\nmodes = [{n = 0, radial = 2, sine = true}]\n", "n = 0 has no sine companions"),
    ("[linear]\nmodes = [{n = 1}]\n", "a family shorthand is a table {n = N, radial = M} (optionally sine = true)"),
    ("[linear]\nmodes = [[1, 1], {n = 1, radial = 2}]\n", "modes must be distinct"),
])
def test_linear_option_errors(tmp_path, capsys, table, message):
    job = tmp_path / "bad.toml"
    job.write_text("[job]\nname = 'bad'\nanalysis = 'linear'\n[grid]\ndelta = [1.1]\ndelta_o = [0.2]\n" + table)
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc")]) == 2
    assert message in capsys.readouterr().err


def test_basis_list_is_a_convergence_study(tmp_path):
    # basis = [4, 8, 16, 32]: one Galerkin solution per size along a dimension basis.  The bases
    # are nested (the first b Bessel functions), so by the min-max principle each frequency can
    # only fall as the basis grows (Rayleigh-Ritz upper bounds), here to rounding (1e-12), and
    # the 32-function solution is the converged one of the default adaptive basis to 1e-5.
    job = tmp_path / "basis.toml"
    head = "[job]\nname = 'basis'\nanalysis = 'linear'\n[grid]\ndelta = [1.1]\ndelta_o = [0.2]\n"
    job.write_text(head + "[linear]\nmodes = [[1, 0], [3, 0], [1, 2]]\nbasis = [4, 8, 16, 32]\n")
    assert cli.main(["run", str(job), "-o", str(tmp_path / "basis.nc")]) == 0
    ds = xr.load_dataset(tmp_path / "basis.nc").squeeze()
    assert ds.omega.dims == ("basis", "mode") and list(ds.basis.values) == [4, 8, 16, 32]
    assert ds.omega_approx.dims == ("mode",) and int(ds.status) == 0
    omega = ds.omega.values
    assert (omega[1:] <= omega[:-1] * (1 + 1e-12)).all()
    assert omega[0, 1] > omega[-1, 1] * (1 + 1e-6)  # the coarse basis is not yet converged
    job.write_text(head + "[linear]\nmodes = [[1, 0], [3, 0], [1, 2]]\n")
    assert cli.main(["run", str(job), "-o", str(tmp_path / "adaptive.nc")]) == 0
    adaptive = xr.load_dataset(tmp_path / "adaptive.nc").squeeze()
    np.testing.assert_allclose(omega[-1], adaptive.omega.values, rtol=1e-5)
    names = [p.name for p in cli_figures(tmp_path / "basis.nc", tmp_path / "fig")]
    assert "fig04_spectrum.png" in names


def test_family_shorthand_and_sine_companions(tmp_path):
    # {n = 1, radial = 2, sine = true} is (1,1), (2,1) and their sine companions (1,-1), (2,-1),
    # whose frequencies are those of the cosine modes (the same Galerkin problem).
    text = ("[job]\nname = 'fam'\nanalysis = 'linear'\n[grid]\ndelta = [1.1]\ndelta_o = [0.2]\n"
            "[linear]\nmodes = [[1, 0], {n = 1, radial = 2, sine = true}]\n")
    job = tmp_path / "fam.toml"
    job.write_text(text)
    out = tmp_path / "fam.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    ds = xr.load_dataset(out).squeeze()
    assert list(zip(ds.m.values, ds.n.values)) == [(1, 0), (1, 1), (2, 1), (1, -1), (2, -1)]
    assert np.array_equal(ds.omega.values[1:3], ds.omega.values[3:5])
    assert [p.name for p in cli_figures(out, tmp_path / "fig")][-1] == "fig07_modes.png"


def test_static_rho_range_error(tmp_path, capsys):
    job = tmp_path / "bad.toml"
    job.write_text("[job]\nname = 'bad'\nanalysis = 'static'\n[grid]\ndelta = [1.1]\ndelta_o = [0.2]\n"
                   "[static]\nrho = {start = 0.5, stop = 2.0, num = 3}\n")
    assert cli.main(["plan", str(job)]) == 2
    assert "static.rho" in capsys.readouterr().err
