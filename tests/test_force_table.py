"""The one-mode force table and the scalar integration paths that read it."""

import dataclasses

import numpy as np
import pytest

from model.forced import ForcedMap
from model.integrate import lockstep_table, monodromy, rk4_one_mode_lockstep, rk4_steps
from model.params import Membrane
from model.prestretch import solve_prestretch
from model.rom import TABLE_MAX_W, Forcing, build_rom, elastic_force, force_jacobian, force_work


@pytest.fixture(scope="module", params=[(1.1, 0.2), (2.0, 0.3), (1.02, 0.6)])
def roms(request):
    delta, delta_o = request.param
    rom = build_rom(solve_prestretch(Membrane(delta=delta, delta_o=delta_o), "numeric"), [(1, 0)],
                    probe_rho=0.5 * (1 + delta_o))
    return rom, rom.tables._replace(table_max=0.0)  # the same ROM read by quadrature


def test_table_reproduces_the_quadrature(roms):
    rom, exact = roms
    tab = rom.tables
    assert tab.table_max > 0 and tab.stiffness_table.shape[1] == 8
    q = np.concatenate([np.random.default_rng(1).uniform(-tab.table_max, tab.table_max, 500),
                        [1e-9, -1e-4, 0.999 * tab.table_max]])
    for x in q:
        g, g_ref = np.zeros(1), np.zeros(1)
        elastic_force(np.array([x]), tab, g, force_work(tab))
        elastic_force(np.array([x]), exact, g_ref, force_work(exact))
        j, j_ref = np.zeros((1, 1)), np.zeros((1, 1))
        force_jacobian(np.array([x]), tab, j)
        force_jacobian(np.array([x]), exact, j_ref)
        assert g[0] == pytest.approx(g_ref[0], rel=1e-12)
        assert j[0, 0] == pytest.approx(j_ref[0, 0], rel=1e-12)


def test_table_covers_the_stated_displacement(roms):
    rom, _ = roms
    rho = np.linspace(rom.membrane.Ro, rom.membrane.Re, 2001)
    w_max = np.abs(rom.displacement(np.array([rom.tables.table_max]), rho)).max()
    assert w_max == pytest.approx(TABLE_MAX_W * rom.membrane.Re, rel=1e-3)


@pytest.mark.parametrize("y0", [[0.1, 0.5], [1.5, -20.0], [0.0, 1000.0], "edge"])
def test_scalar_paths_match_the_general_ones(roms, y0):
    rom, exact = roms
    tab = rom.tables
    # "edge": starts inside the table and leaves it in the first step (hand-over);
    # (0, 1000 m/s) leaves it after 2 or 3 of the 64 steps (a hand-over within the period).
    y0 = np.array([0.999 * tab.table_max, 200.0] if isinstance(y0, str) else y0)
    period = 2 * np.pi / 33.5
    ya, yb = y0.copy(), y0.copy()
    work = np.empty((6, 2))
    forcing = Forcing(0.02, 1.0, 33.5)
    rk4_steps(ya, 0.0, period / 64, 64, tab, forcing, work)
    rk4_steps(yb, 0.0, period / 64, 64, exact, forcing, work)
    np.testing.assert_allclose(ya, yb, rtol=1e-11, atol=1e-12)
    za, pa = monodromy(y0, 0.0, period, 64, tab, forcing)
    zb, pb = monodromy(y0, 0.0, period, 64, exact, forcing)
    np.testing.assert_allclose(za, zb, rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(pa, pb, rtol=1e-10, atol=1e-12)
    amplitude = [ForcedMap(r, forcing, 64).amplitude(y0) for r in (rom, dataclasses.replace(rom, tables=exact))]
    assert amplitude[0] == pytest.approx(amplitude[1], rel=1e-11)


def test_no_table_for_several_modes():
    rom = build_rom(solve_prestretch(Membrane(), "analytic"), [(1, 0), (2, 0)])
    assert rom.tables.table_max == 0.0 and rom.tables.stiffness_table.size == 0


def test_lockstep_batch_is_the_scalar_loop(roms):
    """Lock-step RK4 (vectorised across trajectories) = the scalar table loop, trajectory by
    trajectory, up to rounding (fastmath may reassociate: 1e-12 relative); a trajectory
    that leaves the table within the steps is flagged by its reach."""
    rom, _ = roms
    tab = rom.tables
    forcing = Forcing(0.02, 1.0, 33.5)
    h = 2 * np.pi / 33.5 / 64
    rng = np.random.default_rng(2)
    y0 = np.column_stack([rng.uniform(-0.5, 0.5, 67), rng.uniform(-20.0, 20.0, 67)])
    y0[5] = [0.999 * tab.table_max, 200.0]  # leaves the table
    q, v, reach = y0[:, 0].copy(), y0[:, 1].copy(), np.empty(67)
    rk4_one_mode_lockstep(q, v, 0.0, h, 64, lockstep_table(tab), tab.table_max, tab.k_force[0], tab.load[0],
                          forcing.damping_rate, forcing.P0, forcing.Omega, reach)
    work = np.empty((6, 2))
    for b in range(67):
        y = y0[b].copy()
        rk4_steps(y, 0.0, h, 64, tab, forcing, work)
        assert (reach[b] >= tab.table_max) == (b == 5)
        if b != 5:
            np.testing.assert_allclose([q[b], v[b]], y, rtol=1e-12, atol=1e-13)
