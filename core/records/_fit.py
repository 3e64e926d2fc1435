"""The least-squares fit of ``y_j = D + C r^j`` behind the verdict's trend (:func:`core.records.verdict.fit_trend`).

For each ``r`` the model is linear in ``D`` and ``C``: the residual sum of
squares ``S(r)`` is that of ``y`` (centred) against ``r^j`` (centred). The fit
searches ``r`` over a grid of :data:`GRID` points of the ratio's range, then
refines the best grid point between its neighbours by Brent's bounded search
(the algorithm of :func:`scipy.optimize.minimize_scalar` with ``method="bounded"``,
here compiled with the function it minimises: a run's record fits its trend ten
times, and the interpreted search cost more than the run's solve).
"""

from __future__ import annotations

import math

import numpy as np

from ..base._jit import jit

__all__ = ["fit_window", "GRID", "XATOL"]

#: Points of the grid over the ratio's range (the range's lower end left out).
GRID = 481
#: Absolute tolerance of the refined ratio.
XATOL = 1e-12


@jit
def _squares(r, yc, b):
    """``(S, C, mean of r^j)`` at ``r``: the residual sum of squares of the centred ``yc`` against ``C (r^j - mean)``
    for ``j = 0, 1, ...`` (``b``: scratch of ``yc``'s size)."""
    k = yc.size
    power, mean = 1.0, 0.0
    for i in range(k):  # r^j by products: j = 0, 1, ... (a power a point cost more than the whole fit)
        b[i] = power
        mean += power
        power *= r
    mean /= k
    bb, by = 0.0, 0.0
    for i in range(k):
        c = b[i] - mean
        bb += c * c
        by += c * yc[i]
    C = by / bb if bb > 0.0 else 0.0
    s = 0.0
    for i in range(k):
        e = yc[i] - C * (b[i] - mean)
        s += e * e
    return s, C, mean


@jit
def _bounded(yc, b, x1, x2, xatol):
    """Brent's bounded minimisation of :func:`_squares` over ``[x1, x2]`` (scipy's ``_minimize_scalar_bounded``,
    500 evaluations at most): ``(r, S(r))``."""
    sqrt_eps = math.sqrt(2.2e-16)
    golden_mean = 0.5 * (3.0 - math.sqrt(5.0))
    a, bnd = x1, x2
    fulc = a + golden_mean * (bnd - a)
    nfc, xf = fulc, fulc
    rat, e = 0.0, 0.0
    x = xf
    fx = _squares(x, yc, b)[0]
    num = 1
    ffulc, fnfc = fx, fx
    xm = 0.5 * (a + bnd)
    tol1 = sqrt_eps * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > tol2 - 0.5 * (bnd - a):
        golden = True
        if abs(e) > tol1:  # a parabola through the three best points
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if abs(p) < abs(0.5 * q * r) and p > q * (a - xf) and p < q * (bnd - xf):
                rat = p / q
                x = xf + rat
                if x - a < tol2 or bnd - x < tol2:
                    rat = tol1 if xm >= xf else -tol1
            else:
                golden = True
        if golden:
            e = a - xf if xf >= xm else bnd - xf
            rat = golden_mean * e
        step = max(abs(rat), tol1)
        x = xf + step if rat >= 0.0 else xf - step
        fu = _squares(x, yc, b)[0]
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                bnd = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                bnd = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + bnd)
        tol1 = sqrt_eps * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= 500:
            break
    return xf, fx


@jit
def fit_window(y, lo, hi):
    """Least squares of ``y_j = D + C r^j`` (``j = 0 ... k-1``) for ``r`` in ``[lo, hi]``: ``(D, C, r, S, e)``.

    ``S`` is the residual sum of squares, ``e`` the standard error of ``D`` for a unit scatter of ``y``. The grid
    of :data:`GRID` points over ``(lo, hi]`` brackets the best ``r``, which Brent's bounded search refines to
    :data:`XATOL` between the grid's neighbours (kept only if it does at least as well as the grid's point).
    """
    k = y.size
    mean_y = 0.0
    for i in range(k):
        mean_y += y[i]
    mean_y /= k
    yc = y - mean_y
    b = np.empty(k)
    step = (hi - lo) / GRID
    # no infinity to start from: the kernels are compiled with fastmath, which assumes there is none
    best, ibest = _squares(lo + step, yc, b)[0], 1
    for i in range(2, GRID + 1):
        s = _squares(lo + i * step, yc, b)[0]
        if s < best:
            best, ibest = s, i
    a = lo + max(ibest - 1, 1) * step
    z = lo + min(ibest + 1, GRID) * step
    r, s = _bounded(yc, b, a, z, XATOL)
    if not s <= best:
        r = lo + ibest * step
    s, C, mean_b = _squares(r, yc, b)
    # the standard error of D per unit scatter: the first row of the pseudo-inverse of the Jacobian of
    # (D, C, r) (singular values below 1e-13 of the largest left out: C = 0 or r = 0 leaves a column empty)
    J = np.empty((k, 3))
    power = 1.0
    for i in range(k):
        J[i, 0] = 1.0
        J[i, 1] = power
        J[i, 2] = C * i * (power / r if r != 0.0 else (1.0 if i == 1 else 0.0))
        power *= r
    P = np.linalg.pinv(J, 1e-13)  # (3, k)
    e = 0.0
    for i in range(k):
        e += P[0, i] * P[0, i]
    return mean_y - C * mean_b, C, r, s, math.sqrt(e)
