"""The Fig. 14a resonance with two axisymmetric modes loses its half-period symmetry.

The ROM is odd in q, so the response to P0 cos(Omega t) can be symmetric in time,
q(t + T/2) = -q(t); its monodromy matrix is then the square of the half-period map
H(y) = -P_{T/2}(y), and a real multiplier of H through -1 is a real multiplier of the
monodromy through +1 without a fold: a branch point of the axisymmetric block, where
responses without that symmetry bifurcate (docs/model.md, "Bifurcation test functions").
With the modes (1,0), (2,0) at the paper's damping the resonant branch of Fig. 14a passes
one on its way up.  Checked: the located point has a multiplier +1 and stability changes
across it; beyond it, the Floquet multiplier against the growth of a perturbation
integrated by scipy's DOP853 on a plain numpy right-hand side (an independent integrator
and force), and the half-period map's derivative by central differences of that
integration, whose eigenvalue -sqrt(mu) says the growing perturbation breaks the symmetry.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from plain_rom import plain_rhs
from model.continuation import BRANCH_POINT, continue_orbits
from model.damping import Viscous
from model.forced import ForcedMap, steps_per_period
from model.params import Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom

#: Where the branch is followed to (rad/s): past the branch point, on the resonant stretch
#: (its upper saddle-node with these modes lies near 45.8 rad/s).
TOP = 42.0


@pytest.fixture(scope="module")
def branch():
    rom = build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0), (2, 0)])
    fmap = ForcedMap.build(rom, 1.0, 25.0, Viscous(0.05), steps_per_period(rom, 128))
    br = continue_orbits(fmap, "Omega", 25.0, TOP, ds_max=0.3, max_points=400)
    assert br.complete
    return rom, fmap, br


def test_the_axisymmetric_branch_point_is_located_where_a_multiplier_is_plus_one(branch):
    _, _, br = branch
    points = np.flatnonzero((br.kind == BRANCH_POINT) & (br.family == 0))
    assert points.size == 1
    i = int(points[0])
    mu = br.multipliers[i]
    # a real multiplier +1, to the accuracy the Illinois bracket reached around the
    # singular point (the corrector's retries stop there)
    assert np.min(np.abs(mu - 1.0)) < 1e-4
    assert br.stable[i - 1] and not br.stable[i + 1]
    after = br.multipliers[i + 1]
    outside = after[np.abs(after) > 1.0]
    assert outside.size == 1 and abs(outside[0].imag) < 1e-12 and outside[0].real > 1.0
    # no fold nearby: the branch goes on up in Omega through the point
    assert br.value[i - 1] < br.value[i] < br.value[i + 1]


def test_beyond_it_a_perturbation_grows_at_the_floquet_rate_and_breaks_the_symmetry(branch):
    rom, fmap, br = branch
    y0 = br.state[-1]
    mu = br.multipliers[-1]
    Omega = br.value[-1]
    assert Omega == pytest.approx(TOP)
    K, T = rom.dof, 2.0 * np.pi / Omega
    elastic = plain_rhs(rom)
    rate = fmap.forcing.damping_rate
    load = np.concatenate([np.zeros(K), rom.tables.load])

    def f(t, y):
        return elastic(t, y) + np.concatenate([np.zeros(K), -rate * y[K:]]) + np.cos(Omega * t) * load

    def flow(y, duration, **kw):
        return solve_ivp(f, (0.0, duration), y, method="DOP853", rtol=1e-12, atol=1e-15, **kw)

    # the RK4 orbit is periodic for DOP853 to its discretisation error; take DOP853's point
    y0 = flow(y0, T).y[:, -1]
    # the response is symmetric in time: y(T/2) = -y(0)
    assert np.abs(flow(y0, T / 2).y[:, -1] + y0).max() < 1e-6 * np.abs(y0).max()
    unstable = mu[np.abs(mu) > 1.0]
    assert unstable.size == 1
    growth_floquet = abs(unstable[0])
    # a perturbation of 1e-7 m grows by the largest multiplier per period (the next one,
    # inside the circle or barely out, decays relative to it by (|mu_2| / |mu_1|)^k)
    periods = np.arange(26)
    dy = np.random.default_rng(1).standard_normal(2 * K)
    dy *= 1e-7 / np.abs(dy).max()
    kw = {"t_eval": periods * T}
    deviation = np.abs(flow(y0 + dy, periods[-1] * T, **kw).y - flow(y0, periods[-1] * T, **kw).y).max(axis=0)
    growth = np.exp(np.polyfit(periods[5:], np.log(deviation[5:]), 1)[0])
    assert growth == pytest.approx(growth_floquet, rel=1e-2)
    # the half-period map H(y) = -y(T/2) has the orbit as a fixed point; its derivative's
    # eigenvalues square to the multipliers, and the unstable one is negative: the growing
    # perturbation changes sign under the symmetry, q(t + T/2) = -q(t) is broken
    steps = 1e-6 * np.maximum(np.abs(y0), 1e-3)
    jac = np.column_stack([(flow(y0 - h * e, T / 2).y[:, -1] - flow(y0 + h * e, T / 2).y[:, -1]) / (2 * h)
                           for e, h in zip(np.eye(2 * K), steps)])
    half = np.linalg.eigvals(jac)
    largest = half[np.argmax(np.abs(half))]
    assert abs(largest.imag) < 1e-6 and largest.real < -1.0
    assert largest.real ** 2 == pytest.approx(growth_floquet, rel=1e-4)
