"""Influence kernels: closed-form element integrals against quadrature and each other."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import dblquad, quad

from core.elastic import kernels
from core.theory.approximations import u0_approx


@pytest.mark.parametrize("d", [0.0, 0.05, 0.37, 2.0])
def test_strip_element_integral_matches_quadrature(d):
    dx, L, nu = 0.1, 20.0, 0.3
    bE = kernels.strip_b_coefficient(nu)

    def f(eta, xi):
        rho = np.hypot(d - xi, eta)
        return 2.0 / rho + bE * (d - xi) ** 2 / rho**3

    pts = sorted({-dx / 2, dx / 2, min(max(d, -dx / 2), dx / 2)})
    total = 0.0
    for lo, hi in zip(pts[:-1], pts[1:]):  # split at the singular point
        if hi > lo:
            total += dblquad(f, lo, hi, 0.0, L / 2, epsabs=1e-12, epsrel=1e-10)[0] * 2
    assert_allclose(kernels.strip_influence(d, dx, L, bE), total / np.pi**2, rtol=1e-6)


@pytest.mark.parametrize("d", [0.0, 0.03, 0.5, 3.0])
def test_plane_element_integral_matches_quadrature(d):
    dx = 0.1
    val = quad(lambda t: np.log(4.0 / abs(d - t)), -dx / 2, dx / 2, points=[d] if abs(d) < dx / 2 else None)[0]
    assert_allclose(kernels.plane_strain_influence(d, dx), 4 / np.pi**2 * val, rtol=1e-10)


def test_strip_tends_to_plane_strain_as_strip_lengthens():
    """Increments (zero-sum tractions) see the same kernel once L >> a: the difference is a constant."""
    n, dx = 81, 2 / 81
    Kp = kernels.influence_matrix(n, dx, "plane")
    spreads = []
    for L in (10.0, 100.0, 1000.0, 10000.0):
        Ks = kernels.influence_matrix(n, dx, "strip", L_over_a=L, b_coefficient=2.0)
        D = Ks - Kp
        spreads.append(D.max() - D.min())
    assert all(b < a / 50 for a, b in zip(spreads, spreads[1:])), spreads
    assert spreads[-1] < 1e-8


@pytest.mark.parametrize("kernel, opts", [("plane", {}), ("strip", dict(L_over_a=300.0, b_coefficient=2.0))])
def test_kernel_is_symmetric_positive_definite_over_a_contact(kernel, opts):
    n = 161  # a contact 2a wide at dx = 2/161 and more
    K = kernels.influence_matrix(n, 2 / 80, kernel, **opts)
    assert_allclose(K, K.T, rtol=0, atol=0)
    assert np.linalg.eigvalsh(K).min() > 0


def test_strip_u0_matches_asymptotic_eq14():
    for L in (50.0, 292.5, 3000.0):
        assert_allclose(kernels.strip_u0(L, 2.0), u0_approx(L, 0.5), rtol=2e-5)


def test_bad_kernel_inputs():
    with pytest.raises(ValueError, match="kernel"):
        kernels.influence_matrix(10, 0.1, "cubic")
    with pytest.raises(ValueError, match="dx"):
        kernels.plane_strain_influence(0.0, -1.0)
    with pytest.raises(ValueError, match="nu"):
        kernels.strip_b_coefficient(0.7)
