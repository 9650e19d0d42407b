"""The full model with the in-plane displacements held at zero (``inplane=False``, ``[model]
inplane = false``): the ROM's hypothesis u = v = 0 on the full model's radial discretisation.

Its map holds ``W`` alone, its ``u`` stays exactly at rest in the compiled motion, its
multipliers at rest are the discrete map's closed form under a damping matrix, and its forced
response is what the ROM's converges to as the ROM's Bessel modes are added (two independent
radial bases of the same equations)."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.linalg import eigh

from model.damping import Modal, Rayleigh, Viscous
from model.forced import ForcedMap
from model.full.axisymmetric import AxisymmetricFull
from model.full.forced import ForcedFull, linear_system, steps_per_period
from model.full.families import FullFamily
from model.full.free import FreeFull
from model.full.static import solve_full_prestretch
from model.params import Loading, Membrane
from model.rk4 import stable
from model.rom import build_rom
from model.prestretch import solve_prestretch
from model.shooting import shoot
from sweep import cli, validation

MEMBRANE = Membrane(delta=1.1, delta_o=0.2)
JOBS = Path(__file__).resolve().parents[1] / "jobs"
#: A small held continuation with families (order 6, n = 1 on 2 and 6 functions).
HELD_JOB = """[job]
name = "held"
analysis = "continuation"
[model]
kind = "full"
order = 6
inplane = false
[grid]
delta = 1.1
delta_o = 0.2
P0 = 1.0
c = 0.05
[continuation]
parameter = "Omega"
start = 30.0
stop = 33.0
modes = [[1, 0]]
prestretch = "numeric"
max_points = 40
families = {n = [1], radial = [2, 6]}
"""


@pytest.fixture(scope="module")
def held():
    return AxisymmetricFull(solve_full_prestretch(MEMBRANE, 8), inplane=False)


def test_u_stays_exactly_at_rest_and_the_map_holds_w_alone(held):
    o = held.order
    y0 = np.zeros(2 * held.dof)
    y0[o:held.dof] = 0.05 * np.linspace(1.0, 0.3, o)  # 5 cm (over Re) of w, no u
    record = held.free_motion(y0, 0.2, 400, c=0.05)
    assert np.isfinite(record).all() and np.abs(record[-1, o:held.dof]).max() > 0
    assert np.abs(record[:, :o]).max() == 0.0 and np.abs(record[:, held.dof:held.dof + o]).max() == 0.0
    fmap = ForcedFull.build(held, 1.0, 30.0, Viscous(0.05), steps_per_period(held, 128))
    assert fmap.dof == o and fmap.monodromy(np.zeros(2 * o))[1].shape == (2 * o, 2 * o)
    # the held model's fastest mode is transverse: far fewer steps than with u moving
    moving = AxisymmetricFull(held.state)
    assert held.highest_frequency() < moving.highest_frequency() / 2
    free = FreeFull(held)
    assert free.dof == o and free.odd.all() and free.flow(np.zeros(2 * o), 0.01, 16)[1].shape == (2 * o, 2 * o)


def test_rest_multipliers_under_a_modal_ratio_are_the_discrete_closed_form(held):
    # at rest and P0 = 0 the map is linear: each transverse mode j with q'' + 2 zeta omega_j q'
    # + omega_j^2 q = 0 has the multipliers R(lambda dt)^N, R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24
    # (RK4's amplification), lambda = omega_j (-zeta +- i sqrt(1 - zeta^2)); no multiplier 1 (a
    # held coordinate kept in the state would add one)
    zeta = 0.01
    fmap = ForcedFull.build(held, 0.0, 30.0, Modal(zeta), steps_per_period(held, 128))
    mass, stiffness = linear_system(held)
    omega = np.sqrt(eigh(stiffness, mass, eigvals_only=True))
    dt = fmap.period / fmap.steps
    lam = np.concatenate([omega * (-zeta + 1j * np.sqrt(1 - zeta**2)), omega * (-zeta - 1j * np.sqrt(1 - zeta**2))])
    z = lam * dt
    expected = (1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) ** fmap.steps
    got = fmap.multipliers(np.zeros(2 * fmap.dof))
    assert got.size == expected.size
    np.testing.assert_allclose(np.sort_complex(got), np.sort_complex(expected), rtol=0, atol=1e-9)


def test_the_held_model_is_what_the_roms_bessel_modes_converge_to():
    # P0 = 10 Pa at 30 rad/s: 3.9 cm at 0.5 Re, nonlinear.  The held model on 24 Legendre
    # functions converges spectrally (order 16 -> 24 moves the amplitude by 3e-8 relative); the
    # ROM's Bessel modes of the analytic pre-stretch converge algebraically.  Two radial bases of
    # the same equations: the ROM with 16 modes must agree with the held model within its own
    # truncation error, estimated by its change from 12 to 16 modes
    P0, Omega, c = 10.0, 30.0, 0.05
    model = AxisymmetricFull(solve_full_prestretch(MEMBRANE, 24), inplane=False)
    fmap = ForcedFull.build(model, P0, Omega, Viscous(c), steps_per_period(model, 128))
    held = shoot(fmap, np.zeros(2 * fmap.dof))
    assert held.converged
    prestretch = solve_prestretch(MEMBRANE, "numeric")
    rom = {}
    for K in (12, 16):
        rmap = ForcedMap.from_loading(build_rom(prestretch, [(k, 0) for k in range(1, K + 1)]), Loading(Omega, P0, c),
                                      512)
        orbit = shoot(rmap, np.zeros(2 * K))
        assert orbit.converged
        rom[K] = orbit.amplitude
    assert abs(rom[16] - held.amplitude) < abs(rom[16] - rom[12])
    # and with the in-plane displacements free the same point differs by more than that
    moving = AxisymmetricFull(model.state)
    full = shoot(ForcedFull.build(moving, P0, Omega, Viscous(c), steps_per_period(moving, 128)),
                 np.zeros(4 * model.order))
    assert abs(full.amplitude - held.amplitude) > abs(rom[16] - rom[12])


def test_the_held_backbone_is_what_the_roms_bessel_modes_converge_to():
    # free orbits at 1 mm (linear: the first transverse frequency to (1e-3 / 0.1)^2 x the 6 %
    # bend of the backbone at 0.1 m, 6e-6; measured 8e-6) and at 5 cm; at 5 cm the ROM with 12 Bessel modes
    # lies within its own 8-to-12 change of the held model (two radial bases of the same
    # equations, as for the forced response; measured 3.1e-4 and 5.6e-4 rad/s, and with 16
    # modes 7e-5 within a 2.4e-4 change, 19 s more); with u free the frequency differs by more
    from model.backbone import continue_free_orbits
    from model.free import FreeRom

    model = AxisymmetricFull(solve_full_prestretch(MEMBRANE, 16), inplane=False)
    free = FreeFull(model)
    held = continue_free_orbits(free, [1e-3, 0.05])[0]
    assert held.converged.all()
    omega_1 = free.linear_frequencies()[0][0]
    assert held.omega[0] == pytest.approx(omega_1, rel=5e-5)
    prestretch = solve_prestretch(MEMBRANE, "numeric")
    rom = {K: continue_free_orbits(FreeRom(build_rom(prestretch, [(k, 0) for k in range(1, K + 1)])), [0.05])[0].omega[0]
           for K in (8, 12)}
    assert abs(rom[12] - held.omega[1]) < abs(rom[12] - rom[8])
    full = continue_free_orbits(FreeFull(AxisymmetricFull(model.state)), [0.05])[0].omega[0]
    assert abs(full - held.omega[1]) > abs(rom[12] - rom[8])


def test_a_held_continuation_job_runs_with_families_of_w_alone(tmp_path):
    job = tmp_path / "held.toml"
    job.write_text(HELD_JOB)
    out = tmp_path / "held.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["model_inplane"] == 0 and ds.attrs["model_order"] == 6
        assert (ds.status == 0).all()
        model = AxisymmetricFull(solve_full_prestretch(MEMBRANE, 6), inplane=False)
        fmap = ForcedFull.build(model, 1.0, 30.0, Viscous(0.05), steps_per_period(model, 128))
        first = float(ds.amplitude.isel(point=0).squeeze())
        assert first == pytest.approx(shoot(fmap, np.zeros(12)).amplitude, rel=1e-8)
        assert "family_radial" in ds.dims and ds.sizes["family_radial"] == 2
        assert ds.sizes["family_multiplier"] == 2 * 6  # W alone on 6 functions: (U, V, W) would give 36


@pytest.mark.parametrize("law", [Viscous(0.05), Modal(0.01), Rayleigh(alpha=0.1, beta=1e-4)])
def test_the_harmonic_zero_block_of_w_alone_is_the_held_monodromy(held, law):
    # the n = 0 family of W alone, integrated along the held orbit's stages with its own damping
    # terms, is the derivative of the held map: two codes for the same variational equations
    fmap = ForcedFull.build(held, 5.0, 33.5, law, steps_per_period(held, 128, law))
    y = shoot(fmap, np.zeros(2 * fmap.dof)).state
    phi = fmap.monodromy(y)[1]
    block = fmap.family_monodromy(y, FullFamily.build(held, 0, fields="W"))
    np.testing.assert_allclose(block, phi, rtol=0, atol=1e-12 * np.abs(phi).max())


@pytest.mark.parametrize("direction, inside, outside", [
    (1j, 2.82, 2.84),  # the imaginary axis: 2 sqrt(2)
    (-1.0, 2.78, 2.79),  # the negative real axis: 2.785
    (np.exp(1j * np.radians(123.0)), 2.60, 2.63),  # the closest point of the boundary, 2.6156
])
def test_rk4_stability_region_edges(direction, inside, outside):
    # the boundary |R(z)| = 1 of RK4's region (values from the literature, and the 123-degree
    # minimum from a scan of the boundary) lies between the two radii along each direction
    assert stable([direction], inside) and not stable([direction], outside)
    # and the amplification polynomial evaluated by numpy (not model.rk4's nested form) agrees
    r = np.linspace(inside, outside, 201)
    z = r * direction
    R = np.abs(np.polyval([1 / 24, 1 / 6, 1 / 2, 1, 1], z))
    assert R[0] <= 1.0 < R[-1]


def test_a_family_block_overdamped_beyond_rk4s_region_is_nan(held):
    # stiffness-proportional damping that overdamps the fastest modes (beta omega_max = 6): the
    # map's steps keep its own eigenvalues inside RK4's region, but the n = 20 family is stiffer
    # (its highest frequency about 1.2 times the map's), its overdamped decay beta omega^2 takes
    # it outside, although its frequency alone would pass the undamped bound: its block is NaN (a
    # failed point), not a growth
    law = Rayleigh(alpha=0.0, beta=6.0 / held.highest_frequency())
    fmap = ForcedFull.build(held, 0.0, 30.0, law, steps_per_period(held, 128, law))
    fam = FullFamily.build(held, 20, held.order, "W")
    dt = fmap.period / fmap.steps
    assert fmap.stable_step and dt * fam.omega_max < 2.8  # the premises
    assert np.isnan(fmap.family_monodromy(np.zeros(2 * fmap.dof), fam)).all()
    # the n = 1 family is as fast as the map: inside, finite
    assert np.isfinite(fmap.family_monodromy(np.zeros(2 * fmap.dof), FullFamily.build(held, 1, held.order, "W"))).all()


def test_the_report_section_survives_a_failed_held_branch(tmp_path):
    # the held runs of the paper-damping case, one with no branch: the section says so and
    # does not read the ROM's runs for it
    job = tmp_path / "held.toml"
    job.write_text(HELD_JOB)
    out = tmp_path / "held.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    names = validation.HELD_STUDIES[0][1]
    (tmp_path / "validation").mkdir()
    with xr.open_dataset(out) as ds:
        ds = ds.load()
    for k, name in enumerate(names):
        copy = ds.copy()
        if k == 1:
            copy["n_points"] = copy.n_points * 0
        copy.to_netcdf(tmp_path / f"{name}.nc")
    text = "\n".join(validation.section_held_families(tmp_path))
    assert "No branch at N = 6" in text and "| N | M = 2 |" not in text


def test_a_held_backbone_job_runs_without_in_plane_variables(tmp_path):
    # jobs/fig10-full-backbone.toml with u held, 8 functions, three amplitudes: the held
    # backbone's frequencies, and none of the in-plane extents a model with u free reports
    text = (JOBS / "fig10-full-backbone.toml").read_text().replace("order = 16", "order = 8\ninplane = false")
    text = text.replace("{ start = 0.001, stop = 0.4, num = 40 }", "{ start = 0.01, stop = 0.05, num = 3 }")
    text = text.replace("delta = [1.1, 1.5, 2.0]", "delta = [1.1]")
    job = tmp_path / "held-backbone.toml"
    job.write_text(text)
    out = tmp_path / "held-backbone.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["model_inplane"] == 0 and (ds.status == 0).all()
        assert "max_abs_u" not in ds and "max_abs_v" not in ds and np.isfinite(ds.omega_nl).all()
        # max |w| over the membrane against the probe's: at 1 cm the orbit has the first
        # linear mode's shape (the eigenvector of the linear problem, not the orbit's
        # integration) up to the orbit's O(A^2) change, of the order of its frequency shift
        model = AxisymmetricFull(solve_full_prestretch(MEMBRANE, 8), inplane=False)
        omega, vectors = FreeFull(model).linear_frequencies()
        basis = model.state.basis
        s = np.linspace(basis.s_in, basis.s_out, 20001)
        shape = np.abs(basis.evaluate(vectors[:, 0], s)[0])
        linear = shape.max() / np.abs(basis.evaluate(vectors[:, 0], np.array([0.5]))[0][0])
        shift = float(ds.omega_nl.values.ravel()[0] / omega[0] - 1)
        ratio = float((ds.max_abs_w / ds.amplitude).values.ravel()[0])
        assert abs(ratio / linear - 1) < 3 * shift
        from model.backbone import continue_free_orbits

        expected = continue_free_orbits(FreeFull(model), [0.01, 0.03, 0.05])[0].omega
        np.testing.assert_allclose(ds.omega_nl.values.ravel(), expected, rtol=1e-9)
