"""The full model with the in-plane displacements held at zero (``inplane=False``, ``[model]
inplane = false``): the ROM's hypothesis u = v = 0 on the full model's radial discretisation.

Its map holds ``W`` alone, its ``u`` stays exactly at rest in the compiled motion, its
multipliers at rest are the discrete map's closed form under a damping matrix, and its forced
response is what the ROM's converges to as the ROM's Bessel modes are added (two independent
radial bases of the same equations)."""

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
from model.rom import build_rom
from model.prestretch import solve_prestretch
from model.shooting import shoot
from sweep import cli

MEMBRANE = Membrane(delta=1.1, delta_o=0.2)


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
    with pytest.raises(ValueError, match="held at zero"):
        FreeFull(held)


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


def test_a_held_continuation_job_runs_with_families_of_w_alone(tmp_path):
    job = tmp_path / "held.toml"
    job.write_text("""[job]
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
""")
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
