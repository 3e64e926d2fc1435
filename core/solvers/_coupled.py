"""Compiled kernels of the coupled per-step solver (:mod:`core.solvers.coupled`): its march over the steps in numba.

The alternation of :class:`core.solvers.coupled.CoupledSolver` (the normal problem with
the tractions fixed, then the tangential one with that pressure, until
neither changes) run without leaving compiled code, for a contact that is one
interval of elements, which is the rocking cylinder's. The normal problem
on an interval of ``L`` elements needs the inverse of ``K`` on it; ``K`` is
symmetric Toeplitz, so that block is the same wherever the interval lies:
its explicit inverse ``A_L`` (Trench's algorithm, ``O(L^2)``) is kept for a
few widths at a time (:class:`Inverses`), and each pass applies it twice
(the normal solve and the pressure's tangential shift), a product of
contiguous rows. The tangential solve is :func:`core.solvers._pdas.solve_step`,
the uncoupled solver's own, with its checks and named residuals; once a full
pass has found the tangential set, the
passes keep it and make only the stick solve
(:func:`core.solvers._pdas.fixed_set_stick`, about a fifth of a full solve), until the change,
or the next one predicted from the ratio of the last two, is within the
tolerance (the set is kept after a full pass whose normal solve left the
interval where it was); a full pass then checks it and gives the residuals, and
ends the step if its own change is within the tolerance too (else the
alternation goes on). On the rocking cylinder at ``a/40`` this makes 2.0-2.7
full solves in 6-10 passes a step (``benchmarks/coupled.py``).
A step the kernels cannot take (the contact not one
interval, or its ends not settling) is reported to the caller, which then
solves it with the general Python path (:func:`core.pressure.normal.solve_line`).
:func:`march` runs the steps of a chunk (the alternation, the named
residuals, the record of each step and the periodic test) without returning
to Python, as :func:`core.solvers._pdas.march` does for the uncoupled solver: per-step
Python was half a coupled run's time (``benchmarks/results/coupled_timing_s4.txt``).
The factor ``C`` is computed here too (:func:`cholesky`), not by LAPACK, whose
threads cost more than they gain on a small ``K`` when the cores are shared.
"""

from __future__ import annotations

import numpy as np

from ..base._jit import jit
from collections import namedtuple

from ._pdas import ITERATIONS, MODE, TOEPLITZ, _toeplitz_inverse, block_repeats, fixed_set_stick, solve_step

__all__ = ["alternate", "interval_normal", "cross", "gap_residual", "march", "cholesky", "new_inverses",
           "Inverses", "STATUS_DONE", "STATUS_TANGENTIAL", "STATUS_GENERAL"]

#: :func:`alternate`'s status: solved (or the alternation did not settle: see its change), the tangential solve
#: failed, the normal problem needs the general solve.
STATUS_DONE, STATUS_TANGENTIAL, STATUS_GENERAL = 0, 1, 2
#: The alternation's settled passes stop when the next change, predicted from their ratio, is within this part
#: of the tolerance (:func:`alternate`).
PREDICTED = 0.3
#: Rows of the scratch ``work`` the kernels need (``n`` entries each).
WORK_ROWS = 10

#: Interval widths whose inverse :class:`Inverses` keeps (a contact breathes by an element or two as it rocks).
SLOTS = 4

#: The explicit inverses ``A_L = K_L^-1`` of the Toeplitz ``K`` on intervals of ``L`` elements, a few widths at
#: a time (least recently used replaced): the normal solve and the pressure's shift each need one product with
#: ``A_L`` a pass, and a product (contiguous rows, vectorised) costs a sixth of the two triangular solves with
#: the Cholesky factor it replaces (1.2 us against 7.1 us at 80 elements, ``benchmarks/coupled.py``).
Inverses = namedtuple("Inverses", [
    "column",   # (n,): the first column of K
    "A",        # (SLOTS, n, n): A_L in the leading L x L block
    "ones",     # (SLOTS, n): A_L 1
    "length",   # (SLOTS,) int64: L of each slot, -1 if empty
    "used",     # (SLOTS,) int64: the clock at its last use
    "clock",    # (1,) int64
])


def new_inverses(K) -> Inverses:
    """An empty :class:`Inverses` of the symmetric Toeplitz ``K`` (``n x n``)."""
    n = K.shape[0]
    return Inverses(column=np.ascontiguousarray(K[:, 0], dtype=float), A=np.zeros((SLOTS, n, n)),
                    ones=np.zeros((SLOTS, n)), length=-np.ones(SLOTS, np.int64), used=np.zeros(SLOTS, np.int64),
                    clock=np.zeros(1, np.int64))


@jit
def inverse(inv, C, CT, L):
    """The slot of ``inv`` holding ``A_L``, computed by Trench's algorithm (``O(L^2)``) if no slot holds it, or
    column by column from the Cholesky factor ``C`` (``CT`` its transpose) if that algorithm fails."""
    inv.clock[0] += 1
    dst = 0
    for k in range(SLOTS):
        if inv.length[k] == L:
            inv.used[k] = inv.clock[0]
            return k
        if inv.used[k] < inv.used[dst]:
            dst = k
    A = inv.A[dst]
    if not _toeplitz_inverse(inv.column, L, A):
        e = np.zeros(L)
        col = np.zeros(L)
        for j in range(L):
            e[j] = 1.0
            _chol_solve(C, CT, L, e, col)
            e[j] = 0.0
            for i in range(L):
                A[i, j] = col[i]
    for i in range(L):
        t = 0.0
        for j in range(L):
            t += A[i, j]
        inv.ones[dst, i] = t
    inv.length[dst] = L
    inv.used[dst] = inv.clock[0]
    return dst


@jit
def _apply(A, L, b, out):
    """``out[:L] = A[:L, :L] b[:L]``."""
    for i in range(L):
        t = 0.0
        row = A[i]
        for j in range(L):
            t += row[j] * b[j]
        out[i] = t



@jit
def cross(v, dx, out):
    """``out = S v``, ``(S v)_i = dx (sum_{j < i} v_j - sum_{j > i} v_j)`` (:func:`core.elastic.coupling.cross_apply`)."""
    total = 0.0
    for j in range(v.size):
        total += v[j]
    below = 0.0
    for i in range(v.size):
        out[i] = dx * (below - (total - below - v[i]))
        below += v[i]


@jit
def _chol_solve(C, CT, L, b, out):
    """``out[:L] = (C_L C_L^T)^-1 b[:L]``, ``C_L`` the leading ``L x L`` block of the lower factor ``C`` and ``CT``
    its transpose (both solves then read rows: contiguous, vectorised dot products)."""
    for i in range(L):
        s = b[i]
        row = C[i]
        for j in range(i):
            s -= row[j] * out[j]
        out[i] = s / row[i]
    for i in range(L - 1, -1, -1):
        s = out[i]
        row = CT[i]
        for j in range(i + 1, L):
            s -= row[j] * out[j]
        out[i] = s / row[i]


@jit
def _gap(K, h, delta, s, u, i0, L, j):
    """The gap at element ``j`` of the pressure ``delta s - u`` on ``[i0, i0 + L)``."""
    g = h[j] - delta
    for k in range(L):
        g += K[j, i0 + k] * (delta * s[k] - u[k])
    return g


@jit
def interval_normal(C, CT, K, h, load, dx, i0, i1, p, work, inv, check_all):
    """The normal problem ``h + K p - delta >= 0``, ``p >= 0``, complementary, ``sum p dx = load`` with the contact
    one interval ``[i0, i1)``, by moving its ends. Writes ``p``; returns ``(ok, i0, i1, delta)``. The inverse of
    ``K`` on the interval comes from ``inv`` (:func:`inverse`). The gap away from the ends is checked only with
    ``check_all`` (else :func:`penetrates` checks the final pressure)."""
    n = h.size
    u = work[2]
    for _ in range(2 * n + 8):
        L = i1 - i0
        if L < 3 or i0 < 0 or i1 > n:
            return False, i0, i1, 0.0
        slot = inverse(inv, C, CT, L)
        s = inv.ones[slot]
        _apply(inv.A[slot], L, h[i0:i1], u)
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
            return False, i0, i1, delta
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
        if check_all:
            for j in range(n):
                if (j < i0 - 1 or j > i1) and _gap(K, h, delta, s, u, i0, L, j) < -tol:
                    return False, i0, i1, delta
        for j in range(n):
            p[j] = 0.0
        for k in range(L):
            p[i0 + k] = delta * s[k] - u[k]
        return True, i0, i1, delta
    return False, i0, i1, 0.0


@jit
def _contact_products(K, p, i0, i1, out):
    """``out = K p`` for a pressure ``p`` that vanishes outside ``[i0, i1)``."""
    for j in range(K.shape[0]):
        g = 0.0
        row = K[j]
        for k in range(i0, i1):
            g += row[k] * p[k]
        out[j] = g


@jit
def penetrates(h, kp, delta, i0, i1):
    """Whether the pressure on ``[i0, i1)`` from :func:`interval_normal` (approach ``delta``, ``kp = K p``)
    penetrates the profile ``h`` away from its ends: :func:`interval_normal`'s test with ``check_all``."""
    hmax = 1.0
    for k in range(i0, i1):
        hmax = max(hmax, abs(h[k]))
    tol = 1e-12 * hmax
    for j in range(h.size):
        if (j < i0 - 1 or j > i1) and h[j] + kp[j] - delta < -tol:
            return True
    return False


@jit
def _gap_residual_from(gap0, p, q, kp, cn, dx, gap):
    """:func:`gap_residual` from ``kp = K p`` (``gap``: scratch)."""
    n = gap0.size
    cross(q, dx, gap)
    total = 0.0
    m = 0
    for i in range(n):
        gap[i] = gap0[i] + cn * gap[i] + kp[i]
        if p[i] > 0.0:
            total += gap[i]
            m += 1
    delta = total / m if m else 0.0
    worst = 0.0
    for i in range(n):
        if p[i] > 0.0:
            worst = max(worst, abs(gap[i] - delta))
        else:
            worst = max(worst, delta - gap[i])
    return worst


@jit
def alternate(K, C, CT, gap0, load, dx, cn, ct, coupled, p_prev, has_prev, target, tol, maxiter, max_alt, st,
              i0, i1, p, work, inv, q_start):
    """One coupled step by the alternation, from ``st.q_prev`` (kept) and the previous pressure ``p_prev``.

    ``q_start`` is the first guess of the step's tractions (the normal problem of the first pass sees it).
    Writes the pressure ``p`` and, through :func:`core.solvers._pdas.solve_step`, the step's tractions, slips, codes and
    residuals in ``st``. Returns ``(status, lam, alternations, full, change, i0, i1, delta)`` (:data:`STATUS_DONE`,
    ...; ``delta`` the approach of the last normal solve, whose profile stays in ``work[5]``). The passes check
    the gap only at the contact's ends: the caller checks the final pressure everywhere (:func:`march`).
    """
    n = gap0.size
    q_true = st.q_prev.copy()
    q_in = q_start.copy()
    profile, shift, dp, p_cur = work[5], work[6], work[7], work[8]
    for k in range(n):
        p_cur[k] = p_prev[k]
    lam = 0.0
    delta = 0.0
    change = np.inf
    it = 0
    status = STATUS_DONE
    n_full = 0
    settled = False  # the contact interval and the tangential set are kept
    before = -1.0  # the change of the last settled pass (none: -1; the kernels are compiled with fastmath: no inf)
    while it < max_alt:
        it += 1
        # ---- normal: the pressure with the tractions fixed
        cross(q_in, dx, shift)
        for k in range(n):
            profile[k] = gap0[k] + cn * shift[k]
        j0, j1 = i0, i1
        ok, i0, i1, delta = interval_normal(C, CT, K, profile, load, dx, i0, i1, p, work, inv, False)
        if not ok:
            status = STATUS_GENERAL
            break
        if i0 != j0 or i1 != j1:
            settled = False
        # ---- tangential: the pressure's slip carried by a change of the previous tractions on the contact
        for k in range(n):
            st.q_prev[k] = q_true[k]
        if ct != 0.0:
            for k in range(n):
                dp[k] = p[k] - p_prev[k]
            cross(dp, dx, shift)
            for k in range(i1 - i0):
                shift[k] = ct * shift[i0 + k]
            _apply(inv.A[inverse(inv, C, CT, i1 - i0)], i1 - i0, shift, work[9])
            for k in range(i1 - i0):
                st.q_prev[i0 + k] += work[9][k]
        # once settled, the sets are kept and only the stick solve is made (fixed_set_stick); a full solve with
        # its checks and residuals follows the pass that meets the tolerance, and ends the step if it meets it too
        full = True
        if settled:
            lam, ok = fixed_set_stick(p, target, st)
            full = not ok
        if full:
            n_full += 1
            lam, ok = solve_step(K, p, target, dx, tol, maxiter, st)
            if not ok:
                status = STATUS_TANGENTIAL
                break
            # the set it found is kept if the normal solve left the interval where it was (a set that is still
            # wrong shows in the full pass that ends the settled ones, and the alternation goes on from there)
            settled = st.counters[MODE] == TOEPLITZ and i0 == j0 and i1 == j1
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
        if change <= tol and full:
            break
        # the settled passes contract the change by a steady ratio: the full solve's turn once the change, or the
        # next one by that ratio, is within the tolerance (the full pass is then the next one's work)
        ratio = change / before if before > 0.0 else 1.0
        if full:
            before = -1.0
        elif change <= tol or (ratio < 0.5 and change * ratio <= PREDICTED * tol):
            settled = False
        else:
            before = change
    for k in range(n):
        st.q_prev[k] = q_true[k]
    return status, lam, it, n_full, change, i0, i1, delta


@jit
def gap_residual(K, gap0, p, q, cn, dx, work):
    """The worst gap residual of a solved step [P/E*]: ``|gap|`` where ``p > 0`` and the penetration elsewhere,
    the approach ``delta`` being the gap's mean over the contact (:func:`_gap_residual_from` with ``K p``)."""
    n = gap0.size
    kp = work[5]
    for i in range(n):
        g = 0.0
        for j in range(n):
            if p[j] != 0.0:
                g += K[i, j] * p[j]
        kp[i] = g
    return _gap_residual_from(gap0, p, q, kp, cn, dx, work[6])


@jit
def cholesky(A):
    """The lower Cholesky factor of the symmetric positive definite ``A`` (unblocked, in this thread: LAPACK's
    threads cost more than they gain on the small ``K`` of a line when the cores are shared)."""
    n = A.shape[0]
    C = np.zeros_like(A)
    for j in range(n):
        s = A[j, j]
        for k in range(j):
            s -= C[j, k] * C[j, k]
        if s <= 0.0:
            return C, False
        d = np.sqrt(s)
        C[j, j] = d
        for i in range(j + 1, n):
            t = A[i, j]
            for k in range(j):
                t -= C[i, k] * C[j, k]
            C[i, j] = t / d
    return C, True


@jit
def _start_interval(p_prev, gap0, load, dx, move):
    """The first guess of a step's contact: the previous pressure's moved by ``move`` elements (the centre's
    move), else Hertz's width around the lowest point."""
    n = gap0.size
    i0, i1 = -1, -1
    for k in range(n):
        if p_prev[k] > 0.0:
            if i0 < 0:
                i0 = k
            i1 = k + 1
    if i0 >= 0:
        if 0 <= i0 + move and i1 + move <= n:
            i0 += move
            i1 += move
        return True, i0, i1
    m = 0
    for k in range(1, n):
        if gap0[k] < gap0[m]:
            m = k
    half = int(np.ceil(np.sqrt(max(load, 1e-12) / (0.5 * np.pi)) / dx)) + 1
    return False, max(0, m - half), min(n, m + half + 1)


@jit
def march(K, C, CT, gaps, xc, loads, targets, period, kb, k0, k1, detect_periodic, dx, cn, ct, coupled, tol,
          maxiter, max_alt, st, p_prev, dq_last, work, inv, q_start, bounds, traction, state, disp, diss,
          iters, resid, worst, alternations, full_solves, res_out, info):
    """March through steps ``k0:k1`` by :func:`alternate`, recording each as :meth:`core.solvers.coupled.CoupledSolver.march`
    does (``gaps[k - kb]``: the body's gap of step ``k``, ``kb <= k0`` the first step of the chunk; ``xc``,
    ``loads``, ``targets``: its centre, normal load and tangential target; ``bounds[k - kb]`` receives its
    pressure). ``p_prev`` and ``dq_last`` (the last traction increment, the next step's first guess) advance with
    the steps.

    Returns ``(reached, periodic_from, failed, status)``: ``status`` :data:`STATUS_GENERAL` stops at step
    ``reached`` for the general solve; ``failed >= 0`` names a step that could not be solved (``info`` then
    holds its alternations and last change, ``res_out`` its residuals).
    """
    n = gaps.shape[1]
    steps = targets.size
    nres = st.residuals.size
    q_prev, q = st.q_prev, st.q
    p = np.zeros(n)
    for k in range(k0, k1):
        gap0 = gaps[k - kb]
        move = int(np.rint((xc[k] - xc[k - 1]) / dx)) if k > 0 else 0
        has_prev, i0, i1 = _start_interval(p_prev, gap0, loads[k], dx, move)
        for i in range(n):
            q_start[i] = q_prev[i] + dq_last[i]
            p[i] = 0.0
        status, lam, it, n_full, change, i0, i1, delta = alternate(
            K, C, CT, gap0, loads[k], dx, cn, ct, coupled, p_prev, has_prev, targets[k], tol, maxiter, max_alt, st,
            i0, i1, p, work, inv, q_start)
        if status == STATUS_DONE:
            # ---- the final pressure penetrates nowhere else (the passes checked only the contact's ends)
            _contact_products(K, p, i0, i1, work[4])
            if penetrates(work[5], work[4], delta, i0, i1):
                status = STATUS_GENERAL
        if status == STATUS_GENERAL:
            return k, -1, -1, STATUS_GENERAL
        # ---- the named residuals
        for j in range(nres):
            res_out[j] = st.residuals[j]
        if status != STATUS_DONE or not change <= tol:
            info[0], info[1] = it, change
            return k, -1, k, status
        res_out[nres] = _gap_residual_from(gap0, p, q, work[4], cn, dx, work[6])
        pmin = 0.0
        for i in range(n):
            pmin = min(pmin, p[i])
        res_out[nres + 1] = -pmin
        res_out[nres + 2] = change if np.isfinite(change) else 0.0
        worst_step = 0.0
        for j in range(res_out.size):
            worst_step = max(worst_step, res_out[j])
        if worst_step > 1e3 * tol:
            info[0], info[1] = it, change
            return k, -1, k, status
        # ---- record the step and advance
        st.total[0] += lam
        d = 0.0
        for i in range(n):
            bounds[k - kb, i] = p[i]
            traction[k, i] = q[i]
            state[k, i] = st.codes[i]
            d += q[i] * st.slip[i]
            dq_last[i] = q[i] - q_prev[i]
            q_prev[i] = q[i]
            p_prev[i] = p[i]
        disp[k] = st.total[0]
        diss[k] = d * dx
        iters[k] = st.counters[ITERATIONS]
        resid[k] = worst_step
        for j in range(res_out.size):
            worst[j] = max(worst[j], res_out[j])
        alternations[k] = it
        full_solves[k] = n_full
        if k + 1 < steps and period[k + 1] != period[k]:
            same = block_repeats(q, st.q_block_end, tol)
            if same and detect_periodic and period[k] >= 0:
                return k + 1, period[k], -1, STATUS_DONE
    return k1, -1, -1, STATUS_DONE
