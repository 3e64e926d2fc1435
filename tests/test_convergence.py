"""Error bars (core.api.convergence): the increment's own discretisation error, checked against a fine grid."""

import math

import pytest

import core


@pytest.mark.slow  # the a/400 run: 10 to 30 s
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
    # an order that is not clean is not trusted: the expected order, with Roache's safety factor 3
    assert c.safety == core.api.convergence.SAFETY_FACTOR_UNCLEAN
    assert c.error == pytest.approx(3 * abs(c.value - c.coarse))
    with pytest.raises(ValueError, match="dx"):
        core.converged_increment(0.4, 0.52, dx=0.2)
    with pytest.raises(ValueError, match="grids"):
        core.converged_increment(0.4, 0.52, grids=4)
    assert math.isinf(core.ConvergedIncrement(0.0, 0.0, 0.0, math.nan, False, 0.0, 0.0, 0.1, None).relative_error)


def test_point_contact_error_bar_covers_the_finer_grid():
    """Sphere, ratcheting (ft 0.4, w 0.6): the two-grid error bar of the a/10 run (with a/5) covers the a/20
    run's increment, and is not many times the distance to it; grid_error on the result gives the same."""
    ft, w, periods = 0.4, 0.6, 3
    c = core.converged_increment(ft, w, dx=0.1, body="sphere", grids=2, periods=periods)
    fine = core.simulate_cycles(ft, w, periods, dx=0.05, body="sphere").increment_per_period[-1]
    assert c.grids == 2 and c.body == "sphere" and math.isnan(c.coarser) and c.extrapolated == c.value
    assert abs(c.value - fine) <= c.error <= 6 * abs(c.value - fine), (c.value, c.error, fine)
    assert c.value < fine  # the 3D increment converges from below (issue 21)
    e = core.grid_error(c.result)
    assert (e.value, e.coarse, e.error) == (c.value, pytest.approx(c.coarse, rel=1e-9), pytest.approx(c.error))
    assert e.result is c.result and c.result.dx == pytest.approx(0.1)


def test_grid_error_of_a_cylinder_run():
    r = core.simulate_cycles(0.58, 0.77, periods=4, dx=1 / 80)
    e = core.grid_error(r, grids=3)
    c = core.converged_increment(0.58, 0.77, dx=1 / 80, periods=4)
    assert (e.value, e.coarse, e.coarser, e.order, e.error) == (c.value, c.coarse, c.coarser, c.order, c.error)
    with pytest.raises(ValueError, match="dx"):
        core.grid_error(core.simulate_cycles(0.58, 0.77, periods=1, dx=0.3))  # 0.6 > 0.5
    arrays = core.simulate_cycles(0.3, 0.3, history={"xc": [0.0, 0.1], "P": [1.0, 1.0], "Q": [0.3, 0.3],
                                                     "period": [-1, 0]})
    with pytest.raises(ValueError, match="result"):
        core.grid_error(arrays)


def test_default_grid_per_body_in_one_place():
    """Issue 21.4: point contacts a/20, the cylinder a/40, from core.geometry.resolution, printed with every result."""
    from core.geometry.resolution import default_dx

    assert default_dx("cylinder") == core.api.solver.DEFAULT_DX == 1 / 40
    assert default_dx("sphere") == default_dx("ellipsoid") == core.solvers.solver3d.DEFAULT_DX_3D == 1 / 20
    assert default_dx(core.Sphere()) == 1 / 20
    sphere = core.simulate_cycles(0.3, 0.3, periods=1, body="sphere")
    assert sphere.dx == pytest.approx(1 / 20) and sphere.summary()["dx"] == pytest.approx(1 / 20)
    cylinder = core.simulate_cycles(0.3, 0.3, periods=1)
    assert cylinder.dx == pytest.approx(1 / 40) and cylinder.summary()["dx"] == pytest.approx(1 / 40)
    points = core.sweep_grid([0.2], [0.3], body=["cylinder", "sphere"], periods=1)
    assert [p["dx"] for p in points] == [1 / 40, 1 / 20]
    c = core.converged_increment(0.3, 0.3, body="sphere", grids=2, periods=1)
    assert c.dx == 1 / 20 and c.result.dx == pytest.approx(1 / 20)
