"""The compiled kernels of the patch solver (:mod:`core.solvers.solver3d`): numba building blocks and the increment's loop.

The projected preconditioned conjugate gradients on a patch of square
elements (:func:`_pcg_kernel`, with the mirror-symmetric products of
:func:`core.elastic.halfspace.convolve_mirror`) and the semismooth Newton / active-set
loop of one increment of the tangential problem (:func:`_increment_kernel`).
:func:`core.solvers.solver3d.solve_increment` sets their inputs up and reads their
status; the method, its references and its measured figures are in
:mod:`core.solvers.solver3d`'s docstring. Plain functions over plain arrays, compiled
once per process (and cached on disk, :mod:`core.base._jit`).
"""

from __future__ import annotations

import math

import numpy as np

from ..base._jit import jit
from ..elastic.halfspace import convolve, convolve_mirror

__all__ = ["_increment_kernel", "_pcg_kernel", "_project", "_precondition", "_convolve", "_symmetrize", "_inverse3",
           "_signature"]

# element kinds (internal)
_OUT, _STICK, _SLIP = 0, 1, 2
# active-set iterations that move every violator before moving only the worst ones
_FULL_MOVES = 6
# |s|/g, in units of the self-influence, above which slip directions take the Newton update
_NEWTON_CURV = 1.0
# inexact Newton: each linear solve reduces its residual to this fraction of the last KKT violation
_CG_FORCING = 1e-2
# active sets remembered for the detection of a cycle (see _increment_kernel)
_CYCLE_MEMORY = 16


@jit
def _symmetrize(v):
    """Make ``v[2, ny, nx]`` exactly mirror-symmetric about its centre row (``v_x`` even, ``v_y`` odd, so 0 on it).

    The products of :func:`~core.elastic.halfspace.convolve_mirror` read the upper half
    only, so the lower half's round-off would sit in a direction the operator
    does not see; keeping every iterate symmetric removes it.
    """
    ny, nx = v.shape[1], v.shape[2]
    m = ny // 2
    for j in range(nx):
        v[1, m, j] = 0.0
    for k in range(1, m + 1):
        for j in range(nx):
            v[0, m - k, j] = v[0, m + k, j]
            v[1, m - k, j] = -v[1, m + k, j]


@jit
def _project(pxx, pyy, pxy, minv, v, out, mirror, tv=None):
    """``out = P v``: the orthogonal projection on {x in V, C x = 0}, compiled.

    V holds both components on stick elements and ``d_perp`` on slipping ones:
    ``P_i = [[pxx, pxy], [pxy, pyy]]`` per element (the identity, ``d_perp
    d_perp^T`` or 0). ``C`` holds the constraints: the two force sums, and with
    the twist (``tv``, the rigid slip ``(-(y - y_c), x - x_c)`` of a unit
    rotation about the normal at each element) the moment ``sum tv . x``;
    ``minv`` is the inverse of ``M = C P C^T`` (2 x 2, or 3 x 3 with the
    twist) and ``P C^T M^-1 C P v`` is removed from ``P v``.
    """
    ny, nx = pxx.shape
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(ny):
        for j in range(nx):
            a, b = v[0, i, j], v[1, i, j]
            y0 = pxx[i, j] * a + pxy[i, j] * b
            y1 = pxy[i, j] * a + pyy[i, j] * b
            out[0, i, j] = y0
            out[1, i, j] = y1
            s0 += y0
            s1 += y1
            if tv is not None:
                s2 += tv[0, i, j] * y0 + tv[1, i, j] * y1
    if tv is None:
        m0 = minv[0, 0] * s0 + minv[0, 1] * s1
        m1 = minv[1, 0] * s0 + minv[1, 1] * s1
        for i in range(ny):
            for j in range(nx):
                out[0, i, j] -= pxx[i, j] * m0 + pxy[i, j] * m1
                out[1, i, j] -= pxy[i, j] * m0 + pyy[i, j] * m1
    else:
        m0 = minv[0, 0] * s0 + minv[0, 1] * s1 + minv[0, 2] * s2
        m1 = minv[1, 0] * s0 + minv[1, 1] * s1 + minv[1, 2] * s2
        m2 = minv[2, 0] * s0 + minv[2, 1] * s1 + minv[2, 2] * s2
        for i in range(ny):
            for j in range(nx):
                c0 = m0 + m2 * tv[0, i, j]
                c1 = m1 + m2 * tv[1, i, j]
                out[0, i, j] -= pxx[i, j] * c0 + pxy[i, j] * c1
                out[1, i, j] -= pxy[i, j] * c0 + pyy[i, j] * c1
    if mirror:
        _symmetrize(out)


@jit
def _convolve(q, hxx, hyy, hxy, py, px, mirror):
    """:func:`~core.elastic.halfspace.convolve`, or its half-cost form for a field mirror-symmetric in y."""
    if mirror:
        return convolve_mirror(q, hxx, hyy, hxy, py, px)
    return convolve(q, hxx, hyy, hxy, py, px)


@jit
def _precondition(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, mirror, tv=None):
    """``z = P M r``: the inverse continuous symbol on the stick set, ``r/(curv + K_ii)`` on slip corrections."""
    ny, nx = stick.shape
    w = np.empty((2, ny, nx))
    for c in range(2):
        for i in range(ny):
            for j in range(nx):
                w[c, i, j] = r[c, i, j] if stick[i, j] else 0.0
    zs = _convolve(w, spec[5], spec[6], spec[7], spec[8], spec[9], mirror)
    for c in range(2):
        for i in range(ny):
            for j in range(nx):
                if not stick[i, j]:
                    zs[c, i, j] = r[c, i, j] * slip_diag[i, j]
    _project(pxx, pyy, pxy, minv, zs, z, mirror, tv)


@jit
def _pcg_kernel(spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x, Kdq, tol, maxiter, mirror, tv=None):
    """Projected preconditioned CG for ``P (K dq + curv x) = 0``, ``dq = dq_fixed + x``, ``x`` in V.

    ``Kdq`` is ``K dq`` of the starting ``x``; both are updated in place.
    ``spec`` holds the spectra of the operator and of its preconditioner
    (:meth:`core.elastic.halfspace.HalfSpaceOperator.spectra`). Preconditioner: the
    inverse continuous symbol on the stick set, the inverse diagonal
    ``1/(curv + K_ii)`` on the tangential corrections of slipping elements.
    With ``tv`` (the twist's rigid slip field) the projection also holds the
    moment (:func:`_project`). Returns the iterations and the largest residual component.
    """
    ny, nx = stick.shape
    r = np.empty((2, ny, nx))
    z = np.empty((2, ny, nx))
    Ap = np.empty((2, ny, nx))
    tmp = np.empty((2, ny, nx))
    for c in range(2):
        tmp[c] = -Kdq[c] - curv * x[c]
    _project(pxx, pyy, pxy, minv, tmp, r, mirror, tv)
    rmax = np.abs(r).max()
    if rmax <= tol or maxiter <= 0:
        # the start already solves it (the warm start of a step that is nearly settled: half of a cone's
        # active-set iterations late in a run): no preconditioner product for an iteration that will not come
        return 0, rmax
    _precondition(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, mirror, tv)
    p = z.copy()
    rz = np.sum(r * z)
    its = 0
    # the vector updates in fused loops (no temporaries): a third of a step's time went to them
    # rz == 0: the preconditioned residual vanishes (a zero residual, or one so small that r.z underflows, as with
    # the huge Newton curvatures of elements whose bound is a tiny numerically solved pressure): CG can make no
    # progress and beta = rz_new / rz would divide by zero, so it stops (the caller checks the KKT conditions)
    while its < maxiter and rmax > tol and rz != 0.0:
        its += 1
        Kp = _convolve(p, spec[0], spec[1], spec[2], spec[3], spec[4], mirror)
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    tmp[c, i, j] = Kp[c, i, j] + curv[i, j] * p[c, i, j]
        _project(pxx, pyy, pxy, minv, tmp, Ap, mirror, tv)
        pAp = 0.0
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    pAp += p[c, i, j] * Ap[c, i, j]
        if not pAp > 0.0:
            break
        alpha = rz / pAp
        rmax = 0.0
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    x[c, i, j] += alpha * p[c, i, j]
                    Kdq[c, i, j] += alpha * Kp[c, i, j]
                    r[c, i, j] -= alpha * Ap[c, i, j]
                    rmax = max(rmax, abs(r[c, i, j]))
        _precondition(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, mirror, tv)
        rz_new = 0.0
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    rz_new += r[c, i, j] * z[c, i, j]
        if rz_new == 0.0:
            break
        beta = rz_new / rz
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    p[c, i, j] = z[c, i, j] + beta * p[c, i, j]
        rz = rz_new
    return its, rmax


@jit
def _inverse3(m00, m01, m02, m11, m12, m22, out):
    """``out`` = the inverse of the symmetric 3 x 3 matrix ``[[m00, m01, m02], [m01, m11, m12], [m02, m12, m22]]``."""
    c00 = m11 * m22 - m12 * m12
    c01 = m02 * m12 - m01 * m22
    c02 = m01 * m12 - m02 * m11
    c11 = m00 * m22 - m02 * m02
    c12 = m01 * m02 - m00 * m12
    c22 = m00 * m11 - m01 * m01
    det = m00 * c00 + m01 * c01 + m02 * c02
    out[0, 0], out[0, 1], out[0, 2] = c00 / det, c01 / det, c02 / det
    out[1, 0], out[1, 1], out[1, 2] = c01 / det, c11 / det, c12 / det
    out[2, 0], out[2, 1], out[2, 2] = c02 / det, c12 / det, c22 / det


@jit
def _signature(kind):
    """A 64-bit FNV-1a hash of the element kinds: equal active sets give equal signatures."""
    h = np.uint64(14695981039346656037)
    prime = np.uint64(1099511628211)
    for i in range(kind.shape[0]):
        for j in range(kind.shape[1]):
            h = (h ^ np.uint64(kind[i, j] + 1)) * prime
    return h


@jit
def _increment_kernel(spec, k_self, g, q_prev, target, dA, kind, d, wcurv, x, tol, maxiter, cg_maxiter, measure,
                      mirror, tv=None):
    """The active-set / semismooth Newton loop of :func:`solve_increment`, compiled.

    Updates ``kind``, ``d`` and ``wcurv`` in place; returns the final traction
    (slipping elements on the disk), the slips (0 where sticking), ``lam``,
    ``K dq``, the stick part of the last correction, the stick mask, the
    iterations, the CG iterations, the status (0 converged, 1 out of
    iterations, 2 a cycle that the last fallback did not break), the fallback
    stage reached and the last violations (bound, slip direction, tangential
    correction, linear residual).

    Cycles. The linear solves are inexact (inexact Newton: CG stops at
    :data:`_CG_FORCING` times the last violation), so near the solution an
    element whose traction is at its bound with a slip close to zero (a weakly
    active element) can be tested against the noise of the linear solve: it
    slips with a slip against its traction of the size of that noise, sticks
    with a traction above its bound, and so on for ever (seen at ft 0.65, w 0.3,
    a/40, step 77: violations 9e-8 against CG residuals of 3e-6). Every active
    set solved is remembered (a hash, :func:`_signature`); coming back to one
    is a cycle, and the loop falls back, one stage per cycle: (1) exact linear
    solves (CG to a tenth of ``tol``), so that every decision is taken on a
    solution accurate to the tolerance; (2) in addition, only the worst
    violator changes its kind per iteration (a least-violation pivoting rule,
    as Murty's for P-matrix LCPs), with the slip directions iterated to
    convergence between changes. A cycle in stage 2 stops with status 2.

    Twist. With ``tv`` (shape ``(2, ny, nx)``: the rigid slip ``(-(y - y_c),
    x - x_c)`` of a unit rotation about the normal at each element) the
    increment has a third rigid unknown, the rotation ``phi`` about the
    normal through ``(x_c, y_c)``: the slip is ``s = lam + phi tv - K dq``,
    and the moment ``sum tv . q dA`` is held at ``target[2]`` (its
    multiplier is ``phi``; ``lam`` is then the translation of the point
    ``(x_c, y_c)``). Returned ``lam`` has three entries, ``phi`` last (0
    without the twist). Without ``tv`` numba compiles the kernel without the
    twist's terms (the ``tv is None`` branches are pruned).
    """
    ny, nx = g.shape
    contact = g > 0.0
    for i in range(ny):
        for j in range(nx):
            if not contact[i, j]:
                kind[i, j] = _OUT
            elif kind[i, j] == _OUT:
                kind[i, j] = _STICK
            mag = math.hypot(q_prev[0, i, j], q_prev[1, i, j])
            # predicted active set: what is above its new bound slips back along its traction
            if contact[i, j] and kind[i, j] == _STICK and mag > g[i, j]:
                kind[i, j] = _SLIP
                d[0, i, j] = q_prev[0, i, j] / mag
                d[1, i, j] = q_prev[1, i, j] / mag
                wcurv[i, j] = 0.0
    pxx = np.empty((ny, nx))
    pyy = np.empty((ny, nx))
    pxy = np.empty((ny, nx))
    base = np.empty((2, ny, nx))
    curv = np.empty((ny, nx))
    slip_diag = np.empty((ny, nx))
    x0 = np.empty((2, ny, nx))
    s = np.zeros((2, ny, nx))
    q = np.empty((2, ny, nx))
    Kdq = np.empty((2, ny, nx))
    stick = np.zeros((ny, nx), np.bool_)
    slip = np.zeros((ny, nx), np.bool_)
    over = np.empty((ny, nx))  # the violations of this iteration's check (bound on stick, direction on slip)
    wrong = np.empty((ny, nx))
    minv = np.zeros((3, 3))  # the 2 x 2 block without the twist
    lam = np.zeros(3)
    cg_total = 0
    worst = np.inf
    over_max = wrong_max = tangent = cg_res = np.inf
    status = 1
    stage = 0
    seen = np.zeros(_CYCLE_MEMORY, np.uint64)
    nseen = 0
    it = 0
    while it < maxiter:
        it += 1
        nstick = 0
        for i in range(ny):
            for j in range(nx):
                if kind[i, j] == _STICK:
                    nstick += 1
        if nstick == 0:  # the force balances need at least one free element
            bi, bj, bg = 0, 0, -1.0
            for i in range(ny):
                for j in range(nx):
                    if contact[i, j] and g[i, j] > bg:
                        bi, bj, bg = i, j, g[i, j]
            kind[bi, bj] = _STICK
            nstick = 1
        if tv is not None:
            if nstick == 1:  # the moment needs a second free element (two positions make M regular)
                bi, bj, bg = -1, -1, -1.0
                for i in range(ny):
                    for j in range(nx):
                        if contact[i, j] and kind[i, j] != _STICK and g[i, j] > bg:
                            bi, bj, bg = i, j, g[i, j]
                if bi >= 0:
                    kind[bi, bj] = _STICK
        # ---- the projector of this active set and the fixed part of the traction
        m00 = m01 = m11 = m02 = m12 = m22 = 0.0
        b0 = b1 = b2 = 0.0
        for i in range(ny):
            for j in range(nx):
                st = kind[i, j] == _STICK
                sl = kind[i, j] == _SLIP
                stick[i, j], slip[i, j] = st, sl
                if sl:
                    e0, e1 = -d[1, i, j], d[0, i, j]  # d_perp
                    pxx[i, j], pyy[i, j], pxy[i, j] = e0 * e0, e1 * e1, e0 * e1
                    base[0, i, j], base[1, i, j] = g[i, j] * d[0, i, j], g[i, j] * d[1, i, j]
                    curv[i, j] = wcurv[i, j]
                else:
                    f = 1.0 if st else 0.0
                    pxx[i, j], pyy[i, j], pxy[i, j] = f, f, 0.0
                    base[0, i, j], base[1, i, j] = f * q_prev[0, i, j], f * q_prev[1, i, j]
                    curv[i, j] = 0.0
                slip_diag[i, j] = 1.0 / (curv[i, j] + k_self)
                m00 += pxx[i, j]
                m11 += pyy[i, j]
                m01 += pxy[i, j]
                b0 += base[0, i, j]
                b1 += base[1, i, j]
                if tv is not None:
                    t0, t1 = tv[0, i, j], tv[1, i, j]
                    m02 += pxx[i, j] * t0 + pxy[i, j] * t1
                    m12 += pxy[i, j] * t0 + pyy[i, j] * t1
                    m22 += t0 * (pxx[i, j] * t0 + pxy[i, j] * t1) + t1 * (pxy[i, j] * t0 + pyy[i, j] * t1)
                    b2 += t0 * base[0, i, j] + t1 * base[1, i, j]
        D0, D1, D2 = target[0] / dA - b0, target[1] / dA - b1, 0.0
        if tv is None:
            det = m00 * m11 - m01 * m01  # > 0: at least one stick element
            minv[0, 0], minv[0, 1], minv[1, 0], minv[1, 1] = m11 / det, -m01 / det, -m01 / det, m00 / det
        else:  # M = C P C^T with the moment's row: regular with two stick elements at different places
            D2 = target[2] / dA - b2
            _inverse3(m00, m01, m02, m11, m12, m22, minv)
        c0 = minv[0, 0] * D0 + minv[0, 1] * D1 + minv[0, 2] * D2
        c1 = minv[1, 0] * D0 + minv[1, 1] * D1 + minv[1, 2] * D2
        c2 = minv[2, 0] * D0 + minv[2, 1] * D1 + minv[2, 2] * D2
        # ---- the linear problem of this active set (warm start projected on its space, plus the particular part)
        _project(pxx, pyy, pxy, minv, x, x0, False, tv)
        for i in range(ny):
            for j in range(nx):
                e0, e1 = c0, c1
                if tv is not None:
                    e0 += c2 * tv[0, i, j]
                    e1 += c2 * tv[1, i, j]
                x0[0, i, j] += pxx[i, j] * e0 + pxy[i, j] * e1
                x0[1, i, j] += pxy[i, j] * e0 + pyy[i, j] * e1
        if mirror:
            _symmetrize(x0)
        Kdq = _convolve(base - q_prev + x0, spec[0], spec[1], spec[2], spec[3], spec[4], mirror)
        cg_tol = 0.1 * tol if stage > 0 else max(0.1 * tol, _CG_FORCING * measure)
        its, cg_res = _pcg_kernel(spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x0, Kdq, cg_tol, cg_maxiter,
                                  mirror, tv)
        x = x0.copy()
        cg_total += its
        # ---- the multipliers, the traction and the slips
        y0 = y1 = y2 = 0.0
        for i in range(ny):
            for j in range(nx):
                v0 = Kdq[0, i, j] + curv[i, j] * x[0, i, j]
                v1 = Kdq[1, i, j] + curv[i, j] * x[1, i, j]
                w0 = pxx[i, j] * v0 + pxy[i, j] * v1
                w1 = pxy[i, j] * v0 + pyy[i, j] * v1
                y0 += w0
                y1 += w1
                if tv is not None:
                    y2 += tv[0, i, j] * w0 + tv[1, i, j] * w1
        lam[0] = minv[0, 0] * y0 + minv[0, 1] * y1 + minv[0, 2] * y2
        lam[1] = minv[1, 0] * y0 + minv[1, 1] * y1 + minv[1, 2] * y2
        lam[2] = minv[2, 0] * y0 + minv[2, 1] * y1 + minv[2, 2] * y2
        # ---- check: bounds on the stick set, slip direction on the slip set
        over_max = -np.inf
        wrong_max = -np.inf
        tangent = 0.0
        over[:] = -np.inf
        wrong[:] = -np.inf
        for i in range(ny):
            for j in range(nx):
                for c in range(2):
                    q[c, i, j] = base[c, i, j] + x[c, i, j]
                    rigid = lam[c]
                    if tv is not None:
                        rigid += lam[2] * tv[c, i, j]
                    s[c, i, j] = rigid - Kdq[c, i, j] if contact[i, j] else 0.0
                if stick[i, j]:
                    over[i, j] = math.hypot(q[0, i, j], q[1, i, j]) - g[i, j]
                    over_max = max(over_max, over[i, j])
                elif slip[i, j]:
                    wrong[i, j] = -(d[0, i, j] * s[0, i, j] + d[1, i, j] * s[1, i, j])
                    wrong_max = max(wrong_max, wrong[i, j])
                    t = -d[1, i, j] * x[0, i, j] + d[0, i, j] * x[1, i, j]
                    # off the disk by t; the slip then has the normal component curv t
                    tangent = max(tangent, abs(t * max(1.0, curv[i, j])))
        worst = max(over_max, wrong_max)
        measure = max(worst, tangent)
        if worst <= tol and tangent <= tol and cg_res <= 0.5 * tol:
            status = 0
            break
        if stage == 2 and tangent > tol and worst <= max(tol, tangent):
            worst = -np.inf  # stage 2: converge the slip directions before the next change of kind
        if worst > tol:
            # this active set is about to change: remember it, and detect a return to an earlier one
            sig = _signature(kind)
            if nseen < _CYCLE_MEMORY:
                seen[nseen] = sig
                nseen += 1
            else:
                for k in range(_CYCLE_MEMORY - 1):
                    seen[k] = seen[k + 1]
                seen[_CYCLE_MEMORY - 1] = sig
            level = tol if it <= _FULL_MOVES and stage == 0 else max(tol, 0.5 * worst)
            if stage == 2:
                level = max(tol, (1.0 - 1e-12) * worst)
            for i in range(ny):
                for j in range(nx):
                    if over[i, j] > level:
                        kind[i, j] = _SLIP
                        mag = math.hypot(q[0, i, j], q[1, i, j])
                        mag = mag if mag > 0 else 1.0
                        d[0, i, j], d[1, i, j] = q[0, i, j] / mag, q[1, i, j] / mag
                        wcurv[i, j] = 0.0
                    if wrong[i, j] > level:
                        kind[i, j] = _STICK
                        x[0, i, j] = x[1, i, j] = 0.0
            sig = _signature(kind)
            for k in range(nseen):
                if seen[k] == sig:  # a cycle: next fallback stage, or give up
                    if stage == 2:
                        status = 2
                    stage += 1
                    nseen = 0
                    break
            if status == 2:
                break
        # ---- Newton update of the slip directions and their curvature |s|/g: where the slip dominates (|s|/g
        # above the self-influence) linearise q = g s/|s| about the slip direction (semismooth Newton); elsewhere
        # follow the corrected traction
        for i in range(ny):
            for j in range(nx):
                if slip[i, j] and kind[i, j] == _SLIP:
                    nq = math.hypot(q[0, i, j], q[1, i, j])
                    ns = math.hypot(s[0, i, j], s[1, i, j])
                    cn = ns / g[i, j]
                    if cn > _NEWTON_CURV * k_self:
                        ns = ns if ns > 0 else 1.0
                        d[0, i, j], d[1, i, j] = s[0, i, j] / ns, s[1, i, j] / ns
                    else:
                        nq = nq if nq > 0 else 1.0
                        d[0, i, j], d[1, i, j] = q[0, i, j] / nq, q[1, i, j] / nq
                    wcurv[i, j] = cn
                    x[0, i, j] = x[1, i, j] = 0.0
    # ---- the final traction: slipping elements exactly on the disk; slips where slipping only
    for i in range(ny):
        for j in range(nx):
            if slip[i, j]:
                q[0, i, j], q[1, i, j] = g[i, j] * d[0, i, j], g[i, j] * d[1, i, j]
            if not contact[i, j]:
                q[0, i, j] = q[1, i, j] = 0.0
            if not (slip[i, j] and math.hypot(s[0, i, j], s[1, i, j]) > tol):
                s[0, i, j] = s[1, i, j] = 0.0
            if not stick[i, j]:
                x[0, i, j] = x[1, i, j] = 0.0
    return q, s, lam, Kdq, x, stick, it, cg_total, status, min(stage, 2), over_max, wrong_max, tangent, cg_res
