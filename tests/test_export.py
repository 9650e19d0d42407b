"""``python -m sweep export``: the 2-D FE check's mesh and mode shapes as .vtu files (sweep/export.py).

Read back with meshio and checked against what the fields must be: the pre-stretch meets its
edge conditions (zero on the inner edge, ``(delta - 1) Re`` outward on the outer one), each
mode shape has the wave number of its label on a circle of the mesh, and the frequencies in the
names are those the ``linear`` analysis reports for the same mesh.
"""

import numpy as np
import pytest

from sweep.cli import main

JOB = """
[job]
name = "fe-export"
analysis = "linear"

[model]
kind = "fe2d"
radial = 3
circumferential = 24

[grid]
delta = [1.5]
delta_o = [0.3]

[linear]
modes = [[1, 0], [1, 2]]
"""


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    import meshio

    tmp = tmp_path_factory.mktemp("export")
    (tmp / "job.toml").write_text(JOB)
    assert main(["export", str(tmp / "job.toml"), "-o", str(tmp / "out")]) == 0
    assert main(["run", str(tmp / "job.toml"), "-o", str(tmp / "linear.nc"), "--progress", "none"]) == 0
    return meshio.read(tmp / "out" / "fe-export_delta=1.5_delta_o=0.3.vtu"), tmp / "linear.nc"


def test_the_prestretch_meets_its_edge_conditions(exported):
    mesh, _ = exported
    p, d = mesh.points, mesh.point_data["prestretch"]
    r = np.hypot(p[:, 0], p[:, 1])
    outer, inner = np.isclose(r, 1.0), np.isclose(r, 0.3)
    radial = (d[:, 0] * p[:, 0] + d[:, 1] * p[:, 1]) / r
    assert outer.sum() >= 24 and inner.sum() >= 24
    assert np.allclose(radial[outer], 0.5, atol=1e-12) and np.abs(d[inner]).max() <= 1e-12


@pytest.mark.parametrize("kind", ["W", "UV"])
def test_each_shape_has_the_wave_number_of_its_label(exported, kind):
    mesh, _ = exported
    p = mesh.points
    r, theta = np.hypot(p[:, 0], p[:, 1]), np.arctan2(p[:, 1], p[:, 0])
    ring = np.isclose(r, np.unique(np.round(r, 9))[len(np.unique(np.round(r, 9))) // 2])
    for n in (0, 2):
        name = next(k for k in mesh.point_data if k.startswith(f"{kind} m=1 n={n}:"))
        field = mesh.point_data[name][ring]
        value = field[:, 2] if kind == "W" else field[:, 0] * np.cos(theta[ring]) + field[:, 1] * np.sin(theta[ring])
        power = [abs(np.mean(value * np.exp(-1j * k * theta[ring]))) for k in range(5)]
        assert int(np.argmax(power)) == n


def test_the_frequencies_in_the_names_are_those_of_the_linear_analysis(exported):
    import xarray as xr

    mesh, result = exported
    ds = xr.load_dataset(result).squeeze()
    for k, (m, n) in enumerate(zip(ds.m.values, ds.n.values)):
        for kind, var in (("W", "omega"), ("UV", "omega_inplane")):
            name = next(key for key in mesh.point_data if key.startswith(f"{kind} m={m} n={n}:"))
            assert float(name.split(": ")[1].split()[0]) == pytest.approx(float(ds[var][k]), abs=6e-5)


def test_a_job_on_another_model_is_refused_in_one_line(tmp_path, capsys):
    (tmp_path / "rom.toml").write_text(JOB.replace('kind = "fe2d"\nradial = 3\ncircumferential = 24', 'kind = "rom"'))
    assert main(["export", str(tmp_path / "rom.toml"), "-o", str(tmp_path / "out")]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert any('export needs a linear job on [model] kind = "fe2d"' in line for line in err)
