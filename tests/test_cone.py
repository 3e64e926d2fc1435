"""The rocking cone's limit (core/geometry/cone.py): Melan's p_min over the rotation, the moment condition as an LP."""

import numpy as np
import pytest
from scipy.ndimage import minimum_filter1d
from scipy.optimize import linprog

import core
from core.geometry.cone import Cone, cone_ft_limit, cone_w_limit, lowest_pressure_density


@pytest.mark.parametrize("inner", [0.0, 0.5])
@pytest.mark.parametrize("w", [0.2, 0.6])
def test_restrained_limit_is_melans_integral_over_the_rotation(inner, w):
    """Independently of the per-slice eq 35: the pressure on a polar grid about the apex (slices of half-width
    a(r) = a_m sqrt(r/r_m), peak 2P/(pi a(r))), its minimum over the rotation angles [-Theta, Theta] by a sliding
    minimum in phi, and integral p_min dA / integral p dA. Agrees to 2e-3 (the grid)."""
    a_m, r_m = 0.01, 0.5 * (1 + inner)
    theta = w * a_m / r_m
    r = np.linspace(inner, 1.0, 401)[1:] - 0.5 * (1 - inner) / 400
    k = 200
    dphi = theta / k
    num = den = 0.0
    for ri in r:  # one row of the polar grid per slice: phi covers the slice's contact and the rotation
        a = a_m * np.sqrt(ri / r_m)
        phi = dphi * np.arange(-np.ceil((a / ri + theta) / dphi) - 2, np.ceil((a / ri + theta) / dphi) + 3)
        p = (2 / (np.pi * a)) * np.sqrt(np.clip(1 - (ri * phi / a) ** 2, 0, None))
        p_min = minimum_filter1d(p, 2 * k + 1, mode="constant", cval=0.0)
        num += p_min.sum() * ri
        den += p.sum() * ri
    ratio = num / den
    assert ratio == pytest.approx(cone_ft_limit(w, inner, load_point=None), abs=2e-3)


@pytest.mark.parametrize("inner, rF", [(0.0, "centre"), (0.5, "centre"), (0.5, 0.9), (0.2, 0.3)])
def test_moment_condition_matches_a_linear_programme(inner, rF):
    """max integral f subject to |f| <= m and zero moment about r_F, by scipy's linprog on 400 slices."""
    w = 0.5
    n = 400
    edges = np.linspace(inner, 1.0, n + 1)
    r = 0.5 * (edges[1:] + edges[:-1])
    dr = edges[1] - edges[0]
    m = lowest_pressure_density(r, w, inner)
    r_F = 0.5 * (1 + inner) if rF == "centre" else rF
    res = linprog(-np.full(n, dr), A_eq=[(r - r_F) * dr], b_eq=[0.0], bounds=list(zip(-m, m)), method="highs")
    assert res.success
    assert -res.fun / (1 - inner) == pytest.approx(cone_ft_limit(w, inner, rF), abs=2e-4)


def test_long_frustum_is_the_cylinder_and_bounds():
    for w in (0.1, 0.4, 0.8):
        assert cone_ft_limit(w, 0.999) == pytest.approx(float(core.ft_limit(w)), abs=2e-4)
        free = cone_ft_limit(w, 0.3, None)
        assert cone_ft_limit(w, 0.3) <= free + 1e-12 and cone_ft_limit(w, 0.3, 0.3) <= free + 1e-12
    # the full cone bears less than the cylinder at the same mid-length amplitude (its outer end rocks more)
    assert cone_ft_limit(0.5, 0.0) < float(core.ft_limit(0.5))


def test_w_limit_inverts():
    for inner in (0.0, 0.5):
        w = cone_w_limit(0.4, inner)
        assert cone_ft_limit(w, inner) == pytest.approx(0.4, abs=1e-9)
    assert Cone(0.5).w_limit(0.4) == pytest.approx(cone_w_limit(0.4, 0.5))


@pytest.mark.parametrize("call, match", [
    (lambda: cone_ft_limit(-0.1), "w"),
    (lambda: cone_ft_limit(0.3, inner=1.0), "inner"),
    (lambda: cone_ft_limit(0.3, inner=0.5, load_point=0.2), "load_point"),
    (lambda: cone_w_limit(1.5), "ft"),
    (lambda: Cone(inner=0.5, load_point=2.0), "load_point"),
])
def test_bad_inputs(call, match):
    with pytest.raises(ValueError, match=match):
        call()
