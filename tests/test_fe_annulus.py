"""The two-dimensional finite-element check (model/fe_annulus.py, [model] kind = "fe2d"): its
pre-stretch and frequencies converge to the full model's at the order of its elements."""

import numpy as np
import pytest
import xarray as xr

from model.fe_annulus import AnnulusMesh, fe_frequencies, solve_fe_prestretch
from model.full.linear import inplane_frequencies, transverse_frequencies
from model.full.static import solve_full_prestretch
from model.params import Membrane
from model.prestretch import solve_prestretch
from sweep import cli

MEMBRANE = Membrane(delta=1.5, delta_o=0.2)


def _order(coarse, fine, refinement=2.0):
    return np.log(coarse / fine) / np.log(refinement)


def test_prestretch_converges_to_the_collocation_at_fourth_order():
    # quadratic elements: nodal errors O(h^4) on a quadratic mesh (the edges follow the circles);
    # 3.5 leaves room for the pre-asymptotic meshes of a fast test
    ref = solve_prestretch(MEMBRANE, "numeric")
    errors = []
    for radial in (4, 8):
        rho, r = solve_fe_prestretch(AnnulusMesh.build(MEMBRANE, radial, 8 * radial)).nodal_radius()
        assert rho[0] == pytest.approx(MEMBRANE.Ro) and rho[-1] == pytest.approx(MEMBRANE.Re)
        errors.append(np.abs(r - ref.radius(rho)).max())
    assert _order(*errors) > 3.5


def test_frequencies_converge_to_the_full_model_at_the_order_of_the_elements():
    # eigenvalues of quadratic elements converge as h^4, of bilinear ones as h^2; the full
    # model (spectral in the radius, exact in the angle) is the limit.  The bounds are below
    # the asymptotic orders by the pre-asymptotic margin of these coarse meshes.
    full = solve_full_prestretch(MEMBRANE)
    exact_w = np.array([transverse_frequencies(full, n, 1)[0] for n in range(3)])
    exact_u = np.array([inplane_frequencies(full, n, 1)[0] for n in range(3)])

    def errors(element, radial, circumferential, grading):
        state = solve_fe_prestretch(AnnulusMesh.build(MEMBRANE, radial, circumferential, element, grading))
        w, u = fe_frequencies(state, "W", 1, n_max=2), fe_frequencies(state, "UV", 1, n_max=2)
        return (np.abs(np.array([w[n][0] for n in range(3)]) / exact_w - 1).max(),
                np.abs(np.array([u[n][0] for n in range(3)]) / exact_u - 1).max())

    p2 = [errors("P2", r, 8 * r, "logarithmic") for r in (4, 8)]
    assert _order(p2[0][0], p2[1][0]) > 3.0 and _order(p2[0][1], p2[1][1]) > 3.0
    q1 = [errors("Q1", r, 4 * r, "uniform") for r in (6, 12)]
    for k in range(2):
        assert 1.6 < _order(q1[0][k], q1[1][k]) < 2.6


def test_axisymmetric_inplane_modes_are_the_radial_ones():
    # the eigenvectors of n = 0 are told apart: radial ones reported, torsional ones not (the
    # torsional frequencies lie 10 % and more from the radial ones here, the 8 x 64 mesh's error
    # of these two modes is 1e-3)
    state = solve_fe_prestretch(AnnulusMesh.build(MEMBRANE, 8, 64))
    full = solve_full_prestretch(MEMBRANE)
    np.testing.assert_allclose(fe_frequencies(state, "UV", 2, n_max=0)[0], inplane_frequencies(full, 0, 2), rtol=5e-3)


def test_bad_mesh_options_are_refused():
    state = solve_fe_prestretch(AnnulusMesh.build(MEMBRANE, 2, 16))
    with pytest.raises(ValueError, match="mass = 'lumped' is invalid for element = 'P2'"):
        fe_frequencies(state, "W", 1, mass="lumped")
    with pytest.raises(ValueError, match="grading = 'cubic' is invalid"):
        AnnulusMesh.build(MEMBRANE, 2, 16, grading="cubic")
    with pytest.raises(ValueError, match="circumferential"):
        AnnulusMesh.build(MEMBRANE, 2, 4)
    with pytest.raises(ValueError, match="n = 8 is invalid on 16 elements around"):
        fe_frequencies(state, "W", 1, n_max=8)


FE_JOB = """
[job]
name = "fe"
analysis = "linear"

[model]
kind = "fe2d"
radial = 4
circumferential = 32

[grid]
delta = 1.5
delta_o = 0.2

[linear]
modes = [[1, 0], [1, 1]]
"""


def test_fe2d_job(tmp_path, capsys):
    job = tmp_path / "fe.toml"
    job.write_text(FE_JOB)
    assert cli.main(["run", str(job), "-o", str(tmp_path / "fe.nc")]) == 0
    ds = xr.load_dataset(tmp_path / "fe.nc")
    assert ds.attrs["model"] == "fe2d" and ds.attrs["model_radial"] == 4 and ds.attrs["model_element"] == "P2"
    assert (ds.status == 0).all() and np.isnan(ds.omega_approx).all()
    full = solve_full_prestretch(MEMBRANE)
    expected = [transverse_frequencies(full, 0, 1)[0], transverse_frequencies(full, 1, 1)[0]]
    np.testing.assert_allclose(ds.omega.squeeze(), expected, rtol=5e-3)  # the 4 x 32 mesh's error: 2e-3
    job.write_text(FE_JOB.replace('circumferential = 32', 'circumferential = 32\nmass = "lumped"'))
    assert cli.main(["run", str(job), "-o", str(tmp_path / "bad.nc")]) != 0
    assert "model.mass = 'lumped' is invalid" in capsys.readouterr().err
