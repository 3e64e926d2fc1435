"""Melan's limit under the rocking with an oscillating normal force (core.pressure.melan.ft_limit_oscillating, issue 30 item
5): the constant force's closed forms at A = 0, the engine's grid limit of a run, its bounds and its inputs."""

import math

import numpy as np
import pytest

import core
from core.pressure.melan import ft_limit_oscillating


@pytest.mark.parametrize("w", [0.0, 0.26, 0.52, 0.77])
def test_a_constant_force_gives_the_bodies_own_limits(w):
    np.testing.assert_allclose(ft_limit_oscillating(w, core.Cylinder(), 0.0), core.ft_limit(w), atol=2e-4,
                               err_msg="eq 35")
    np.testing.assert_allclose(ft_limit_oscillating(w, core.Punch(flat=0.5), 0.0),
                               core.ft_limit(w, body=core.Punch(flat=0.5)), atol=2e-3, err_msg="punch")


def test_a_sphere_under_a_constant_force_gives_its_closed_form():
    np.testing.assert_allclose(ft_limit_oscillating(0.3, core.Ellipsoid(), 0.0, dx=0.02, samples=40),
                               core.ft_limit(0.3, body="sphere"), atol=1e-3)


@pytest.mark.parametrize("phase", [0.0, math.pi / 2, math.pi])
def test_it_is_the_engines_limit_of_a_run(phase):
    """The run's own Melan limit (its grid's lowest bound over the last period) to the grid's step."""
    r = core.simulate_cycles(0.3, 0.26, periods=1, history="normal", amplitude=0.2, phase=phase, dx=0.01)
    lo, hi = r.melan_limit
    assert lo == hi
    np.testing.assert_allclose(ft_limit_oscillating(0.26, core.Cylinder(), 0.2, phase), lo, atol=1e-4,
                               err_msg=f"phase {phase}")


def test_an_oscillating_force_lowers_the_limit_below_gross_sliding():
    w = np.linspace(0.0, 0.9, 10)
    constant = core.ft_limit(w)
    for A in (0.1, 0.3, 0.6):
        lim = ft_limit_oscillating(w, core.Cylinder(), A, math.pi / 3)
        assert lim.shape == w.shape
        assert np.all(lim <= constant + 1e-4) and np.all(lim <= 1.0 - A + 1e-4), A  # (sampling: 4e-6 above)
        assert np.all(np.diff(lim) < 0), A  # a larger rocking shakes down under a smaller load
    # at w = 0 the lowest pressure is that of the lowest force: ft_lim = 1 - A exactly (the cylinder: p ~ sqrt(P))
    np.testing.assert_allclose(ft_limit_oscillating(0.0, core.Cylinder(), 0.3), 0.7, atol=1e-3)


@pytest.mark.parametrize("kwargs, name", [
    (dict(w=1.0), "w"), (dict(w=-0.1), "w"), (dict(amplitude=1.0), "amplitude"), (dict(amplitude=-0.1), "amplitude"),
    (dict(phase=float("nan")), "phase"), (dict(shape="square"), "shape"), (dict(samples=4), "samples"),
    (dict(samples=True), "samples"), (dict(dx=0.5), "dx"), (dict(body=object()), "body")])
def test_bad_inputs_are_refused_by_name(kwargs, name):
    args = dict(w=0.3, body=core.Cylinder(), amplitude=0.2)
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        ft_limit_oscillating(**args)
