"""Numba kernels of the matrix-free per-step solver (private; the interface is :mod:`core.solvers.matrix_free`).

The same algorithm as described in :mod:`core.solvers.matrix_free`, compiled: the
primal-dual active set over steps, projected preconditioned conjugate
gradients on the stick set, and the FFT products with the operator and the
preconditioner (``np.fft`` inside numba, provided by the ``rocket-fft``
extension). Every product is on the zero-padded circulant of size ``N`` fixed
per solver (``N >= 2 n``), so a step costs ``O(N log N)`` per product with no
Python in the loop.
"""

from __future__ import annotations

import importlib.util

import numpy as np

from ..base._jit import jit
from ._pdas import FREE, LOWER, OUT, UPPER, block_repeats, move_violators, record_step, state_codes, zero_increment

#: Whether numba can compile ``np.fft`` (the ``rocket-fft`` extension registers itself with numba when present).
HAVE_FFT = importlib.util.find_spec("rocket_fft") is not None
# CG stops when the stick-set displacement is constant to this fraction of the KKT tolerance: tight
# enough that tractions repeat to the tolerance at the ends of a periodic state (periodic detection)
CG_TOL_FRACTION = 0.001
# restarts of CG from its iterate when the recomputed residual misses the tolerance
CG_RESTARTS = 3
# indices of the counters array: active-set iterations, CG iterations, FFT products of the last step
ITERATIONS, CG, PRODUCTS = 0, 1, 2


@jit
def _product(v, spectrum, N, counters):
    """First ``v.size`` entries of the circulant product of ``v`` (zero-padded to ``N``) with ``spectrum``."""
    counters[PRODUCTS] += 1
    return np.fft.irfft(np.fft.rfft(v, N) * spectrum, N)[:v.size]


@jit
def _range_on(r, f):
    lo, hi = np.inf, -np.inf
    for i in range(r.size):
        if f[i] > 0.0:
            lo = min(lo, r[i])
            hi = max(hi, r[i])
    return hi - lo


@jit
def _project(pre, N, r, f, Mf, c, counters):
    """Projected preconditioned residual ``z = M r - M 1 (1^T M r) / (1^T M 1)`` on ``F``, and ``r . z``."""
    m = r.size
    mean, cnt = 0.0, 0
    for i in range(m):
        if f[i] > 0.0:
            mean += r[i]
            cnt += 1
    mean /= cnt
    rs = (r - mean) * f
    z = _product(rs, pre, N, counters) * f
    s = z.sum() / c
    rz = 0.0
    for i in range(m):
        z[i] -= s * Mf[i]
        rz += rs[i] * z[i]
    return z, rz


@jit
def _stick_solve(spec, pre, N, dq, f, D, tol, maxit, counters):
    """Projected PCG for ``dq`` on the stick set (mask ``f``): ``(K dq)_F = lam 1``, ``sum dq_F = D``.

    Returns ``(lam, u, cg)`` with ``u = K dq`` recomputed from the final ``dq``.
    """
    Mf = _product(f, pre, N, counters) * f
    c = Mf.sum()
    s = 0.0
    for i in range(dq.size):
        if f[i] > 0.0:
            s += dq[i]
    dq += (D - s) / c * Mf
    cg = 0
    stop = 2.0 * CG_TOL_FRACTION * tol
    u = _product(dq, spec, N, counters)
    for _ in range(CG_RESTARTS + 1):
        r = u * f
        if _range_on(r, f) <= stop:
            break
        z, rz = _project(pre, N, r, f, Mf, c, counters)
        p = -z
        while cg < maxit:
            if rz <= 0.0:
                break
            Ap = _product(p, spec, N, counters) * f
            pAp = p @ Ap
            if not pAp > 0.0:
                break
            alpha = rz / pAp
            dq += alpha * p
            r += alpha * Ap
            cg += 1
            if _range_on(r, f) <= stop:
                break
            z, rz_new = _project(pre, N, r, f, Mf, c, counters)
            p *= rz_new / rz
            p -= z
            rz = rz_new
        u = _product(dq, spec, N, counters)
    return 0.5 * (_max_on(u, f) + _min_on(u, f)), u, cg


@jit
def _max_on(u, f):
    best = -np.inf
    for i in range(u.size):
        if f[i] > 0.0:
            best = max(best, u[i])
    return best


@jit
def _min_on(u, f):
    best = np.inf
    for i in range(u.size):
        if f[i] > 0.0:
            best = min(best, u[i])
    return best


@jit
def _residuals(q, g, slip, kind, total, target, dx, res):
    """The named residuals (stick slip, bound, slip direction, out of contact, load balance) into ``res``."""
    out, bound, stick, direction = 0.0, 0.0, 0.0, 0.0
    for i in range(q.size):
        if g[i] > 0.0:
            bound = max(bound, abs(q[i]) - g[i])
        else:
            out = max(out, abs(q[i]))
        if kind[i] == FREE:
            stick = max(stick, abs(slip[i]))
        elif kind[i] == UPPER or kind[i] == LOWER:
            sg = 1.0 if q[i] > 0.0 else (-1.0 if q[i] < 0.0 else 0.0)
            direction = max(direction, -slip[i] * sg)
    res[0] = stick
    res[1] = max(bound, 0.0)
    res[2] = direction
    res[3] = out
    res[4] = abs(total - target) * dx


@jit
def solve_step(spec, pre, N, g, q_prev, target, dx, kind, tol, maxiter, maxcg, guess, q, dq, slip, codes, res,
               counters):
    """One increment from ``q_prev`` (see :mod:`core.solvers.matrix_free`); writes ``q``, ``dq``, ``slip``, ``codes``,
    ``res`` and ``counters``; updates ``kind``. Returns ``(lam, ok)``."""
    n = g.size
    counters[:] = 0
    # ---- the zero increment, if feasible, is the unique solution
    if zero_increment(g, q_prev, target, dx, tol, kind, q, dq, slip, codes, res):
        return 0.0, True
    total_prev = q_prev.sum()
    # ---- the window: elements in contact now or loaded before
    lo, hi = n, 0
    for i in range(n):
        if kind[i] != OUT or q_prev[i] != 0.0:
            lo = min(lo, i)
            hi = i + 1
    m = hi - lo
    gw = g[lo:hi]
    qp = q_prev[lo:hi]
    kw = kind[lo:hi]
    d = guess[lo:hi].copy()
    s = np.zeros(m)
    f = np.zeros(m)
    qw = qp.copy()
    outside = total_prev - qp.sum()
    lam = 0.0
    it = 0
    cg = 0
    ok = False
    evaluated = False
    tightened = False
    cg_tol = tol
    while it < maxiter:
        it += 1
        # ---- prescribed increments off the stick set
        nfree = 0
        fixed_sum = 0.0
        for i in range(m):
            if kw[i] == OUT:
                d[i] = -qp[i]
            elif kw[i] == UPPER:
                d[i] = gw[i] - qp[i]
            elif kw[i] == LOWER:
                d[i] = -gw[i] - qp[i]
            if kw[i] == FREE:
                f[i] = 1.0
                nfree += 1
            else:
                f[i] = 0.0
                fixed_sum += d[i]
        if nfree == 0:
            best, gbest = -1, -np.inf
            for i in range(m):
                if kw[i] != OUT and gw[i] > gbest:
                    best, gbest = i, gw[i]
            kw[best] = FREE
            continue
        D = target - total_prev - fixed_sum
        lam, u, c = _stick_solve(spec, pre, N, d, f, D, cg_tol, maxcg, counters)
        cg += c
        for i in range(m):
            qw[i] = qp[i] + d[i]
            s[i] = 0.0 if (kw[i] == FREE or kw[i] == OUT) else lam - u[i]
        # ---- violators: bounds on the stick set, slip direction on the fixed set
        n_bad = 0
        worst_free, i_free = -np.inf, np.int64(-1)  # not literals: see Literals in core/solvers/_pdas.py
        worst_fix, i_fix = -np.inf, np.int64(-1)
        for i in range(m):
            if kw[i] == FREE:
                excess = abs(qw[i]) - gw[i]
                if excess > tol:
                    n_bad += 1
                    if excess > worst_free:
                        worst_free, i_free = excess, i
            elif (kw[i] == UPPER and s[i] < -tol) or (kw[i] == LOWER and s[i] > tol):
                n_bad += 1
                if abs(s[i]) > worst_fix:
                    worst_fix, i_fix = abs(s[i]), i
        if n_bad > 0:
            move_violators(kw, qw, gw, s, tol, it, i_free, i_fix)
            continue
        stick = np.empty(m)
        for i in range(m):
            stick[i] = (lam - u[i] if kw[i] == FREE else 0.0) + s[i]
        _residuals(qw, gw, stick, kw, qw.sum() + outside, target, dx, res)
        evaluated = True
        if res.max() <= tol:
            ok = True
            break
        if tightened:  # the sets are settled but CG cannot reach the tolerance
            break
        cg_tol = 0.1 * tol
        tightened = True
    counters[ITERATIONS] = it
    counters[CG] = cg
    if not evaluated:
        res[:] = np.inf
    for i in range(n):
        q[i] = q_prev[i]
        dq[i] = 0.0
        slip[i] = 0.0
    if evaluated:
        q[lo:hi] = qw
        dq[lo:hi] = d
        slip[lo:hi] = s
    state_codes(kind, slip, tol, codes)
    return lam, ok


@jit
def march(spec, pre, N, bounds, Q, period, load_scale, dx, tol, maxiter, maxcg, warm, detect_periodic, k0, k1,
          kind, q_prev, dq_prev, q_block_end, total, res, counters, q, dq, slip, codes,
          traction, state, disp, diss, iters, cgs, resid, worst):
    """March through steps ``k0:k1`` (``bounds[k - k0]`` the bound of step ``k``); as :func:`core.solvers._pdas.march`.

    Returns ``(steps done, periodic_from, failed step)``.
    """
    steps = Q.size
    for k in range(k0, k1):
        lam, ok = solve_step(spec, pre, N, bounds[k - k0], q_prev, Q[k] * load_scale, dx, kind, tol, maxiter,
                             maxcg, dq_prev, q, dq, slip, codes, res, counters)
        if not ok:
            return k, -1, k
        total[0] += lam
        record_step(k, q, codes, slip, res, total[0], dx, q_prev, traction, state, disp, diss, resid, worst)
        if warm and counters[ITERATIONS] > 0:
            dq_prev[:] = dq
        iters[k] = counters[ITERATIONS]
        cgs[k] = counters[CG]
        if k + 1 < steps and period[k + 1] != period[k]:
            # end of a block: a period that ends where the previous one ended repeats for ever
            if block_repeats(q, q_block_end, tol) and detect_periodic and period[k] >= 0:
                return k + 1, period[k], -1
    return k1, -1, -1
