"""Standing and rotating waves in the O(2) ROM (model/waves.py).

Checks from the symmetry and from bifurcation theory, independent of the code under test:
the ROM with sine companions commutes with the rotation as the code defines it (the map of a
turned state is the turned image); a standing wave's monodromy splits into even and odd blocks
and the odd one carries the group orbit's multiplier 1, the even one equals the cosine-mode
ROM's own; rotating waves are born at the family's Neimark-Sacker point with the drift its
multiplier angle gives and grow like the square root of the parameter distance (the Hopf
normal form of a map with O(2) symmetry).
"""

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.linalg import expm

from model import waves
from model.continuation import BRANCH_POINT, NEIMARK_SACKER, continue_orbits
from model.families import build_family, embedded
from model.params import Membrane
from model.switching import follow_bifurcated_branch
from sweep.analyses.continuation import CONTINUATION
from sweep.jobspec import grid_point


@pytest.fixture(scope="module")
def n3(fig14a_n1):
    """The Fig. 14a branch from 25 rad/s up past the first n = 3 Neimark-Sacker point, and the
    first 12 points of the rotating waves born there (to 40.63 rad/s; 40 points, to 41.5 rad/s,
    took 12 s more of the suite)."""
    family = build_family(fig14a_n1.prestretch, fig14a_n1.rom, 3, 2)
    br = continue_orbits(fig14a_n1.fmap, "Omega", 25.0, 41.5, ds_max=0.3, max_points=400, families=[family])
    i = br.special(NEIMARK_SACKER)[0]
    rw, o2 = waves.continue_rotating_waves(fig14a_n1.fmap, family, "Omega", 25.0, 41.5, br.state[i],
                                           br.value[i], ds_max=0.3, max_points=12)
    return SimpleNamespace(family=family, branch=br, ns=i, waves=rw, o2=o2, fmap_o2=o2.fmap)


def test_rotation_is_the_exponential_of_its_generator():
    modes = [(1, 0), (1, 3), (2, 3), (1, -3), (2, -3)]
    for phi in (0.3, -1.7, 2 * np.pi / 3):
        assert np.allclose(waves.rotation(modes, phi), expm(phi * waves.rotation_generator(modes)), atol=1e-13)
    assert np.allclose(waves.rotation(modes, 2 * np.pi / 3), np.eye(10), atol=1e-13)  # n = 3: a third of a turn


def test_the_rotation_turns_the_pattern_as_documented():
    """``R_phi`` maps the coordinates of ``w`` to those of ``w(theta - phi)``: the field of the
    turned coordinates, evaluated with the mode shapes of the ROM, at a radius and eight angles."""
    from model.modes import bessel_roots, mode_shape

    modes = [(1, 0), (1, 3), (2, 3), (1, -3), (2, -3)]
    rho, theta, phi = 0.6, np.linspace(0.0, 2 * np.pi, 8, endpoint=False), 0.37
    shapes = np.array([mode_shape(np.array([rho]), bessel_roots(abs(n), 0.2, m)[-1], abs(n), 1.0, 0.2)[0][0]
                       for m, n in modes])

    def field(q, angle):
        angular = np.array([np.cos(n * angle) if n >= 0 else np.sin(-n * angle) for _, n in modes])
        return (q * shapes) @ angular

    q = np.array([0.3, 0.02, -0.01, 0.005, 0.015])
    turned = waves.rotation(modes, phi)[:5, :5] @ q
    assert np.allclose(field(turned, theta), field(q, theta - phi), atol=1e-15)


def test_deflation_keeps_every_other_multiplier():
    """The removed multiplier and the kept ones are the matrix's eigenvalues: a random matrix
    with a known eigenvector of eigenvalue 1."""
    rng = np.random.default_rng(7)
    v = rng.standard_normal(5)
    basis = np.column_stack([v, rng.standard_normal((5, 4))])
    jac = basis @ np.block([[np.diag([1.0, 0.9, -0.5]), np.zeros((3, 2))],
                            [np.zeros((2, 3)), np.array([[0.3, 0.2], [-0.2, 0.3]])]]) @ np.linalg.inv(basis)
    rest, neutral = waves.deflated_multipliers(jac, v)
    assert neutral == pytest.approx(v @ jac @ v / (v @ v), abs=1e-14)
    assert np.sort_complex(np.append(rest, 1.0)) == pytest.approx(np.sort_complex(np.linalg.eigvals(jac)), abs=1e-12)


def test_the_rom_commutes_with_the_rotation(n3):
    """``P(R_phi y) = R_phi P(y)`` for a generic state of the size of the waves (centimetres):
    the rotation as coded is the symmetry of the ROM built from the mode shapes.  Only turns by
    multiples of ``2 pi / theta_points`` are exact symmetries of the angular rule; others hold
    to its (spectrally small) error, here below rounding with the default rule."""
    f = n3.fmap_o2.varied("Omega", 41.0)
    K = f.dof
    rng = np.random.default_rng(3)
    y = np.concatenate([0.01 * rng.standard_normal(K), 0.3 * rng.standard_normal(K)])
    r = waves.rotation(f.rom.modes, 0.4)
    left, right = f.advance(r @ y), r @ f.advance(y)
    assert np.linalg.norm(left - right) <= 1e-11 * np.linalg.norm(right)


def test_standing_waves_split_into_even_and_odd_blocks(fig14a_n1):
    fmap, br = fig14a_n1.fmap, fig14a_n1.branch
    i = br.special(BRANCH_POINT)[0]
    sw, _, asym = follow_bifurcated_branch(fmap, fig14a_n1.family, "Omega", 25.0, 55.0, br.state[i],
                                                    br.value[i], ds=0.01, ds_max=0.3, max_points=8)
    o2 = fmap.companions(fig14a_n1.family)
    assert o2.fmap.rom.modes == waves.o2_rom(fmap.rom, fig14a_n1.family).modes
    for k in (3, 7):
        at = o2._replace(fmap=o2.fmap.varied("Omega", sw.value[k]))
        st = waves.standing_wave_stability(at, embedded(sw.state[k], o2.fmap.dof))
        assert st.coupling <= 1e-12
        assert abs(st.neutral - 1.0) <= 1e-9
        # the even block is the cosine-mode ROM's monodromy (a folded angular rule there)
        assert np.allclose(st.even, sw.multipliers[k], atol=1e-10)
        assert st.odd.size == 3
    with pytest.raises(ValueError, match="not a standing wave"):
        y = embedded(sw.state[3], o2.fmap.dof)
        y[3] = 1e-6
        waves.standing_wave_stability(o2, y)


def test_rotating_waves_near_the_point_drift_by_its_multiplier_angle(n3):
    """The drift of the corrected rotating waves (Newton on the map, not the start) tends to
    ``-theta / n`` of the critical multiplier ``exp(i theta)`` of the n = 3 block found by the
    continuation: the difference shrinks with the wave size squared."""
    rw = n3.waves
    mu = n3.branch.family_multipliers[n3.ns, 0]
    theta = np.angle(mu[np.argmin(np.abs(np.abs(mu) - 1.0) + (mu.imag <= 0))])
    gap = np.abs(rw.drift[1:6] + theta / 3)
    assert gap[0] <= 1e-5
    assert np.all(gap / rw.wave_amplitude[1:6] ** 2 <= 2 * gap[-1] / rw.wave_amplitude[5] ** 2 + 1e-9)


def test_rotating_waves_grow_like_a_square_root(n3):
    rw = n3.waves
    d = rw.value[2:8] - rw.value[0]
    assert np.all(d > 0)  # supercritical here: beyond the point, where the axisymmetric response is unstable
    ratio = rw.wave_amplitude[2:8] ** 2 / d
    assert np.ptp(ratio) <= 0.1 * ratio.mean()


def test_a_rotating_wave_turns_its_pattern_at_a_constant_rate(n3):
    """Three periods of the map from a rotating wave: the pattern's size stays, its angle
    advances by the drift each period (the defining property, from the map itself)."""
    rw = n3.waves
    k = rw.value.size - 1
    f = n3.fmap_o2.varied("Omega", rw.value[k])
    r = waves.rotation(f.rom.modes, rw.drift[k])
    y = rw.state[k]
    for _ in range(3):
        y_next = f.advance(y)
        assert np.linalg.norm(y_next - r @ y) <= 1e-8 * np.linalg.norm(y)
        y = y_next
    assert abs(rw.neutral[k] - 1.0) <= 1e-9 and rw.stable[k]


def test_wave_motion_reads_the_drift_of_a_turning_pattern(n3):
    """A map that only turns the pattern: the drift read back is the turn, with no spread."""
    modes = n3.fmap_o2.rom.modes
    r = waves.rotation(modes, -0.3)

    class Turning:
        @staticmethod
        def advance(y, periods=1):
            for _ in range(periods):
                y = r @ y
            return y

    y0 = np.zeros(2 * len(modes))
    y0[1:5] = [1e-3, 2e-4, -5e-4, 1e-4]
    motion = waves.wave_motion(n3.o2._replace(fmap=Turning), y0, 3, 40)
    assert motion.drift == pytest.approx(-0.3, abs=1e-12)
    assert motion.drift_spread <= 1e-12 and motion.wave_spread <= 1e-12
    assert motion.wave_amplitude == pytest.approx(np.linalg.norm(y0[1:5]), rel=1e-12)


def test_the_continuation_job_reports_standing_and_rotating_waves():
    """``branch_switching`` with ``periods`` and ``rotating_waves`` through the analysis: the
    rotating waves start with the drift of the n = 3 block's multipliers at the located
    Neimark-Sacker point as the output reports them, the group orbits' multipliers are 1, and
    the checks are run."""
    grid = {"delta": np.array([1.1]), "delta_o": np.array([0.2]), "P0": np.array([1.0]), "c": np.array([0.05])}
    options = CONTINUATION.parse_options({
        "parameter": "Omega", "start": 25.0, "stop": 42.5, "max_points": 400, "ds_max": 0.3,
        "families": {"n": [1, 3], "radial": 2}, "branch_switching": {"max_points": 5, "periods": 20},
        "rotating_waves": {"max_points": 5, "n": 3, "periods": 20}}, grid, Membrane())
    point = grid_point(Membrane(), {"delta": 1.1, "delta_o": 0.2, "P0": 1.0, "c": 0.05})
    out = CONTINUATION.compute(point, options, 0)
    shapes = {v.name: v.shape for v in CONTINUATION.variables(options)}
    assert all(np.shape(out[k]) == s for k, s in shapes.items())
    assert out["status"] == 0, out["message"]
    ns = np.flatnonzero((out["point_type"] == NEIMARK_SACKER) & (out["point_family"] == 3))[0]
    mu = out["family_multiplier_real"][ns, 1] + 1j * out["family_multiplier_imag"][ns, 1]
    upper = mu[mu.imag > 0]
    theta = np.angle(upper[np.argmin(np.abs(np.abs(upper) - 1.0))])
    assert out["rotating_Omega"][0] == pytest.approx(out["Omega"][ns], abs=1e-12)
    assert out["rotating_drift"][0] == pytest.approx(-theta / 3, abs=1e-6)
    assert np.all(np.abs(out["rotating_neutral_multiplier"][1:] - 1.0) <= 1e-9)
    assert np.all(np.abs(out["switched_neutral_multiplier"][1:] - 1.0) <= 1e-9)
    assert list(out["rotating_mode_n"]) == [0, 3, 3, -3, -3] and list(out["switched_mode_n"]) == [0, 1, 1]
    assert out["switched_stable_o2"][0] == 0 and set(out["switched_stable_o2"][1:]) <= {0, 1}
    for prefix in ("switched", "rotating"):
        assert np.isfinite([out[f"{prefix}_check_{k}"] for k in ("Omega", "drift", "wave_amplitude")]).all()


def test_the_rotating_check_is_taken_inside_the_unstable_interval_of_its_point():
    """The check starts where the axisymmetric response is unstable to the family: the wave
    nearest the middle of the interval that ends at the Neimark-Sacker point (a branch may run
    backwards in the parameter), none when no wave lies inside."""
    from sweep.analyses.wave_features import _check_point

    branch = SimpleNamespace(value=np.array([40.0, 41.0, 44.0, 46.0, 45.0]),
                             unstable_intervals=lambda j: [(44.0, 41.0), (46.0, 47.0)])
    waves_at = np.array([41.0, 41.5, 42.4, 43.9, 45.0])
    assert _check_point(branch, 0, 1, waves_at) == 2  # nearest 42.5, inside (41, 44)
    assert _check_point(branch, 0, 1, np.array([40.5, 44.5])) is None
    assert _check_point(SimpleNamespace(value=branch.value, unstable_intervals=lambda j: []), 0, 1, waves_at) is None
