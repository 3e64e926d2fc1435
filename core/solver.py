"""The cycle solver: the incremental tangential contact problem, step by step.

At each step ``n`` of a :class:`~core.schedule.Schedule` the pressure is the
Hertz pressure at the current centre (uncoupled, Dundurs beta = 0) and the
unknowns are the element tractions ``q_n`` and the rigid-body displacement
increment ``lam`` of the cylinder. With ``K`` the influence matrix
(:mod:`core.kernels`) and ``dq = q_n - q_{n-1}``, the slip increment of an
element in contact is ``s = lam - K dq`` and Coulomb's law reads

* ``|q_i| <= mu p_i`` (``g_i`` below), ``q_i = 0`` out of contact;
* stick (``s_i = 0``) where ``|q_i| < g_i``;
* where ``s_i != 0``, ``q_i = g_i sign(s_i)``: friction opposes slip, so the
  dissipation ``sum q_i s_i dx`` is never negative;
* ``sum q_i dx = Q`` (load balance).

These are the KKT conditions of the strictly convex quadratic programme
``min 1/2 dq^T K dq`` over the box and the load equality, ``lam`` its
multiplier. :func:`solve_increment` solves it exactly by a primal-dual active
set iteration warm-started from the previous step, keeping the inverse of
``K`` on the stick set up to date by rank-one updates; it stops on the KKT
residual, not on an iteration count, and reports failure. Most steps of a
shaken-down period are settled by the zero increment, which is checked first
(it is the unique solution whenever it is feasible).

Normalised units: lengths in ``a``, tractions in ``mu p0``, loads in ``mu P``,
displacements in ``mu P / E*`` (see :mod:`core.kernels`).

References
----------
.. [1] J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*,
   Kluwer 1990 (the incremental tangential problem; program CONTACT).
.. [2] M. Hintermueller, K. Ito, K. Kunisch, "The primal-dual active set
   strategy as a semismooth Newton method", SIAM J. Optim. 13 (2003) 865-888.
.. [3] R. Wetter, Physical Mesomechanics 18 (2015).
"""

from __future__ import annotations

import math
import time

import numba as nb
import numpy as np

from ._validate import check_int, check_scalar
from .analytical import hertz_pressure_element_mean
from .kernels import KERNELS, influence_matrix, strip_b_coefficient, strip_u0
from .result import CycleResult, SolveCancelled, SolverError, below_bound, central_halfwidth
from .schedule import Schedule, rocking_schedule

__all__ = ["simulate_cycles", "simulate_contact", "strip_options", "solve_schedule", "solve_static", "shakedown_state",
           "make_grid", "DEFAULT_DX", "MAX_ELEMENTS", "MAX_STORED_VALUES", "KKT_TOL"]

#: Default element width [a]: 80 elements across the contact. The increment per
#: period is then within about 1 % of the converged value (tests/test_solver.py).
DEFAULT_DX = 1.0 / 40.0
#: Largest grid the solver accepts (the dense kernel needs 8 n^2 bytes).
MAX_ELEMENTS = 4000
#: Largest steps x elements a run may store (traction float64 + state int8: ~9 bytes each).
MAX_STORED_VALUES = 2.5e8
#: Default tolerance of the KKT residual (tractions in mu p0, slips in mu P/E*).
KKT_TOL = 1e-10

# active-set kinds of an element (internal)
_OUT, _FREE, _UPPER, _LOWER = 0, 1, 2, 3
# iterations moving every violator at once before moving one at a time
_PDAS_FULL_STEPS = 8
# rank-one updates of the stick-set inverse before it is rebuilt from K
_REBUILD_EVERY = 20000


# --------------------------------------------------------------------------
# the inverse of K on the stick set, kept current by rank-one updates
# --------------------------------------------------------------------------
# The loops below run over slices with range() indices: numba then knows the
# indices are non-negative and LLVM vectorises them (4-5x faster than indexing
# with offsets, see benchmarks/solver.py).
@nb.njit(cache=True, fastmath=True, nogil=True)
def _dot(a, b):
    s = 0.0
    for t in range(a.size):
        s += a[t] * b[t]
    return s


@nb.njit(cache=True, fastmath=True, nogil=True)
def _axpy(alpha, x, y):
    """``y += alpha * x`` in place."""
    for t in range(y.size):
        y[t] += alpha * x[t]


@nb.njit(cache=True, fastmath=True, nogil=True)
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


@nb.njit(cache=True, fastmath=True, nogil=True)
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


@nb.njit(cache=True, fastmath=True, nogil=True)
def _inverse_rebuild(K, B, fidx, pos, kind):
    """Recompute ``B = K[F, F]^-1`` from scratch for the free set ``F``; return its size."""
    n = kind.size
    m = 0
    for i in range(n):
        if kind[i] == _FREE:
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
    return m


@nb.njit(cache=True, fastmath=True, nogil=True)
def _inverse_sync(K, B, fidx, pos, m, kind, work):
    """Bring the inverse to the current free set; return (size, updates done), size -1 on loss of definiteness."""
    n = kind.size
    updates = 0
    for i in range(n):
        if pos[i] >= 0 and kind[i] != _FREE:
            m = _inverse_remove(B, fidx, pos, m, i)
            updates += 1
    for i in range(n):
        if pos[i] < 0 and kind[i] == _FREE:
            m = _inverse_add(K, B, fidx, pos, m, i, work)
            updates += 1
            if m < 0:
                return -1, updates
    return m, updates


# --------------------------------------------------------------------------
# one step
# --------------------------------------------------------------------------
@nb.njit(cache=True, fastmath=True, nogil=True)
def _element_bounds(edges, xc, P, g):
    """Traction bound ``mu p`` per element [mu p0]: the exact element mean of the Hertz pressure at ``xc``."""
    a = math.sqrt(P)
    for i in range(g.size):
        t1 = min(max((edges[i] - xc) / a, -1.0), 1.0)
        t2 = min(max((edges[i + 1] - xc) / a, -1.0), 1.0)
        F1 = 0.5 * (t1 * math.sqrt(1.0 - t1 * t1) + math.asin(t1))
        F2 = 0.5 * (t2 * math.sqrt(1.0 - t2 * t2) + math.asin(t2))
        g[i] = max(a * a * (F2 - F1) / (edges[i + 1] - edges[i]), 0.0)


@nb.njit(cache=True, fastmath=True, nogil=True)
def _row_dot(K, i, v, lo, hi):
    """``K[i, lo:hi] @ v[lo:hi]`` (v is zero outside [lo, hi))."""
    return _dot(K[i, lo:hi], v[lo:hi])


@nb.njit(cache=True, fastmath=True, nogil=True)
def solve_increment(K, g, q_prev, target, dx, kind, B, fidx, pos, m0, tol, maxiter,
                    q, dq, slip, codes, work):
    """Solve one increment of the tangential contact problem (see the module docstring).

    Parameters
    ----------
    K : (n, n) float array
        Influence matrix [mu P/E* per mu p0].
    g : (n,) float array
        Traction bounds ``mu p`` of this step [mu p0]; 0 out of contact.
    q_prev : (n,) float array
        Tractions after the previous step.
    target : float
        Required ``sum q_i`` (the load ``Q`` over ``dx``, in mu p0).
    dx : float
        Element width [a].
    kind, B, fidx, pos, m0 :
        Warm-start state: the active-set guess per element and the inverse of
        ``K`` on the free (stick) set, updated in place.
    tol : float
        KKT tolerance.
    maxiter : int
        Largest number of active-set iterations.
    q, dq, slip, codes, work :
        Outputs (tractions, increments, slip increments, element states) and
        scratch (``work`` of 4 n floats).

    Returns
    -------
    lam : float
        Rigid-body displacement increment [mu P/E*].
    iterations : int
        Active-set iterations (0 when the zero increment solved the step).
    residual : float
        Worst KKT residual.
    m : int
        Size of the free set held in ``B`` (``-1``: the step failed).
    updates : int
        Rank-one updates applied to ``B``.
    """
    n = g.size
    # ---- contact: released elements carry nothing, new ones start sticking
    for i in range(n):
        if g[i] <= 0.0:
            kind[i] = _OUT
        elif kind[i] == _OUT:
            kind[i] = _FREE
    # ---- the zero increment, if feasible, is the unique solution
    total = 0.0
    feasible = True
    for i in range(n):
        total += q_prev[i]
        if kind[i] == _OUT:
            if q_prev[i] != 0.0:
                feasible = False
        elif abs(q_prev[i]) > g[i] + tol:
            feasible = False
    if feasible and abs(total - target) * dx <= tol:
        for i in range(n):
            q[i] = q_prev[i]
            dq[i] = 0.0
            slip[i] = 0.0
            if kind[i] == _OUT:
                codes[i] = 0
            else:
                codes[i] = 1
                if kind[i] != _FREE and abs(q_prev[i]) < g[i] - tol:
                    kind[i] = _FREE
        return 0.0, 0, abs(total - target) * dx, m0, 0

    m = m0
    updates = 0
    rebuilt = False
    lam = 0.0
    residual = np.inf
    it = 0
    while it < maxiter:
        it += 1
        # ---- prescribed increments of the elements at a bound or released
        sum_prev = 0.0
        sum_fixed = 0.0
        lo, hi = n, 0  # dq is zero outside [lo, hi)
        for i in range(n):
            sum_prev += q_prev[i]
            if kind[i] == _OUT:
                d = -q_prev[i]
            elif kind[i] == _UPPER:
                d = g[i] - q_prev[i]
            elif kind[i] == _LOWER:
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
            if kind[i] == _FREE:
                nfree += 1
        if nfree == 0:
            best, gbest = -1, -1.0
            for i in range(n):
                if kind[i] != _OUT and g[i] > gbest:
                    best, gbest = i, g[i]
            if best < 0:
                return 0.0, it, np.inf, -1, updates
            kind[best] = _FREE
            continue
        # ---- stick-set inverse for this free set
        m, u = _inverse_sync(K, B, fidx, pos, m, kind, work)
        updates += u
        if m < 0:
            m = _inverse_rebuild(K, B, fidx, pos, kind)
            rebuilt = True
        # ---- stick: K[F,F] dq_F = lam - K[F,fixed] dq_fixed, sum dq_F = D
        D = target - sum_prev - sum_fixed
        sb1 = 0.0
        sby = 0.0
        for r in range(m):
            work[n + r] = _row_dot(K, fidx[r], dq, lo, hi)  # y_F
        y = work[n:n + m]
        for r in range(m):
            row = B[r, :m]
            b1 = 0.0
            for c in range(m):
                b1 += row[c]
            by = _dot(row, y)
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
            if kind[i] == _FREE:
                slip[i] = 0.0
                excess = abs(q[i]) - g[i]
                if excess > tol:
                    n_viol += 1
                    if excess > worst_free:
                        worst_free, i_free = excess, i
            elif kind[i] == _UPPER or kind[i] == _LOWER:
                s = lam - _row_dot(K, i, dq, lo, hi)
                slip[i] = s
                wrong = -s if kind[i] == _UPPER else s
                if wrong > tol:
                    n_viol += 1
                    if wrong > worst_fix:
                        worst_fix, i_fix = wrong, i
            else:
                slip[i] = 0.0
        if n_viol > 0:
            if it <= _PDAS_FULL_STEPS:
                # primal-dual active set: move every violator
                for i in range(n):
                    if kind[i] == _FREE:
                        if abs(q[i]) - g[i] > tol:
                            kind[i] = _UPPER if q[i] > 0 else _LOWER
                    elif kind[i] == _UPPER:
                        if slip[i] < -tol:
                            kind[i] = _FREE
                    elif kind[i] == _LOWER:
                        if slip[i] > tol:
                            kind[i] = _FREE
            elif i_free >= 0:
                kind[i_free] = _UPPER if q[i_free] > 0 else _LOWER
            else:
                kind[i_fix] = _FREE
            continue
        # ---- converged sets: KKT residual with the true K (not the updated inverse)
        residual = abs(sum_prev + D + sum_fixed - target) * dx
        for i in range(n):
            if kind[i] == _FREE:
                r = abs(lam - _row_dot(K, i, dq, lo, hi))
                if r > residual:
                    residual = r
            elif kind[i] == _OUT:
                if q[i] != 0.0:
                    residual = max(residual, abs(q[i]))
            else:
                residual = max(residual, abs(q[i]) - g[i])
        s_total = 0.0
        for i in range(n):
            s_total += q[i]
        residual = max(residual, abs(s_total - target) * dx)
        if residual <= tol:
            break
        if rebuilt:
            return lam, it, residual, -1, updates
        m = _inverse_rebuild(K, B, fidx, pos, kind)
        rebuilt = True
    else:
        return lam, it, residual, -1, updates
    # ---- element states: at a bound with no slip counts as stick
    for i in range(n):
        if kind[i] == _OUT:
            codes[i] = 0
        elif kind[i] == _UPPER and slip[i] > tol:
            codes[i] = 2
        elif kind[i] == _LOWER and slip[i] < -tol:
            codes[i] = 3
        else:
            codes[i] = 1
    return lam, it, residual, m, updates


# --------------------------------------------------------------------------
# a whole schedule
# --------------------------------------------------------------------------
@nb.njit(cache=True, fastmath=True, nogil=True)
def _run_steps(K, edges, xc, P, Q, period, dx, tol, maxiter, detect_periodic, k0, k1,
               q_prev, kind, B, fidx, pos, work, q_block_end, counters, total_arr,
               traction, state, disp, diss, iters, resid):
    """March through steps ``k0:k1`` of the schedule, carrying the solver state in the arrays passed.

    Returns (steps done, periodic_from, failed step, its residual): ``steps done < k1`` with
    ``periodic_from >= 0`` means the period ``periodic_from`` repeats for ever.
    """
    n = K.shape[0]
    steps = xc.size
    q = np.zeros(n)
    dq = np.zeros(n)
    slip = np.zeros(n)
    g = np.zeros(n)
    codes = np.zeros(n, dtype=np.int8)
    m = counters[0]
    updates = counters[1]
    total = total_arr[0]
    load_scale = 0.5 * np.pi / dx
    for k in range(k0, k1):
        _element_bounds(edges, xc[k], P[k], g)
        if updates > _REBUILD_EVERY:
            m = _inverse_rebuild(K, B, fidx, pos, kind)
            updates = 0
        lam, it, res, m, u = solve_increment(K, g, q_prev, Q[k] * load_scale, dx, kind, B, fidx, pos, m,
                                             tol, maxiter, q, dq, slip, codes, work)
        updates += u
        if m < 0:
            return k, -1, k, res
        total += lam
        d = 0.0
        for i in range(n):
            traction[k, i] = q[i]
            state[k, i] = codes[i]
            d += q[i] * slip[i]
            q_prev[i] = q[i]
        disp[k] = total
        diss[k] = d * dx
        iters[k] = it
        resid[k] = res
        counters[0] = m
        counters[1] = updates
        total_arr[0] = total
        if k + 1 < steps and period[k + 1] != period[k]:
            # end of a block: a period that ends where the previous one ended repeats for ever
            if detect_periodic and period[k] >= 0:
                same = True
                for i in range(n):
                    if abs(q[i] - q_block_end[i]) > tol:
                        same = False
                        break
                if same:
                    return k + 1, period[k], -1, 0.0
            for i in range(n):
                q_block_end[i] = q[i]
    return k1, -1, -1, 0.0


def make_grid(reach, dx):
    """Uniform world-fixed element edges, symmetric about 0, covering ``[-reach, reach]``.

    Parameters
    ----------
    reach : float
        Largest distance from 0 that the contact reaches [a].
    dx : float
        Element width [a].

    Returns
    -------
    ndarray, shape (n + 1,)
        Element edges; ``n`` is even and the grid has one spare element each side.
    """
    half = math.ceil(reach / dx - 1e-9) + 1
    n = 2 * half
    if n > MAX_ELEMENTS:
        raise ValueError(f"dx = {dx:g} needs {n} elements (> {MAX_ELEMENTS}): use a larger dx")
    return dx * (np.arange(n + 1) - half)


def _kernel_options(kernel, L_over_a, nu):
    if kernel not in KERNELS:
        raise ValueError(f"kernel must be one of {sorted(KERNELS)}, got {kernel!r:.60}")
    if kernel == "plane":
        return {}
    if L_over_a is None:
        raise ValueError("L_over_a is required with kernel='strip'")
    L_over_a = check_scalar("L_over_a", L_over_a, 2.0, 1e9)
    return {"L_over_a": L_over_a, "b_coefficient": strip_b_coefficient(nu) if np.ndim(nu) == 0 else nu}


def solve_schedule(schedule, dx=DEFAULT_DX, kernel="plane", *, kernel_options=None, tol=KKT_TOL,
                   maxiter=None, detect_periodic=True, shakedown_rtol=1e-3, params=None,
                   time_budget=None, cancel=None, progress=None, chunk=256):
    """Run the incremental solver over any :class:`~core.schedule.Schedule`.

    Parameters
    ----------
    schedule : Schedule
        The steps (centre, normal and tangential load, period).
    dx : float
        Element width [a], in [1e-4, 0.5].
    kernel : {"plane", "strip"}
        Influence kernel (:mod:`core.kernels`).
    kernel_options : dict, optional
        Passed to the kernel (``L_over_a``, ``b_coefficient`` for ``"strip"``).
    tol : float
        KKT tolerance, in [1e-14, 1e-4].
    maxiter : int, optional
        Active-set iterations allowed per step (default ``50 + 2 n``).
    detect_periodic : bool
        Stop recomputing once a period ends in the state the previous one
        ended in, and copy it for the remaining periods (the per-step problem
        has a unique solution, so the remaining periods repeat it to the
        solver tolerance; ``tests/test_solver.py`` checks this). Only used when
        every period of the schedule has the same steps.
    shakedown_rtol : float
        Relative size of the last increment per period, against the largest,
        below which the run counts as shaken down.
    params : dict, optional
        Recorded on the result.
    time_budget : float, optional
        Wall-time budget [s]; past it the solve stops with :class:`SolveCancelled`.
    cancel : callable, optional
        Called between chunks of steps; returning True stops the solve with
        :class:`SolveCancelled` (e.g. when a newer request superseded this one).
    progress : callable, optional
        Called with the fraction of steps done, between chunks and at the end.
    chunk : int
        Steps run between checks of the budget, ``cancel`` and ``progress``.

    Returns
    -------
    CycleResult

    Raises
    ------
    SolverError
        If a step cannot be solved to ``tol`` (names the step, ``xc`` and the residual).
    SolveCancelled
        If ``cancel`` asked for it or the time budget ran out.
    ValueError
        For invalid inputs, or a run whose stored fields would exceed
        :data:`MAX_STORED_VALUES` (steps x elements).
    """
    if not isinstance(schedule, Schedule):
        raise ValueError(f"schedule must be a core.Schedule, got {type(schedule).__name__}")
    dx = check_scalar("dx", dx, 1e-4, 0.5)
    tol = check_scalar("tol", tol, 1e-14, 1e-4)
    shakedown_rtol = check_scalar("shakedown_rtol", shakedown_rtol, 0.0, 1.0)
    kernel_options = dict(kernel_options or {})
    t0 = time.perf_counter()
    edges = make_grid(schedule.reach, dx)
    n = edges.size - 1
    maxiter = check_int("maxiter", 50 + 2 * n if maxiter is None else maxiter, 1, 10**7)
    chunk = check_int("chunk", chunk, 1, 10**7)
    if time_budget is not None:
        time_budget = check_scalar("time_budget", time_budget, 0.0, None, lo_closed=False)
    if len(schedule) * n > MAX_STORED_VALUES:
        raise ValueError(f"{len(schedule)} steps x {n} elements exceeds {MAX_STORED_VALUES:.0e} stored values "
                         "(about 2.4 GB): use fewer periods, a larger dx or a larger dW")
    K = influence_matrix(n, dx, kernel, **kernel_options)
    steps = len(schedule)
    traction = np.empty((steps, n))
    state = np.empty((steps, n), dtype=np.int8)
    disp = np.empty(steps)
    diss = np.empty(steps)
    iters = np.empty(steps, dtype=np.int64)
    resid = np.empty(steps)
    periodic = bool(detect_periodic) and schedule.is_periodic()
    # solver state carried between chunks of steps
    q_prev, q_block_end, work = np.zeros(n), np.zeros(n), np.zeros(4 * n)
    kind, B = np.zeros(n, np.int8), np.zeros((n, n))
    fidx, pos = np.zeros(n, np.int64), -np.ones(n, np.int64)
    counters, total = np.zeros(2, np.int64), np.zeros(1)
    done, periodic_from = 0, -1
    budget_end = None if time_budget is None else t0 + time_budget
    while done < steps:
        k1 = min(steps, done + chunk)
        reached, periodic_from, failed, res = _run_steps(
            K, edges, schedule.xc, schedule.P, schedule.Q, schedule.period, dx, tol, maxiter, periodic, done, k1,
            q_prev, kind, B, fidx, pos, work, q_block_end, counters, total,
            traction, state, disp, diss, iters, resid)
        if failed >= 0:
            raise SolverError(failed, schedule.xc[failed], res,
                              "the active set did not settle" if np.isfinite(res) else "no feasible active set")
        done = reached
        if periodic_from >= 0:
            break
        if done < steps:
            if cancel is not None and cancel():
                raise SolveCancelled(f"solve cancelled after {done} of {steps} steps")
            if budget_end is not None and time.perf_counter() > budget_end:
                raise SolveCancelled(f"solve stopped after {time_budget:g} s (its time budget) at step "
                                     f"{done} of {steps}: use fewer periods or a coarser grid")
            if progress is not None:
                progress(done / steps)
    if done < steps:
        _repeat_last_period(schedule.period, done, periodic_from, traction, state, disp, diss, iters, resid)
    u0 = strip_u0(kernel_options["L_over_a"], kernel_options["b_coefficient"]) if kernel == "strip" else None
    if progress is not None:
        progress(1.0)
    return CycleResult(
        edges=edges, xc=schedule.xc, P=schedule.P, Q=schedule.Q, period=schedule.period,
        traction=traction, state=state, displacement=disp, dissipation=diss, iterations=iters,
        kkt_residual=resid, kernel=kernel, u0=u0,
        periodic_from=None if periodic_from < 0 else int(periodic_from),
        params=dict(params or {}), tol=tol, shakedown_rtol=shakedown_rtol,
        runtime=time.perf_counter() - t0,
    )


def _repeat_last_period(period, done, p, traction, state, disp, diss, iters, resid):
    """Fill steps ``done:`` by repeating period ``p`` (its displacement advancing by its increment)."""
    block = np.flatnonzero(period == p)
    m = block.size
    start = block[0]
    before = disp[start - 1] if start > 0 else 0.0
    increment = disp[block[-1]] - before
    rest = np.arange(done, period.size)
    src = start + (rest - done) % m
    repeats = 1 + (rest - done) // m
    traction[rest] = traction[src]
    state[rest] = state[src]
    disp[rest] = disp[src] + repeats * increment
    diss[rest] = diss[src]
    iters[rest] = 0
    resid[rest] = resid[src]


def solve_static(bound, Q, dx, kernel="plane", *, kernel_options=None, tol=KKT_TOL):
    """Static partial slip under an arbitrary traction bound, loaded from zero in one step.

    Solves ``min 1/2 q^T K q`` subject to ``|q_i| <= bound_i`` and
    ``sum q_i dx = (pi/2) Q``: with ``bound = mu p`` it is Cattaneo-Mindlin;
    with ``bound = mu`` times the lowest pressure of a rocking period it is the
    shaken-down state (:func:`shakedown_state`).

    Parameters
    ----------
    bound : array_like, shape (n,)
        Traction bound per element [mu p0], >= 0.
    Q : float
        Tangential load [mu P]; ``|Q| < (2/pi) sum(bound) dx``.
    dx : float
        Element width [a].
    kernel, kernel_options :
        As in :func:`solve_schedule`.
    tol : float
        KKT tolerance.

    Returns
    -------
    q : ndarray, shape (n,)
        Tractions [mu p0].
    displacement : float
        Rigid-body displacement [mu P/E*].
    """
    from ._validate import check_range

    bound = check_range("bound", bound, 0.0, None)
    if bound.ndim != 1 or bound.size < 1 or bound.size > MAX_ELEMENTS:
        raise ValueError(f"bound must be a 1-D array of 1 to {MAX_ELEMENTS} elements")
    dx = check_scalar("dx", dx, 1e-4, 0.5)
    Q = check_scalar("Q", Q, -1.0, 1.0)
    tol = check_scalar("tol", tol, 1e-14, 1e-4)
    target = Q * 0.5 * np.pi / dx
    if abs(target) >= bound.sum():
        raise ValueError(f"Q = {Q:g} exceeds what the bound can carry ({2 / np.pi * bound.sum() * dx:g})")
    n = bound.size
    K = influence_matrix(n, dx, kernel, **dict(kernel_options or {}))
    q, dq, slip = np.zeros(n), np.zeros(n), np.zeros(n)
    codes, kind = np.zeros(n, np.int8), np.zeros(n, np.int8)
    B, fidx, pos = np.zeros((n, n)), np.zeros(n, np.int64), -np.ones(n, np.int64)
    lam, it, res, m, _ = solve_increment(K, np.ascontiguousarray(bound), np.zeros(n), target, dx, kind, B, fidx,
                                         pos, 0, tol, 50 + 2 * n, q, dq, slip, codes, np.zeros(4 * n))
    if m < 0:
        raise SolverError(0, 0.0, res, "static partial slip")
    return q, float(lam)


def shakedown_state(ft, w, dx=DEFAULT_DX, *, kernel="plane", L_over_a=None, nu=0.5, tol=KKT_TOL):
    """The shaken-down traction, computed directly as one static partial-slip problem.

    After shakedown nothing slips, and every element carries at most ``mu``
    times the lowest pressure it sees in a period. This computes the
    partial-slip solution with that bound, loaded once: the observation of
    ``shared/PHYSICS.md`` that it equals the end state of the transient is
    checked in ``tests/test_solver.py``
    (``test_direct_shakedown_state_matches_transient``). It takes one solve
    instead of a whole transient.

    Parameters
    ----------
    ft, w, dx, kernel, L_over_a, nu, tol :
        As in :func:`simulate_cycles` (the rocking steps do not matter here).

    Returns
    -------
    x : ndarray
        Element centres [a].
    q : ndarray
        Traction [mu p0].
    bound : ndarray
        ``mu p_min`` per element [mu p0].
    stick_halfwidth : float
        Half-width of the central zone with ``|q| < bound`` [a] (0 if none).
    """
    ft = check_scalar("ft", ft, -1.0, 1.0, lo_closed=False, hi_closed=False)
    w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
    dx = check_scalar("dx", dx, 1e-4, 0.5)
    edges = make_grid(1.0 + w, dx)
    # lowest element-mean pressure over the period: the mean of the concave Hertz profile
    # is quasi-concave in the centre position, so its minimum is at a turning point
    bound = np.minimum(hertz_pressure_element_mean(edges, -w), hertz_pressure_element_mean(edges, w))
    q, _ = solve_static(bound, ft, dx, kernel, kernel_options=_kernel_options(kernel, L_over_a, nu), tol=tol)
    x = 0.5 * (edges[1:] + edges[:-1])
    return x, q, bound, central_halfwidth(below_bound(q, bound), edges)


def simulate_cycles(ft, w, periods=10, dx=DEFAULT_DX, dW=None, *, kernel="plane", shape="triangle",
                    load_steps=1, L_over_a=None, nu=0.5, tol=KKT_TOL, detect_periodic=True,
                    shakedown_rtol=1e-3, time_budget=None, cancel=None, progress=None,
                    body="cylinder", ratio=None, angle=0.0):
    """Simulate the rocking contact in normalised units (``a = 1``): loading, then ``periods`` periods.

    Parameters
    ----------
    ft : float
        ``Ft / (mu Fn)`` in [0, 1) (negative: pulled the other way).
    w : float
        Rocking amplitude ``W / a`` in [0, 1).
    periods : int
        Number of rocking periods, in [1, 10000].
    dx : float
        Element width over ``a``, in [1e-4, 0.5]; default 1/40.
    dW : float, optional
        Rocking step over ``a``; defaults to ``dx`` (as in the paper).
    kernel : {"plane", "strip"}
        Plane strain (default) or the truncated-3D strip of length ``L``.
    shape : {"triangle", "sine"}
        Waveform of the rocking (see :func:`core.schedule.rocking_schedule`).
    load_steps : int
        Steps of the initial loading.
    L_over_a : float, optional
        Strip length over ``a`` (``kernel="strip"`` only), >= 2.
    nu : float
        Poisson ratio of the substrate under a rigid cylinder (``"strip"`` only), in [0, 0.5].
    tol : float
        KKT tolerance of every step.
    detect_periodic : bool
        Copy periods once the state repeats (see :func:`solve_schedule`).
    time_budget, cancel, progress :
        Stop after ``time_budget`` seconds, or when ``cancel()`` returns True
        (:class:`SolveCancelled`); report the fraction done to ``progress``
        (see :func:`solve_schedule`).
    shakedown_rtol : float
        Tolerance of the shakedown verdict: the run has shaken down when the
        last increment per period is at most this fraction of the largest
        (default 1e-3). Shakedown increments decay geometrically (by 3 to 10
        each period away from the limit), ratcheting ones settle to a constant.

    body : {"cylinder", "sphere", "ellipsoid"} or core.Ellipsoid
        ``"cylinder"`` (default) is the line contact; the point contacts run
        :func:`core.solver3d.simulate_point_contact` (with ``ratio = Ry/Rx`` of
        an ellipsoid and ``angle`` of Ft to the rocking direction [rad]; ``dx``
        is the element side, ``nu`` the substrate's; ``kernel``, ``L_over_a``
        and ``tol`` are the cylinder's) and return a
        :class:`core.solver3d.PointContactResult`.

    Returns
    -------
    CycleResult
        With ``increment_per_period`` [mu P/E*], ``stick_halfwidth`` [a],
        ``regime``, and every per-step field.

    Examples
    --------
    >>> import core
    >>> r = core.simulate_cycles(0.2, 0.3, periods=4)
    >>> r.regime
    'shakedown'
    >>> abs(r.stick_halfwidth - float(core.shakedown_stick_halfwidth(0.2, 0.3))) < 0.05
    True
    """
    if not (isinstance(body, str) and body == "cylinder"):  # point contacts: core/solver3d.py
        from .solver3d import simulate_point_contact
        return simulate_point_contact(ft, w, periods, dx, dW, body=body, ratio=ratio, angle=angle, nu=nu, shape=shape,
                                      load_steps=load_steps, detect_periodic=detect_periodic,
                                      shakedown_rtol=shakedown_rtol, time_budget=time_budget, cancel=cancel,
                                      progress=progress)
    dx = check_scalar("dx", dx, 1e-4, 0.5)
    dW = dx if dW is None else check_scalar("dW", dW, 1e-4, 1.0)
    options = _kernel_options(kernel, L_over_a, nu)
    schedule = rocking_schedule(ft, w, periods=periods, dW=dW, shape=shape, load_steps=load_steps)
    params = dict(ft=float(ft), w=float(w), periods=int(periods), dx=dx, dW=dW, kernel=kernel, shape=shape,
                  load_steps=int(load_steps))
    if kernel == "strip":
        params.update(L_over_a=options["L_over_a"], nu=float(nu))
    return solve_schedule(schedule, dx, kernel, kernel_options=options, tol=tol,
                          detect_periodic=detect_periodic, shakedown_rtol=shakedown_rtol, params=params,
                          time_budget=time_budget, cancel=cancel, progress=progress)


def strip_options(contact):
    """The strip-kernel options of :func:`simulate_cycles` for a physical contact.

    Parameters
    ----------
    contact : Contact
        The contact (SI units).

    Returns
    -------
    dict
        ``L_over_a`` (strip length over half-width) and ``nu``, the Poisson
        ratio of a substrate under a rigid cylinder with the same strip kernel:
        ``2 nu / (1 - nu) = E* sum(nu_i / G_i)`` (exact for a rigid cylinder or
        two equal bodies, an equivalent value otherwise).

    Examples
    --------
    >>> import core
    >>> opts = core.strip_options(core.PAPER_SIMULATION)
    >>> round(opts["L_over_a"], 1), opts["nu"]
    (292.6, 0.5)
    """
    from .contact import Contact

    if not isinstance(contact, Contact):
        raise ValueError(f"contact must be a core.Contact, got {type(contact).__name__}")
    b = contact.E_star * contact.nu / contact.G
    return {"L_over_a": contact.L / contact.a, "nu": b / (2.0 + b)}  # 2 nu/(1 - nu) = b <=> nu = b/(2 + b)


def simulate_contact(contact, periods=10, dx=DEFAULT_DX, dW=None, *, kernel="strip", **options):
    """Simulate a :class:`~core.contact.Contact` given in physical units.

    Runs :func:`simulate_cycles` with the contact's ``ft``, ``w`` and, for the
    strip kernel, its ``L / a`` and materials. The result stays normalised;
    convert with ``contact.a`` [m], ``contact.traction_unit`` (``mu p0``, Pa)
    and ``contact.displacement_unit`` (``mu P/E*``, m).

    Parameters
    ----------
    contact : Contact
        The contact (``ft`` and ``w`` included).
    periods, dx, dW : see :func:`simulate_cycles`.
    kernel : {"strip", "plane"}
        Default ``"strip"``: the truncated-3D model with the contact's length.
    **options
        Further options of :func:`simulate_cycles`.
    """
    from .contact import Contact

    if not isinstance(contact, Contact):
        raise ValueError(f"contact must be a core.Contact, got {type(contact).__name__}")
    dx = check_scalar("dx", dx, 1e-4, 0.5)
    if kernel == "strip":
        for key, value in strip_options(contact).items():
            options.setdefault(key, value)
    result = simulate_cycles(contact.ft, contact.w, periods, dx, dW, kernel=kernel, **options)
    result.params.update({f"contact_{k}": v for k, v in contact.summary().items()})
    return result
