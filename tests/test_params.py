"""Parameter validation: every impossible value is rejected with a message naming it."""

import math

import pytest

from model.params import Loading, Membrane


def test_defaults_are_the_papers():
    m = Membrane()
    assert (m.C1, m.h, m.Gamma, m.Re) == (0.17e6, 1e-3, 2200.0, 1.0)
    assert m.Ro == pytest.approx(0.2) and m.Rf == pytest.approx(1.1)


@pytest.mark.parametrize("kwargs,pattern", [
    ({"delta": 1.0}, r"delta = 1\.0 is invalid: must be a finite number > 1"),
    ({"delta": 0.5}, r"delta = 0\.5 is invalid: must be a finite number > 1"),
    ({"delta": math.nan}, r"delta = nan is invalid"),
    ({"delta_o": 0.0}, r"delta_o = 0\.0 is invalid: must be a finite number in the open interval \(0, 1\)"),
    ({"delta_o": 1.0}, r"delta_o = 1\.0 is invalid"),
    ({"delta_o": -0.1}, r"delta_o = -0\.1 is invalid"),
    ({"C1": 0.0}, r"C1 = 0\.0 is invalid: must be a finite number > 0 \(Pa\)"),
    ({"h": -1e-3}, r"h = -0\.001 is invalid: must be a finite number > 0 \(m\)"),
    ({"Gamma": math.inf}, r"Gamma = inf is invalid: must be a finite number > 0 \(kg m-3\)"),
    ({"Re": 0}, r"Re = 0\.0 is invalid: must be a finite number > 0 \(m\)"),
    ({"delta": "2"}, r"delta = '2' is invalid"),
    ({"delta": True}, r"delta = True is invalid"),
])
def test_membrane_rejects(kwargs, pattern):
    with pytest.raises(ValueError, match=pattern):
        Membrane(**kwargs)


@pytest.mark.parametrize("kwargs,pattern", [
    ({"Omega": 0.0}, r"Omega = 0\.0 is invalid: must be a finite number > 0 \(rad s-1\)"),
    ({"P0": -1.0}, r"P0 = -1\.0 is invalid: must be a finite number >= 0 \(Pa\)"),
    ({"c": -0.05}, r"c = -0\.05 is invalid: must be a finite number >= 0 \(N s m-3\)"),
    ({"c": math.nan}, r"c = nan is invalid"),
])
def test_loading_rejects(kwargs, pattern):
    with pytest.raises(ValueError, match=pattern):
        Loading(**kwargs)


def test_integers_are_accepted_as_floats():
    assert Membrane(delta=2, Re=1).delta == 2.0
