"""Compiled kernels of the coupled per-step solver (:mod:`core.solvers.coupled`): its march over the steps in numba.

A step is first solved at once (:func:`joint`). With the contact interval and the
tangential sets fixed (which elements stick, which are at the bound ``q = +-p``),
the coupled step is a linear system in ``(p, q, delta, lam)``: the fixed point the
alternation's passes only approach (by a factor 0.01-0.06 a pass at ``|beta|``
0.1-0.25). ``K`` and the cross operator ``S`` are Toeplitz, so the system of a
window of ``Lw`` elements in full stick is the same wherever the window lies:
its inverse ``W`` (:func:`window_inverse`) is made once for a contact, and a step
is ``W b`` corrected for the few rows of the elements that do not stick (off the
contact, at the bound) by a small capacitance system (Sherman-Morrison-Woodbury,
:func:`direct`). From the last step's solution, ``b`` is the last pressure's gap
under this step's profile: affine on the last contact for a parabolic body that
moved, so that ``W b`` is two prefix sums of ``W``'s columns (:func:`direct_rhs_step`).
:func:`check` then tests the solution as the full solves do (the
pressure not negative, no penetration, the sticking tractions within their
bound, the bound ones slipping their way, the named residuals with the true
``K``), and where a set is wrong moves it and solves again: a primal-dual active
set on both problems at once. The first guess is the last step's sets moved with
the contact; on the rocking cylinder at ``a/40`` most steps are one solve and one
check (``benchmarks/coupled.py``). Off the contact the gap is made exactly only
where Jensen's lower bound of ``K p`` does not already leave it open
(:func:`off_contact`).

Where that does not end the step, the alternation of
:class:`core.solvers.coupled.CoupledSolver` (the normal problem with
the tractions fixed, then the tangential one with that pressure, until
neither changes) goes on, for a contact that is one
interval of elements, which is the rocking cylinder's. The normal problem
on an interval of ``L`` elements needs the inverse of ``K`` on it; ``K`` is
symmetric Toeplitz, so that block is the same wherever the interval lies:
its explicit inverse ``A_L`` (Trench's algorithm, ``O(L^2)``) is kept for a
few widths at a time (:class:`Inverses`), and each pass applies it twice
(the normal solve and the pressure's tangential shift), a product of
contiguous rows. The tangential solve is :func:`core.solvers._pdas.solve_step`,
the uncoupled solver's own, with its checks and named residuals; after a full
pass the step is solved directly again with the sets it found; failing that, the
passes keep the set and make only the stick solve
(:func:`core.solvers._pdas.fixed_set_stick`, about a fifth of a full solve), until the change,
or the next one predicted from the ratio of the last two, is within the
tolerance (the set is kept after a full pass whose normal solve left the
interval where it was); a full pass then checks it and gives the residuals, and
ends the step if its own change is within the tolerance too (else the
alternation goes on).
A step the kernels cannot take (the contact not one
interval, or its ends not settling) is reported to the caller, which then
solves it with the general Python path (:func:`core.pressure.normal.solve_line`).
:func:`march` runs the steps of a chunk (the direct solves, the alternation, the named
residuals, the record of each step and the periodic test) without returning
to Python, as :func:`core.solvers._pdas.march` does for the uncoupled solver: per-step
Python was half a coupled run's time (``benchmarks/results/coupled_timing_s4.txt``).
The factor ``C`` and the window's inverse are computed here too (:func:`cholesky`, :func:`_invert`), not by
LAPACK, whose threads cost more than they gain on these small matrices when the cores are shared.
"""

from __future__ import annotations

import numpy as np

from ..base._jit import jit
from ..elastic.coupling import cross_matrix
from collections import namedtuple

from ._pdas import (_axpy, _dot as _pdas_dot, FREE, ITERATIONS, LOWER, MODE, OUT, TOEPLITZ, UPPER, _toeplitz_inverse,
                    block_repeats, fixed_set_stick, solve_step, state_codes)

__all__ = ["alternate", "interval_normal", "cross", "gap_residual", "march", "cholesky", "new_inverses",
           "Inverses", "window_inverse", "direct", "direct_rhs", "direct_sets", "check", "joint", "STATUS_DONE",
           "STATUS_TANGENTIAL", "STATUS_GENERAL", "STATUS_WINDOW"]

#: :func:`alternate`'s status: solved (or the alternation did not settle: see its change), the tangential solve
#: failed, the normal problem needs the general solve; :func:`march`'s: a step was solved without the direct solve,
#: whose window (:func:`window_inverse`) is narrower than the contact (the caller widens it and goes on).
STATUS_DONE, STATUS_TANGENTIAL, STATUS_GENERAL, STATUS_WINDOW = 0, 1, 2, 3
#: Direct solves of a :func:`joint` call (:func:`direct`) at most; then the passes.
DIRECT_TRIES = 4
#: :func:`joint` calls after a full pass of the alternation (with the sets it found) at most in a step.
JOINT_AFTER_PASS = 2
#: Rows of the window's system a direct solve replaces at most (the capacitance solve costs ``m^3 / 3``); beyond,
#: the settled passes.
DIRECT_ROWS = 48
#: Elements a new window (:func:`window_inverse`) has beyond the contact that asked for it.
WINDOW_MARGIN = 4
#: The alternation's settled passes stop when the next change, predicted from their ratio, is within this part
#: of the tolerance (:func:`alternate`).
PREDICTED = 0.3
#: The alternation's change before a pass has measured one (finite: the kernels are compiled with fastmath, which
#: assumes no infinities).
UNMEASURED = 1e300
#: Rows of the scratch ``work`` the kernels need (``n`` entries each).
WORK_ROWS = 14
#: A normal row's right-hand side that differs from the affine part of the others by no more than this times its
#: terms' size (at least 1) counts as on it (:func:`direct_rhs_step`): the part left out is a gap residual of that
#: size on the contact, a hundredth of the tolerance (1e-10); the last solution's own gap residuals are 1e-14 to 1e-13.
AFFINE_SLACK = 1e-12

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


def window_inverse(K, dx, cn, ct, Lw):
    """The inverse ``W`` of the coupled system of a window of ``Lw`` elements in full stick (:func:`direct`), as its
    transpose ``W^T`` (C-contiguous: :func:`direct` reads the columns of ``W``), followed by the prefix sums of
    ``W``'s normal columns, plain and weighted by their index (:func:`_prefix_sums`): an array ``(N + 2 (Lw + 1), N)``,
    ``N = 2 Lw + 2``, whose first ``N`` rows are ``W^T``.

    Unknowns ``x = (p, q, delta, lam)`` (``2 Lw + 2``), rows: the normal ``K p + cn S q - delta = -h``, the
    tangential ``K q - ct S p - lam = K q_prev - ct S p_prev`` (the stick condition: no slip increment), the load
    ``sum p`` and the target ``sum q``. ``K`` is symmetric Toeplitz and ``S`` (:func:`cross`) Toeplitz, so the
    system is the same wherever the window lies on the grid: one inverse serves every step whose contact fits it.
    """
    Lw = int(Lw)
    N = 2 * Lw + 2
    S = cross_matrix(Lw, dx)
    KL = np.asarray(K, dtype=float)[:Lw, :Lw]
    M = np.zeros((N, N))
    M[:Lw, :Lw], M[:Lw, Lw:2 * Lw], M[:Lw, 2 * Lw] = KL, cn * S, -1.0
    M[Lw:2 * Lw, :Lw], M[Lw:2 * Lw, Lw:2 * Lw], M[Lw:2 * Lw, 2 * Lw + 1] = -ct * S, KL, -1.0
    M[2 * Lw, :Lw] = 1.0
    M[2 * Lw + 1, Lw:2 * Lw] = 1.0
    if not _invert(M):
        raise ValueError("the coupled system of a window in full stick is singular: no direct solve on it")
    out = np.zeros((N + 2 * (Lw + 1), N))
    out[:N] = M.T
    out[N + 1:N + Lw + 1] = np.cumsum(out[:Lw], axis=0)  # _prefix_sums: ones
    out[N + Lw + 2:] = np.cumsum(np.arange(Lw, dtype=float)[:, None] * out[:Lw], axis=0)  # ramp
    return out


@jit
def _prefix_sums(WT):
    """The prefix sums of the normal columns of ``W`` kept after ``W^T`` (:func:`window_inverse`): ``ones[a]`` is the
    sum of the columns ``0 .. a-1`` and ``ramp[a]`` that of ``c W[:, c]``, so that ``W`` times a right-hand side
    ``alpha + slope (c - c0)`` on the normal rows ``c0 <= c < c1`` costs ``O(N)`` (:func:`direct_rhs_step`)."""
    N = WT.shape[1]
    Lw = (N - 2) // 2
    return WT[N:N + Lw + 1], WT[N + Lw + 1:N + 2 * Lw + 2]


@jit
def _invert(A):
    """Invert ``A`` in place by Gauss-Jordan elimination with partial pivoting, in this thread (LAPACK's threads
    took 60-90 ms for ``N = 174`` on two shared cores, against about 2 ms here); False if a pivot vanishes."""
    n = A.shape[0]
    piv = np.arange(n)
    for c in range(n):
        p = c
        for i in range(c + 1, n):
            if abs(A[i, c]) > abs(A[p, c]):
                p = i
        if A[p, c] == 0.0:
            return False
        if p != c:
            for j in range(n):
                A[c, j], A[p, j] = A[p, j], A[c, j]
        piv[c] = p
        d = 1.0 / A[c, c]
        A[c, c] = 1.0
        rc = A[c]
        for j in range(n):
            rc[j] *= d
        for i in range(n):
            if i != c:
                f = A[i, c]
                if f != 0.0:
                    A[i, c] = 0.0
                    ri = A[i]
                    for j in range(n):
                        ri[j] -= f * rc[j]
    for c in range(n - 1, -1, -1):
        p = piv[c]
        if p != c:
            for i in range(n):
                A[i, c], A[i, p] = A[i, p], A[i, c]
    return True


@jit
def _lu_solve(C, b, m):
    """Solve ``C[:m, :m] z = b[:m]`` in place (``b`` becomes ``z``) by Gaussian elimination with partial
    pivoting; False if a pivot vanishes."""
    scale = 0.0
    for i in range(m):
        for j in range(m):
            scale = max(scale, abs(C[i, j]))
    if scale == 0.0:
        return False
    for c in range(m):
        piv = c
        for i in range(c + 1, m):
            if abs(C[i, c]) > abs(C[piv, c]):
                piv = i
        if abs(C[piv, c]) <= 1e-13 * scale:
            return False
        if piv != c:
            for j in range(m):
                C[c, j], C[piv, j] = C[piv, j], C[c, j]
            b[c], b[piv] = b[piv], b[c]
        d = C[c, c]
        for i in range(c + 1, m):
            f = C[i, c] / d
            if f != 0.0:
                for j in range(c + 1, m):
                    C[i, j] -= f * C[c, j]
                b[i] -= f * b[c]
    for c in range(m - 1, -1, -1):
        t = b[c]
        for j in range(c + 1, m):
            t -= C[c, j] * b[j]
        b[c] = t / C[c, c]
    return True


@jit
def direct(WT, K, gap0, load, dx, ct, target, q_old, p_old, i0, i1, kind, q_out, p_out, scratch):
    """The coupled step with its sets fixed, solved at once: the fixed point of the alternation's passes.

    The contact is ``[i0, i1)``; on it the tangential set ``kind`` (:mod:`core.solvers._pdas`: FREE sticks, UPPER
    and LOWER are at the bound ``q = +-p``); ``q_old``, ``p_old`` are the previous step's tractions and pressure.
    The system is :func:`window_inverse`'s (``WT``: the transpose of its inverse ``W``, from that function) with the
    rows of the elements that do not stick replaced: ``p = 0``
    and ``q = 0`` off the contact, ``q = +-p`` at a bound. Its solution is ``y - W_U z`` with ``y = W b``, ``W_U``
    the replaced rows' columns and ``z`` from the small capacitance system ``(R W_U) z = R y`` (``R`` the new rows;
    Sherman-Morrison-Woodbury): ``O(N^2 + N m + m^3)`` for ``N = 2 Lw + 2`` and ``m`` replaced rows. Writes
    ``p_out`` and ``q_out``; returns ``(ok, lam, delta)``, ``ok`` False if the contact does not fit the window, more
    than :data:`DIRECT_ROWS` rows are replaced or the capacitance system is singular. Whether the sets were right
    is :func:`check`'s question.
    """
    N = WT.shape[1]
    b = np.empty(N)
    y = np.empty(N)
    w0 = direct_rhs(WT, K, gap0, load, dx, ct, target, q_old, p_old, i0, i1, scratch, b, y)
    if w0 < 0:
        return False, 0.0, 0.0
    return direct_sets(WT, i0, i1, w0, kind, b, y, q_out, p_out, q_old, p_old, False)


@jit
def direct_rhs(WT, K, gap0, load, dx, ct, target, q_old, p_old, i0, i1, scratch, b, ybase):
    """The part of :func:`direct` that does not depend on the sets: the window's first element ``w0`` (returned;
    -1 if the contact does not fit the window), the right-hand side ``b`` of every row in stick on the contact
    (``-h``, ``K q_old - ct S p_old``, the load and the target; 0 off it) and ``ybase = W b`` (``N^2``). The
    direct solves of one step on one contact share it (:func:`joint`)."""
    n = gap0.size
    N, Lw, w0 = _window(WT, n, i0, i1)
    if w0 < 0:
        return -1
    for j in range(N):
        b[j] = 0.0
    lo, hi = n, 0
    for j in range(n):
        if q_old[j] != 0.0:
            lo = min(lo, j)
            hi = j + 1
    cross(p_old, dx, scratch)
    for a in range(Lw):
        g = w0 + a
        if i0 <= g < i1:
            b[a] = -gap0[g]
            b[Lw + a] = _dot(K[g], q_old, lo, hi) - ct * scratch[g]
    b[2 * Lw] = load / dx
    b[2 * Lw + 1] = target
    _times(WT, b, ybase)
    return w0


@jit
def _window(WT, n, i0, i1):
    """``(N, Lw, w0)``: the size of the window's system ``W^T``, its elements, and its first element on a grid of
    ``n`` when centred on the contact ``[i0, i1)`` (-1 if there is no window or the contact does not fit it)."""
    N = WT.shape[1]
    Lw = (N - 2) // 2
    L = i1 - i0
    if Lw < 1 or L > Lw or Lw > n:
        return N, Lw, -1
    return N, Lw, min(max(i0 - (Lw - L) // 2, 0), n - Lw)


@jit
def _times(WT, b, y):
    """``y = W b`` from ``W^T``: the columns of ``W`` (rows of ``W^T``, contiguous) of the nonzero entries of ``b``."""
    N = b.size
    for i in range(N):
        y[i] = 0.0
    for j in range(N):
        bj = b[j]
        if bj != 0.0:
            col = WT[j]
            for i in range(N):
                y[i] += bj * col[i]


@jit
def direct_rhs_step(WT, K, gap0, load, dx, cn, target, q_old, p_old, kp_old, i0, i1, scratch, b, ybase):
    """:func:`direct_rhs` for the increment from the last step's solution ``(p_old, q_old)``, ``kp_old = K p_old``
    on the rows where ``p_old > 0`` (those of the last contact; the others are made here): unknowns
    ``(dp, dq, delta, lam)``. The tangential rows' right-hand side is then 0 (no slip where it sticks:
    ``K dq - ct S dp - lam = 0``), the normal rows' the last pressure's gap under this step's profile, the load's and
    the target's what the last solution misses of them. On the rows of the last contact that gap is the profile's
    change less the last approach: for a body that moves rigidly with a parabolic profile (the cylinder) it is
    affine in the element's index, and ``W b`` is two differences of :func:`_prefix_sums` (``O(N)``) and a column
    of ``W`` for each row that differs from the affine part by more than round-off (the elements that join the
    contact, a profile that is not parabolic). Returns ``w0``; -1 if the contact, or the last solution, does not
    fit the window (then :func:`direct_rhs`)."""
    n = gap0.size
    N, Lw, w0 = _window(WT, n, i0, i1)
    if w0 < 0:
        return -1
    sp, sq = 0.0, 0.0
    lo, hi = n, 0  # where p_old > 0
    for j in range(n):
        if (p_old[j] != 0.0 or q_old[j] != 0.0) and not w0 <= j < w0 + Lw:
            return -1
        if p_old[j] != 0.0:
            lo = min(lo, j)
            hi = j + 1
        sp += p_old[j]
        sq += q_old[j]
    for j in range(N):
        b[j] = 0.0
        ybase[j] = 0.0
    cross(q_old, dx, scratch)
    c0, c1 = i0 - w0, i1 - w0  # the contact's normal rows
    size = 0.0
    for c in range(c0, c1):
        g = w0 + c
        kp = kp_old[g]
        if p_old[g] == 0.0:  # off the last contact
            kp = _dot(K[g], p_old, lo, hi)
        b[c] = -gap0[g] - kp - cn * scratch[g]
        size = max(size, abs(gap0[g]) + abs(kp) + abs(cn * scratch[g]))
    b[2 * Lw] = load / dx - sp
    b[2 * Lw + 1] = target - sq
    # ---- W b: the affine part through the end rows of the last contact by the prefix sums, the rest by columns
    e0, e1 = max(lo - w0, c0), min(hi - w0, c1) - 1  # the first and last rows of both contacts
    alpha, slope = 0.0, 0.0
    if e1 > e0:
        slope = (b[e1] - b[e0]) / (e1 - e0)
        alpha = b[e0] - slope * (e0 - c0)
        ones, ramp = _prefix_sums(WT)
        for i in range(N):
            s1 = ones[c1, i] - ones[c0, i]
            ybase[i] = alpha * s1 + slope * (ramp[c1, i] - ramp[c0, i] - c0 * s1)
    slack = AFFINE_SLACK * max(size, 1.0)
    for c in range(c0, c1):
        d = b[c] - (alpha + slope * (c - c0))
        if abs(d) > slack:
            _axpy(d, WT[c], ybase)
    for c in (2 * Lw, 2 * Lw + 1):
        if b[c] != 0.0:
            _axpy(b[c], WT[c], ybase)
    return w0


@jit
def direct_sets(WT, i0, i1, w0, kind, b, ybase, q_out, p_out, q_old, p_old, increment):
    """The part of :func:`direct` that depends on the sets ``kind``, from :func:`direct_rhs`'s (or, with
    ``increment``, :func:`direct_rhs_step`'s) ``b`` and ``ybase``: the rows of the elements that do not stick replaced
    (``p = 0``, ``q = 0`` off the contact, ``q = +-p`` at the bound: in the increment form ``dp = -p_old``, ...,
    ``dq -+ dp = +-p_old - q_old``), their right-hand sides put in ``ybase`` in place of the stick ones (a row of
    ``W^T`` each), the capacitance system, the solution (the last one added to the increment). Returns
    ``(ok, lam, delta)``."""
    n = q_out.size
    N = WT.shape[1]
    Lw = (N - 2) // 2
    rows = np.empty(2 * Lw, np.int64)
    other = np.empty(2 * Lw, np.int64)
    sign = np.empty(2 * Lw)
    c = np.empty(2 * Lw)  # the replaced rows' right-hand sides
    m = np.int64(0)  # not a literal 0 (core/solvers/_pdas.py, Literals): _lu_solve compiled once more for it
    for a in range(Lw):
        g = w0 + a
        if not i0 <= g < i1:  # off the contact: p = 0
            rows[m], other[m], sign[m] = a, -1, 0.0
            c[m] = -p_old[g] if increment else 0.0
            m += 1
    for a in range(Lw):
        g = w0 + a
        if not (i0 <= g < i1 and kind[g] == FREE):  # at a bound (q = +-p) or off the contact (q = 0)
            rows[m] = Lw + a
            if i0 <= g < i1 and kind[g] == UPPER:
                other[m], sign[m] = a, 1.0
            elif i0 <= g < i1 and kind[g] == LOWER:
                other[m], sign[m] = a, -1.0
            else:
                other[m], sign[m] = -1, 0.0
            c[m] = sign[m] * p_old[g] - q_old[g] if increment else 0.0
            m += 1
            if m > DIRECT_ROWS:
                return False, 0.0, 0.0
    y = ybase.copy()
    for i in range(m):  # this row's right-hand side is c, not its stick one
        r = rows[i]
        d = c[i] - b[r]
        if d != 0.0:
            col = WT[r]
            for j in range(N):
                y[j] += d * col[j]
    C = np.empty((m, m))
    z = np.empty(m)
    for i in range(m):
        r, o, s = rows[i], other[i], sign[i]
        for j in range(m):
            col = WT[rows[j]]
            C[i, j] = col[r] - s * col[o] if o >= 0 else col[r]
        z[i] = (y[r] - s * y[o] if o >= 0 else y[r]) - c[i]
    if not _lu_solve(C, z, m):
        return False, 0.0, 0.0
    for j in range(m):  # x = y - W_U z
        col = WT[rows[j]]
        zj = z[j]
        for i in range(N):
            y[i] -= zj * col[i]
    for j in range(n):
        p_out[j] = 0.0
        q_out[j] = 0.0
    for a in range(Lw):
        g = w0 + a
        if i0 <= g < i1:
            p_out[g] = y[a] + p_old[g] if increment else y[a]
            q_out[g] = y[Lw + a] + q_old[g] if increment else y[Lw + a]
    return True, y[2 * Lw + 1], y[2 * Lw]


#: :func:`check`'s verdicts: the solution, sets moved (solve again), no direct solution (the passes go on).
ACCEPTED, MOVED, REFUSED = 0, 1, 2


@jit
def check(K, gap0, dx, cn, ct, target, tol, q_old, p_old, i0, i1, p, q, lam, delta, st, profile, scratch, kp):
    """Whether :func:`direct`'s ``(p, q, lam, delta)`` on the contact ``[i0, i1)`` with the sets ``st.kind`` solves
    the step, and if not, the next sets: a primal-dual active set on both problems at once.

    The normal problem: the pressure not negative (a negative end leaves the contact; a negative inside refuses)
    and the contact's neighbours not penetrating (one that does joins it, sticking); the caller checks the rest of
    the grid, as after the passes. The tangential: :func:`core.solvers._pdas.solve_step`'s checks with the coupled
    slip ``lam - K (q - q_old) + ct S (p - p_old)`` (a sticking traction past its bound goes to it, a bound one
    slipping against it sticks; the slips of the bound rows first, so that a set that moves costs little). With
    nothing to move, the named residuals with the true ``K`` must be within ``tol``; then writes what a full
    tangential solve writes (``st.q``, ``st.dq``, ``st.slip``, ``st.codes``, ``st.residuals``; its iterations as
    1), the profile ``gap0 + cn S q`` of the normal problem (``profile``) and ``K p`` on the contact (``kp``, made
    beside the stick residual from the same rows of ``K``). Returns ``(verdict, i0, i1)``: :data:`ACCEPTED`,
    :data:`MOVED` (``st.kind`` and the contact moved) or
    :data:`REFUSED`.
    """
    n = gap0.size
    kind, slip, res = st.kind, st.slip, st.residuals
    moved = False
    # ---- normal: a negative end leaves, a penetrating neighbour joins
    j0, j1 = i0, i1
    for k in range(i0, i1):
        if p[k] < 0.0:
            if k == i0:
                j0 = i0 + 1
            elif k == i1 - 1:
                j1 = i1 - 1
            else:
                return REFUSED, i0, i1
    cross(q, dx, scratch)
    hmax = 1.0
    for k in range(n):
        profile[k] = gap0[k] + cn * scratch[k]
    for k in range(i0, i1):
        hmax = max(hmax, abs(profile[k]))
    if j0 == i0 and j1 == i1:
        for j in (i0 - 1, i1):
            if 0 <= j < n:
                g = profile[j] - delta + _dot(K[j], p, i0, i1)
                if g < -1e-12 * hmax:
                    if j < i0:
                        j0 = j
                    else:
                        j1 = j + 1
    # ---- tangential: the bounds of the sticking tractions and the slips' directions at the bound (the slips of
    # the bound rows only: a set that moves costs no more)
    for k in range(n):
        scratch[k] = p[k] - p_old[k]
    dp = st.dq  # scratch until the end: st.dq is written last
    cross(scratch, dx, dp)
    lo, hi = i0, i1
    for k in range(n):
        scratch[k] = q[k] - q_old[k]
        if scratch[k] != 0.0:
            lo = min(lo, k)
            hi = max(hi, k + 1)
    bound_res, dir_res, total = 0.0, 0.0, 0.0
    for i in range(n):
        total += q[i]
        slip[i] = 0.0
        if kind[i] == OUT:
            continue
        if kind[i] == FREE:
            excess = abs(q[i]) - p[i]
            if excess > tol:
                kind[i] = UPPER if q[i] > 0.0 else LOWER
                moved = True
            bound_res = max(bound_res, excess)
        else:
            s = lam + ct * dp[i] - _dot(K[i], scratch, lo, hi)
            slip[i] = s
            wrong = -s if kind[i] == UPPER else s
            if wrong > tol:
                kind[i] = FREE
                moved = True
            dir_res = max(dir_res, wrong)
            bound_res = max(bound_res, abs(abs(q[i]) - p[i]))
    if j0 != i0 or j1 != i1:
        for k in range(min(i0, j0), max(i1, j1)):
            if k < j0 or k >= j1:
                kind[k] = OUT
            elif kind[k] == OUT:
                kind[k] = FREE
        return MOVED, j0, j1
    if moved:
        return MOVED, i0, i1
    # ---- the sets hold: the stick residual (no slip where it sticks) and K p on the contact, from the same rows
    stick_res = 0.0
    for i in range(n):
        if kind[i] == OUT:
            continue
        if kind[i] == FREE:
            moved_by, g = _dot2(K[i], scratch, p, lo, hi)  # p vanishes off [i0, i1), inside [lo, hi)
            stick_res = max(stick_res, abs(lam + ct * dp[i] - moved_by))
        else:
            g = _dot(K[i], p, i0, i1)
        kp[i] = g
    res[0] = stick_res
    res[1] = max(bound_res, 0.0)
    res[2] = dir_res
    res[3] = 0.0  # q = 0 off the contact by construction
    res[4] = abs(total - target) * dx
    for j in range(5):
        if res[j] > tol:
            return REFUSED, i0, i1
    sq, sdq = st.q, st.dq  # a member of st read in the loop cost 7 of this check's 10 us
    for k in range(n):
        sq[k] = q[k]
        sdq[k] = scratch[k]
    st.counters[ITERATIONS] = 1
    state_codes(kind, slip, tol, st.codes)
    return ACCEPTED, i0, i1


@jit
def joint(WT, K, gap0, load, dx, cn, ct, target, tol, q_old, p_old, kp_old, i0, i1, st, q_d, p_d, profile, scratch,
          kp, tries):
    """The step by :func:`direct` solves and :func:`check`'s moves of the sets, from the sets ``st.kind`` on the
    contact ``[i0, i1)`` (elements off it are set released, those on it that were released start sticking), at
    most ``tries`` solves: for the increment from the last step's solution ``(p_old, q_old)`` when its ``K p_old``
    is given (``kp_old``, on the rows where ``p_old > 0``; empty: none) and it fits the window
    (:func:`direct_rhs_step`), else whole.
    Returns ``(verdict, solves, lam, delta, i0, i1)``: :data:`ACCEPTED` with the solution in ``p_d``, ``q_d`` and
    ``st`` (:func:`check`), else the last direct solution, if any (``solves > 0``), in ``q_d`` and ``p_d``."""
    n = gap0.size
    kind = st.kind
    for k in range(n):
        if k < i0 or k >= i1:
            kind[k] = OUT
        elif kind[k] == OUT:
            kind[k] = FREE
    solves = 0
    lam, delta = 0.0, 0.0
    verdict = REFUSED
    N = WT.shape[1]
    b = np.empty(N)
    ybase = np.empty(N)
    base = (-1, -1)  # the contact of b and ybase
    w0 = -1
    increment = False
    for _ in range(tries):
        if base != (i0, i1):
            increment = kp_old.size > 0
            w0 = -1
            if increment:
                w0 = direct_rhs_step(WT, K, gap0, load, dx, cn, target, q_old, p_old, kp_old, i0, i1, scratch, b,
                                     ybase)
            if w0 < 0:
                increment = False
                w0 = direct_rhs(WT, K, gap0, load, dx, ct, target, q_old, p_old, i0, i1, scratch, b, ybase)
            base = (i0, i1)
        if w0 < 0:
            return REFUSED, solves, lam, delta, i0, i1
        ok, lam_d, delta_d = direct_sets(WT, i0, i1, w0, st.kind, b, ybase, q_d, p_d, q_old, p_old, increment)
        if not ok:
            return REFUSED, solves, lam, delta, i0, i1
        solves += 1
        lam, delta = lam_d, delta_d
        verdict, i0, i1 = check(K, gap0, dx, cn, ct, target, tol, q_old, p_old, i0, i1, p_d, q_d, lam, delta, st,
                                profile, scratch, kp)
        if verdict != MOVED:
            break
    return verdict, solves, lam, delta, i0, i1


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
def _dot(row, v, lo, hi):
    """``sum(row[k] v[k])`` over ``[lo, hi)``: :func:`core.solvers._pdas._dot` of the slices, whose loop starts at
    0 (a loop from ``lo`` indexes with a value that could be negative, which numba wraps, and that kept LLVM from
    vectorising these products: 5 times slower)."""
    return _pdas_dot(row[lo:hi], v[lo:hi])


@jit
def _dot2(row, u, v, lo, hi):
    """``(sum(row[k] u[k]), sum(row[k] v[k]))`` over ``[lo, hi)``: :func:`_dot` of two vectors, ``row`` read once."""
    a = row[lo:hi]
    b = u[lo:hi]
    c = v[lo:hi]
    s, t = 0.0, 0.0
    for k in range(hi - lo):
        s += a[k] * b[k]
        t += a[k] * c[k]
    return s, t


@jit
def _contact_products(K, p, i0, i1, out):
    """``out = K p`` for a pressure ``p`` that vanishes outside ``[i0, i1)``."""
    for j in range(K.shape[0]):
        out[j] = _dot(K[j], p, i0, i1)


@jit
def convex_reach(K):
    """How far the influence of an element stays convex in the distance: the largest ``D`` with
    ``k(d - 1) - 2 k(d) + k(d + 1) >= 0`` for ``2 <= d < D`` (``k(d) = K[0, d]``, ``K`` symmetric Toeplitz): ``k``
    is convex on the distances ``1 .. D`` (:func:`off_contact`)."""
    k = K[0]
    D = 2
    while D + 1 < k.size and k[D - 1] - 2.0 * k[D] + k[D + 1] >= 0.0:
        D += 1
    return D


@jit
def off_contact(K, p, i0, i1, profile, delta, kp, reach):
    """``K p`` on the rows off the contact ``[i0, i1)`` where the pressure ``p >= 0`` could close the gap, and a
    lower bound of it on the others: what :func:`penetrates` and :func:`_gap_residual_from` need of those rows.

    For a row at a distance the kernel is convex over (:func:`convex_reach`), ``K p`` is at least ``P k(|j - c|)``
    (Jensen's inequality; ``P`` the pressure's sum, ``c`` its centroid, ``k`` interpolated linearly between
    elements). A row whose gap under that bound, ``profile - delta + P k``, is open by more than the round-off
    margin of :func:`penetrates` keeps the bound (it neither penetrates nor changes the gap residual); the others,
    the rows near the contact's ends, are made exactly (``L`` products each). Returns the rows made exactly."""
    n = p.size
    total, moment = 0.0, 0.0
    bounded = i1 > i0
    for k in range(i0, i1):
        if p[k] < 0.0:
            bounded = False
        total += p[k]
        moment += k * p[k]
    if total <= 0.0:
        bounded = False
    margin = _penetration_margin(profile, i0, i1)
    ic, t = i0, 0.0
    if bounded:
        c = moment / total
        ic = min(max(int(c), i0), i1 - 1)
        t = c - ic
        if ic + 1 >= n:
            t = 0.0
    exact = 0
    for j in range(n):
        if i0 <= j < i1:
            continue
        row = K[j]
        if bounded and (j - i0 if j >= i1 else i1 - 1 - j) <= reach:
            lower = total * (row[ic] + t * (row[ic + 1] - row[ic]) if t > 0.0 else row[ic])
            if profile[j] + lower - delta >= margin:
                kp[j] = lower
                continue
        kp[j] = _dot(row, p, i0, i1)
        exact += 1
    return exact


@jit
def _penetration_margin(h, i0, i1):
    """The round-off a gap may close by and still count as open: ``1e-12`` of the profile ``h`` on the contact
    ``[i0, i1)`` (at least of 1). :func:`penetrates` and :func:`off_contact` share it: a row the bound keeps must be
    one the test passes."""
    hmax = 1.0
    for k in range(i0, i1):
        hmax = max(hmax, abs(h[k]))
    return 1e-12 * hmax


@jit
def penetrates(h, kp, delta, i0, i1):
    """Whether the pressure on ``[i0, i1)`` from :func:`interval_normal` (approach ``delta``, ``kp = K p``)
    penetrates the profile ``h`` away from its ends: :func:`interval_normal`'s test with ``check_all``."""
    tol = _penetration_margin(h, i0, i1)
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
def _shift_kinds(kind, move):
    """Move the tangential sets with the contact by ``move`` elements (the step's first guess: the slip zones of
    a rocking contact stay at its edges)."""
    n = kind.size
    if move < 0:
        for j in range(n):
            kind[j] = kind[j - move] if j - move < n else OUT
    elif move > 0:
        for j in range(n - 1, -1, -1):
            kind[j] = kind[j - move] if j - move >= 0 else OUT


@jit
def alternate(K, C, CT, gap0, load, dx, cn, ct, coupled, p_prev, has_prev, target, tol, maxiter, max_alt, st,
              i0, i1, p, work, inv, q_start, W, need, move):
    """One coupled step, from ``st.q_prev`` (kept) and the previous pressure ``p_prev``: first :func:`joint` from the
    last step's sets moved by ``move`` elements on the contact ``[i0, i1)``, then the alternation's passes.

    ``W`` is the transposed window inverse of :func:`direct` (empty: none yet); ``need[0]`` receives the width of a
    contact it is too narrow for, and ``need[0] = -1`` turns the direct solves off (the passes alone). ``q_start`` is the
    first guess of the step's tractions (the normal problem of the first pass sees it, or the last direct
    solution). Writes the pressure ``p`` and, through :func:`check` or :func:`core.solvers._pdas.solve_step`, the
    step's tractions, slips, codes and residuals in ``st``. Returns ``(status, lam, alternations, full, direct,
    change, i0, i1, delta, checked)`` (:data:`STATUS_DONE`, ...; passes, of which full tangential solves, direct
    solves, the last pass's change (0 for a step a direct solve ended), ``delta`` the approach of the last normal
    solve, whose profile stays in ``work[5]``, and whether :func:`check` ended the step, leaving ``K p`` on the
    contact in ``work[4]``). The passes and :func:`check` test the gap only at the contact's ends: the caller
    checks the final pressure everywhere (:func:`march`).
    """
    n = gap0.size
    q_true = st.q_prev.copy()
    q_in = q_start.copy()
    profile, shift, dp, p_cur = work[5], work[6], work[7], work[8]
    for k in range(n):
        p_cur[k] = p_prev[k]
    lam = 0.0
    delta = 0.0
    change = UNMEASURED
    it = 0
    status = STATUS_DONE
    n_full = 0
    settled = False  # the contact interval and the tangential set are kept
    before = -1.0  # the change of the last settled pass (none: -1; the kernels are compiled with fastmath: no inf)
    tries = 0  # joint calls after a full pass
    n_direct = 0
    p_d, q_d, scratch, kp_old = work[10], work[11], work[12], work[13]
    kp_last = work[4]  # a row of work taken in the loop costs a view an element (as a member of st does)
    for k in range(n):  # K p_prev, exact on its contact: the last step's (march leaves it in work[4], which check
        # rewrites; off the contact it may hold off_contact's lower bound)
        kp_old[k] = kp_last[k]
    # ---- first the direct solves from the last step's sets on the predicted contact: most steps end here
    direct_on = coupled and need[0] >= 0  # need[0] = -1: no direct solves (the alternation alone)
    if direct_on and has_prev and W.shape[0] > 0:
        _shift_kinds(st.kind, move)
        verdict, solves, lam_d, delta_d, j0, j1 = joint(W, K, gap0, load, dx, cn, ct, target, tol, q_true, p_prev,
                                                        kp_old, i0, i1, st, q_d, p_d, profile, scratch, work[4],
                                                        DIRECT_TRIES)
        n_direct += solves
        if verdict == ACCEPTED:
            for k in range(n):
                p[k] = p_d[k]
            return STATUS_DONE, lam_d, 0, 0, n_direct, 0.0, j0, j1, delta_d, True
        if solves > 0:  # not the solution, but nearer it than the guess
            for k in range(n):
                q_in[k] = q_d[k]
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
        q_prev = st.q_prev  # (st's members read outside the loops: one read a pass, not one an element)
        for k in range(n):
            q_prev[k] = q_true[k]
        if ct != 0.0:
            for k in range(n):
                dp[k] = p[k] - p_prev[k]
            cross(dp, dx, shift)
            for k in range(i1 - i0):
                shift[k] = ct * shift[i0 + k]
            _apply(inv.A[inverse(inv, C, CT, i1 - i0)], i1 - i0, shift, work[9])
            moved = work[9]
            for k in range(i1 - i0):
                q_prev[i0 + k] += moved[k]
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
        q_out = st.q
        for k in range(n):
            change = max(change, abs(q_out[k] - q_in[k]))
            q_in[k] = q_out[k]
        if has_prev or it > 1:
            for k in range(n):
                change = max(change, abs(p[k] - p_cur[k]))
        else:
            change = UNMEASURED
        for k in range(n):
            p_cur[k] = p[k]
        if not coupled:
            change = 0.0
        if change <= tol and full:
            break
        # after a full pass, the step with the sets it found is solved at once (direct); the next pass, a full
        # one, checks those sets: the step ends if it leaves the solution where it is
        if full and direct_on and tries < JOINT_AFTER_PASS:
            tries += 1
            verdict, solves, lam_d, delta_d, j0, j1 = joint(W, K, gap0, load, dx, cn, ct, target, tol, q_true,
                                                            p_prev, kp_old, i0, i1, st, q_d, p_d, profile, scratch,
                                                            work[4], DIRECT_TRIES)
            n_direct += solves
            if verdict == ACCEPTED:
                q_prev = st.q_prev
                for k in range(n):
                    p[k] = p_d[k]
                    q_prev[k] = q_true[k]
                return STATUS_DONE, lam_d, it, n_full, n_direct, 0.0, j0, j1, delta_d, True
            if solves > 0:  # the next pass, a full one, starts from the last direct solution
                for k in range(n):
                    q_in[k] = q_d[k]
                settled = False
                before = -1.0
                continue
            if i1 - i0 > (W.shape[1] - 2) // 2:
                need[0] = max(need[0], i1 - i0)
        # the settled passes contract the change by a steady ratio: the full solve's turn once the change, or the
        # next one by that ratio, is within the tolerance (the full pass is then the next one's work)
        ratio = change / before if before > 0.0 else 1.0
        if full:
            before = -1.0
        elif change <= tol or (ratio < 0.5 and change * ratio <= PREDICTED * tol):
            settled = False
        else:
            before = change
    q_prev = st.q_prev
    for k in range(n):
        q_prev[k] = q_true[k]
    return status, lam, it, n_full, n_direct, change, i0, i1, delta, False


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
          iters, resid, worst, alternations, full_solves, direct_solves, res_out, info, W, need):
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
    reach = convex_reach(K)
    q_prev, q = st.q_prev, st.q
    p = np.zeros(n)
    for k in range(k0, k1):
        gap0 = gaps[k - kb]
        move = int(np.rint((xc[k] - xc[k - 1]) / dx)) if k > 0 else 0
        has_prev, i0, i1 = _start_interval(p_prev, gap0, loads[k], dx, move)
        for i in range(n):
            q_start[i] = q_prev[i] + dq_last[i]
            p[i] = 0.0
        status, lam, it, n_full, n_direct, change, i0, i1, delta, checked = alternate(
            K, C, CT, gap0, loads[k], dx, cn, ct, coupled, p_prev, has_prev, targets[k], tol, maxiter, max_alt, st,
            i0, i1, p, work, inv, q_start, W, need, move)
        if status == STATUS_DONE:
            # ---- the final pressure penetrates nowhere else (the passes checked only the contact's ends); after a
            # direct solve the rows whose gap is open by Jensen's bound need no product (off_contact)
            if checked:  # check made K p on the contact
                off_contact(K, p, i0, i1, work[5], delta, work[4], reach)
            else:
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
        res_out[nres + 2] = change  # within the tolerance here
        worst_step = 0.0
        for j in range(res_out.size):
            worst_step = max(worst_step, res_out[j])
        if worst_step > 1e3 * tol:
            info[0], info[1] = it, change
            return k, -1, k, status
        # ---- record the step and advance
        st.total[0] += lam
        d = 0.0
        codes, slip = st.codes, st.slip
        for i in range(n):
            bounds[k - kb, i] = p[i]
            traction[k, i] = q[i]
            state[k, i] = codes[i]
            d += q[i] * slip[i]
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
        direct_solves[k] = n_direct
        if k + 1 < steps and period[k + 1] != period[k]:
            same = block_repeats(q, st.q_block_end, tol)
            if same and detect_periodic and period[k] >= 0:
                return k + 1, period[k], -1, STATUS_DONE
        if need[0] > 0:  # the contact outgrew the direct solve's window: the caller widens it
            return k + 1, -1, -1, STATUS_WINDOW
    return k1, -1, -1, STATUS_DONE
