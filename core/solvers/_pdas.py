"""Numba kernels of the dense per-step solver (private; the interface is :mod:`core.solvers.dense`).

The state a step leaves for the next one lives in one structure,
:class:`PdasState` (a named tuple of arrays, updated in place): the active-set
guess of every element, the inverse of the influence matrix on the stick set
(kept current by rank-one updates), the inverses of a Toeplitz matrix on the
contact interval (one per contact width, see :func:`_toeplitz_stick`), the
tractions and the running sums. LAPACK only for large rebuilds: a
multithreaded BLAS costs more than it gains on small systems when the two
cores are shared.

The loops run over slices with ``range()`` indices: numba then knows the
indices are non-negative and LLVM vectorises them (4-5x faster than indexing
with offsets).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from ..base._jit import jit

# active-set kinds of an element (internal to the solver, not the recorded states)
OUT, FREE, UPPER, LOWER = 0, 1, 2, 3
# recorded element states (core.base.states.State; numba needs plain integers)
RELEASED, STICK, SLIP_FORWARD, SLIP_BACKWARD = 0, 1, 2, 3
# iterations moving every violator at once before moving one at a time
PDAS_FULL_STEPS = 8
# rank-one updates of the stick-set inverse before it is rebuilt from K
REBUILD_EVERY = 20000
# the named residuals, in the order of PdasState.residuals
RESIDUALS = ("stick_slip", "bound", "slip_direction", "out_of_contact", "load_balance")
# indices of PdasState.counters
M, UPDATES, ITERATIONS, MODE, CLOCK = 0, 1, 2, 3, 4
# MODE: how the last stick set was solved
TOEPLITZ, CLASSICAL = 0, 1
# inverses of contact-interval blocks of a Toeplitz K kept at once (lengths L, L + 1 and one spare)
NSLOT = 3
# updates chained from one fresh interval inverse before it is recomputed
CHAIN_MAX = 256
# length differences bridged by bordering or downdating a held inverse (beyond: a fresh one)
CHAIN_STEP = 24
# stick sets above which a rebuild of their inverse calls LAPACK rather than bordering
REBUILD_LAPACK = 300
# an FFT product K dq replaces row products above FFT_WORK N log2 N multiply-adds
FFT_WORK = 8.0
# free-set differences above which the stick-set inverse is rebuilt rather than updated
SYNC_MAX = 16
# Literals. An integer a kernel passes on to another starts as np.int64(0), not 0: numba types a variable first
# assigned a constant as that literal (Literal[int](0)) while it infers a loop's types, and compiles the kernel called
# with it once more for the literal, a signature no run needs (8 s of the 160 s of CPU of the cold cache's precompile
# of the line solvers, tests/conftest.py). An int64 from the start compiles each callee once, to the same code.

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
    "codes",       # (n,) int8: element states of this step (core.base.states.State)
    "q_block_end",  # (n,): tractions at the end of the last block (periodic detection)
    "counters",    # (5,) int64: size m of B, rank-one updates since the last rebuild, iterations of the last
                   # step, MODE of the last solve, clock of the interval inverses
    "total",       # (1,): rigid-body displacement so far
    "residuals",   # (5,): the named residuals of the last step (RESIDUALS)
    # ---- a Toeplitz K (empty kfull otherwise): inverses of K on contact intervals
    "kfull",       # (2 n + 1,): kfull[n + d] = K[i, i + d]; (0,) if K is not Toeplitz
    "slots",       # (NSLOT, Lcap, Lcap): A_L = inverse of K on L contiguous elements
    "slot_vec",    # (NSLOT, 3, Lcap): A_L 1, A_L K[I, left neighbour], A_L K[I, right neighbour]
    "slot_info",   # (NSLOT, 3) int64: length L (-1: empty), last use, updates chained since a fresh inverse
    "hidx",        # (Lcap,) int64: offsets of the non-stick elements of the interval
    "chol",        # (Hcap, Hcap): Cholesky factor of A_L on those elements
    "tw",          # (4, max(Lcap, Hcap)): scratch
    # ---- a Toeplitz K: products K dq by FFT (empty spec otherwise)
    "spec",        # (N // 2 + 1,): real FFT of the circulant of size N >= 2 n that embeds K
    "fftn",        # (1,) int64: N
    "ku",          # (n,): K dq on the window of the last product
])


@jit
def hmax(L):
    """Non-stick elements of an ``L``-element contact above which the Toeplitz solve gives way to the classical one.

    The Toeplitz solve costs about ``h^3 / 3 + 4 L h`` per iteration, the
    classical one a few passes over an ``m x m`` inverse (``m = L - h``).
    """
    return max(24, int(2.0 * L ** (2.0 / 3.0)))


def new_state(n: int, column=None, Lcap: int = 0, spectrum=None, N: int = 0) -> PdasState:
    """A cold state for ``n`` elements (nothing in contact, empty inverse).

    ``column`` (the first column of a Toeplitz K) enables the interval
    inverses, for contacts of up to ``Lcap`` elements; ``spectrum`` (of its
    circulant embedding of size ``N >= 2 n``, :meth:`core.elastic.operators.DenseOperator.spectrum`)
    the products ``K dq`` by FFT where they are cheaper than by rows.
    """
    if column is None:
        kfull = np.zeros(0)
    else:
        column = np.asarray(column, dtype=float)
        kfull = np.zeros(2 * n + 1)
        kfull[n:2 * n] = column[:n]
        kfull[1:n + 1] = column[:n][::-1]
    Lcap = min(int(Lcap), n) if kfull.size else 0
    Hcap = hmax(Lcap) if Lcap else 0
    return PdasState(kind=np.zeros(n, np.int8), B=np.zeros((n, n)), fidx=np.zeros(n, np.int64),
                     pos=-np.ones(n, np.int64), work=np.zeros(4 * n), q_prev=np.zeros(n), q=np.zeros(n),
                     dq=np.zeros(n), slip=np.zeros(n), codes=np.zeros(n, np.int8), q_block_end=np.zeros(n),
                     counters=np.array([0, 0, 0, CLASSICAL, 0], np.int64), total=np.zeros(1), residuals=np.zeros(5),
                     kfull=kfull, slots=np.zeros((NSLOT, Lcap, Lcap)), slot_vec=np.zeros((NSLOT, 3, Lcap)),
                     slot_info=np.array([[-1, -1, 0]] * NSLOT, np.int64), hidx=np.zeros(Lcap, np.int64),
                     chol=np.zeros((Hcap, Hcap)), tw=np.zeros((4, max(Lcap, Hcap))),
                     spec=np.zeros(0) if spectrum is None or not kfull.size else np.ascontiguousarray(spectrum, float),
                     fftn=np.array([N], np.int64), ku=np.zeros(n))


def with_capacity(st: PdasState, Lcap: int) -> PdasState:
    """``st`` with room for contacts of ``Lcap`` elements (the same state if it has it; the inverses are dropped)."""
    n = st.kind.size
    Lcap = min(int(Lcap), n)
    if st.kfull.size == 0 or Lcap <= st.hidx.size:
        return st
    Hcap = hmax(Lcap)
    return st._replace(slots=np.zeros((NSLOT, Lcap, Lcap)), slot_vec=np.zeros((NSLOT, 3, Lcap)),
                       slot_info=np.array([[-1, -1, 0]] * NSLOT, np.int64), hidx=np.zeros(Lcap, np.int64),
                       chol=np.zeros((Hcap, Hcap)), tw=np.zeros((4, max(Lcap, Hcap))))


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
    """Recompute ``B = K[F, F]^-1`` from scratch for the free set ``F``; return its size.

    Up to :data:`REBUILD_LAPACK` elements by bordering one element at a time
    (plain loops: a multithreaded BLAS is several times slower than one thread
    on these small systems when the cores are shared), above by LAPACK.
    """
    kind, B, fidx, pos = st.kind, st.B, st.fidx, st.pos
    m = 0
    for i in range(kind.size):
        pos[i] = -1
        if kind[i] == FREE:
            m += 1
    if m > REBUILD_LAPACK:
        m = 0
        for i in range(kind.size):
            if kind[i] == FREE:
                fidx[m] = i
                pos[i] = m
                m += 1
        sub = np.empty((m, m))
        for r in range(m):
            for c in range(m):
                sub[r, c] = K[fidx[r], fidx[c]]
        B[:m, :m] = np.linalg.inv(sub)
    else:
        m = np.int64(0)  # not a literal 0: see Literals at the top
        for i in range(kind.size):
            if kind[i] == FREE:
                grown = _inverse_add(K, B, fidx, pos, m, i, st.work)
                if grown > 0:  # an element that would break definiteness stays out (the KKT check catches it)
                    m = grown
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
def _kdot(K, kf, i, v, lo, hi):
    """``K[i, lo:hi] @ v[lo:hi]`` (v is zero outside [lo, hi)), from the Toeplitz column when there is one.

    The column (``kfull``, a few kB) stays in the first-level cache where the
    rows of ``K`` come from memory; the products are the same numbers.
    """
    if kf.size > 0:
        n = K.shape[0]
        return _dot(kf[n + lo - i:n + hi - i], v[lo:hi])
    return _dot(K[i, lo:hi], v[lo:hi])


# --------------------------------------------------------------------------
# a Toeplitz K: the inverse on a contact interval, and the stick solve from it
# --------------------------------------------------------------------------
# K on L contiguous elements is the same matrix wherever they lie, so its
# inverse A_L serves every step whose contact spans L elements. With H the
# elements of the interval I that are not free (at a bound or released), the
# inverse of K on the free set F = I \ H is (block elimination)
#     K_FF^-1 = A_FF - A_FH (A_HH)^-1 A_HF,
# so a stick solve costs O(L h + h^3) for h = |H| instead of updates of an
# m x m inverse.
@jit
def _slot_vectors(st, slot, L):
    """``A 1`` and ``A`` times the columns of K of the elements left and right of the interval."""
    n = st.kind.size
    kf = st.kfull
    A = st.slots[slot]
    vec = st.slot_vec[slot]
    tmp = st.tw[3]
    for r in range(L):
        s = 0.0
        row = A[r, :L]
        for c in range(L):
            s += row[c]
        vec[0, r] = s
    for j in range(L):
        tmp[j] = kf[n + j + 1]  # K[s0 + j, s0 - 1]
    for r in range(L):
        vec[1, r] = _dot(A[r, :L], tmp[:L])
    for j in range(L):
        tmp[j] = kf[n + L - j]  # K[s0 + j, s0 + L]
    for r in range(L):
        vec[2, r] = _dot(A[r, :L], tmp[:L])


@jit
def _border(st, A, m):
    """Grow the inverse of the Toeplitz K on ``m`` elements in ``A[:m, :m]`` to ``m + 1`` in place; False if not PD."""
    n = st.kind.size
    kf = st.kfull
    Av = st.tw[2]
    kv = st.tw[3]
    for j in range(m):
        kv[j] = kf[n + m - j]
    for r in range(m):
        Av[r] = _dot(A[r, :m], kv[:m])
    schur = kf[n] - _dot(kv[:m], Av[:m])
    if not schur > 0.0:
        return False
    inv = 1.0 / schur
    for r in range(m):
        wr = Av[r] * inv
        _axpy(wr, Av[:m], A[r, :m])
        A[r, m] = -wr
        A[m, r] = -wr
    A[m, m] = inv
    return True


@jit
def _toeplitz_inverse(t, L, A):
    """Inverse of the symmetric positive definite Toeplitz matrix of first column ``t[:L]`` into ``A[:L, :L]``.

    Trench's algorithm (Golub and Van Loan, *Matrix Computations*, algorithm
    4.7.3): Durbin's recursion for the Yule-Walker equations, then the
    entries from their neighbours, ``O(L^2)``. False if a Schur complement is
    not positive.
    """
    t0 = t[0]
    if L == 1:
        A[0, 0] = 1.0 / t0
        return True
    m = L - 1
    r = t[1:L] / t0
    # Durbin: T_m y = -r
    y = np.empty(m)
    z = np.empty(m)
    y[0] = -r[0]
    beta = 1.0
    alpha = -r[0]
    for k in range(1, m):
        beta = (1.0 - alpha * alpha) * beta
        if not beta > 0.0:
            return False
        s = r[k]
        for j in range(k):
            s += r[k - 1 - j] * y[j]
        alpha = -s / beta
        for j in range(k):
            z[j] = y[j] + alpha * y[k - 1 - j]
        for j in range(k):
            y[j] = z[j]
        y[k] = alpha
    s = 1.0
    for j in range(m):
        s += r[j] * y[j]
    gamma = 1.0 / s
    if not gamma > 0.0:
        return False
    v = np.empty(m)
    for j in range(m):
        v[j] = gamma * y[m - 1 - j]
    # 0-based: B[0,0] = gamma, B[0, j] = v[m - j] for j = 1..m  (v(n-1:-1:1))
    A[0, 0] = gamma
    for j in range(1, L):
        A[0, j] = v[m - j]
    for i in range(1, (L - 1) // 2 + 1):
        for j in range(i, L - i):
            A[i, j] = A[i - 1, j - 1] + (v[m - j] * v[m - i] - v[i - 1] * v[j - 1]) / gamma
    # symmetry and persymmetry fill
    for i in range(L):
        for j in range(i, L):
            # (i,j) in the wedge if i <= j <= L-1-i
            if j > L - 1 - i:
                A[i, j] = A[L - 1 - j, L - 1 - i]
    for i in range(L):
        for j in range(i):
            A[i, j] = A[j, i]
    inv = 1.0 / t0
    for i in range(L):
        for j in range(L):
            A[i, j] *= inv
    return True


@jit
def _slot_fresh(st, slot, L):
    """Compute ``A_L`` from the Toeplitz column (Trench's algorithm, ``O(L^2)``; bordering if it fails)."""
    n = st.kind.size
    kf = st.kfull
    A = st.slots[slot]
    if not _toeplitz_inverse(kf[n:n + L], L, A):
        A[0, 0] = 1.0 / kf[n]
        for m in range(1, L):
            _border(st, A, m)
    st.slot_info[slot, 0] = L
    st.slot_info[slot, 2] = 0
    _slot_vectors(st, slot, L)


@jit
def _slot_from(st, dst, src, L):
    """``A_L`` into slot ``dst`` from the inverse of another length in ``src``; False if definiteness is lost.

    Copies it, then borders it with one element at a time (growing) or
    downdates the last one (shrinking): ``O(L^2)`` per element of difference.
    """
    As = st.slots[src]
    A = st.slots[dst]
    m = st.slot_info[src, 0]
    for r in range(m):
        A[r, :m] = As[r, :m]
    while m > L:  # drop the last element
        last = m - 1
        d = A[last, last]
        if not d > 0.0:
            return False
        lrow = A[last, :last]
        for r in range(last):
            _axpy(-A[r, last] / d, lrow, A[r, :last])
        m = last
    while m < L:  # border with the next element
        if not _border(st, A, m):
            return False
        m += 1
    st.slot_info[dst, 0] = L
    st.slot_info[dst, 2] = st.slot_info[src, 2] + abs(st.slot_info[src, 0] - L)
    _slot_vectors(st, dst, L)
    return True


@jit
def _slot_get(st, L):
    """The slot holding ``A_L``, made from a neighbouring length or from scratch if none holds it."""
    info = st.slot_info
    st.counters[CLOCK] += 1
    dst = np.int64(0)  # not literals: see Literals at the top
    for k in range(NSLOT):
        if info[k, 0] == L:
            info[k, 1] = st.counters[CLOCK]
            return k
        if info[k, 1] < info[dst, 1]:
            dst = k
    info[dst, 1] = st.counters[CLOCK]
    # the nearest length held, if a few updates away
    src = np.int64(-1)
    for k in range(NSLOT):
        if k != dst and info[k, 0] > 0 and abs(info[k, 0] - L) <= CHAIN_STEP and info[k, 2] < CHAIN_MAX:
            if src < 0 or abs(info[k, 0] - L) < abs(info[src, 0] - L):
                src = k
    if src >= 0 and _slot_from(st, dst, src, L):
        return dst
    _slot_fresh(st, dst, L)
    return dst


@jit
def _cholesky(G, h):
    """In-place lower Cholesky factor of the leading ``h x h`` block of ``G``; False if not positive definite."""
    for j in range(h):
        s = G[j, j] - _dot(G[j, :j], G[j, :j])
        if not s > 0.0:
            return False
        djj = math.sqrt(s)
        G[j, j] = djj
        for i in range(j + 1, h):
            G[i, j] = (G[i, j] - _dot(G[i, :j], G[j, :j])) / djj
    return True


@jit
def _cholesky_solve(G, h, x):
    """Overwrite ``x[:h]`` with ``(G G^T)^-1 x``."""
    for i in range(h):
        x[i] = (x[i] - _dot(G[i, :i], x[:i])) / G[i, i]
    for i in range(h - 1, -1, -1):
        x[i] /= G[i, i]
        xi = x[i]
        row = G[i, :i]
        for k in range(i):
            x[k] -= row[k] * xi


@jit
def _toeplitz_stick(st, slot, s0, L, D, lo, hi):
    """The stick solve on the interval ``[s0, s0 + L)`` from ``A_L`` (the fixed increments are in ``st.dq``).

    Writes ``dq`` on the free set; returns ``(lam, lo, hi, ok)`` with the
    range ``[lo, hi)`` outside which ``dq`` is zero, ``ok`` False if the
    elimination lost definiteness.
    """
    n = st.kind.size
    kind, dq, kf, H, G = st.kind, st.dq, st.kfull, st.hidx, st.chol
    A = st.slots[slot]
    w1 = st.slot_vec[slot, 0]
    p = st.tw[0]
    z1 = st.tw[1]
    r = st.tw[2]
    h = np.int64(0)  # not a literal 0: see Literals at the top
    for j in range(L):
        if kind[s0 + j] != FREE:
            H[h] = j
            h += 1
    # p = A K[I, X] dq_X for the fixed elements X that move: unit vectors inside I, the neighbours' columns outside
    for j in range(L):
        p[j] = 0.0
    for i in range(lo, hi):
        d = dq[i]
        if d != 0.0:
            j = i - s0
            if 0 <= j < L:
                p[j] += d
            elif j == -1:
                _axpy(d, st.slot_vec[slot, 1, :L], p[:L])
            elif j == L:
                _axpy(d, st.slot_vec[slot, 2, :L], p[:L])
            else:
                tmp = st.tw[3]
                for jj in range(L):
                    tmp[jj] = kf[n + i - s0 - jj]
                for rr in range(L):
                    p[rr] += d * _dot(A[rr, :L], tmp[:L])
    for a in range(h):
        row = A[H[a]]
        for b in range(a + 1):
            G[a, b] = row[H[b]]
    if not _cholesky(G, h):
        return 0.0, lo, hi, False
    # z = A r + A[:, H] u with u = -(A_HH)^-1 (A r)_H is K_FF^-1 r on F and 0 on H, for r = 1 and r = y
    for a in range(h):
        r[a] = w1[H[a]]
    _cholesky_solve(G, h, r)
    u1 = st.tw[3]
    for a in range(h):
        u1[a] = -r[a]
        r[a] = p[H[a]]
    _cholesky_solve(G, h, r)
    for j in range(L):
        z1[j] = w1[j]
    for a in range(h):
        row = A[H[a], :L]
        _axpy(u1[a], row, z1[:L])
        _axpy(-r[a], row, p[:L])
    s1 = 0.0
    sy = 0.0
    for j in range(L):
        if kind[s0 + j] == FREE:
            s1 += z1[j]
            sy += p[j]
    lam = (D + sy) / s1
    for j in range(L):
        i = s0 + j
        if kind[i] == FREE:
            dq[i] = lam * z1[j] - p[j]
            if dq[i] != 0.0:
                lo = min(lo, i)
                hi = max(hi, i + 1)
    return lam, lo, hi, True


@jit
def _k_product(st, dq, a, b):
    """``st.ku[a:b] = (K dq)[a:b]`` by FFT of the circulant embedding (``dq`` is zero outside ``[a, b)``)."""
    N = st.fftn[0]
    v = np.fft.irfft(np.fft.rfft(dq[a:b], N) * st.spec, N)
    st.ku[a:b] = v[:b - a]


@jit
def _fft_cheaper(st, rows, width):
    """Whether one FFT product costs less than ``rows`` row products of ``width`` entries."""
    if st.spec.size == 0:
        return False
    N = st.fftn[0]
    return rows * width > FFT_WORK * N * math.log2(N)


@jit
def contact_span(g):
    """First element with a positive bound and the number of elements up to the last one (0 if none)."""
    n = g.size
    s0 = 0
    while s0 < n and not g[s0] > 0.0:
        s0 += 1
    if s0 == n:
        return 0, 0
    e = n
    while not g[e - 1] > 0.0:
        e -= 1
    return s0, e - s0


@jit
def max_span(bounds, rows):
    """Largest :func:`contact_span` length over the first ``rows`` rows of ``bounds``."""
    best = 0
    for k in range(rows):
        best = max(best, contact_span(bounds[k])[1])
    return best


@jit
def _free_set_differences(st):
    """Elements whose membership of the stick-set inverse differs from the active-set guess."""
    diff = 0
    pos, kind = st.pos, st.kind  # read once: a member of st read in the loop costs a reference count an element
    for i in range(kind.size):
        if (pos[i] >= 0) != (kind[i] == FREE):
            diff += 1
    return diff


@jit
def _classical_stick(K, st, m, D, lo, hi):
    """The stick solve from the stick-set inverse ``B`` (current for the free set); returns ``(lam, lo, hi)``."""
    n = K.shape[0]
    B, fidx, dq, work = st.B, st.fidx, st.dq, st.work
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
    return lam, lo, hi


# --------------------------------------------------------------------------
# one step
# --------------------------------------------------------------------------
@jit
def _prescribed(kind, g, q_prev, dq):
    """The increments ``dq`` prescribed by the active set (a released element sheds its traction, one at a bound
    goes to it; a free element's is left 0). Returns ``(sum q_prev, sum of the prescribed increments, lo, hi)``,
    ``dq`` being zero outside ``[lo, hi)``."""
    n = g.size
    sum_prev = 0.0
    sum_fixed = 0.0
    lo, hi = n, 0
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
    return sum_prev, sum_fixed, lo, hi


@jit
def fixed_set_stick(g, target, st):
    """The tangential increment with the active set as it stands, no check of it: ``st.q`` and ``st.dq`` from the
    stick solve of :func:`solve_step`'s Toeplitz path (the last solve's set, bounds ``g``, previous tractions
    ``st.q_prev``). For the passes of the coupled alternation (:func:`core.solvers._coupled.alternate`) once its
    sets have settled: the bounds and the previous tractions then change by little and the set not at all, and a
    full :func:`solve_step` after them checks the set and evaluates the residuals. Returns ``(lam, ok)``, ``ok``
    False where that path does not apply (no Toeplitz ``K``, too many elements off the free set, an empty free
    set, a lost definiteness): the caller then solves with :func:`solve_step`."""
    kind, q_prev, q, dq = st.kind, st.q_prev, st.q, st.dq
    n = g.size
    s0, L = contact_span(g)
    if not (st.kfull.size > 0 and 0 < L <= st.hidx.size):
        return 0.0, False
    h = 0
    for i in range(s0, s0 + L):
        if kind[i] != FREE:
            h += 1
    if h >= L or h > hmax(L):
        return 0.0, False
    sum_prev, sum_fixed, lo, hi = _prescribed(kind, g, q_prev, dq)
    lam, lo, hi, ok = _toeplitz_stick(st, _slot_get(st, L), s0, L, target - sum_prev - sum_fixed, lo, hi)
    if not ok:
        return 0.0, False
    for i in range(n):
        q[i] = q_prev[i] + dq[i]
    return lam, True


@jit
def solve_step(K, g, target, dx, tol, maxiter, st):
    """Solve one increment of the tangential contact problem from ``st.q_prev``.

    The KKT conditions and the method are described in :mod:`core.solvers.dense`.
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
    kind, q_prev, q, dq, slip, codes, res = st.kind, st.q_prev, st.q, st.dq, st.slip, st.codes, st.residuals
    kf = st.kfull
    n = g.size
    for j in range(5):
        res[j] = 0.0
    st.counters[ITERATIONS] = 0
    if zero_increment(g, q_prev, target, dx, tol, kind, q, dq, slip, codes, res):
        return 0.0, True

    m = st.counters[M]
    rebuilt = False
    lam = 0.0
    it = 0
    converged = False
    evaluated = False
    # a Toeplitz K: solve on the contact interval from its inverse while few of its elements are not free
    s0, L = contact_span(g)
    toeplitz = st.kfull.size > 0 and 0 < L <= st.hidx.size
    h_max = hmax(L)
    slot = -1
    fast = False
    while it < maxiter:
        it += 1
        # ---- prescribed increments of the elements at a bound or released
        sum_prev, sum_fixed, lo, hi = _prescribed(kind, g, q_prev, dq)
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
        # ---- stick: K[F,F] dq_F = lam - K[F,fixed] dq_fixed, sum dq_F = D
        D = target - sum_prev - sum_fixed
        fast = False
        if toeplitz:
            h = 0
            for i in range(s0, s0 + L):
                if kind[i] != FREE:
                    h += 1
            # hysteresis: back from the classical solve only well below the threshold
            fast = h <= (h_max if st.counters[MODE] == TOEPLITZ else h_max // 2)
        if fast:
            if slot < 0:
                slot = _slot_get(st, L)
            lam, lo, hi, fast = _toeplitz_stick(st, slot, s0, L, D, lo, hi)
        if fast:
            st.counters[MODE] = TOEPLITZ
        else:
            # ---- stick-set inverse for this free set
            if st.counters[MODE] == TOEPLITZ and _free_set_differences(st) > SYNC_MAX:
                m = _inverse_rebuild(K, st)
            else:
                m = _inverse_sync(K, st, m)
                if m < 0:
                    m = _inverse_rebuild(K, st)
                    rebuilt = True
            st.counters[MODE] = CLASSICAL
            lam, lo, hi = _classical_stick(K, st, m, D, lo, hi)
        # ---- check: bounds on the free set, slip direction on the fixed set
        n_viol = 0
        worst_free, i_free = 0.0, np.int64(-1)  # not literals: see Literals at the top
        worst_fix, i_fix = 0.0, np.int64(-1)
        # K dq where needed: row by row, or by one FFT product over the window when that is cheaper
        nfix = np.int64(0)
        for i in range(n):
            if kind[i] == UPPER or kind[i] == LOWER:
                nfix += 1
        wa, wb = (min(lo, s0), max(hi, s0 + L)) if L > 0 else (lo, hi)
        by_fft = hi > lo and _fft_cheaper(st, nfix, hi - lo)
        if by_fft:
            _k_product(st, dq, wa, wb)
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
                s = lam - (st.ku[i] if by_fft else _kdot(K, kf, i, dq, lo, hi))
                slip[i] = s
                wrong = -s if kind[i] == UPPER else s
                if wrong > tol:
                    n_viol += 1
                    if wrong > worst_fix:
                        worst_fix, i_fix = wrong, i
            else:
                slip[i] = 0.0
        if n_viol > 0:
            move_violators(kind, q, g, slip, tol, it, i_free, i_fix)
            continue
        # ---- converged sets: the named KKT residuals with the true K (not the updated inverse)
        stick_res, bound_res, dir_res, out_res = 0.0, 0.0, 0.0, 0.0
        s_total = 0.0
        if not by_fft and hi > lo and _fft_cheaper(st, n - nfix, hi - lo):
            _k_product(st, dq, wa, wb)
            by_fft = True
        for i in range(n):
            s_total += q[i]
            if kind[i] == FREE:
                stick_res = max(stick_res, abs(lam - (st.ku[i] if by_fft else _kdot(K, kf, i, dq, lo, hi))))
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
        if fast:
            _slot_fresh(st, slot, L)
        else:
            m = _inverse_rebuild(K, st)
        rebuilt = True
    st.counters[ITERATIONS] = it
    st.counters[M] = m
    if not converged:
        if not evaluated:  # no active set got as far as the residual check
            for j in range(5):
                res[j] = np.inf
        return lam, False
    state_codes(kind, slip, tol, codes)
    return lam, True


@jit
def zero_increment(g, q_prev, target, dx, tol, kind, q, dq, slip, codes, res):
    """Set the contact (released elements carry nothing, new ones start sticking), then try the zero increment.

    Whenever it is feasible (the previous tractions within the new bounds and
    carrying the load) it is the unique solution: writes the step's outputs
    and residuals and returns True. Otherwise returns False and writes nothing.
    """
    n = g.size
    for i in range(n):
        if g[i] <= 0.0:
            kind[i] = OUT
        elif kind[i] == OUT:
            kind[i] = FREE
    total = 0.0
    out_res = 0.0
    bound_res = 0.0
    for i in range(n):
        total += q_prev[i]
        if kind[i] == OUT:
            out_res = max(out_res, abs(q_prev[i]))
        else:
            bound_res = max(bound_res, abs(q_prev[i]) - g[i])
    if not (out_res == 0.0 and bound_res <= tol and abs(total - target) * dx <= tol):
        return False
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
    for j in range(5):
        res[j] = 0.0
    res[1] = max(bound_res, 0.0)
    res[4] = abs(total - target) * dx
    return True


@jit
def move_violators(kind, q, g, slip, tol, it, i_free, i_fix):
    """The active-set update: for the first :data:`PDAS_FULL_STEPS` iterations every violator moves (a
    sticking element past its bound to the bound, a bound element slipping against its traction back to
    stick: the primal-dual active set); after them only the worst, ``i_free`` or else ``i_fix``."""
    if it <= PDAS_FULL_STEPS:
        for i in range(kind.size):
            if kind[i] == FREE:
                if abs(q[i]) - g[i] > tol:
                    kind[i] = UPPER if q[i] > 0 else LOWER
            elif (kind[i] == UPPER and slip[i] < -tol) or (kind[i] == LOWER and slip[i] > tol):
                kind[i] = FREE
    elif i_free >= 0:
        kind[i_free] = UPPER if q[i_free] > 0 else LOWER
    else:
        kind[i_fix] = FREE


@jit
def record_step(k, q, codes, slip, res, total, dx, q_prev, traction, state, disp, diss, resid, worst):
    """Write step ``k``'s outputs (tractions, states, displacement, dissipation ``sum q s dx``, worst residual)
    and advance ``q_prev`` to ``q``."""
    d = 0.0
    for i in range(q.size):
        traction[k, i] = q[i]
        state[k, i] = codes[i]
        d += q[i] * slip[i]
        q_prev[i] = q[i]
    disp[k] = total
    diss[k] = d * dx
    r = 0.0
    for j in range(res.size):
        r = max(r, res[j])
        worst[j] = max(worst[j], res[j])
    resid[k] = r


@jit
def state_codes(kind, slip, tol, codes):
    """Element states (:class:`core.base.states.State`) from the active set and the slips: at a bound with no
    slip (within ``tol``) counts as stick."""
    for i in range(kind.size):
        if kind[i] == OUT:
            codes[i] = RELEASED
        elif kind[i] == UPPER and slip[i] > tol:
            codes[i] = SLIP_FORWARD
        elif kind[i] == LOWER and slip[i] < -tol:
            codes[i] = SLIP_BACKWARD
        else:
            codes[i] = STICK


@jit
def block_repeats(q, q_block_end, tol):
    """At the end of a block: whether it ended where the previous one did (then it repeats for ever); and
    remember where it ended."""
    same = True
    for i in range(q.size):
        if abs(q[i] - q_block_end[i]) > tol:
            same = False
            break
    q_block_end[:] = q
    return same


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
    steps = Q.size
    q_prev, q, slip, codes, res = st.q_prev, st.q, st.slip, st.codes, st.residuals
    for k in range(k0, k1):
        if st.counters[UPDATES] > REBUILD_EVERY:
            _inverse_rebuild(K, st)
        lam, ok = solve_step(K, bounds[k - k0], Q[k] * load_scale, dx, tol, maxiter, st)
        if not ok:
            return k, -1, k
        st.total[0] += lam
        record_step(k, q, codes, slip, res, st.total[0], dx, q_prev, traction, state, disp, diss, resid, worst)
        iters[k] = st.counters[ITERATIONS]
        if k + 1 < steps and period[k + 1] != period[k]:
            # end of a block: a period that ends where the previous one ended repeats for ever
            if block_repeats(q, st.q_block_end, tol) and detect_periodic and period[k] >= 0:
                return k + 1, period[k], -1
    return k1, -1, -1
