"""Integrity measures (model/integrity.py) on synthetic label arrays with known answers."""

import numpy as np
import pytest

from model.integrity import global_integrity_measure, integrity_factor


def _disc(n=201, radius=0.25, centre=(0.5, 0.5)):
    u = np.linspace(0.0, 1.0, n)
    inside = (u[:, None] - centre[0]) ** 2 + (u[None, :] - centre[1]) ** 2 < radius**2
    return u, np.where(inside, 0, 1).astype(np.int32)


def test_gim_is_the_area_fraction_of_a_disc():
    u, lab = _disc()
    assert global_integrity_measure(lab, 0) == pytest.approx(np.pi * 0.25**2, rel=0.02)
    assert global_integrity_measure(lab, 0) + global_integrity_measure(lab, 1) == 1.0


def test_if_of_a_disc_basin_is_its_radius_over_one_half():
    u, lab = _disc(radius=0.25)
    # the window [0, 1]^2 in physical units [-0.3, 0.3] x [-10, 10]
    x, y = -0.3 + 0.6 * u, -10 + 20 * u
    value = integrity_factor(lab, x, y, [(0.0, 0.0)], 0)
    assert value == pytest.approx(0.5, abs=2 * 2 / 200)


def test_if_is_limited_by_the_window_and_the_worst_point_of_a_cycle():
    u = np.linspace(0.0, 1.0, 101)
    lab = np.zeros((101, 101), np.int32)
    assert integrity_factor(lab, u, u, [(0.5, 0.5)], 0) == pytest.approx(1.0)
    assert integrity_factor(lab, u, u, [(0.5, 0.5), (0.9, 0.5)], 0) == pytest.approx(0.2)
    assert integrity_factor(lab, u, u, [(1.5, 0.5)], 0) == 0.0


def test_if_of_an_attractor_without_basin_points_nearby():
    u, lab = _disc(radius=0.1, centre=(0.3, 0.3))
    assert integrity_factor(lab, u, u, [(0.8, 0.8)], 0) == 0.0


def test_if_rejects_mismatched_shapes():
    with pytest.raises(ValueError, match=r"labels of shape \(3, 3\) is invalid: need "
                                         r"\(len\(x\), len\(y\)\) = \(3, 4\)"):
        integrity_factor(np.zeros((3, 3)), np.arange(3.0), np.arange(4.0), [(0, 0)], 0)
