"""Compiled kernels of the coupled per-step solver (:mod:`core.coupled`): one step's alternation in numba.

The alternation of :class:`core.coupled.CoupledSolver` (the normal problem with
the tractions fixed, then the tangential one with that pressure, until
neither changes) run without leaving compiled code, for a contact that is one
interval of elements, which is the rocking cylinder's. The normal problem
on an interval of ``L`` elements needs the inverse of ``K`` on it; ``K`` is
symmetric Toeplitz, so that block is the leading ``L x L`` block of ``K``, and
its Cholesky factor is the leading block of the Cholesky factor ``C`` of the
whole ``K``: one factor, computed once, solves every interval by two
triangular solves. The tangential solve is :func:`core._pdas.solve_step`, the
uncoupled solver's own. A step the kernels cannot take (the contact not one
interval, or its ends not settling) is reported to the caller, which then
solves it with the general Python path (:func:`core.normal.solve_line`).
"""

from __future__ import annotations

import numpy as np

from ._jit import jit
from ._pdas import solve_step

__all__ = ["alternate", "interval_normal", "cross", "gap_residual", "STATUS_DONE", "STATUS_TANGENTIAL", "STATUS_GENERAL"]

#: :func:`alternate`'s status: solved (or the alternation did not settle: see its change), the tangential solve
#: failed, the normal problem needs the general solve.
STATUS_DONE, STATUS_TANGENTIAL, STATUS_GENERAL = 0, 1, 2


@jit
def cross(v, dx, out):
    """``out = S v``, ``(S v)_i = dx (sum_{j < i} v_j - sum_{j > i} v_j)`` (:func:`core.coupling.cross_apply`)."""
    total = 0.0
    for j in range(v.size):
        total += v[j]
    below = 0.0
    for i in range(v.size):
        out[i] = dx * (below - (total - below - v[i]))
        below += v[i]


@jit
def _chol_solve(C, L, b, out):
    """``out[:L] = (C_L C_L^T)^-1 b[:L]``, ``C_L`` the leading ``L x L`` block of the lower factor ``C``."""
    for i in range(L):
        s = b[i]
        for j in range(i):
            s -= C[i, j] * out[j]
        out[i] = s / C[i, i]
    for i in range(L - 1, -1, -1):
        s = out[i]
        for j in range(i + 1, L):
            s -= C[j, i] * out[j]
        out[i] = s / C[i, i]


@jit
def _gap(K, h, delta, s, u, i0, L, j):
    """The gap at element ``j`` of the pressure ``delta s - u`` on ``[i0, i0 + L)``."""
    g = h[j] - delta
    for k in range(L):
        g += K[j, i0 + k] * (delta * s[k] - u[k])
    return g


@jit
def interval_normal(C, K, h, load, dx, i0, i1, p, work, ones_inv, known):
    """The normal problem ``h + K p - delta >= 0``, ``p >= 0``, complementary, ``sum p dx = load`` with the contact
    one interval ``[i0, i1)``, by moving its ends. Writes ``p``; returns ``(ok, i0, i1)``. ``ones_inv[L]`` keeps
    ``K_L^-1 1`` of each width met (``known[L]``)."""
    n = h.size
    ones, u = work[0], work[2]
    for k in range(n):
        ones[k] = 1.0
    for _ in range(2 * n + 8):
        L = i1 - i0
        if L < 3 or i0 < 0 or i1 > n:
            return False, i0, i1
        s = ones_inv[L]
        if not known[L]:
            _chol_solve(C, L, ones, s)
            known[L] = True
        _chol_solve(C, L, h[i0:i1], u)
        s1 = 0.0
        su = 0.0
        hmax = 1.0
        for k in range(L):
            s1 += s[k]
            su += u[k]
            hmax = max(hmax, abs(h[i0 + k]))
        delta = (load / dx + su) / s1
        neg_first = delta * s[0] - u[0] < 0.0
        neg_last = delta * s[L - 1] - u[L - 1] < 0.0
        neg_inside = False
        for k in range(1, L - 1):
            if delta * s[k] - u[k] < 0.0:
                neg_inside = True
        if neg_first or neg_last:
            if neg_first:
                i0 += 1
            if neg_last:
                i1 -= 1
            continue
        if neg_inside:
            return False, i0, i1
        tol = 1e-12 * hmax
        # ---- the neighbours first: a penetrating one joins the contact
        grow0 = i0 > 0 and _gap(K, h, delta, s, u, i0, L, i0 - 1) < -tol
        grow1 = i1 < n and _gap(K, h, delta, s, u, i0, L, i1) < -tol
        if grow0 or grow1:
            if grow0:
                i0 -= 1
            if grow1:
                i1 += 1
            continue
        # ---- settled ends: no penetration anywhere else
        for j in range(n):
            if (j < i0 - 1 or j > i1) and _gap(K, h, delta, s, u, i0, L, j) < -tol:
                return False, i0, i1
        for j in range(n):
            p[j] = 0.0
        for k in range(L):
            p[i0 + k] = delta * s[k] - u[k]
        return True, i0, i1
    return False, i0, i1


@jit
def alternate(K, C, gap0, load, dx, cn, ct, coupled, p_prev, has_prev, target, tol, maxiter, max_alt, st,
              i0, i1, p, work, ones_inv, known, q_start):
    """One coupled step by the alternation, from ``st.q_prev`` (kept) and the previous pressure ``p_prev``.

    ``q_start`` is the first guess of the step's tractions (the normal problem of the first pass sees it).
    Writes the pressure ``p`` and, through :func:`core._pdas.solve_step`, the step's tractions, slips, codes and
    residuals in ``st``. Returns ``(status, lam, alternations, change, i0, i1)`` (:data:`STATUS_DONE`, ...).
    """
    n = gap0.size
    q_true = st.q_prev.copy()
    q_in = q_start.copy()
    profile, shift, dp, p_cur = work[5], work[6], work[7], work[8]
    for k in range(n):
        p_cur[k] = p_prev[k]
    lam = 0.0
    change = np.inf
    it = 0
    status = STATUS_DONE
    while it < max_alt:
        it += 1
        # ---- normal: the pressure with the tractions fixed
        cross(q_in, dx, shift)
        for k in range(n):
            profile[k] = gap0[k] + cn * shift[k]
        ok, i0, i1 = interval_normal(C, K, profile, load, dx, i0, i1, p, work, ones_inv, known)
        if not ok:
            status = STATUS_GENERAL
            break
        # ---- tangential: the pressure's slip carried by a change of the previous tractions on the contact
        for k in range(n):
            st.q_prev[k] = q_true[k]
        if ct != 0.0:
            for k in range(n):
                dp[k] = p[k] - p_prev[k]
            cross(dp, dx, shift)
            for k in range(i1 - i0):
                shift[k] = ct * shift[i0 + k]
            _chol_solve(C, i1 - i0, shift, work[9])
            for k in range(i1 - i0):
                st.q_prev[i0 + k] += work[9][k]
        lam, ok = solve_step(K, p, target, dx, tol, maxiter, st)
        if not ok:
            status = STATUS_TANGENTIAL
            break
        # ---- the change of both fields in this pass
        change = 0.0
        for k in range(n):
            change = max(change, abs(st.q[k] - q_in[k]))
            q_in[k] = st.q[k]
        if has_prev or it > 1:
            for k in range(n):
                change = max(change, abs(p[k] - p_cur[k]))
        else:
            change = np.inf
        for k in range(n):
            p_cur[k] = p[k]
        if not coupled:
            change = 0.0
        if change <= tol:
            break
    for k in range(n):
        st.q_prev[k] = q_true[k]
    return status, lam, it, change, i0, i1


@jit
def gap_residual(K, gap0, p, q, cn, dx, work):
    """The worst gap residual of a solved step [P/E*]: ``|gap|`` where ``p > 0`` and the penetration elsewhere,
    the approach ``delta`` being the gap's mean over the contact."""
    n = gap0.size
    shift, gap = work[5], work[6]
    cross(q, dx, shift)
    total = 0.0
    m = 0
    for i in range(n):
        g = gap0[i] + cn * shift[i]
        for j in range(n):
            if p[j] != 0.0:
                g += K[i, j] * p[j]
        gap[i] = g
        if p[i] > 0.0:
            total += g
            m += 1
    delta = total / m if m else 0.0
    worst = 0.0
    for i in range(n):
        if p[i] > 0.0:
            worst = max(worst, abs(gap[i] - delta))
        else:
            worst = max(worst, delta - gap[i])
    return worst
