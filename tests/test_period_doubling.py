"""Period doubling located by the continuation code, on a textbook oscillator.

The escape equation (tests/escape_oscillator.py) at beta = 0.1, Omega = 1, continued in the
forcing amplitude F: its periodic response period-doubles.  Independent checks: a second
discretisation (4x the RK4 steps) locates it at the same F, and scipy's DOP853 integration
of the equation settles on a period-1 response just below it and on a period-2 response just
above it.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from escape_oscillator import EscapeMap, Forcing, rhs
from model.continuation import PERIOD_DOUBLING, continue_orbits


def _pd(steps):
    m = EscapeMap(0.1, Forcing(0.1, 0.0, 1.0), steps)
    br = continue_orbits(m, "P0", 0.0, 0.3, ds_max=0.1, max_points=400)
    i = br.special(PERIOD_DOUBLING)
    assert br.complete and i.size == 1
    return br, int(i[0])


@pytest.fixture(scope="module")
def located():
    return _pd(128)


def test_a_multiplier_is_minus_one_at_the_located_point(located):
    br, i = located
    mu = br.multipliers[i]
    assert np.min(np.abs(mu + 1.0)) <= 1e-8
    assert br.stable[i - 1] and not br.stable[i + 1]
    # beyond the point a real multiplier lies below -1
    after = br.multipliers[i + 1]
    assert np.any((np.abs(after.imag) < 1e-12) & (after.real < -1.0))


def test_a_finer_discretisation_agrees(located):
    br, i = located
    fine, j = _pd(512)
    # RK4 error ~ (2 pi / steps)^4: ~6e-6 at 128 steps
    assert fine.value[j] == pytest.approx(br.value[i], rel=2e-5)


@pytest.mark.parametrize("side", [-1, 1])
def test_time_integration_gives_period_one_below_and_period_two_above(located, side):
    br, i = located
    F = br.value[i] * (1 + 0.02 * side)
    T = 2 * np.pi
    sol = solve_ivp(rhs(0.1, F, 1.0), (0, 400 * T), br.state[i], method="DOP853", rtol=1e-11, atol=1e-12,
                    t_eval=T * np.arange(396, 401))
    x = sol.y[0]
    one, two = abs(x[4] - x[3]), abs(x[4] - x[2])
    if side < 0:
        assert one <= 1e-6
    else:
        assert two <= 1e-6 and one >= 1e-3


class _TruncatedMap(EscapeMap):
    """A map whose monodromy matrix lacks a row and a column (a user's map gone wrong)."""

    def monodromy_parameter(self, y, parameter):
        yT, phi, d = super().monodromy_parameter(y, parameter)
        return yT, phi[:1, :1], d


def test_a_map_returning_the_wrong_shapes_is_refused():
    # The compiled residual reads the arrays by index: it must check their shapes rather
    # than read past them and converge to a wrong point.
    with pytest.raises(ValueError, match="wrong shape"):
        continue_orbits(_TruncatedMap(0.1, Forcing(0.1, 0.0, 1.0), 64), "P0", 0.0, 0.3, max_points=5)
