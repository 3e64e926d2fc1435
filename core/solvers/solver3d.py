"""The 3D incremental tangential problem of a rocking point contact, matrix-free.

At each step the pressure ``p`` is the body's at the current centre (uncoupled,
Dundurs beta = 0: Hertz's for the sphere and ellipsoids, solved on the grid or
sampled, ``normal=``; a height map's solved numerically, :mod:`core.geometry.heightmap`) and the unknowns are the element tractions ``q`` (a vector
per element) and the rigid-body displacement increment ``lam = (lam_x,
lam_y)``. With ``K`` the half-space operator (:mod:`core.elastic.halfspace`) and
``dq = q - q_prev``, the slip increment of an element is ``s = lam - K dq``
(the sign convention of :mod:`core.api.solver`), and Coulomb's law reads

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
preconditioner (:meth:`core.elastic.halfspace.HalfSpaceOperator.precondition`), and
warm-started from the previous iteration and step. The zero increment is
checked first (it is the unique solution whenever it is feasible). A return
to an active set already solved (a cycle, from decisions taken on the noise
of inexact linear solves) switches to exact linear solves, then to one change
of kind per iteration; a step that still cannot settle raises an error naming
the KKT condition it cannot meet (:func:`_increment_kernel`).

The traction bound ``g = mu p`` of an element is the pressure of the discrete
normal problem on the same grid (same elements, collocation and Boussinesq
coefficients; :func:`core.geometry.patch._pressure`), as in CONTACT, rather than a sample of
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
is taken at half cost (:func:`core.elastic.halfspace.convolve_mirror`) and the
iterates are kept exactly symmetric, which also removes the asymmetric
round-off directions from CG (fewer CG iterations per step); the result equals
the full solver's to its tolerance (``tests/test_solver3d.py``).
Measured figures and iterations per step: ``benchmarks/solver3d.py``.

In the package this is the per-step solver of a patch of elements,
:class:`PatchSolver` (``"pcg3d"`` in :data:`core.march.engine.STEP_SOLVERS`), on a
point body's grid, :class:`core.geometry.patch.PatchGrid`: :func:`core.api.point_runs.solve_point_schedule`
builds them and calls :func:`core.march.engine.run`, the one run loop of every body,
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

# the compiled kernels (core/solvers/_pcg3d.py) and their constants, kept importable from here
from ._pcg3d import (_CG_FORCING, _CYCLE_MEMORY, _FULL_MOVES, _NEWTON_CURV, _OUT, _SLIP, _STICK,  # noqa: F401
                     _convolve, _increment_kernel, _inverse3, _pcg_kernel, _precondition, _project, _signature,
                     _symmetrize)
from ..elastic.halfspace import HalfSpaceOperator
# the point body's grid and bound (core/geometry/patch.py), kept importable from here
from ..geometry.patch import MAX_GRID_ELEMENTS, PatchGrid, twist_field  # noqa: F401
from ..geometry.resolution import DEFAULT_DX_POINT, GRID_DEFAULTS
from ..records.result import PointContactResult  # noqa: F401 (kept importable from here)
from ..base.states import RESIDUAL_NAMES as _RESIDUAL_NAMES, State

__all__ = ["solve_increment", "twist_field", "PatchGrid", "PatchSolver", "PatchTrajectory", "PointContactResult",
           "RESIDUAL_NAMES", "TOL_3D", "PERIODIC_TOL", "DEFAULT_DX_3D", "MAX_GRID_ELEMENTS"]

#: Names of the per-step residuals (see :func:`solve_increment`): the one set of every solver,
#: :data:`core.base.states.RESIDUAL_NAMES`.
RESIDUAL_NAMES = _RESIDUAL_NAMES
#: Default KKT tolerance of the 3D steps (tractions in mu p0, slips in mu Fn/(E* a), loads in mu Fn).
TOL_3D = GRID_DEFAULTS["patch"].tol
#: The patch solver's ``periodic_tol``: change of the traction [mu p0] between the ends of two blocks below
#: which the state counts as periodic (the one rule of :mod:`core.march.engine`; the line solvers' is their KKT
#: tolerance). The CG solves are inexact (forcing term :data:`_CG_FORCING`, acceptance at ``10 tol``), so a
#: period repeats to about ``10 TOL_3D``, not to round-off: 100 ``TOL_3D``.
PERIODIC_TOL = GRID_DEFAULTS["patch"].periodic_tol
#: Default element side [a] of point-contact runs. The increment per period of a ratcheting sphere (ft = 0.4,
#: w = 0.6) is 0.1742, 0.1779, 0.1790, 0.1797 at a/5, a/10, a/20, a/40 with the discrete normal bound
#: (benchmarks/solver3d.py): a/20 is 0.4 % below a/40, at an eighth of its cost.
DEFAULT_DX_3D = DEFAULT_DX_POINT  # one place for every body's default grid: core/geometry/resolution.py
#: Largest number of stored full-field values (snapshots at the turning points).
MAX_SNAPSHOT_VALUES = 2e7

# warm-start each step from the same phase of the previous period (see solve_point_schedule)
_PHASE_WARM = True
# step of the sizes of the windows (see _Window)
_WINDOW_QUANTUM = 1
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
    may use :func:`~core.elastic.halfspace.convolve_mirror` throughout.

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

    It is the elastic operator of a patch grid as :func:`core.march.engine.run` sees
    it: ``shape`` ``(ny, nx)``, ``size`` (elements) and ``nu``; its elements
    are ``h`` by ``hy`` (default ``h``: square; a cone's are longer along its
    line, :attr:`core.geometry.cone.Cone.aspect`).
    """

    def __init__(self, ny, nx, h, nu, scale, hy=None):
        self.shape, self.args = (ny, nx), (h, nu, scale)
        self.hy = None if hy is None or hy == h else float(hy)
        self.size = ny * nx
        self.nu = nu
        self.ops = {}

    def operator(self, shape):
        op = self.ops.get(shape)
        if op is None:
            op = self.ops[shape] = HalfSpaceOperator(*shape, *self.args, hy=self.hy)
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
    """Element states (:class:`core.base.states.State`): released out of contact, stick, slip forward where the slip
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
        """The per-step fields of a :class:`core.records.result.CycleResult` on a patch."""
        return dict(traction=self.traction, state=self.state, displacement=self.displacement,
                    dissipation=self.dissipation, iterations=self.iterations, cg_iterations=self.cg_iterations,
                    kkt_residual=self.kkt_residual, snapshot_steps=self.snapshot_steps,
                    traction_snapshots=self.traction_snapshots, state_snapshots=self.state_snapshots,
                    step_residuals=self.step_residuals,
                    **({} if self.rotation is None else {"rotation": self.rotation}))


class PatchSolver:
    """The per-step solver of a patch of elements (``"pcg3d"`` in :data:`core.march.engine.STEP_SOLVERS`).

    Each increment is the 3D active-set / projected-CG solve of
    :func:`solve_increment` on the window of elements carrying traction
    (:class:`_Window`), warm-started from the same phase of the previous period
    in a periodic history. It has the protocol of :class:`core.solvers.dense.DenseSolver`
    and :class:`core.solvers.matrix_free.FFTSolver` (``march``, ``step``, ``residuals``),
    so :func:`core.march.engine.run` chunks, cancels, budgets, reports progress,
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
    #: Its main compiled kernel (:data:`core.base._jit.KERNELS`): a run says once that it compiles it if it is not cached.
    kernels = ("core.solvers._pcg3d._increment_kernel",)
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
        core.solvers.dense.StepReport
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
            As :meth:`core.solvers.dense.DenseSolver.march`; a failed step leaves its
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


