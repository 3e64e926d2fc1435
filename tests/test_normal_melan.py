"""Melan's limit for any uncoupled body (core/pressure/melan.py): the numerical integral equals the closed forms."""

import numpy as np
import pytest

import core
from core.pressure.melan import ft_limit_numerical, lowest_pressure


@pytest.mark.parametrize("w", [0.0, 0.1, 0.26, 0.52, 0.77, 0.95])
def test_cylinder(w):
    exact = float(core.theory.analytical.ft_limit(w))
    assert ft_limit_numerical(w, core.Cylinder()) == pytest.approx(exact, abs=2e-6)
    assert ft_limit_numerical(w, core.Cylinder(), normal="numerical") == pytest.approx(exact, abs=2e-5)


@pytest.mark.parametrize("w", [0.0, 0.1, 0.3, 0.6, 0.9])
def test_sphere_and_ellipsoid(w):
    exact = 1 - 1.5 * w + 0.5 * w**3
    assert float(core.ft_limit(w, body="sphere")) == pytest.approx(exact, abs=1e-14)
    assert ft_limit_numerical(w, core.Sphere()) == pytest.approx(exact, abs=2e-4)
    assert ft_limit_numerical(w, core.Ellipsoid(2.0), dx=1 / 300) == pytest.approx(exact, abs=3e-4)


def test_convergence_with_dx():
    """The numerical limit of the cylinder converges about as dx^1.5 (w = 0.3)."""
    exact = float(core.theory.analytical.ft_limit(0.3))
    errs = [abs(ft_limit_numerical(0.3, core.Cylinder(), dx=dx) - exact) for dx in (1e-2, 1e-3)]
    assert errs[1] < errs[0] / 20 and errs[1] < 2e-5


def test_default_and_names():
    """core.ft_limit keeps its closed form and signature for the cylinder; names and objects both work."""
    assert float(core.ft_limit(0.26)) == pytest.approx(0.6727, abs=1e-4)
    # Melan's integral over the numerical normal solve of the cylinder (not its closed form) is eq 35
    assert ft_limit_numerical(0.3, core.Cylinder(), normal="numerical") == pytest.approx(0.6238377, abs=2e-3)
    # a punch without a flat is the cylinder: its limit by name and parameter is eq 35's
    assert float(core.ft_limit(0.3, body=core.geometry.registry.make_body("punch", flat=0.0))) == pytest.approx(
        0.6238377, abs=1e-5)
    ws = np.array([0.1, 0.5])
    assert core.ft_limit(ws, body="punch").shape == (2,)


def test_lowest_pressure_is_below_every_centre():
    b = core.Punch(flat=0.5)
    x, p, p_min = lowest_pressure(b, 0.4, dx=1e-3)
    for xc in np.linspace(-0.4, 0.4, 17):
        assert np.all(p_min <= b.pressure(x, xc) + 1e-12)
