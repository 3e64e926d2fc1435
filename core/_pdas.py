"""Numba kernels of the dense per-step solver (private; the interface is :mod:`core.dense`).

The state a step leaves for the next one lives in one structure,
:class:`PdasState` (a named tuple of arrays, updated in place): the active-set
guess of every element, the inverse of the influence matrix on the stick set
(kept current by rank-one updates), the tractions and the running sums.

The loops run over slices with ``range()`` indices: numba then knows the
indices are non-negative and LLVM vectorises them (4-5x faster than indexing
with offsets).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from ._jit import jit

# active-set kinds of an element (internal to the solver, not the recorded states)
OUT, FREE, UPPER, LOWER = 0, 1, 2, 3
# recorded element states (core.states.State; numba needs plain integers)
RELEASED, STICK, SLIP_FORWARD, SLIP_BACKWARD = 0, 1, 2, 3
# iterations moving every violator at once before moving one at a time
PDAS_FULL_STEPS = 8
# rank-one updates of the stick-set inverse before it is rebuilt from K
REBUILD_EVERY = 20000
# the named residuals, in the order of PdasState.residuals
RESIDUALS = ("stick_slip", "bound", "slip_direction", "out_of_contact", "load_balance")
# indices of PdasState.counters
M, UPDATES, ITERATIONS = 0, 1, 2

#: The solver's state between steps, updated in place by the kernels.
PdasState = namedtuple("PdasState", [
    "kind",        # (n,) int8: active-set guess (OUT, FREE, UPPER, LOWER)
    "B",           # (n, n): inverse of K on the free (stick) set, leading m x m block
    "fidx",        # (n,) int64: element of each row of B
    "pos",         # (n,) int64: row of each element in B, -1 if not free
    "work",        # (4 n,): scratch
    "q_prev",      # (n,): tractions after the previous step
    "q",           # (n,): tractions of this step
    "dq",          # (n,): their increment
    "slip",        # (n,): slip increments of this step
    "codes",       # (n,) int8: element states of this step (core.states.State)
    "q_block_end",  # (n,): tractions at the end of the last block (periodic detection)
    "counters",    # (3,) int64: size m of B, rank-one updates since the last rebuild, iterations of the last step
    "total",       # (1,): rigid-body displacement so far
    "residuals",   # (5,): the named residuals of the last step (RESIDUALS)
])


def new_state(n: int) -> PdasState:
    """A cold state for ``n`` elements (nothing in contact, empty inverse)."""
    return PdasState(kind=np.zeros(n, np.int8), B=np.zeros((n, n)), fidx=np.zeros(n, np.int64),
                     pos=-np.ones(n, np.int64), work=np.zeros(4 * n), q_prev=np.zeros(n), q=np.zeros(n),
                     dq=np.zeros(n), slip=np.zeros(n), codes=np.zeros(n, np.int8), q_block_end=np.zeros(n),
                     counters=np.zeros(3, np.int64), total=np.zeros(1), residuals=np.zeros(5))


# --------------------------------------------------------------------------
# the inverse of K on the stick set, kept current by rank-one updates
# --------------------------------------------------------------------------
@jit
def _dot(a, b):
    s = 0.0
    for t in range(a.size):
        s += a[t] * b[t]
    return s


@jit
def _axpy(alpha, x, y):
    """``y += alpha * x`` in place."""
    for t in range(y.size):
        y[t] += alpha * x[t]


@jit
def _inverse_add(K, B, fidx, pos, m, i, work):
    """Border the inverse ``B = K[F, F]^-1`` with element ``i``; return the new size (-1 if not PD)."""
    Bv = work[:m]
    v = work[m:2 * m]
    for c in range(m):
        v[c] = K[i, fidx[c]]
    for r in range(m):
        Bv[r] = _dot(B[r, :m], v)
    schur = K[i, i] - _dot(v, Bv)
    if not schur > 0.0:
        return -1
    inv = 1.0 / schur
    for r in range(m):
        wr = Bv[r] * inv
        _axpy(wr, Bv, B[r, :m])
        B[r, m] = -wr
        B[m, r] = -wr
    B[m, m] = inv
    fidx[m] = i
    pos[i] = m
    return m + 1


@jit
def _inverse_remove(B, fidx, pos, m, i):
    """Remove element ``i`` from the inverse (swap it last, then a rank-one downdate)."""
    k = pos[i]
    last = m - 1
    if k != last:
        for c in range(m):
            tmp = B[k, c]
            B[k, c] = B[last, c]
            B[last, c] = tmp
        for r in range(m):
            tmp = B[r, k]
            B[r, k] = B[r, last]
            B[r, last] = tmp
        j = fidx[last]
        fidx[k] = j
        pos[j] = k
        fidx[last] = i
    d = B[last, last]
    row = B[last, :last]
    for r in range(last):
        _axpy(-B[r, last] / d, row, B[r, :last])
    pos[i] = -1
    return last


@jit
def _inverse_rebuild(K, st):
    """Recompute ``B = K[F, F]^-1`` from scratch for the free set ``F``; return its size."""
    kind, B, fidx, pos = st.kind, st.B, st.fidx, st.pos
    m = 0
    for i in range(kind.size):
        if kind[i] == FREE:
            fidx[m] = i
            pos[i] = m
            m += 1
        else:
            pos[i] = -1
    if m > 0:
        sub = np.empty((m, m))
        for r in range(m):
            for c in range(m):
                sub[r, c] = K[fidx[r], fidx[c]]
        B[:m, :m] = np.linalg.inv(sub)
    st.counters[M] = m
    st.counters[UPDATES] = 0
    return m


@jit
def _inverse_replace(K, B, fidx, pos, m, k, i, work):
    """Put element ``i`` in place of the element in row ``k`` of ``B``; return False (B untouched) if not PD.

    ``K_FF`` changes by the symmetric rank-two term ``e_k d^T + d e_k^T``; the
    Sherman-Morrison-Woodbury formula updates ``B`` in one read and one
    read-write pass, where a removal and an addition would take three and a
    row and column swap.
    """
    j = fidx[k]
    w1 = work[:m]
    w2 = work[m:2 * m]
    d = work[2 * m:3 * m]
    for c in range(m):
        d[c] = K[i, fidx[c]] - K[j, fidx[c]]
        w1[c] = B[k, c]
    d[k] = 0.5 * (K[i, i] - K[j, j])
    for r in range(m):
        w2[r] = _dot(B[r, :m], d)
    # M = C + U^T B U with U = [e_k, d], C = [[0, 1], [1, 0]]
    m11 = w1[k]
    m12 = 1.0 + _dot(w1, d)
    m22 = _dot(d, w2)
    det = m11 * m22 - m12 * m12
    if det == 0.0 or not math.isfinite(det):
        return False
    i11, i12, i22 = m22 / det, -m12 / det, m11 / det
    # the new diagonal entry of the inverse must stay positive (K' positive definite)
    a, b = w1[k], w2[k]
    if not B[k, k] - (a * (i11 * a + i12 * b) + b * (i12 * a + i22 * b)) > 0.0:
        return False
    for r in range(m):
        u = w1[r] * i11 + w2[r] * i12
        v = w1[r] * i12 + w2[r] * i22
        row = B[r, :m]
        for c in range(m):
            row[c] -= u * w1[c] + v * w2[c]
    fidx[k] = i
    pos[i] = k
    pos[j] = -1
    return True


@jit
def _inverse_sync(K, st, m):
    """Bring the inverse to the current free set; return its size, -1 on loss of definiteness.

    Elements leaving and entering the free set are paired and replaced in place
    (:func:`_inverse_replace`); the rest are removed or added one at a time.
    """
    kind, B, fidx, pos, work = st.kind, st.B, st.fidx, st.pos, st.work
    n = kind.size
    updates = 0
    i_in = 0
    for i_out in range(n):
        if pos[i_out] >= 0 and kind[i_out] != FREE:
            while i_in < n and not (pos[i_in] < 0 and kind[i_in] == FREE):
                i_in += 1
            if i_in < n and _inverse_replace(K, B, fidx, pos, m, pos[i_out], i_in, work):
                i_in += 1
            else:
                m = _inverse_remove(B, fidx, pos, m, i_out)
            updates += 1
    for i in range(n):
        if pos[i] < 0 and kind[i] == FREE:
            m = _inverse_add(K, B, fidx, pos, m, i, work)
            updates += 1
            if m < 0:
                break
    st.counters[UPDATES] += updates
    return m


@jit
def _row_dot(K, i, v, lo, hi):
    """``K[i, lo:hi] @ v[lo:hi]`` (v is zero outside [lo, hi))."""
    return _dot(K[i, lo:hi], v[lo:hi])


# --------------------------------------------------------------------------
# one step
# --------------------------------------------------------------------------
@jit
def solve_step(K, g, target, dx, tol, maxiter, st):
    """Solve one increment of the tangential contact problem from ``st.q_prev``.

    The KKT conditions and the method are described in :mod:`core.dense`.
    Writes ``st.q``, ``st.dq``, ``st.slip``, ``st.codes``, ``st.residuals`` and
    the iteration count ``st.counters[ITERATIONS]``; keeps the active-set guess
    and the stick-set inverse for the next step.

    Returns
    -------
    lam : float
        Rigid-body displacement increment [mu P/E*].
    ok : bool
        False if no active set satisfied the KKT conditions to ``tol``.
    """
    kind, q_prev, q, dq, slip, codes, work, res = st.kind, st.q_prev, st.q, st.dq, st.slip, st.codes, st.work, st.residuals
    fidx = st.fidx
    n = g.size
    for j in range(5):
        res[j] = 0.0
    st.counters[ITERATIONS] = 0
    # ---- contact: released elements carry nothing, new ones start sticking
    for i in range(n):
        if g[i] <= 0.0:
            kind[i] = OUT
        elif kind[i] == OUT:
            kind[i] = FREE
    # ---- the zero increment, if feasible, is the unique solution
    total = 0.0
    out_res = 0.0
    bound_res = 0.0
    for i in range(n):
        total += q_prev[i]
        if kind[i] == OUT:
            out_res = max(out_res, abs(q_prev[i]))
        else:
            bound_res = max(bound_res, abs(q_prev[i]) - g[i])
    if out_res == 0.0 and bound_res <= tol and abs(total - target) * dx <= tol:
        for i in range(n):
            q[i] = q_prev[i]
            dq[i] = 0.0
            slip[i] = 0.0
            if kind[i] == OUT:
                codes[i] = RELEASED
            else:
                codes[i] = STICK
                if kind[i] != FREE and abs(q_prev[i]) < g[i] - tol:
                    kind[i] = FREE
        res[1] = max(bound_res, 0.0)
        res[4] = abs(total - target) * dx
        return 0.0, True

    m = st.counters[M]
    rebuilt = False
    lam = 0.0
    it = 0
    converged = False
    evaluated = False
    while it < maxiter:
        it += 1
        # ---- prescribed increments of the elements at a bound or released
        sum_prev = 0.0
        sum_fixed = 0.0
        lo, hi = n, 0  # dq is zero outside [lo, hi)
        for i in range(n):
            sum_prev += q_prev[i]
            if kind[i] == OUT:
                d = -q_prev[i]
            elif kind[i] == UPPER:
                d = g[i] - q_prev[i]
            elif kind[i] == LOWER:
                d = -g[i] - q_prev[i]
            else:
                d = 0.0
            dq[i] = d
            sum_fixed += d
            if d != 0.0:
                lo = min(lo, i)
                hi = max(hi, i + 1)
        # ---- the free set must not be empty: free the element farthest from its bound
        nfree = 0
        for i in range(n):
            if kind[i] == FREE:
                nfree += 1
        if nfree == 0:
            best, gbest = -1, -1.0
            for i in range(n):
                if kind[i] != OUT and g[i] > gbest:
                    best, gbest = i, g[i]
            if best < 0:
                break
            kind[best] = FREE
            continue
        # ---- stick-set inverse for this free set
        m = _inverse_sync(K, st, m)
        if m < 0:
            m = _inverse_rebuild(K, st)
            rebuilt = True
        B = st.B
        # ---- stick: K[F,F] dq_F = lam - K[F,fixed] dq_fixed, sum dq_F = D
        D = target - sum_prev - sum_fixed
        # y_F = K[F, fixed] dq_fixed: only the few fixed elements that move contribute (K is symmetric)
        y = work[n:n + m]
        for r in range(m):
            y[r] = 0.0
        for i in range(lo, hi):
            d = dq[i]
            if d != 0.0:
                Ki = K[i]
                for r in range(m):
                    y[r] += d * Ki[fidx[r]]
        # B 1 and B y in one pass over B (memory-bound)
        sb1 = 0.0
        sby = 0.0
        for r in range(m):
            row = B[r, :m]
            b1 = 0.0
            by = 0.0
            for c in range(m):
                b1 += row[c]
                by += row[c] * y[c]
            work[2 * n + r] = b1
            work[3 * n + r] = by
            sb1 += b1
            sby += by
        lam = (D + sby) / sb1
        for r in range(m):
            i = fidx[r]
            dq[i] = lam * work[2 * n + r] - work[3 * n + r]
            if dq[i] != 0.0:
                lo = min(lo, i)
                hi = max(hi, i + 1)
        # ---- check: bounds on the free set, slip direction on the fixed set
        n_viol = 0
        worst_free, i_free = 0.0, -1
        worst_fix, i_fix = 0.0, -1
        for i in range(n):
            q[i] = q_prev[i] + dq[i]
            if kind[i] == FREE:
                slip[i] = 0.0
                excess = abs(q[i]) - g[i]
                if excess > tol:
                    n_viol += 1
                    if excess > worst_free:
                        worst_free, i_free = excess, i
            elif kind[i] == UPPER or kind[i] == LOWER:
                s = lam - _row_dot(K, i, dq, lo, hi)
                slip[i] = s
                wrong = -s if kind[i] == UPPER else s
                if wrong > tol:
                    n_viol += 1
                    if wrong > worst_fix:
                        worst_fix, i_fix = wrong, i
            else:
                slip[i] = 0.0
        if n_viol > 0:
            if it <= PDAS_FULL_STEPS:
                # primal-dual active set: move every violator
                for i in range(n):
                    if kind[i] == FREE:
                        if abs(q[i]) - g[i] > tol:
                            kind[i] = UPPER if q[i] > 0 else LOWER
                    elif kind[i] == UPPER:
                        if slip[i] < -tol:
                            kind[i] = FREE
                    elif kind[i] == LOWER:
                        if slip[i] > tol:
                            kind[i] = FREE
            elif i_free >= 0:
                kind[i_free] = UPPER if q[i_free] > 0 else LOWER
            else:
                kind[i_fix] = FREE
            continue
        # ---- converged sets: the named KKT residuals with the true K (not the updated inverse)
        stick_res, bound_res, dir_res, out_res = 0.0, 0.0, 0.0, 0.0
        s_total = 0.0
        for i in range(n):
            s_total += q[i]
            if kind[i] == FREE:
                stick_res = max(stick_res, abs(lam - _row_dot(K, i, dq, lo, hi)))
                bound_res = max(bound_res, abs(q[i]) - g[i])
            elif kind[i] == OUT:
                out_res = max(out_res, abs(q[i]))
            else:
                bound_res = max(bound_res, abs(abs(q[i]) - g[i]))
                dir_res = max(dir_res, -slip[i] if kind[i] == UPPER else slip[i])
        evaluated = True
        res[0] = stick_res
        res[1] = max(bound_res, 0.0)
        res[2] = dir_res
        res[3] = out_res
        res[4] = abs(s_total - target) * dx
        worst = 0.0
        for j in range(5):
            worst = max(worst, res[j])
        if worst <= tol:
            converged = True
            break
        if rebuilt:
            break
        m = _inverse_rebuild(K, st)
        rebuilt = True
    st.counters[ITERATIONS] = it
    st.counters[M] = m
    if not converged:
        if not evaluated:  # no active set got as far as the residual check
            for j in range(5):
                res[j] = np.inf
        return lam, False
    # ---- element states: at a bound with no slip counts as stick
    for i in range(n):
        if kind[i] == OUT:
            codes[i] = RELEASED
        elif kind[i] == UPPER and slip[i] > tol:
            codes[i] = SLIP_FORWARD
        elif kind[i] == LOWER and slip[i] < -tol:
            codes[i] = SLIP_BACKWARD
        else:
            codes[i] = STICK
    return lam, True


# --------------------------------------------------------------------------
# a run of steps
# --------------------------------------------------------------------------
@jit
def march(K, bounds, Q, period, load_scale, dx, tol, maxiter, detect_periodic, k0, k1, st,
          traction, state, disp, diss, iters, resid, worst):
    """March through steps ``k0:k1``; ``bounds[k - k0]`` is the traction bound of step ``k``.

    Writes the per-step outputs and the worst named residuals so far (``worst``).

    Returns
    -------
    (steps done, periodic_from, failed step): ``steps done < k1`` with
    ``periodic_from >= 0`` means the period ``periodic_from`` repeats for ever;
    ``failed >= 0`` names a step that could not be solved (its residuals are in
    ``st.residuals``).
    """
    n = K.shape[0]
    steps = Q.size
    q_prev, q, slip, codes, res = st.q_prev, st.q, st.slip, st.codes, st.residuals
    for k in range(k0, k1):
        if st.counters[UPDATES] > REBUILD_EVERY:
            _inverse_rebuild(K, st)
        lam, ok = solve_step(K, bounds[k - k0], Q[k] * load_scale, dx, tol, maxiter, st)
        if not ok:
            return k, -1, k
        st.total[0] += lam
        d = 0.0
        for i in range(n):
            traction[k, i] = q[i]
            state[k, i] = codes[i]
            d += q[i] * slip[i]
            q_prev[i] = q[i]
        disp[k] = st.total[0]
        diss[k] = d * dx
        iters[k] = st.counters[ITERATIONS]
        r = 0.0
        for j in range(5):
            r = max(r, res[j])
            worst[j] = max(worst[j], res[j])
        resid[k] = r
        if k + 1 < steps and period[k + 1] != period[k]:
            # end of a block: a period that ends where the previous one ended repeats for ever
            if detect_periodic and period[k] >= 0:
                same = True
                for i in range(n):
                    if abs(q[i] - st.q_block_end[i]) > tol:
                        same = False
                        break
                if same:
                    return k + 1, period[k], -1
            for i in range(n):
                st.q_block_end[i] = q[i]
    return k1, -1, -1
