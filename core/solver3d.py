"""The 3D incremental tangential problem of a rocking point contact, matrix-free.

At each step the pressure ``p`` is the body's at the current centre (uncoupled,
Dundurs beta = 0: Hertz's for the sphere and ellipsoids, solved on the grid or
sampled, ``normal=``; a height map's solved numerically, :mod:`core.heightmap`) and the unknowns are the element tractions ``q`` (a vector
per element) and the rigid-body displacement increment ``lam = (lam_x,
lam_y)``. With ``K`` the half-space operator (:mod:`core.halfspace`) and
``dq = q - q_prev``, the slip increment of an element is ``s = lam - K dq``
(the sign convention of :mod:`core.solver`), and Coulomb's law reads

* ``|q_i| <= g_i = mu p_i`` (the Coulomb disk), ``q_i = 0`` out of contact;
* stick (``s_i = 0``) where ``|q_i| < g_i``;
* where ``s_i != 0``: ``q_i = g_i s_i/|s_i|`` (friction dissipates, ``q.s >= 0``);
* ``sum q_i dA = Ft`` (both components; ``lam`` their multipliers).

These are the KKT conditions of ``min 1/2 dq^T K dq`` over the disks and the
two force balances (a second-order-cone programme). :func:`solve_increment`
solves them by a semismooth Newton / active-set loop: stick elements are
free, slipping elements are held on the disk at their slip direction ``d``
with the tangential correction ``t d_perp`` free and the Newton curvature
``|s|/g`` on it (the linearisation of ``q = g s/|s|``); the linear system of
each iteration is solved by conjugate gradients projected on the force
balances, with FFT products and the inverse continuous symbol as
preconditioner (:meth:`core.halfspace.HalfSpaceOperator.precondition`), and
warm-started from the previous iteration and step. The zero increment is
checked first (it is the unique solution whenever it is feasible). A return
to an active set already solved (a cycle, from decisions taken on the noise
of inexact linear solves) switches to exact linear solves, then to one change
of kind per iteration; a step that still cannot settle raises an error naming
the KKT condition it cannot meet (:func:`_increment_kernel`).

The traction bound ``g = mu p`` of an element is the pressure of the discrete
normal problem on the same grid (same elements, collocation and Boussinesq
coefficients; :func:`core.patch._pressure`), as in CONTACT, rather than a sample of
Hertz's continuous pressure: the increments per period then agree with
CONTACT's to 0.25 % at 40 elements across the contact
(``docs/guide/numerics.md``).

Speed: each step is solved on the rectangle of elements that carry traction
before or after it (:class:`_Window`; the operator is a convolution, so its
block there is a smaller grid's operator), and the whole loop, FFT products
included, is compiled with numba (FFTs through ``rocket-fft``). In a
periodic history a step is warm-started from the same phase of the previous
period (kinds, slip directions, curvatures, correction), which predicts it
better than the step before: a third fewer active-set and CG iterations.
When the increment is mirror-symmetric in y (Ft along the rocking direction
x, an ellipsoid with its axes on the grid, ``nu > 0``: ``q_x`` even and
``q_y`` odd about ``y = 0``, since the solution is unique), every FFT product
is taken at half cost (:func:`core.halfspace.convolve_mirror`) and the
iterates are kept exactly symmetric, which also removes the asymmetric
round-off directions from CG (fewer CG iterations per step); the result equals
the full solver's to its tolerance (``tests/test_solver3d.py``).
Measured figures and iterations per step: ``benchmarks/solver3d.py``.

In the package this is the per-step solver of a patch of elements,
:class:`PatchSolver` (``"pcg3d"`` in :data:`core.engine.STEP_SOLVERS`), on a
point body's grid, :class:`core.patch.PatchGrid`: :func:`core.point_runs.solve_point_schedule`
builds them and calls :func:`core.engine.run`, the one run loop of every body,
which returns a :class:`core.CycleResult`.

References
----------
.. [1] J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990.
.. [2] E. A. H. Vollebregt, J. Comput. Phys. 257 (2014) 333-351; I. A. Polonsky,
   L. M. Keer, Wear 231 (1999) 206-219 (CG with FFT products).
.. [3] M. Hintermueller, K. Ito, K. Kunisch, SIAM J. Optim. 13 (2003) 865-888.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._jit import jit
from .halfspace import HalfSpaceOperator, convolve, convolve_mirror
# the point body's grid and bound (core/patch.py), kept importable from here
from .patch import MAX_GRID_ELEMENTS, PatchGrid, twist_field  # noqa: F401
from .resolution import DEFAULT_DX_POINT, GRID_DEFAULTS
from .result import PointContactResult  # noqa: F401 (kept importable from here)
from .states import RESIDUAL_NAMES as _RESIDUAL_NAMES, State

__all__ = ["solve_increment", "twist_field", "PatchGrid", "PatchSolver", "PatchTrajectory", "PointContactResult",
           "RESIDUAL_NAMES", "TOL_3D", "PERIODIC_TOL", "DEFAULT_DX_3D", "MAX_GRID_ELEMENTS"]

#: Names of the per-step residuals (see :func:`solve_increment`): the one set of every solver,
#: :data:`core.states.RESIDUAL_NAMES`.
RESIDUAL_NAMES = _RESIDUAL_NAMES
#: Default KKT tolerance of the 3D steps (tractions in mu p0, slips in mu Fn/(E* a), loads in mu Fn).
TOL_3D = GRID_DEFAULTS["patch"].tol
#: The patch solver's ``periodic_tol``: change of the traction [mu p0] between the ends of two blocks below
#: which the state counts as periodic (the one rule of :mod:`core.engine`; the line solvers' is their KKT
#: tolerance). The CG solves are inexact (forcing term :data:`_CG_FORCING`, acceptance at ``10 tol``), so a
#: period repeats to about ``10 TOL_3D``, not to round-off: 100 ``TOL_3D``.
PERIODIC_TOL = GRID_DEFAULTS["patch"].periodic_tol
#: Default element side [a] of point-contact runs. The increment per period of a ratcheting sphere (ft = 0.4,
#: w = 0.6) is 0.1742, 0.1779, 0.1790, 0.1797 at a/5, a/10, a/20, a/40 with the discrete normal bound
#: (benchmarks/solver3d.py): a/20 is 0.4 % below a/40, at an eighth of its cost.
DEFAULT_DX_3D = DEFAULT_DX_POINT  # one place for every body's default grid: core/resolution.py
#: Largest number of stored full-field values (snapshots at the turning points).
MAX_SNAPSHOT_VALUES = 2e7

# element kinds (internal)
_OUT, _STICK, _SLIP = 0, 1, 2
# active-set iterations that move every violator before moving only the worst ones
_FULL_MOVES = 6
# |s|/g, in units of the self-influence, above which slip directions take the Newton update
_NEWTON_CURV = 1.0
# warm-start each step from the same phase of the previous period (see solve_point_schedule)
_PHASE_WARM = True
# step of the sizes of the windows (see _Window)
_WINDOW_QUANTUM = 1
# inexact Newton: each linear solve reduces its residual to this fraction of the last KKT violation
_CG_FORCING = 1e-2
# active sets remembered for the detection of a cycle (see _increment_kernel)
_CYCLE_MEMORY = 16
# solve increments that are mirror-symmetric in y with half-cost FFT products (see _mirror_symmetric)
_MIRROR = True
# asymmetry [relative to the largest value] below which the inputs count as mirror-symmetric (round-off)
_MIRROR_RTOL = 1e-12


@dataclass
class _WarmStart:
    """Solver state carried from step to step: kinds, slip directions, Newton curvatures, last increment."""

    kind: np.ndarray
    d: np.ndarray
    curv: np.ndarray
    x: np.ndarray

    @classmethod
    def empty(cls, shape):
        return cls(np.zeros(shape, np.int8), np.zeros((2,) + shape), np.zeros(shape), np.zeros((2,) + shape))


@jit
def _symmetrize(v):
    """Make ``v[2, ny, nx]`` exactly mirror-symmetric about its centre row (``v_x`` even, ``v_y`` odd, so 0 on it).

    The products of :func:`~core.halfspace.convolve_mirror` read the upper half
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
    """:func:`~core.halfspace.convolve`, or its half-cost form for a field mirror-symmetric in y."""
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
    (:meth:`core.halfspace.HalfSpaceOperator.spectra`). Preconditioner: the
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


def _mirror(a, sign):
    """Copy the rows above the centre row of ``a[..., ny, nx]`` onto those below, times ``sign``, in place."""
    m = a.shape[-2] // 2
    a[..., :m, :] = sign * a[..., :m:-1, :]


def _mirror_symmetric(g, q_prev, target, warm):
    """Whether an increment is mirror-symmetric in y about the grid's centre row; if so, symmetrise its inputs.

    The bound, the previous traction (``q_x`` even, ``q_y`` odd) and the
    load (no y component) symmetric, to round-off, make the solution
    symmetric too, since it is unique: the Ft-along-x, rocking-along-x
    problem of an ellipsoid with its axes on the grid (the centre row on
    ``y = 0``). Then ``g``, ``q_prev`` (copies, returned) and the warm start
    (in place; a guess only) are made exactly symmetric, so that the solver
    may use :func:`~core.halfspace.convolve_mirror` throughout.

    Returns
    -------
    g, q_prev : ndarray or None
        Symmetrised copies, or None when the increment is not symmetric.
    """
    ny = g.shape[0]
    if not _MIRROR or ny % 2 == 0 or target[1] != 0.0:
        return None, None
    gs = max(float(g.max()), 1e-300)
    qs = max(float(np.abs(q_prev).max()), gs)
    if (np.abs(g - g[::-1]).max() > _MIRROR_RTOL * gs
            or np.abs(q_prev[0] - q_prev[0, ::-1]).max() > _MIRROR_RTOL * qs
            or np.abs(q_prev[1] + q_prev[1, ::-1]).max() > _MIRROR_RTOL * qs):
        return None, None
    g, q_prev = g.copy(), q_prev.copy()
    m = ny // 2
    q_prev[1, m] = 0.0
    warm.d[1, m] = 0.0
    warm.d[0, m] = np.sign(warm.d[0, m])
    warm.x[1, m] = 0.0
    for a, sign in ((g, 1.0), (q_prev[0], 1.0), (q_prev[1], -1.0), (warm.kind, 1), (warm.curv, 1.0),
                    (warm.d[0], 1.0), (warm.d[1], -1.0), (warm.x[0], 1.0), (warm.x[1], -1.0)):
        _mirror(a, sign)
    return g, q_prev


def _failure(status, stage, it, maxiter, cg_maxiter, tol, over, wrong, tangent, cg_res):
    """The message of an increment that did not settle: which KKT condition is not met, by how much, and why."""
    parts = []
    if over > tol:
        parts.append(f"a sticking traction above its bound by {over:.3g} [mu p0]")
    if wrong > tol:
        parts.append(f"a slip against its traction of {wrong:.3g}")
    if tangent > tol:
        parts.append(f"a slipping traction off its disk or a slip not parallel to it by {tangent:.3g}")
    if stage > 0 and cg_res > 0.5 * tol:  # stage 0 stops CG early on purpose (inexact Newton)
        parts.append(f"the linear solve of the last active set reaching only {cg_res:.3g} in {cg_maxiter} CG iterations")
    unmet = "; ".join(parts) or "no single condition above the tolerance in the last iterate"
    stages = ("inexact linear solves", "exact linear solves", "exact linear solves and one change of kind per iteration")
    if status == 2:
        why = (f"the active set cycled even with {stages[2]} (the last fallback): the problem is degenerate to "
               f"the tolerance {tol:g}; a larger tol would accept it")
    else:
        why = f"the active set did not settle in {maxiter} iterations (last stage: {stages[stage]})"
    return f"{why}; unmet: {unmet} (worst violation {max(over, wrong):.3g})"


def _moment_residual(q, twist, target, dA):
    """``|sum twist . q dA - target[2]|`` over the largest arm: the moment balance as a force [mu p0 a^2]."""
    arm = max(float(np.abs(twist).max()), 1e-300)
    moment = float(np.sum(twist * q)) * dA
    return abs(moment - (float(target[2]) if len(target) > 2 else 0.0)) / arm


def solve_increment(op, g, q_prev, target, dA, warm, tol=TOL_3D, maxiter=200, cg_maxiter=500, twist=None):
    """Solve one increment of the 3D tangential problem (see the module docstring).

    Parameters
    ----------
    op : HalfSpaceOperator
        The elastic operator of the grid.
    g : ndarray, shape (ny, nx)
        Traction bounds ``mu p`` [mu p0]; 0 out of contact.
    q_prev : ndarray, shape (2, ny, nx)
        Tractions after the previous step [mu p0].
    target : ndarray, shape (2,) or (3,)
        Required ``sum q dA`` [mu p0 a^2]; with ``twist``, a third entry: the
        required moment ``sum twist . q dA`` [mu p0 a^3] (0 if omitted).
    dA : float
        Element area [a^2].
    warm : _WarmStart
        Kinds, slip directions, curvatures and last increment; updated in place.
    tol : float
        KKT tolerance (tractions [mu p0], slips [displacement unit]).
    maxiter, cg_maxiter : int
        Largest numbers of active-set and CG iterations.
    twist : ndarray, shape (2, ny, nx), optional
        The body is also free to turn about the normal: the rigid slip of a
        unit rotation at each element (:func:`twist_field`, ``(-(y - y_c), x -
        x_c)`` [a]). The increment then has a third rigid unknown, the rotation
        ``phi`` [displacement unit / a], with the slip ``lam + phi twist - K
        dq`` and the moment balance above; ``lam`` is the translation of
        ``(x_c, y_c)``. Default None: no rotation (the two force balances only).

    Returns
    -------
    q : ndarray, shape (2, ny, nx)
        Tractions.
    s : ndarray, shape (2, ny, nx)
        Slip increments (0 where sticking or out of contact).
    lam : ndarray, shape (2,)
        Rigid-body displacement increment.
    info : dict
        ``iterations`` (active set), ``cg_iterations``, ``fallback`` (the
        stage of the cycle fallback reached: 0 none, 1 exact linear solves, 2
        one change of kind per iteration; see :func:`_increment_kernel`),
        ``twist`` (``phi``, 0 without ``twist``) and the residuals of
        :data:`RESIDUAL_NAMES` (``load_balance`` in ``sum q dA`` units; with
        the twist, also the moment's residual over the largest arm).

    Raises
    ------
    RuntimeError
        If the iteration does not settle within ``maxiter``, or cycles in the
        last fallback stage; the message names the KKT condition not met, by
        how much, and the stage.
    """
    # one compiled specialisation: C-contiguous, writeable float64 (int8 kinds) arrays
    g, q_prev = (np.require(a, np.float64, ["C", "W"]) for a in (g, q_prev))
    warm.kind = np.require(warm.kind, np.int8, ["C", "W"])
    warm.d, warm.curv, warm.x = (np.require(a, np.float64, ["C", "W"]) for a in (warm.d, warm.curv, warm.x))
    target = np.asarray(target, dtype=float)
    if twist is not None:
        twist = np.require(twist, np.float64, ["C", "W"])
        if twist.shape != q_prev.shape:
            raise ValueError(f"twist must have the shape {q_prev.shape} of q_prev, got {twist.shape}")
        target = np.concatenate([target[:3], np.zeros(3 - min(target.size, 3))])
    contact = g > 0
    kind, d = warm.kind, warm.d
    kind[~contact] = _OUT
    kind[contact & (kind == _OUT)] = _STICK
    mag_prev = np.hypot(q_prev[0], q_prev[1])
    # ---- the zero increment, if feasible, is the unique solution
    balance = np.abs(q_prev.sum(axis=(1, 2)) * dA - target[:2]).max()
    if twist is not None:
        balance = max(balance, _moment_residual(q_prev, twist, target, dA))
    if (not np.any(q_prev[:, ~contact])) and np.all(mag_prev <= g + tol) and balance <= tol:
        kind[(kind == _SLIP) & (mag_prev < g - tol)] = _STICK
        warm.x[:] = 0.0
        zero = np.zeros_like(q_prev)
        info = dict(iterations=0, cg_iterations=0, stick_slip=0.0, bound=max(float((mag_prev - g).max()), 0.0),
                    slip_direction=0.0, out_of_contact=0.0, load_balance=float(balance))
        info["fallback"] = 0
        info["twist"] = 0.0
        return q_prev.copy(), zero, np.zeros(2), info
    measure = max(float((mag_prev - g).max()), balance)
    # at nu = 0 the y problem decouples and the full products keep q_y exactly 0 (the half-cost ones to round-off)
    tv = twist
    mirror_ok = op.nu > 0
    if twist is not None and mirror_ok:
        # a mirror-symmetric increment has no moment about a point on the centre row (q_x even, q_y odd against
        # twist_x odd, twist_y even): the rotation is 0 by symmetry and the half-cost path drops it; a centre off
        # that row (or a moment required) breaks the symmetry
        ny = g.shape[0]
        ts = max(float(np.abs(twist).max()), 1e-300)
        mirror_ok = (ny % 2 == 1 and target[2] == 0.0
                     and np.abs(twist[0] + twist[0, ::-1]).max() <= _MIRROR_RTOL * ts
                     and np.abs(twist[1] - twist[1, ::-1]).max() <= _MIRROR_RTOL * ts)
    gm, qm = _mirror_symmetric(g, q_prev, target[:2], warm) if mirror_ok else (None, None)
    mirror = gm is not None
    if mirror:
        g, q_prev = gm, qm
        tv = None
    q, s, lam, Kdq, x, stick, it, cg_total, status, stage, over, wrong, tangent, cg_res = _increment_kernel(
        op.spectra(), op.self_influence, g, q_prev, target, float(dA), kind, d, warm.curv, warm.x,
        float(tol), int(maxiter), int(cg_maxiter), float(measure), mirror, tv)
    if status != 0:
        raise RuntimeError(_failure(status, stage, it, maxiter, cg_maxiter, tol, over, wrong, tangent, cg_res))
    if mirror:  # exactly symmetric results (the solver's sums leave round-off in the lower half)
        for a, sign in ((q[0], 1.0), (q[1], -1.0), (s[0], 1.0), (s[1], -1.0), (Kdq[0], 1.0), (Kdq[1], -1.0),
                        (x[0], 1.0), (x[1], -1.0), (stick, True)):
            _mirror(a, sign)
        lam[1] = 0.0
    warm.x = x
    slipping = np.hypot(s[0], s[1]) > 0
    qn = np.hypot(q[0], q[1])
    e = q / np.where(qn > 0, qn, 1.0)
    along = e[0] * s[0] + e[1] * s[1]
    direction = np.where(slipping, np.maximum(np.abs(e[0] * s[1] - e[1] * s[0]), -along), 0.0)
    rigid = lam[:2, None, None] + (lam[2] * tv if tv is not None else 0.0)
    load = float(np.abs(q.sum(axis=(1, 2)) * dA - target[:2]).max())
    if twist is not None:
        load = max(load, _moment_residual(q, twist, target, dA))
    info = dict(
        iterations=it, cg_iterations=cg_total, fallback=int(stage), twist=float(lam[2]),
        stick_slip=float(np.abs(np.where(stick, rigid - Kdq, 0.0)).max()),
        bound=max(float((np.hypot(q[0], q[1]) - g).max()), 0.0),
        slip_direction=float(direction.max()),
        out_of_contact=float(np.abs(q[:, ~contact]).max()) if (~contact).any() else 0.0,
        load_balance=load,
    )
    return q, s, lam[:2].copy(), info


class _Window:
    """Solve each increment on the rectangle of elements that carry traction before or after it.

    The operator is a convolution, so the block of the whole grid's operator on
    a rectangle of elements is the operator of a grid of the rectangle's size,
    wherever the rectangle sits: out of it the tractions are zero before and
    after the step, and slips there are not needed. The FFTs shrink from the
    whole rocking range to the contact's size. Widths are rounded up to a
    multiple of :data:`_WINDOW_QUANTUM` elements so that a few operators serve a run.

    It is the elastic operator of a patch grid as :func:`core.engine.run` sees
    it: ``shape`` ``(ny, nx)``, ``size`` (elements) and ``nu``.
    """

    def __init__(self, ny, nx, h, nu, scale):
        self.shape, self.args = (ny, nx), (h, nu, scale)
        self.size = ny * nx
        self.nu = nu
        self.ops = {}

    def operator(self, shape):
        op = self.ops.get(shape)
        if op is None:
            op = self.ops[shape] = HalfSpaceOperator(*shape, *self.args)
        return op

    @staticmethod
    def _span(used, n):
        idx = np.flatnonzero(used)
        i0, i1 = (int(idx[0]), int(idx[-1]) + 1) if idx.size else (0, 1)
        width = min(n, -(-(i1 - i0) // _WINDOW_QUANTUM) * _WINDOW_QUANTUM)
        lo = min(max(i0 - (width - (i1 - i0)) // 2, 0), n - width)
        return slice(lo, lo + width)

    def solve(self, g, q_prev, target, dA, warm, tol, **options):
        """:func:`solve_increment` on the window; ``options`` (``maxiter``, ``cg_maxiter``, a body's own) pass to it
        (a ``twist`` field, given on the whole grid, cut to the window)."""
        used = (g > 0) | (q_prev != 0).any(axis=0)
        win = (self._span(used.any(axis=1), self.shape[0]), self._span(used.any(axis=0), self.shape[1]))
        if options.get("twist") is not None:
            options = dict(options, twist=np.ascontiguousarray(options["twist"][(slice(None),) + win]))
        part = _WarmStart(*(np.ascontiguousarray(a[(Ellipsis,) + win]) for a in (warm.kind, warm.d, warm.curv, warm.x)))
        try:
            q, s, lam, info = solve_increment(self.operator(part.kind.shape), np.ascontiguousarray(g[win]),
                                              np.ascontiguousarray(q_prev[(slice(None),) + win]), target, dA, part, tol,
                                              **options)
        finally:
            warm.kind[win], warm.d[(slice(None),) + win], warm.curv[win] = part.kind, part.d, part.curv
        warm.x = np.zeros_like(warm.x)
        warm.x[(slice(None),) + win] = part.x
        q_full, s_full = np.zeros_like(q_prev), np.zeros_like(q_prev)
        q_full[(slice(None),) + win], s_full[(slice(None),) + win] = q, s
        return q_full, s_full, lam, info


def _state_codes(q, s, g, tol):
    """Element states (:class:`core.states.State`): released out of contact, stick, slip forward where the slip
    increment's x component is >= 0, slip backward where it is < 0 (a slip increment longer than ``tol``)."""
    codes = np.where(g > 0, State.STICK, State.RELEASED).astype(np.int8)
    slipping = (np.hypot(s[0], s[1]) > tol) & (g > 0)
    codes[slipping & (s[0] >= 0)] = State.SLIP_FORWARD
    codes[slipping & (s[0] < 0)] = State.SLIP_BACKWARD
    return codes


def _turning_points(schedule):
    xc, per = schedule.xc, schedule.period
    steps = []
    for k in range(1, xc.size - 1):
        if per[k] >= 0 and ((xc[k] > xc[k - 1] and xc[k] >= xc[k + 1]) or (xc[k] < xc[k - 1] and xc[k] <= xc[k + 1])):
            steps.append(k)
    return steps


class PatchTrajectory:
    """The per-step outputs of a march on a patch of elements (:class:`PatchSolver`).

    Per step: the rigid-body displacement ``(steps, 2)``, the traction and the
    states on the cut ``y = 0`` (``traction`` ``(steps, 2, nx)``, ``state``
    ``(steps, nx)``), dissipation, iterations and the named residuals
    (``step_residuals``, and their worst ``kkt_residual``); the full fields
    at ``snapshot_steps`` only (``traction_snapshots``, ``state_snapshots``).
    """

    def __init__(self, steps, shape, snapshot_steps):
        ny, nx = shape
        self.row = ny // 2
        self.displacement = np.zeros((steps, 2))
        self.traction = np.zeros((steps, 2, nx))
        self.state = np.zeros((steps, nx), np.int8)
        self.dissipation = np.zeros(steps)
        self.iterations = np.zeros(steps, np.int64)
        self.cg_iterations = np.zeros(steps, np.int64)
        self.kkt_residual = np.zeros(steps)
        self.step_residuals = {name: np.zeros(steps) for name in RESIDUAL_NAMES}
        self.snapshot_steps = np.array(snapshot_steps, dtype=np.int64)
        self.snap_index = {int(k): i for i, k in enumerate(snapshot_steps)}
        self.traction_snapshots = np.zeros((len(snapshot_steps), 2, ny, nx))
        self.state_snapshots = np.zeros((len(snapshot_steps), ny, nx), np.int8)
        self.last_traction = None
        #: A body free to turn about the normal (a ``twist`` solver option): its rotation after each step.
        self.rotation = None
        self._turned = 0.0

    def record(self, k, q, codes, total, info):
        """Store step ``k``: traction ``q`` (2, ny, nx), states, displacement so far, the solver's ``info``."""
        self.displacement[k] = total
        self.traction[k], self.state[k] = q[:, self.row], codes[self.row]
        self.iterations[k], self.cg_iterations[k] = info["iterations"], info["cg_iterations"]
        for name in RESIDUAL_NAMES:
            self.step_residuals[name][k] = info[name]
        self.kkt_residual[k] = max(info[name] for name in RESIDUAL_NAMES)
        if self.rotation is not None:
            self._turned += info["twist"]
            self.rotation[k] = self._turned
        if k in self.snap_index:
            self.traction_snapshots[self.snap_index[k]], self.state_snapshots[self.snap_index[k]] = q, codes
        self.last_traction = q

    def copied(self):
        """The per-step arrays a repeated period copies as they are (the displacement advances, iterations are 0)."""
        return [self.traction, self.state, self.dissipation, self.kkt_residual, *self.step_residuals.values()]

    def advancing(self):
        """The per-step arrays a repeated period advances by its increment: the displacement, and the rotation
        of a body free to turn."""
        return [self.displacement] + ([] if self.rotation is None else [self.rotation])

    def repeat_snapshots(self, done, rest, src):
        """Fill the snapshots of the repeated steps ``rest`` (copies of steps ``src``)."""
        for kk in self.snapshot_steps.tolist():
            if kk >= done:
                j = int(src[kk - done])
                stored = j in self.snap_index
                self.traction_snapshots[self.snap_index[kk]] = (self.traction_snapshots[self.snap_index[j]] if stored
                                                                else self.last_traction)
                self.state_snapshots[self.snap_index[kk]] = (self.state_snapshots[self.snap_index[j]] if stored
                                                             else self.state_snapshots[0])

    def residuals(self) -> dict:
        """Worst of each named residual over the steps."""
        return {name: float(v.max()) if v.size else 0.0 for name, v in self.step_residuals.items()}

    def result_fields(self) -> dict:
        """The per-step fields of a :class:`core.result.CycleResult` on a patch."""
        return dict(traction=self.traction, state=self.state, displacement=self.displacement,
                    dissipation=self.dissipation, iterations=self.iterations, cg_iterations=self.cg_iterations,
                    kkt_residual=self.kkt_residual, snapshot_steps=self.snapshot_steps,
                    traction_snapshots=self.traction_snapshots, state_snapshots=self.state_snapshots,
                    step_residuals=self.step_residuals,
                    **({} if self.rotation is None else {"rotation": self.rotation}))


class PatchSolver:
    """The per-step solver of a patch of elements (``"pcg3d"`` in :data:`core.engine.STEP_SOLVERS`).

    Each increment is the 3D active-set / projected-CG solve of
    :func:`solve_increment` on the window of elements carrying traction
    (:class:`_Window`), warm-started from the same phase of the previous period
    in a periodic history. It has the protocol of :class:`core.dense.DenseSolver`
    and :class:`core.matrix_free.FFTSolver` (``march``, ``step``, ``residuals``),
    so :func:`core.engine.run` chunks, cancels, budgets, reports progress,
    detects the periodic state and repeats the last period the same way for
    every grid.

    Parameters
    ----------
    operator : _Window
        The windowed half-space operator of the grid (``shape`` ``(ny, nx)``).
    element_size : float
        Element area ``dx^2`` [a^2] (the load balance is ``sum q dA``).
    tol : float
        KKT tolerance of every step; a step whose worst residual exceeds ``10 tol`` fails.
    maxiter : int, optional
        Active-set iterations per step (default 200).
    angle : float
        Angle of ``Ft`` to x [rad]: the target of step ``k`` is ``Q[k] load_scale (cos, sin)``.
    periodic_tol : float
        Traction tolerance [mu p0] of the periodic detection (:data:`PERIODIC_TOL`):
        the CG solves are inexact, so a repeated period repeats to about ``10 tol``, not to round-off.
    **options
        Passed to every :func:`solve_increment` (a body's own options, :attr:`PatchGrid.solver_options`).
    """

    name = "pcg3d"
    #: Its main compiled kernel (:data:`core._jit.KERNELS`): a run says once that it compiles it if it is not cached.
    kernels = ("core.solver3d._increment_kernel",)
    #: The operator form it needs: the windowed half-space operator of a patch grid.
    form = "patch"
    #: The grid shape it solves.
    grid = "patch"

    def __init__(self, operator, *, element_size, tol, maxiter=None, angle=0.0, periodic_tol=PERIODIC_TOL, **options):
        self.window = operator
        self.shape = tuple(operator.shape)
        self.dA = float(element_size)
        self.tol = float(tol)
        self.maxiter = self.default_maxiter(operator.size) if maxiter is None else int(maxiter)
        self.angle = float(angle)
        self.direction = np.array([math.cos(self.angle), math.sin(self.angle)])
        self.periodic_tol = float(periodic_tol)
        self.options = dict(options)
        self.q = np.zeros((2,) + self.shape)
        self.q_block_end = np.zeros_like(self.q)
        self.warm = _WarmStart.empty(self.shape)
        self.total = 0.0 * self.direction
        self.period_steps = 0
        self.phase_warm = {}
        self.failure = ""
        self._residuals = dict.fromkeys(RESIDUAL_NAMES, 0.0)

    @staticmethod
    def default_maxiter(n):
        """Active-set iterations per step: 200 (the semismooth Newton steps do not grow with the grid)."""
        return 200

    @staticmethod
    def trajectory(history, shape):
        """The :class:`PatchTrajectory` of ``history`` on a ``(ny, nx)`` grid, with its snapshot steps: the end
        of the loading, the turning points and the last step (the last period's only, beyond
        :data:`MAX_SNAPSHOT_VALUES`)."""
        ny, nx = shape
        steps = len(history)
        turning = set(_turning_points(history))
        load_end = int(np.flatnonzero(history.period < 0)[-1]) if (history.period < 0).any() else -1
        snap_all = sorted(turning | {load_end, steps - 1} - {-1})
        if len(snap_all) * 3 * ny * nx > MAX_SNAPSHOT_VALUES:  # keep the last period's turning points only
            last = set(np.flatnonzero(history.period == history.period[-1]).tolist())
            snap_all = sorted((turning & last) | {load_end, steps - 1} - {-1})
        return PatchTrajectory(steps, shape, snap_all)

    def start(self, history):
        """Before the march: in a periodic history, warm-start each step from the same phase one period earlier."""
        self.period_steps = (int(np.count_nonzero(history.period == 0)) if _PHASE_WARM and history.is_periodic()
                             else 0)

    @property
    def traction(self):
        """Tractions after the last step, shape (2, ny, nx)."""
        return self.q

    @property
    def residuals(self) -> dict:
        """The named residuals of the last step."""
        return dict(self._residuals)

    def step(self, bound, target):
        """Solve one increment from the current tractions and advance to it.

        Parameters
        ----------
        bound : ndarray, shape (ny, nx)
            Traction bound ``mu p`` [mu p0].
        target : array_like, shape (2,)
            Required ``sum q dA`` [mu p0 a^2].

        Returns
        -------
        core.dense.StepReport
            With the traction (2, ny, nx), the states, the displacement increment (2,).
        """
        from .dense import StepReport
        try:
            q, s, lam, info = self.window.solve(bound, self.q, np.asarray(target, float), self.dA, self.warm,
                                                self.tol, maxiter=self.maxiter, **self.options)
        except RuntimeError as e:
            self.failure = str(e)
            self._residuals = dict.fromkeys(RESIDUAL_NAMES, math.inf)
            return StepReport(traction=self.q.copy(), state=_state_codes(self.q, 0 * self.q, bound, self.tol),
                              displacement=np.zeros(2), iterations=self.maxiter, residuals=self.residuals,
                              converged=False)
        self._residuals = {name: info[name] for name in RESIDUAL_NAMES}
        ok = max(self._residuals.values()) <= 10.0 * self.tol
        if ok:
            self.q = q
            self.total = self.total + lam
        return StepReport(traction=q, state=_state_codes(q, s, bound, self.tol), displacement=lam,
                          iterations=int(info["iterations"]), residuals=self.residuals, converged=bool(ok),
                          cg_iterations=int(info["cg_iterations"]))

    def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out: PatchTrajectory):
        """Solve steps ``k0:k1`` in order (``bounds[k - k0]``: the bound ``(ny, nx)`` of step ``k``; target
        ``Q[k] load_scale`` along ``angle``).

        Returns
        -------
        (reached, periodic_from, failed) : tuple of int
            As :meth:`core.dense.DenseSolver.march`; a failed step leaves its
            reason in :attr:`failure`.
        """
        steps = Q.size
        if self.options.get("twist") is not None and out.rotation is None:  # free to turn: record the rotation
            out.rotation = np.zeros(steps)
        for k in range(int(k0), int(k1)):
            g = bounds[k - k0]
            per = int(period[k])
            target = Q[k] * load_scale * self.direction
            if k - self.period_steps in self.phase_warm:  # the same phase one period earlier predicts this step best
                self.warm = self.phase_warm.pop(k - self.period_steps)
            # ---- solve the increment
            try:
                q, s, lam, info = self.window.solve(g, self.q, target, self.dA, self.warm, self.tol,
                                                    maxiter=self.maxiter, **self.options)
            except RuntimeError as e:
                self.failure = str(e)
                self._residuals = dict.fromkeys(RESIDUAL_NAMES, math.inf)
                return k, -1, k
            self._residuals = {name: info[name] for name in RESIDUAL_NAMES}
            if not max(self._residuals.values()) <= 10.0 * self.tol:
                self.failure = "residual above tolerance"
                return k, -1, k
            # ---- record it
            out.dissipation[k] = float(np.vdot(q, s)) * self.dA / load_scale
            if self.period_steps and per >= 0:
                w = self.warm
                self.phase_warm[k] = _WarmStart(w.kind.copy(), w.d.copy(), w.curv.copy(), w.x.copy())
            self.q = q
            self.total = self.total + lam
            out.record(k, q, _state_codes(q, s, g, self.tol), self.total, info)
            # ---- periodic detection: a period that ends where the previous block ended repeats for ever
            if k + 1 < steps and period[k + 1] != per:
                same = float(np.abs(q - self.q_block_end).max()) <= self.periodic_tol
                self.q_block_end = q.copy()
                if same and detect_periodic and per >= 0:
                    return k + 1, per, -1
        return int(k1), -1, -1


