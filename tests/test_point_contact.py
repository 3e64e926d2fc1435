"""Point-contact bodies: Hertz ellipse, element pressures, the exact shakedown limit and its inverse."""

import math

import numpy as np
import pytest
from scipy.integrate import dblquad
from scipy.special import ellipe, ellipk

import core
from core.api.contact import Contact
from core.theory.point_contact import Ellipsoid, ft_limit_point, hertz_element_means, hertz_pressure_3d, w_limit_point


@pytest.mark.parametrize("w", [0.0, 0.3, 0.8])
@pytest.mark.parametrize("kappa", [1.0, 0.5, 2.5])
def test_limit_equals_direct_integral_of_lowest_pressure(w, kappa):
    """ft_lim = integral of p_min over the plane / Fn, p_min the pressure of the farther turning point."""
    def pmin(y, x):
        return math.sqrt(max(1.0 - (abs(x) + w) ** 2 - (y / kappa) ** 2, 0.0))

    def edge(x):  # the support of p_min: |y| < kappa sqrt(1 - (|x| + w)^2)
        return kappa * math.sqrt(max(1.0 - (abs(x) + w) ** 2, 0.0))

    half, _ = dblquad(pmin, 0.0, 1.0 - w, lambda x: -edge(x), edge, epsabs=1e-12, epsrel=1e-10)
    np.testing.assert_allclose(ft_limit_point(w), 2 * half / (2 * math.pi * kappa / 3), rtol=1e-8, atol=1e-10,
                               err_msg=f"w = {w}, kappa = {kappa}")


def test_limit_from_grid_lowest_pressure():
    """The same limit from the element means on a grid (what the solver sees)."""
    w = 0.4
    h = 0.01
    xe = h * (np.arange(-141, 142) - 0.5)[:-1]
    ye = h * (np.arange(-101, 102) - 0.5)[:-1]
    pmin = np.minimum(hertz_element_means(xe, ye, -w), hertz_element_means(xe, ye, w))
    np.testing.assert_allclose(pmin.sum() * h * h / (2 * math.pi / 3), ft_limit_point(w), rtol=2e-3)


def test_w_limit_inverts_ft_limit():
    w = np.linspace(0, 1, 101)
    np.testing.assert_allclose(w_limit_point(ft_limit_point(w)), w, atol=1e-7)
    ft = np.linspace(0, 1, 101)
    np.testing.assert_allclose(ft_limit_point(w_limit_point(ft)), ft, atol=1e-12)


def test_public_dispatch_of_limits():
    w = np.array([0.1, 0.5])
    np.testing.assert_array_equal(core.ft_limit(w, body="sphere"), ft_limit_point(w))
    np.testing.assert_array_equal(core.ft_limit(w, body=Ellipsoid(3.0)), ft_limit_point(w))
    np.testing.assert_array_equal(core.w_limit(0.5, body="ellipsoid"), w_limit_point(0.5))
    np.testing.assert_array_equal(core.ft_limit(w), core.ft_limit(w, body="cylinder"))
    with pytest.raises(ValueError, match="body"):
        core.ft_limit(0.3, body="cube")


def test_cylinder_bears_more_than_sphere_at_same_amplitude():
    """Against the paper's statement: under the mu p_min bound the cylinder carries MORE than the sphere.

    Cylinder: (2/pi)(arccos w - w sqrt(1 - w^2)) ~ 1 - (4/pi) w; sphere: (1 - w)^2 (1 + w/2) ~ 1 - 1.5 w.
    """
    w = np.linspace(0.01, 0.99, 99)
    assert np.all(core.ft_limit(w) > core.ft_limit(w, body="sphere"))
    np.testing.assert_allclose(core.ft_limit(0.3), 0.6238, atol=1e-4)
    np.testing.assert_allclose(core.ft_limit(0.3, body="sphere"), 0.5635, atol=1e-4)


@pytest.mark.parametrize("ratio", [0.2, 0.5, 2.0, 4.0, 10.0])
def test_hertz_ellipse_matches_johnson(ratio):
    """Semi-axes and p0 reproduce both principal curvatures through Johnson's eqs 4.39-4.40."""
    c = Contact(Rx=0.01, Ry=0.01 * ratio, Fn=5.0, mu=0.4, E2=2e6)
    a, b = c.a, c.b
    major, minor = max(a, b), min(a, b)
    e2 = 1 - (minor / major) ** 2
    K, E = ellipk(e2), ellipe(e2)
    f = c.p0 * minor / (c.E_star * major**2 * e2)
    C_major, C_minor = f * (K - E), f * ((major / minor) ** 2 * E - K)
    C_x, C_y = 0.5 / c.Rx, 0.5 / c.Ry
    got = (C_major, C_minor) if a >= b else (C_minor, C_major)
    np.testing.assert_allclose(got, (C_x, C_y), rtol=1e-9)
    np.testing.assert_allclose(c.p0 * 2 * math.pi * a * b / 3, c.Fn, rtol=1e-12)
    # Greenwood's approximation b/a ~ (Ry/Rx)^(2/3), within a few per cent
    np.testing.assert_allclose(c.body.kappa, ratio ** (2 / 3), rtol=0.05)


def test_sphere_contact_radius():
    c = Contact(Rx=0.02, Ry=0.02, Fn=3.0, mu=0.5, E2=1e6, nu2=0.3)
    np.testing.assert_allclose(c.a, (3 * 3.0 * 0.02 / (4 * c.E_star)) ** (1 / 3), rtol=1e-12)
    assert c.nu == pytest.approx(0.3)


@pytest.mark.parametrize("kappa, xc", [(1.0, 0.0), (1.0, 0.37), (2.0, -0.2), (0.6, 0.5)])
def test_element_means_add_up_and_match_pressure(kappa, xc):
    h = 0.05
    xe = h * (np.arange(63) - 31.5)
    ye = h * (np.arange(2 * math.ceil(kappa / h) + 4) - (math.ceil(kappa / h) + 1.5))
    p = hertz_element_means(xe, ye, xc, kappa)
    np.testing.assert_allclose(p.sum() * h * h, 2 * math.pi * kappa / 3, rtol=1e-13)
    x = 0.5 * (xe[1:] + xe[:-1])
    y = 0.5 * (ye[1:] + ye[:-1])
    mid = hertz_pressure_3d(x[None, :], y[:, None], xc, kappa)
    inner = mid > 0.5  # away from the edge the mean is the midpoint value to O(h^2)
    np.testing.assert_allclose(p[inner], mid[inner], atol=5e-3)


@pytest.mark.parametrize("kw, match", [({"ratio": 0.0}, "ratio"), ({"ratio": 50}, "ratio")])
def test_bad_ellipsoid(kw, match):
    with pytest.raises(ValueError, match=match):
        Ellipsoid(**kw)


def test_bad_contact_inputs():
    with pytest.raises(ValueError, match="Ft"):
        Contact(Rx=0.01, Ry=0.01, Fn=1.0, mu=0.5, E2=1e6, Ft=0.6)
    with pytest.raises(ValueError, match="nu2"):
        Contact(Rx=0.01, Ry=0.01, Fn=1.0, mu=0.5, E2=1e6, nu2=0.7)
    with pytest.raises(ValueError, match="ratio"):
        core.simulate_cycles(0.2, 0.2, body="ellipsoid")


def test_physical_contact_runs_normalised():
    c = Contact(Rx=0.01, Ry=0.02, Fn=10.0, mu=0.5, E2=3e6, nu2=0.4, Ft=1.0, W=2e-4)
    r = c.simulate(periods=1, dx=0.25)
    assert r.params["ft"] == pytest.approx(c.ft) and r.params["w"] == pytest.approx(c.w)
    assert r.body.ratio == pytest.approx(2.0) and r.nu == pytest.approx(0.4)


def test_replace_keeps_the_normalised_loads_as_contact_replace_does():
    c = Contact(Rx=0.01, Ry=0.02, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4, angle=0.3)
    stiffer = c.replace(E2=6e6, mu=0.8)
    assert stiffer.E2 == 6e6 and stiffer.angle == c.angle and stiffer.Ry == c.Ry
    assert stiffer.ft == pytest.approx(c.ft, rel=1e-12) and stiffer.w == pytest.approx(c.w, rel=1e-12)
    assert stiffer.a < c.a and stiffer.W < c.W, "W follows the new, smaller a"
    loads = c.replace(ft=0.25, w=0.5)
    assert loads.Ft == pytest.approx(0.25 * 0.5 * 10.0) and loads.W == pytest.approx(0.5 * c.a)
    assert c.replace(Ft=1.0).Ft == 1.0 and c.replace(W=2e-5).W == 2e-5
    assert c.replace() == c
    geometry = c.replace(ft=0.0, w=0.0)
    assert (geometry.Ft, geometry.W) == (0.0, 0.0)


@pytest.mark.parametrize("changes, match", [
    (dict(Ft=1.0, ft=0.2), "Ft: give Ft or ft"),
    (dict(W=1e-5, w=0.2), "W: give W or w"),
    (dict(radius=0.1), "radius: not an input"),
    (dict(mu=-1.0), "mu"),
    (dict(ft=1.5), "ft"),
])
def test_replace_refuses_what_is_not_a_point_contact(changes, match):
    c = Contact(Rx=0.01, Ry=0.01, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4)
    with pytest.raises(ValueError, match=match):
        c.replace(**changes)
