"""The material model (core/theory/materials.py): E*, Dundurs' beta and its sign, the presets, the checks, and the closed
forms of coupled contact the coupled operator is checked against (Spence's stick zone, Bufler's sliding pressure)."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import quad
from scipy.special import ellipk

import core
from core.theory import materials as m


def test_beta_sign_and_special_pairs():
    # a rigid rocking body on a compressible substrate: beta = (1 - 2 nu)/(2 (1 - nu)) > 0 (body 1 = the rocking body)
    assert m.dundurs_beta(math.inf, 0.3, 1e9, 0.2) == pytest.approx(0.6 / 1.6, rel=1e-14)
    # swapping the bodies flips the sign
    b = m.dundurs_beta(210e9, 0.3, 70e9, 0.33)
    assert m.dundurs_beta(70e9, 0.33, 210e9, 0.3) == pytest.approx(-b, rel=1e-14)
    assert m.dundurs_beta(210e9, 0.3, 210e9, 0.3) == 0.0
    assert m.dundurs_beta(math.inf, 0.1, 5e6, 0.5) == 0.0
    assert m.effective_modulus(math.inf, 0.3, 1e9, 0.5) == pytest.approx(1e9 / 0.75, rel=1e-14)


def test_presets_have_the_issue_s_magnitudes():
    beta = {k: p.beta for k, p in m.PAIRS.items()}
    assert beta["steel/steel"] == 0.0 and beta["rigid/incompressible"] == 0.0
    assert 0.09 < beta["steel/aluminium"] < 0.13, beta
    assert 0.04 < beta["steel/titanium"] < 0.08, beta
    assert 0.18 < beta["steel/PMMA"] < 0.25, beta
    assert abs(beta["steel/rubber"]) < 1e-4, beta
    assert all(abs(b) < m.MAX_BETA for b in beta.values())
    assert m.material_pair("Steel/Aluminium") is m.PAIRS["steel/aluminium"]
    assert m.material_pair("titanium/steel").beta == pytest.approx(-beta["steel/titanium"])


def test_contact_takes_materials():
    c = core.Contact(R1=0.02, L=0.1, Fn=1e3, mu=0.3, materials="steel/aluminium")
    assert c.beta == pytest.approx(m.PAIRS["steel/aluminium"].beta, rel=1e-12)
    assert c.E_star == pytest.approx(m.PAIRS["steel/aluminium"].E_star, rel=1e-12)
    with pytest.raises(ValueError, match="materials"):
        core.Contact(R1=0.02, L=0.1, Fn=1e3, mu=0.3, E2=1e9, nu2=0.3, materials="steel/aluminium")
    with pytest.raises(ValueError, match="materials"):
        core.Contact(R1=0.02, L=0.1, Fn=1e3, mu=0.3, materials="steel/cheese")


@pytest.mark.parametrize("call, name", [
    (lambda: m.Material(0.0, 0.3), "E"),
    (lambda: m.Material(-1.0, 0.3), "E"),
    (lambda: m.Material(1e9, 0.51), "nu"),
    (lambda: m.Material(1e9, -0.01), "nu"),
    (lambda: m.dundurs_beta(-1.0, 0.3, 1e9, 0.3), "E1"),
    (lambda: m.dundurs_beta(1e9, 0.3, 0.0, 0.3), "E2"),
    (lambda: m.dundurs_beta(1e9, 0.6, 1e9, 0.3), "nu1"),
    (lambda: m.effective_modulus(1e9, 0.3, 1e9, -0.2), "nu2"),
    (lambda: m.effective_modulus(math.inf, 0.3, math.inf, 0.3), "E1 and E2"),
    (lambda: m.check_beta(0.5), "beta"),
    (lambda: m.check_beta(-0.7), "beta"),
])
def test_bad_input_names_it(call, name):
    with pytest.raises(ValueError, match=name):
        call()


@pytest.mark.parametrize("r", [0.3, 1.0, 1.7])
def test_spence_ratio_solves_its_equation(r):
    k = m.spence_stick_ratio(r)
    assert_allclose(ellipk(1 - k * k) / ellipk(k * k), r, rtol=1e-10)
    assert m.spence_stick_ratio(r) > m.spence_stick_ratio(r * 1.2)  # more coupling or less friction: less stick


@pytest.mark.parametrize("gamma", [0.03, -0.08, 0.15])
def test_bufler_pressure_solves_the_sliding_problem(gamma):
    """PV int p(s)/(x - s) ds - pi tan(pi gamma) p(x) = pi x on the contact, and the nominal load (quadrature)."""
    b, e = m._bufler_geometry(gamma)
    p = lambda s: float(m.bufler_pressure(s, gamma))
    for t in (-0.6, 0.1, 0.8):
        x = e + t * b
        pv = -quad(p, e - b, e + b, weight="cauchy", wvar=x, limit=400)[0]
        assert_allclose(pv - math.pi * math.tan(math.pi * gamma) * p(x), math.pi * x, rtol=1e-7, atol=1e-9,
                        err_msg=f"gamma={gamma}, x={x}")
    assert_allclose(quad(p, e - b, e + b, limit=400)[0], math.pi / 2, rtol=1e-8)
    assert m.bufler_exponent(0.2, 0.5) == pytest.approx(math.atan(0.1) / math.pi)
    assert np.all(m.bufler_pressure(np.array([e - 1.01 * b, e + 1.01 * b]), gamma) == 0.0)
