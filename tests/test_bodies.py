"""The body (core.geometry.bodies) and the state codes (core.base.states): grid, traction bound, Hertz scales, registry."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import quad

import core
import core.api.export
from core.geometry.bodies import MAX_ELEMENTS, Cylinder, get_body
from core.base.states import STATE_NAMES, ZONE_NAMES, State, Zone


def test_state_and_zone_codes_are_the_stored_numbers_and_the_old_aliases():
    assert [int(s) for s in State] == [0, 1, 2, 3]
    assert State.SLIP_BACKWARD.label == "slip backward" and STATE_NAMES[State.STICK] == "stick"
    assert Zone.RELEASED.label == "zero traction" and ZONE_NAMES[Zone.NONE] == "no contact"
    assert core.records.result.STATE_SLIP_FORWARD is State.SLIP_FORWARD
    assert core.ZONE_STICK is Zone.STICK and core.ZONE_RELEASED == 3
    assert core.STATE_NAMES is STATE_NAMES and core.api.export.ZONE_NAMES is ZONE_NAMES


def test_grid_is_symmetric_with_a_spare_element_each_side():
    b = Cylinder.for_reach(1.3, 0.1)
    assert b.size % 2 == 0 and b.edges[0] == -b.edges[-1]
    assert b.edges[-1] >= 1.3 + 0.1 - 1e-12 and b.dx == pytest.approx(0.1)
    assert_allclose(b.x, 0.5 * (b.edges[1:] + b.edges[:-1]))
    with pytest.raises(ValueError, match="dx"):
        Cylinder.for_reach(1.0, 2.0 / MAX_ELEMENTS)
    with pytest.raises(ValueError, match="edges"):
        Cylinder([0.0, 1.0, 0.5])


@pytest.mark.parametrize("xc, P", [(0.0, 1.0), (0.37, 1.0), (-0.5, 0.64), (0.2, 1.44)])
def test_bound_is_the_exact_element_mean_of_the_hertz_pressure(xc, P):
    b = Cylinder.for_reach(2.0, 0.07)
    a = np.sqrt(P)  # eq 5: half-width and peak both scale as sqrt(P)
    mean = [quad(lambda x: a * np.sqrt(max(0.0, 1 - ((x - xc) / a) ** 2)), lo, hi, epsabs=1e-13)[0] / b.dx
            for lo, hi in zip(b.edges[:-1], b.edges[1:])]
    g = b.bounds([xc], [P])[0]
    assert_allclose(g, mean, atol=1e-10)
    # the element loads add up to the normal load whatever the grid: sum p dx = (pi/2) P
    assert g.sum() * b.dx == pytest.approx(0.5 * np.pi * P, rel=1e-12)
    assert b.load_target(0.3) == pytest.approx(0.3 * 0.5 * np.pi / b.dx)


def test_the_runs_bound_is_the_element_mean_of_hertzs_pressure():
    """The bound a run stores is the mean of sqrt(1 - (x - xc)^2) over each element, checked by quadrature (not by
    the function that computes it)."""
    r = core.simulate_cycles(0.3, 0.4, periods=1, dx=1 / 20)
    for k in (0, 3, r.xc.size - 1):
        xc = float(r.xc[k])
        mean = [quad(lambda x: np.sqrt(max(1.0 - (x - xc) ** 2, 0.0)), lo, hi, points=[xc - 1, xc + 1])[0]
                / (hi - lo) for lo, hi in zip(r.edges[:-1], r.edges[1:])]
        assert_allclose(r.pressure[k], mean, rtol=0, atol=1e-10, err_msg=f"step {k}")


def test_lowest_bound_is_the_minimum_over_a_sampled_period():
    b = Cylinder.for_reach(1.5, 1 / 25)
    w = 0.4
    sampled = b.bounds(np.linspace(-w, w, 801), np.ones(801)).min(axis=0)
    assert np.all(b.lowest_bound(w) <= sampled + 1e-15)
    assert_allclose(b.lowest_bound(w), sampled, atol=2e-3)


def test_references_and_registry():
    assert Cylinder.ft_limit(0.26) == pytest.approx(0.6727, abs=1e-4)  # eq 35
    assert Cylinder.reach(np.array([0.0, 0.5]), np.array([1.0, 0.25])) == pytest.approx(1.0)
    assert core.geometry.registry.resolve("cylinder") == Cylinder() and core.geometry.registry.kind("punch") == "line"
    with pytest.raises(ValueError, match="body must be one of"):
        get_body("torus")
    with pytest.raises(ValueError, match="body"):
        core.simulate_cycles(0.2, 0.3, periods=1, body="torus")
