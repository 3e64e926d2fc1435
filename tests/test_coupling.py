"""The coupled plane-strain operator (core/elastic/coupling.py): its sign kernel, its forms, the direction of its cross
terms, and Bufler's sliding pressure solved with it (the normal problem under q = mu p everywhere)."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from core.elastic.coupling import CoupledOperator, cross_apply, cross_matrix, coupling_factors
from core.theory.materials import bufler_exponent, bufler_pressure
from core.pressure.normal import solve_line


def test_cross_apply_is_the_sign_matrix():
    v = np.random.default_rng(3).normal(size=(2, 17))
    assert_allclose(cross_apply(v, 0.05), v @ cross_matrix(17, 0.05).T, atol=1e-13)
    S = cross_matrix(9, 0.1)
    assert_allclose(S, -S.T, atol=0) and np.all(np.diag(S) == 0)


def test_cross_terms_point_the_physical_way():
    """beta > 0 (rigid body on a compressible substrate): a pressure draws the substrate's surface in towards it
    (g < 0 to its right, > 0 to its left); a traction along +x lowers the substrate ahead of it (h grows there)."""
    n, dx = 41, 0.05
    op = CoupledOperator(n, dx, 0.2, 0.5)
    load = np.zeros(n)
    load[n // 2] = 1.0
    h, g = op.apply(np.zeros(n), load)
    assert h[-1] - h[0] > 0
    h0, _ = CoupledOperator(n, dx, 1e-12, 0.5).apply(np.zeros(n), load)
    assert_allclose(h - h0, op.normal_factor * dx * np.sign(np.arange(n) - n // 2), atol=1e-12)
    _, g = op.apply(load, np.zeros(n))
    _, g0 = CoupledOperator(n, dx, 0.0, 0.5).apply(load, np.zeros(n))
    assert np.all((g - g0)[n // 2 + 1:] < 0) and np.all((g - g0)[: n // 2] > 0)
    assert coupling_factors(0.2, 0.5) == pytest.approx((0.2 / math.pi, 0.8 / math.pi))
    with pytest.raises(ValueError, match="beta"):
        CoupledOperator(n, dx, 0.5, 0.5)
    with pytest.raises(ValueError, match="mu"):
        CoupledOperator(n, dx, 0.1, 0.0)


@pytest.mark.parametrize("beta, mu, direction", [(0.3, 0.6, 1), (0.25, 0.5, -1), (-0.2, 0.8, 1)])
def test_sliding_pressure_is_bufler_s(beta, mu, direction):
    """A Hertzian profile sliding (the substrate's traction direction * mu p at every element): the normal problem
    with the coupled operator, by fixed point on the pressure, gives Bufler's shifted pressure (element means of
    the closed form, to the discretisation's error at the edges) and its centre of pressure."""
    dx = 0.02
    n = int(round(3 / dx))
    x = (np.arange(n) + 0.5) * dx - 1.5
    op = CoupledOperator(n, dx, beta, mu)
    p = np.sqrt(np.clip(1 - x ** 2, 0, None))
    for _ in range(60):
        s = solve_line((2 / np.pi) * x ** 2 + op.normal_factor * op.cross(direction * p), dx,
                       initial=np.maximum(p, 1e-300))
        change = float(np.abs(s.pressure - p).max())
        p = np.array(s.pressure)
        if change < 1e-12:
            break
    assert change < 1e-12
    gamma = bufler_exponent(beta, mu, direction)
    fine = np.linspace(-1.5, 1.5, 50 * n + 1)
    means = bufler_pressure(0.5 * (fine[1:] + fine[:-1]), gamma).reshape(n, 50).mean(axis=1)
    inner = np.all([np.roll(means, k) > 0 for k in range(-2, 3)], axis=0)  # two elements off the edges
    assert_allclose(p[inner], means[inner], atol=0.012, err_msg=f"gamma={gamma:.4f}")
    assert_allclose(p, means, atol=0.05, err_msg=f"gamma={gamma:.4f}")
    centre, expected = (x * p).sum() / p.sum(), (x * means).sum() / means.sum()
    assert_allclose(centre, expected, atol=2e-4)
    assert np.sign(centre) == -np.sign(gamma)  # beta mu direction > 0: towards -x
