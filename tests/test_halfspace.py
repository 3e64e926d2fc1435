"""The 3D half-space operator: exact element integrals, FFT == dense, symmetry, preconditioner."""

import numpy as np
import pytest
from scipy.integrate import dblquad

from core.elastic.halfspace import HalfSpaceOperator, convolve, convolve_mirror, rectangle_integrals

KERNELS = {
    "1/rho": lambda v, u: 1.0 / np.hypot(u, v),
    "x^2/rho^3": lambda v, u: u * u / np.hypot(u, v) ** 3,
    "y^2/rho^3": lambda v, u: v * v / np.hypot(u, v) ** 3,
    "xy/rho^3": lambda v, u: u * v / np.hypot(u, v) ** 3,
}


@pytest.mark.parametrize("x, y", [(0.3, 0.0), (0.6, -0.3), (-0.9, 0.6), (1.5, 0.9), (0.0, 2.1)])
def test_rectangle_integrals_match_quadrature(x, y):
    h = 0.3
    exact = rectangle_integrals(x, y, h)
    for (name, f), value in zip(KERNELS.items(), exact):
        num, err = dblquad(f, x - h / 2, x + h / 2, y - h / 2, y + h / 2, epsabs=1e-13, epsrel=1e-11)
        np.testing.assert_allclose(value, num, rtol=1e-9, atol=1e-12, err_msg=f"{name} at offset ({x}, {y})")


@pytest.mark.parametrize("x, y", [(0.0, 0.0), (0.6, -0.3), (-0.9, 1.2)])
def test_rectangle_is_the_sum_of_its_squares(x, y):
    """A rectangle h by 2h (a cone's element, longer along y) integrates like the two squares it is made of, and
    like the quadrature over it."""
    h = 0.3
    rect = rectangle_integrals(x, y, h, 2 * h)
    halves = [rectangle_integrals(x, y + s * h / 2, h) for s in (-1.0, 1.0)]
    for name, value, a, b in zip(KERNELS, rect, *halves):
        np.testing.assert_allclose(value, a + b, rtol=1e-12, atol=1e-14, err_msg=f"{name} at offset ({x}, {y})")
    if (x, y) != (0.0, 0.0):  # the quadrature away from the kernel's singularity
        num, _ = dblquad(KERNELS["1/rho"], x - h / 2, x + h / 2, y - h, y + h, epsabs=1e-13, epsrel=1e-11)
        np.testing.assert_allclose(rect[0], num, rtol=1e-9)


@pytest.mark.parametrize("hy", [0.1, 0.25])
def test_rectangular_operator_fft_equals_dense_and_default_is_square(hy):
    """Elements h by hy: the FFT product equals the dense matrix, whose entries are the rectangle integrals at
    offsets (i h, j hy); hy = h (or omitted) is the square operator."""
    op = HalfSpaceOperator(7, 5, 0.1, 0.5, 0.2, hy=hy)
    q = np.random.default_rng(2).normal(size=op.shape)
    np.testing.assert_allclose(op.apply(q).ravel(), op.matrix() @ q.ravel(), rtol=0, atol=1e-13)
    I1, Ixx, Iyy, Ixy = rectangle_integrals(-2 * 0.1, -3 * hy, 0.1, hy)  # element (0, 0) seen from (3, 2)
    np.testing.assert_allclose(op.matrix()[3 * 5 + 2, 0], 0.2 * (I1 + Ixx), rtol=1e-12)
    square = HalfSpaceOperator(7, 5, 0.1, 0.5, 0.2)
    if hy == 0.1:
        np.testing.assert_array_equal(op.apply(q), square.apply(q))
    else:
        assert not np.allclose(op.apply(q), square.apply(q))


def test_self_element_closed_form():
    """Integral of 1/rho over a square of side h about its centre: 4 h asinh(1)."""
    h = 0.25
    I1, Ixx, Iyy, Ixy = rectangle_integrals(0.0, 0.0, h)
    np.testing.assert_allclose(I1, 4 * h * np.arcsinh(1.0), rtol=1e-14)
    np.testing.assert_allclose(Ixx, 0.5 * I1, rtol=1e-14)  # x^2 + y^2 = rho^2, symmetric
    np.testing.assert_allclose(Ixy, 0.0, atol=1e-15)


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
@pytest.mark.parametrize("ny, nx", [(1, 1), (5, 8), (9, 6)])
def test_fft_equals_dense(ny, nx, nu):
    op = HalfSpaceOperator(ny, nx, 0.1, nu, 0.2)
    q = np.random.default_rng(1).normal(size=op.shape)
    np.testing.assert_allclose(op.apply(q).ravel(), op.matrix() @ q.ravel(), rtol=0, atol=1e-13)



@pytest.mark.parametrize("ny, nx", [(1, 4), (9, 6), (21, 30)])
def test_mirror_product_equals_full_on_symmetric_fields(ny, nx):
    """q_x even, q_y odd in y: the half-cost product equals the full one (the preconditioner's too, but for the
    xy part of its sampled symbol on the Nyquist row of an even periodic grid, which an odd kernel lacks)."""
    op = HalfSpaceOperator(ny, nx, 0.1, 0.5, 0.2)
    q = np.random.default_rng(2).normal(size=op.shape)
    q[0] += q[0, ::-1]
    q[1] -= q[1, ::-1]
    spec = op.spectra()
    full, half = convolve(q, *spec[:5]), convolve_mirror(q, *spec[:5])
    np.testing.assert_allclose(half, full, rtol=0, atol=1e-13 * np.abs(full).max())
    np.testing.assert_array_equal(half[0], half[0, ::-1])
    np.testing.assert_array_equal(half[1], -half[1, ::-1])
    pre_full, pre_half = convolve(q, *spec[5:]), convolve_mirror(q, *spec[5:])
    if spec[8] % 2:  # odd periodic grid: no Nyquist row
        np.testing.assert_allclose(pre_half, pre_full, rtol=0, atol=1e-13 * np.abs(pre_full).max())
    assert np.vdot(q, pre_half) > 0

def test_dense_matrix_symmetric_positive_definite_with_coupling():
    op = HalfSpaceOperator(6, 7, 0.15, 0.5, 0.2)
    K = op.matrix()
    np.testing.assert_allclose(K, K.T, atol=1e-15)
    assert np.linalg.eigvalsh(K).min() > 0
    # the x-y coupling vanishes for nu = 0
    K0 = HalfSpaceOperator(6, 7, 0.15, 0.0, 0.2).matrix()
    n = K0.shape[0] // 2
    assert np.abs(K0[:n, n:]).max() == 0.0
    assert np.abs(K[:n, n:]).max() > 1e-3


def test_operator_matches_point_force_far_away():
    """Far from a loaded element the displacement is Cerruti's point-force solution."""
    h, nu, s = 0.1, 0.4, 1.0 / np.pi
    op = HalfSpaceOperator(31, 31, h, nu, s)
    q = np.zeros(op.shape)
    q[0, 0, 0] = 1.0  # unit traction on the corner element: force h^2 along x
    u = op.apply(q)
    X, Y = 30 * h, 20 * h
    rho = np.hypot(X, Y)
    c = nu / (1 - nu)
    ux = s * h * h * (1 / rho + c * X * X / rho**3)
    uy = s * h * h * c * X * Y / rho**3
    np.testing.assert_allclose(u[0, 20, 30], ux, rtol=1e-4)
    np.testing.assert_allclose(u[1, 20, 30], uy, rtol=1e-4)


def test_preconditioner_is_an_approximate_inverse():
    """On oscillating fields (what CG sees once the force balances remove the mean) the preconditioned
    operator is close to the identity."""
    op = HalfSpaceOperator(40, 40, 0.05, 0.5, 0.15)
    y, x = np.mgrid[-1:1:40j, -1:1:40j]
    for k in (6, 12):
        bump = np.exp(-8 * (x**2 + y**2)) * np.cos(k * x)
        q = np.stack([bump, 0.5 * bump])
        back = op.precondition(op.apply(q))
        inner = slice(10, 30)
        ratio = back[:, inner, inner].ravel() @ q[:, inner, inner].ravel() / (q[:, inner, inner] ** 2).sum()
        assert 0.8 < ratio < 1.2, (k, ratio)


def test_dense_refused_above_cap():
    with pytest.raises(ValueError, match="dense matrix"):
        HalfSpaceOperator(100, 100, 0.01).matrix()


@pytest.mark.parametrize("kw, match", [({"nu": 0.6}, "nu"), ({"h": 0.0}, "h"), ({"ny": 0}, "ny")])
def test_bad_inputs(kw, match):
    args = dict(ny=4, nx=4, h=0.1, nu=0.3)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        HalfSpaceOperator(**args)
