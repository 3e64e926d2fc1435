"""Elastic operators: element influences against quadrature, dense = FFT, and the preconditioner."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from numpy.testing import assert_allclose
from scipy.integrate import quad
from scipy.linalg import eigh, null_space

from core.elastic import kernels
from core.elastic.operators import MAX_DENSE_SIZE, elastic_operator

STRIP = dict(L_over_a=40.0, b_coefficient=kernels.strip_b_coefficient(0.3))
KERNELS = [("plane", {}), ("strip", STRIP)]


def _plane_point_kernel(t):
    """Plane strain: displacement [mu P/E*] at distance t [a] per unit traction density [mu p0]."""
    return 4 / np.pi**2 * np.log(kernels.PLANE_REFERENCE_LENGTH / abs(t))


def _strip_point_kernel(t, L_over_a, b_coefficient):
    """Strip: the Cerruti kernel integrated over eta in [-L/2, L/2] in closed form (2/pi^2 normalisation)."""
    S = L_over_a / 2
    return 2 / np.pi**2 * (2 * np.arcsinh(S / abs(t)) + b_coefficient * S / np.hypot(t, S))


@pytest.mark.parametrize("kernel, opts", KERNELS)
@pytest.mark.parametrize("form", ["dense", "fft"])
def test_element_influences_match_quadrature_of_the_kernel(kernel, opts, form):
    n, dx = 40, 0.07
    op = elastic_operator(n, dx, kernel, form, **opts)
    point = _plane_point_kernel if kernel == "plane" else (lambda t: _strip_point_kernel(t, **opts))
    j = 11
    e = np.zeros(n)
    e[j] = 1.0
    u = op.apply(e)
    x = (np.arange(n) - j) * dx  # collocation points relative to the loaded element's centre
    for i in (0, j - 1, j, j + 1, j + 5, n - 1):
        d = x[i]
        inner = [d] if abs(d) < dx / 2 else None  # the log singularity, when inside the element
        val = quad(lambda xi: point(d - xi), -dx / 2, dx / 2, points=inner, epsabs=1e-13, epsrel=1e-12)[0]
        assert_allclose(u[i], val, rtol=1e-9, err_msg=f"element {i}")


@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 700), dx=st.floats(1e-3, 0.5), seed=st.integers(0, 2**32 - 1),
       kernel=st.sampled_from(["plane", "strip"]))
def test_dense_and_fft_forms_agree_to_round_off(n, dx, seed, kernel):
    opts = dict(KERNELS)[kernel]
    q = np.random.default_rng(seed).normal(size=n)
    dense = elastic_operator(n, dx, kernel, "dense", **opts)
    fft = elastic_operator(n, dx, kernel, "fft", **opts)
    ud, uf = dense.apply(q), fft.apply(q)
    scale = np.abs(dense.column).max() * np.abs(q).sum()  # bound of |K q|
    assert np.abs(ud - uf).max() <= 1e-14 * scale * np.log2(2 * n + 2)
    assert_allclose(dense.matrix(), fft.matrix(), rtol=0, atol=0)
    assert_allclose(ud, dense.matrix() @ q, rtol=0, atol=1e-15 * scale)


@pytest.mark.parametrize("kernel, opts", [("plane", {}), ("strip", dict(L_over_a=50.0, b_coefficient=2.0))])
def test_continuous_symbol_is_the_limit_of_the_discrete_one(kernel, opts):
    """At wavenumbers well inside (2 pi / N dx, pi / dx) the padded DFT of the kernel column
    approaches the continuous symbol: this checks the constant of the preconditioner."""
    N, dx = 2**16, 1 / 200
    op = elastic_operator(8, dx, kernel, "fft", **opts)
    spec = op.spectrum(N)
    k = 2 * np.pi * np.arange(spec.size) / (N * dx)
    for j in (100, 300, 1000):
        assert_allclose(spec[j], kernels.kernel_symbol(k[j], kernel, **opts), rtol=3e-3)
    assert_allclose(op.inverse_symbol(N)[1:], 1 / kernels.kernel_symbol(k[1:], kernel, **opts), rtol=1e-14)
    if kernel == "plane":
        assert_allclose(kernels.kernel_symbol(k[1:]), 4 / (np.pi * k[1:]), rtol=1e-14)


@pytest.mark.parametrize("kernel, opts", KERNELS)
def test_preconditioner_is_spd_and_its_spectrum_stays_narrow(kernel, opts):
    """The generalised eigenvalues of (K, M^-1) on zero-sum fields (the subspace the solver's CG
    works in) stay within a factor of about 4 from 50 to 400 elements (measured 2.4 to 3.2)."""
    spreads = []
    for n in (50, 400):
        op = elastic_operator(n, 2 / n, kernel, "dense", **opts)
        M = np.array([op.precondition(e) for e in np.eye(n)])
        assert_allclose(M, M.T, atol=1e-12)
        assert eigh(M, eigvals_only=True).min() > 0
        Z = null_space(np.ones((1, n)))
        ev = eigh(Z.T @ op.matrix() @ Z, Z.T @ np.linalg.inv(M) @ Z, eigvals_only=True)
        spreads.append(ev.max() / ev.min())
    assert spreads[-1] < 4.0, spreads
    assert np.linalg.cond(op.matrix()) > 100 * spreads[-1]  # the preconditioner earns its keep


def test_operator_interface_and_bad_inputs():
    op = elastic_operator(30, 0.1, "plane", "fft")
    assert op.shape == (30,) and op.size == 30 and op.form == "fft"
    with pytest.raises(ValueError, match="shape"):
        op.apply(np.zeros(29))
    with pytest.raises(ValueError, match="form"):
        elastic_operator(30, 0.1, "plane", "sparse")
    with pytest.raises(ValueError, match="kernel"):
        elastic_operator(30, 0.1, "cubic")
    with pytest.raises(ValueError, match="dx"):
        elastic_operator(30, 0.0)
    with pytest.raises(ValueError, match="MAX_DENSE_SIZE"):
        elastic_operator(MAX_DENSE_SIZE + 1, 0.1, "plane", "fft").matrix()
    with pytest.raises(ValueError, match="k must"):
        kernels.kernel_symbol(0.0)
    with pytest.raises(ValueError, match="L_over_a"):
        kernels.kernel_symbol(1.0, "strip")
