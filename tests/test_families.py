"""Asymmetric mode families on axisymmetric orbits (model.families).

The independent reference is the full mixed ROM of model.rom: its 2-D quadrature (uniform
rule in theta, no closed-form theta integrals), its own force Jacobian and its own RK4
variational equations (model.integrate.monodromy), and its nonlinear time integration from
a perturbed orbit.  The family blocks use radial quadrature only, the theta integrals in
closed form and, for one-mode ROMs, Chebyshev tables of the Jacobian.
"""

import numpy as np
import pytest

from model.continuation import BRANCH_POINT, FOLD, NEIMARK_SACKER, continue_orbits
from model.families import build_family, family_jacobian, perturbation_growth
from model.forced import ForcedMap, sorted_multipliers
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom, force_jacobian
from model.shooting import shoot

FIG14A = Loading(Omega=44.0, P0=1.0, c=0.05)


@pytest.fixture(scope="module")
def prestretch():
    return solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")


@pytest.fixture(scope="module")
def one_mode(prestretch):
    return build_rom(prestretch, [(1, 0)])


@pytest.fixture(scope="module")
def resonant_orbit(one_mode):
    """The resonant (upper) periodic response of Fig. 14a at Omega = 44 rad/s."""
    fmap = ForcedMap.from_loading(one_mode, FIG14A)
    res = shoot(fmap, np.array([0.5, 0.0]))
    assert res.converged and fmap.amplitude(res.state) > 0.4
    return fmap, res.state


def _embed(y, K_axi, K):
    # an axisymmetric state (q, q') of K_axi modes as a state of a K-mode ROM whose first
    # K_axi modes are the axisymmetric ones
    z = np.zeros(2 * K)
    z[:K_axi], z[K:K + K_axi] = y[:K_axi], y[K_axi:]
    return z


@pytest.mark.parametrize("axi, n", [([(1, 0)], 1), ([(1, 0)], 3), ([(1, 0), (2, 0)], 2)])
def test_family_jacobian_is_the_block_of_the_2d_rom(prestretch, axi, n):
    rom = build_rom(prestretch, axi)
    fam = build_family(prestretch, rom, n, 2)
    full = build_rom(prestretch, axi + list(fam.modes))
    Ka = len(axi)
    P = fam.tables.weight.size
    for q_axi in ([0.0] * Ka, [0.3] + [0.01] * (Ka - 1), [-0.8] + [-0.02] * (Ka - 1)):
        q = np.zeros(full.dof)
        q[:Ka] = q_axi
        ref = np.empty((full.dof, full.dof))
        force_jacobian(q, full.tables, ref)
        jac = np.empty((2, 2))
        family_jacobian(np.array(q_axi, dtype=float), fam.tables, np.empty(P), np.empty(P), jac)
        scale = np.abs(ref).max()
        assert np.abs(jac - ref[Ka:, Ka:]).max() <= 1e-11 * scale
        assert np.abs(ref[:Ka, Ka:]).max() <= 1e-12 * scale   # the blocks decouple
    assert np.allclose(fam.tables.k_force, full.tables.k_force[Ka:], rtol=1e-12)


def test_family_monodromy_is_the_block_of_the_2d_monodromy(prestretch, one_mode, resonant_orbit):
    fmap, y = resonant_orbit
    fam = build_family(prestretch, one_mode, 1, 2)
    block = fmap.family_monodromy(y, fam)
    full = build_rom(prestretch, [(1, 0)] + list(fam.modes))
    yT, phi = ForcedMap(full, fmap.forcing, fmap.steps).monodromy(_embed(y, 1, 3))
    sub = np.ix_([1, 2, 4, 5], [1, 2, 4, 5])
    assert np.abs(block - phi[sub]).max() <= 1e-8 * np.abs(phi[sub]).max()
    # the resonant orbit is unstable to n = 1 (a real multiplier well above 1)
    mu = sorted_multipliers(block)
    assert mu[0].imag == 0 and mu[0].real > 1.2


def test_perturbation_growth_matches_the_largest_multiplier(prestretch, one_mode, resonant_orbit):
    # Nonlinear 2-D ROM (1,0) + (1,1) + (2,1) started on the axisymmetric orbit with an
    # asymmetric perturbation of 1e-9 m: its growth over 10 periods (after 20 periods for the
    # dominant Floquet mode to take over; still small enough, ~1e-5 m, to be linear) is the
    # largest multiplier of the n = 1 block.
    fmap, y = resonant_orbit
    fam = build_family(prestretch, one_mode, 1, 2)
    mu = sorted_multipliers(fmap.family_monodromy(y, fam))
    full = ForcedMap(build_rom(prestretch, [(1, 0)] + list(fam.modes)), fmap.forcing, fmap.steps)
    z = _embed(y, 1, 3)
    z[[1, 2]] = 1e-9
    z20 = full.advance(z, 20)
    z30 = full.advance(z20, 10)
    growth = (np.linalg.norm(z30[[1, 2, 4, 5]]) / np.linalg.norm(z20[[1, 2, 4, 5]])) ** 0.1
    # the other multipliers contribute ~ |mu_2/mu_1|^20 relative to the first
    assert growth == pytest.approx(abs(mu[0]), rel=2 * abs(mu[1] / mu[0]) ** 20)
    # and the axisymmetric orbit is still followed at this size of perturbation
    assert np.abs(z30[[0, 3]] - y).max() <= 1e-6 * np.abs(y).max()


def test_stable_orbit_decays_like_its_multipliers(prestretch, one_mode):
    # The non-resonant response at Omega = 30 rad/s: every n = 1 multiplier inside the unit
    # circle (two pairs of modulus 0.99762); the perturbation decays at that rate.  The fitted
    # rate carries the beats of the pairs (~1e-4 over 100 periods); the bound, 5e-4, stays well
    # inside the 2.4e-3 between the multipliers and the stability limit, so growth would fail.
    fmap = ForcedMap.from_loading(one_mode, Loading(Omega=30.0, P0=1.0, c=0.05))
    y = shoot(fmap, np.zeros(2)).state
    fam = build_family(prestretch, one_mode, 1, 2)
    mu = sorted_multipliers(fmap.family_monodromy(y, fam))
    assert abs(mu[0]) < 1.0
    full = ForcedMap(build_rom(prestretch, [(1, 0)] + list(fam.modes)), fmap.forcing, fmap.steps)
    growth, (low, high), _ = perturbation_growth(full, y, (1, 2), periods=100)
    assert growth < 1.0 and growth == pytest.approx(abs(mu[0]), rel=5e-4)
    assert np.isnan(low) and np.isnan(high)  # no saturate periods, no range
    # 200 periods more: the asymmetric displacement's samples over the last 20 lie within
    # the decayed perturbation, 1e-9 m per coordinate times |mu|^300 = 0.49, at the probe
    probe = full.rom.tables.probe * (np.arange(full.dof) > 0)  # the asymmetric modes' part
    _, (low, high), _ = perturbation_growth(full, y, (1, 2), periods=100, saturate=200, probe=probe)
    size = 1e-9 * np.abs(full.rom.tables.probe[[1, 2]]).sum() * abs(mu[0]) ** 300
    assert -size < low <= high < size


@pytest.fixture(scope="module")
def fig14a_branch(prestretch, one_mode):
    fams = [build_family(prestretch, one_mode, n, 2) for n in (1, 3)]
    fmap = ForcedMap.from_loading(one_mode, Loading(Omega=25.0, P0=1.0, c=0.05))
    return continue_orbits(fmap, "Omega", 25.0, 55.0, ds_max=0.3, max_points=1000, families=fams), fams


def test_branch_points_and_neimark_sacker_points_are_located(prestretch, one_mode, fig14a_branch):
    br, fams = fig14a_branch
    assert br.complete
    assert br.special(FOLD).size == 2 and set(br.family[br.special(FOLD)]) == {0}
    bps = br.special(BRANCH_POINT)
    ns = br.special(NEIMARK_SACKER)
    assert bps.size >= 2 and set(br.family[bps]) == {1}
    assert ns.size >= 2 and set(br.family[ns]) == {3}
    for i in bps:
        # checked on the 2-D ROM (1,0) + (1,1) + (2,1): a multiplier at +1 besides the
        # axisymmetric ones
        fmap = ForcedMap.from_loading(one_mode, Loading(Omega=br.value[i], P0=1.0, c=0.05))
        full = ForcedMap(build_rom(prestretch, [(1, 0)] + list(fams[0].modes)), fmap.forcing, fmap.steps)
        mu = sorted_multipliers(full.monodromy(_embed(br.state[i], 1, 3))[1][np.ix_([1, 2, 4, 5], [1, 2, 4, 5])])
        assert np.min(np.abs(mu - 1.0)) <= 1e-7
    mixed3 = build_rom(prestretch, [(1, 0)] + list(fams[1].modes))
    for i in ns:
        # checked on the 2-D ROM (1,0) + (1,3) + (2,3): a complex pair on the unit circle
        fmap = ForcedMap.from_loading(one_mode, Loading(Omega=br.value[i], P0=1.0, c=0.05))
        full = ForcedMap(mixed3, fmap.forcing, fmap.steps)
        mu = sorted_multipliers(full.monodromy(_embed(br.state[i], 1, 3))[1][np.ix_([1, 2, 4, 5], [1, 2, 4, 5])])
        pair = mu[np.abs(mu.imag) > 1e-6]
        assert pair.size >= 2 and np.abs(np.abs(pair) - 1.0).min() <= 1e-7
    # between a branch point and the fold, the resonant branch is unstable to n = 1
    first_bp, fold = bps.min(), br.special(FOLD).min()
    between = np.arange(first_bp + 1, fold)
    assert np.all(np.abs(br.family_multipliers[between, 0, 0]) > 1.0)
    assert not br.stable[between].any()


def test_a_pair_crossing_without_a_located_point_is_recorded_between_its_neighbours(monkeypatch, one_mode,
                                                                                    fig14a_branch):
    # With every located NS zero discarded (as where the zero found is a pair meeting on the
    # real axis), the n = 3 Neimark-Sacker points of the branch are not inserted but recorded
    # in Branch.unlocated from the count of multipliers outside the circle, each between the
    # regular points around the located one; every other point is as before
    import model.continuation as continuation

    br, fams = fig14a_branch
    monkeypatch.setattr(continuation, "_complex_pair_on_circle", lambda *args: False)
    fmap = ForcedMap.from_loading(one_mode, Loading(Omega=25.0, P0=1.0, c=0.05))
    again = continue_orbits(fmap, "Omega", 25.0, 55.0, ds_max=0.3, max_points=1000, families=fams)
    kept = br.kind != NEIMARK_SACKER
    np.testing.assert_array_equal(again.value, br.value[kept])
    np.testing.assert_array_equal(again.kind, br.kind[kept])
    regular = np.flatnonzero(br.kind == 0)
    expected = [(NEIMARK_SACKER, 3, br.value[regular[regular < i].max()], br.value[regular[regular > i].min()])
                for i in br.special(NEIMARK_SACKER)]
    assert [u for u in again.unlocated] == expected


def test_families_need_an_axisymmetric_rom_and_n_at_least_one(prestretch, one_mode):
    with pytest.raises(ValueError, match="axisymmetric ROM"):
        build_family(prestretch, build_rom(prestretch, [(1, 0), (1, 1)]), 1, 2)
    with pytest.raises(ValueError, match="n = 0 is invalid"):
        build_family(prestretch, one_mode, 0, 2)
    with pytest.raises(ValueError, match="radial"):
        build_family(prestretch, one_mode, 1, [2, 2])
