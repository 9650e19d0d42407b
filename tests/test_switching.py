"""Branch switching at the n = 1 branch point of the Fig. 14a resonance (model/switching.py).

Checks from theory, independent of the continuation: near a supercritical pitchfork the
asymmetric amplitude grows like sqrt(Omega - Omega_bp) and the bifurcated orbits take over the
stability the symmetric ones lose; the mirror image of a bifurcated orbit (theta -> theta + pi
for n = 1, i.e. u -> -u) is a periodic orbit of the mixed ROM too.
"""

import numpy as np
import pytest

from model.continuation import BRANCH_POINT, FOLD
from model.shooting import shoot
from model.switching import follow_bifurcated_branch


@pytest.fixture(scope="module")
def switched(fig14a_n1):
    fmap, br = fig14a_n1.fmap, fig14a_n1.branch
    i = br.special(BRANCH_POINT)[0]
    sw, fmap_mixed, asym = follow_bifurcated_branch(fmap, fig14a_n1.family, "Omega", 25.0,
                                                    55.0, br.state[i], br.value[i], ds=0.01, ds_max=0.3,
                                                    max_points=8)
    return br.value[i], (fmap, br), sw, fmap_mixed, asym


def test_asymmetric_amplitude_grows_like_a_square_root(switched):
    omega_bp, _, sw, _, asym = switched
    assert sw.value.size == 8 and np.all(sw.value[1:] > omega_bp)   # supercritical: past the point
    d = sw.value[2:] - omega_bp
    ratio = asym[2:] ** 2 / d
    # the normal form's a^2 ~ d holds to first order: the ratio drifts by O(d) relative
    assert np.ptp(ratio) <= 0.1 * ratio.mean()
    assert asym[-1] > 1e-3


def test_bifurcated_orbits_are_stable_where_the_symmetric_ones_are_not(switched):
    _, (fmap, br), sw, fmap_mixed, _ = switched
    assert sw.stable[1:].all()
    omega = sw.value[-1]
    resonant = br.value[:br.special(FOLD)[0]]      # from the start to the upper saddle-node
    j = int(np.argmin(np.abs(resonant - omega)))
    symmetric = shoot(fmap.varied("Omega", omega), br.state[j])
    assert symmetric.converged
    K = fmap_mixed.dof
    y = np.zeros(2 * K)
    y[0], y[K] = symmetric.state
    mu = fmap_mixed.varied("Omega", omega).multipliers(y)
    assert np.abs(mu).max() > 1.0


def test_the_mirror_image_is_a_periodic_orbit(switched):
    _, _, sw, fmap_mixed, _ = switched
    y = sw.state[-1].copy()
    K = fmap_mixed.dof
    mirror = y.copy()
    mirror[1:K] *= -1.0
    mirror[K + 1:] *= -1.0
    at = fmap_mixed.varied("Omega", sw.value[-1])
    scale = at.state_scale()
    assert np.linalg.norm(scale * (at.advance(mirror) - mirror)) <= 1e-8 * np.linalg.norm(scale * y)
    assert np.abs(mirror[1:K]).max() > 1e-4
