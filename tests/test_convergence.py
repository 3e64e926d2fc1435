"""Error bars (core.convergence): the increment's own discretisation error, checked against a fine grid."""

import math

import pytest

import core


def test_extrapolation_from_a40_and_a80_against_a400():
    """The increment converges at first order in dx: Richardson's extrapolation from a/40 and a/80 is
    closer to the a/400 run than a/80 itself, and the error estimate has the size of the true error."""
    ft, w, periods = 0.58, 0.77, 4   # ratcheting (Fig 7): the increment settles within 3 periods
    c = core.converged_increment(ft, w, dx=1 / 80, periods=periods)
    fine = core.simulate_cycles(ft, w, periods=periods, dx=1 / 400).increment_per_period[-1]
    assert c.clean and abs(c.order - 1.0) < 0.5
    raw_error = abs(c.value - fine)
    assert abs(c.extrapolated - fine) < 0.3 * raw_error, (c.extrapolated, c.value, fine)
    assert 0.5 < raw_error / c.error < 2.0, (raw_error, c.error)
    assert c.result.dx == pytest.approx(1 / 80) and c.value == c.result.increment_per_period[-1]


def test_no_extrapolation_where_the_order_is_not_clean():
    c = core.converged_increment(0.4, 0.52, dx=1 / 40, periods=4)  # a/10 is too coarse for a clean order
    assert not c.clean and c.extrapolated == c.value
    assert c.error == pytest.approx(abs(c.value - c.coarse))
    with pytest.raises(ValueError, match="dx"):
        core.converged_increment(0.4, 0.52, dx=0.2)
    assert math.isinf(core.ConvergedIncrement(0.0, 0.0, 0.0, math.nan, False, 0.0, 0.0, 0.1, None).relative_error)
