"""core/records/_fit.py: the compiled least-squares fit of ``y_j = D + C r^j`` behind the verdict's trend, against
closed forms (exact geometric sequences) and scipy's own fits of the same model."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares, minimize_scalar

from core.records._fit import GRID, fit_window
from core.records.verdict import RATIO_RANGE


def _reference(y):
    """The fit as the verdict made it before it was compiled: numpy's grid and scipy's bounded Brent."""
    k = y.size
    j = np.arange(k, dtype=float)
    yc = y - y.mean()

    def linear(r):
        b = np.power.outer(np.atleast_1d(r), j)
        bc = b - b.mean(axis=1, keepdims=True)
        bb = np.einsum("ij,ij->i", bc, bc)
        C = np.where(bb > 0, bc @ yc / np.where(bb > 0, bb, 1.0), 0.0)
        res = yc - C[:, None] * bc
        return np.einsum("ij,ij->i", res, res), C, y.mean() - C * b.mean(axis=1)

    grid = np.linspace(*RATIO_RANGE, GRID + 1)[1:]
    ssr = linear(grid)[0]
    i = int(np.argmin(ssr))
    opt = minimize_scalar(lambda r: float(linear(r)[0][0]), bounds=(grid[max(i - 1, 0)], grid[min(i + 1, GRID - 1)]),
                          method="bounded", options={"xatol": 1e-12})
    r = float(opt.x) if opt.fun <= ssr[i] else float(grid[i])
    s, C, D = (float(v[0]) for v in linear(r))
    J = np.column_stack([np.ones(k), r ** j, C * j * r ** np.maximum(j - 1.0, 0.0)])
    P = np.linalg.pinv(J, rcond=1e-13)
    return D, C, r, s, math.sqrt(float(P[0] @ P[0]))


@pytest.mark.parametrize("D, C, r, k", [(0.3, 0.5, 0.5, 12), (0.0, 0.1, 0.95, 40), (-2e-3, 1e-2, 0.2, 6),
                                        (1e-5, -3e-4, 0.999, 20), (0.05, 0.2, 1.1, 8)])
def test_an_exact_geometric_sequence_is_recovered(D, C, r, k):
    # Brent's search stops within sqrt(eps) |r| + 1e-12 / 3 of the best r (as scipy's does): r to 1e-7, and D and
    # C to what that moves them (most near r = 1, where D and C r^j are nearly the same column)
    y = D + C * r ** np.arange(k)
    d, c, q, s, e = fit_window(y, *RATIO_RANGE)
    assert q == pytest.approx(r, abs=1e-7)
    assert d == pytest.approx(D, abs=1e-5 * abs(C) + 1e-15)
    assert c == pytest.approx(C, rel=1e-5)
    assert s <= 1e-15 * k * C * C and e > 0


@settings(max_examples=60, deadline=None)
@given(st.floats(-1, 1), st.floats(-1, 1).filter(lambda c: abs(c) > 1e-3), st.floats(0.01, 1.15),
       st.integers(4, 64), st.floats(-14, -3), st.integers(0, 2 ** 31))
def test_the_fit_is_scipys_to_its_tolerance(D, C, r, k, noise, seed):
    y = D + C * r ** np.arange(k) + np.random.default_rng(seed).normal(0.0, 10 ** noise, k)
    d, c, q, s, e = fit_window(y, *RATIO_RANGE)
    D0, C0, r0, s0, e0 = _reference(y)
    scale = float(np.abs(y).max())
    # Brent's tolerance on r is sqrt(eps) |r| + xatol / 3 in both: the least squares agree to what it moves S
    # (at most ~1e-16 k C^2 about a minimum of S near 0)
    assert s <= s0 * (1 + 1e-6) + 1e-15 * k * scale ** 2
    # the fitted curves agree; D, C and r each may not where they are nearly degenerate (r near 1: D and C r^j are
    # nearly the same column, and a shift of r within the tolerance moves D and C by much more)
    j = np.arange(k)
    assert np.abs((d + c * q ** j) - (D0 + C0 * r0 ** j)).max() <= 1e-6 * scale
    if abs(1.0 - r0) > 0.05 and s0 > 0.0:
        assert q == pytest.approx(r0, abs=1e-6)
        assert e == pytest.approx(e0, rel=1e-4, abs=1e-9)


@settings(max_examples=30, deadline=None)
@given(st.floats(-1, 1), st.floats(-1, 1).filter(lambda c: abs(c) > 1e-2), st.floats(0.05, 1.1),
       st.integers(5, 40), st.integers(0, 2 ** 31))
def test_no_least_squares_fit_of_the_model_in_the_range_does_better(D, C, r, k, seed):
    # an independent solver of the same problem (trust-region least squares on D, C, r), started from the truth
    j = np.arange(k)
    y = D + C * r ** j + np.random.default_rng(seed).normal(0.0, 1e-4, k)
    s = fit_window(y, *RATIO_RANGE)[3]
    other = least_squares(lambda x: x[0] + x[1] * x[2] ** j - y, [D, C, r],
                          bounds=([-np.inf, -np.inf, RATIO_RANGE[0]], [np.inf, np.inf, RATIO_RANGE[1]]))
    assert s <= 2 * other.cost * (1 + 1e-6) + 1e-24
