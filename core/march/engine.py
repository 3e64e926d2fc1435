"""One run function: a body on a grid, an elastic operator, a per-step solver and a loading history give a result.

:func:`run` marches a :class:`~core.loading.schedule.Schedule` (the loading history as
data) step by step, whatever the grid's shape: a line of elements (the line
contacts: cylinder, punch, sampled profiles; the 1D operators of
:mod:`core.elastic.operators`) or a patch of square elements (the point contacts:
sphere, ellipsoid, height map; the half-space operator of
:mod:`core.elastic.halfspace`). The body gives the traction bound of every element at
every step, the per-step solver solves the KKT conditions of each increment on
the operator, and the per-step arrays become a frozen
:class:`~core.records.result.CycleResult`. Chunking, cancelling, the time budget,
progress, the periodic detection's stop and the repetition of the last period
live here once, for every grid and solver. The public entry points
(:func:`core.simulate_cycles`, :func:`core.simulate_contact`,
:func:`core.solve_schedule`, :func:`core.api.point_runs.solve_point_schedule`)
build the parts and call it.

The per-step solvers are chosen by name in :data:`STEP_SOLVERS`, the one place
where a solver is registered: ``"dense"`` and ``"fft"`` for a line,
``"pcg3d"`` for a patch (:data:`SOLVER_CHOICES_BY_GRID`).

**The body protocol** (what a discretised body gives :func:`run`):

``shape``
    ``(n,)`` for a line, ``(ny, nx)`` for a patch (:func:`grid_shape`); equal to the operator's.
``dx``, ``edges``
    Element width [a] and the edges along x (a patch also has ``y_edges``); the
    element measure of the load balance is ``dx`` (line) or ``dx^2`` (patch).
``bounds(xc, P, out)``
    The traction bound ``mu p`` [mu p0] of each step with the centres ``xc``
    and normal loads ``P``: a line grid fills ``out`` (steps, n); a patch grid
    returns one ``(ny, nx)`` array a step (shared and cached: a translating
    body is solved once per offset and load, not per step).
``load_target(Q)``
    The sum of the element tractions (times the element measure, for a patch)
    that carries ``Q``; ``load_target(1.0)`` is the solver's load scale.
``name``, ``body_spec``
    The body's name and the body object (with its parameters), kept on the result.
``solver_options`` (patch, optional)
    A dict of keyword options of the per-step solver that the body needs (e.g.
    a cone's twist centre), merged into ``solver_options``.

A point body object (e.g. :class:`core.theory.point_contact.Ellipsoid`) becomes a
patch grid through :class:`core.geometry.patch.PatchGrid`, which asks it for: its
run grid (``run_grid(reach_x, scale, h)``; default: the box of its Hertz
ellipse, ``kappa``), its pressure on the grid at a step
(``grid_pressure(x_edges, y_edges, xc, scale)``; default: Hertz's, solved on
the grid or in closed form), ``kernel_scale``, ``total_load`` and, optionally,
``load_scale(P)`` (the length scale ``scale`` of its contact under the normal
load ``P``; default ``P^(1/3)``), ``default_dx`` and ``solver_options`` (a
dict of keyword options of :func:`core.solvers.solver3d.solve_increment`, e.g. a
cone's twist centre, passed on every step). ``tests/test_engine.py`` defines
such a body in the test file alone and runs it. A line body object
(:class:`core.geometry.bodies.Body`) becomes a line grid through ``body.grid(history, dx, ...)``.

**The per-step solver protocol.** A class of :data:`STEP_SOLVERS` has ``name``, ``form`` (the operator form it
needs), ``grid`` (``"line"`` or ``"patch"``), ``default_maxiter(n)``,
``trajectory(history, shape)`` (the per-step arrays it fills: ``displacement``,
``iterations``, ``cg_iterations``, ``copied()``, ``advancing()``; a patch's
also its snapshots), is built as ``cls(operator, element_size=, tol=, maxiter=,
**solver_options)``, may have ``start(history)`` (called once before the
march), and has ``step(bound, target)``, ``residuals`` (the named residuals of
:data:`core.base.states.RESIDUAL_NAMES` of the last step), ``periodic_tol`` and
``march(bounds, Q, period, load_scale, k0, k1, periodic, out) -> (reached,
periodic_from, failed)``.

**The periodic detection (one rule).** At the end of every block of steps (the loading, then each period) the
solver compares the tractions with those at the end of the previous block;
if no element differs by more than its ``periodic_tol`` [mu p0] and the
block is a period of a history whose periods all have the same steps
(:meth:`core.loading.schedule.Schedule.is_periodic`), that period repeats for ever:
the march stops and :func:`run` copies it for the remaining periods (the
displacement advancing by its increment each time). ``periodic_tol`` is the
KKT tolerance for the exact line solvers and :data:`core.solvers.solver3d.PERIODIC_TOL`
for the patch solver, whose inexact CG solves repeat a period only to about
ten times its tolerance.
"""

from __future__ import annotations

import functools
import time

import numpy as np

from ..pressure import melan
from ..base._jit import announce_compile
from ..geometry.bodies import MAX_ELEMENTS
from ..solvers.coupled import CoupledSolver
from ..solvers.dense import DenseSolver, Trajectory
from ..solvers.matrix_free import FFTSolver
from ..elastic.operators import elastic_operator
from ..records.result import CycleResult, SolveCancelled, SolverError
from ..loading.schedule import Schedule
from ..solvers.solver3d import PatchSolver

__all__ = ["run", "solve_step", "STEP_SOLVERS", "SOLVER_CHOICES", "SOLVER_CHOICES_BY_GRID", "AUTO_CROSSOVER", "select_solver",
           "make_operator", "grid_shape", "Trajectory"]

#: The per-step solvers by name: each is built as ``cls(operator, element_size=, tol=, maxiter=, **options)``
#: and has ``name``, ``form`` (the operator form it needs), ``grid`` (the grid shape it solves), ``march``,
#: ``step`` and ``residuals`` (the protocol in the module docstring; :class:`core.solvers.dense.DenseSolver`,
#: :class:`core.solvers.matrix_free.FFTSolver`, :class:`core.solvers.solver3d.PatchSolver`).
STEP_SOLVERS = {"dense": DenseSolver, "fft": FFTSolver, "pcg3d": PatchSolver, "coupled": CoupledSolver}
#: The values of the ``solver`` keyword for a line contact.
SOLVER_CHOICES = ("auto", "dense", "fft")
#: The values of the ``solver`` keyword by grid shape (``"auto"`` picks one of the others). ``"coupled"``
#: (:class:`core.solvers.coupled.CoupledSolver`) solves the normal and tangential problems together: chosen by the
#: entry points when Dundurs' ``beta != 0``; given by name at ``beta = 0`` it reproduces the uncoupled run.
SOLVER_CHOICES_BY_GRID = {"line": SOLVER_CHOICES + ("coupled",), "patch": ("auto", "pcg3d")}
#: Elements above which ``solver="auto"`` picks "fft", measured by ``benchmarks/solver.py`` (docs/dev/
#: benchmarks.md): the dense solver (interval inverses of the Toeplitz matrix, FFT residuals) is faster per
#: rocking step at every size up to its grid cap (about 5x at 3800 elements: 1.1 ms against 5.6 ms a step,
#: 2 cores shared), so "auto" runs it up to :data:`core.geometry.bodies.MAX_ELEMENTS` and the matrix-free one above,
#: up to :data:`core.geometry.bodies.MAX_FFT_ELEMENTS`.
AUTO_CROSSOVER = MAX_ELEMENTS


def grid_shape(body) -> str:
    """``"line"`` or ``"patch"``: the shape of a discretised body's grid (its ``shape`` has 1 or 2 entries)."""
    dims = len(body.shape)
    if dims not in (1, 2):
        raise ValueError(f"a body's grid must be a line (n,) or a patch (ny, nx), got shape {body.shape}")
    return "line" if dims == 1 else "patch"


def check_solver(solver, shape="line", body=None):
    """``solver`` if it is valid for a grid of ``shape``, else ValueError naming the valid choices."""
    choices = SOLVER_CHOICES_BY_GRID[shape]
    if not isinstance(solver, str) or solver not in choices:
        name = body if isinstance(body, str) else getattr(body, "name", None)
        what = f"the {name} (a {shape} of elements)" if name else f"a {shape} of elements"
        other = [s for s, c in STEP_SOLVERS.items() if c.grid != shape]
        hint = (f" ({', '.join(repr(s) for s in other)} solve{'s' if len(other) == 1 else ''} the other grid "
                f"shape)" if solver in other else "")
        raise ValueError(f"solver must be one of {choices} for {what}, got {solver!r:.60}{hint}")
    return solver


def select_solver(solver, n, shape="line"):
    """The per-step solver class for ``solver`` on ``n`` unknowns of a grid of ``shape`` (``"line"``, ``"patch"``).

    ``"auto"`` is ``"fft"`` above :data:`AUTO_CROSSOVER` elements of a line,
    ``"dense"`` below, and ``"pcg3d"`` on a patch.

    Raises
    ------
    ValueError
        If ``solver`` is not one of ``SOLVER_CHOICES_BY_GRID[shape]``.
    """
    check_solver(solver, shape)
    if solver == "auto":
        solver = "pcg3d" if shape == "patch" else ("fft" if n > AUTO_CROSSOVER else "dense")
    return STEP_SOLVERS[solver]


def make_operator(step_solver, n, dx, kernel="plane", **options):
    """The elastic operator (:mod:`core.elastic.operators`) of a line grid in the form ``step_solver`` needs.

    The dense matrix only for the dense solver; the FFT form (the kernel's
    column and its circulant spectra, never an ``n x n`` matrix) for the
    matrix-free one.

    Parameters
    ----------
    step_solver : type
        A line class of :data:`STEP_SOLVERS` (its ``form``: ``"dense"`` or ``"fft"``).
    n, dx, kernel, **options :
        As in :func:`core.elastic.operators.elastic_operator`.
    """
    return elastic_operator(n, dx, kernel, form=step_solver.form, **options)


def solve_step(operator, bound, target, *, solver="auto", element_size, tol, maxiter=None, solver_options=None):
    """A static solve: one increment from zero tractions, on a line or a patch, by the grid's per-step solver.

    The one path of :func:`core.solve_static` for both grids (a static solve
    is a run of one step): the solver class of :data:`STEP_SOLVERS` that
    :func:`select_solver` picks for the bound's shape, built as :func:`run`
    builds it, and its ``step``.

    Parameters
    ----------
    operator : object
        The grid's elastic operator in the form the solver needs (:func:`make_operator` for a line, the
        windowed half-space operator for a patch).
    bound : ndarray, shape (n,) or (ny, nx)
        Traction bound [mu p0].
    target : float or array_like of 2
        The load ``sum q`` (times the element measure on a patch) to carry.
    solver, element_size, tol, maxiter, solver_options :
        As in :func:`run` (``element_size``: ``dx`` on a line, ``dx^2`` on a patch).

    Returns
    -------
    core.solvers.dense.StepReport

    Raises
    ------
    SolverError
        If the step's KKT residuals are not within the tolerance.
    """
    shape = "line" if np.ndim(bound) == 1 else "patch"
    n = int(np.size(bound))
    cls = select_solver(solver, n, shape)
    announce_compile(*getattr(cls, "kernels", ()))  # once per process, before a first solve's compiling
    step_solver = cls(operator, element_size=element_size, tol=tol,
                      maxiter=cls.default_maxiter(n) if maxiter is None else maxiter, **dict(solver_options or {}))
    report = step_solver.step(bound, target)
    if not report.converged:
        raise SolverError(0, 0.0, max(report.residuals.values()),
                          getattr(step_solver, "failure", "") or "static partial slip")
    return report


def run(body, operator, history, *, solver="auto", tol, maxiter=None, detect_periodic=True, shakedown_rtol=1e-3,
        params=None, time_budget=None, cancel=None, progress=None, chunk=256, kernel="plane", u0=None,
        solver_options=None):
    """March a loading history on a discretised body with an elastic operator and a per-step solver.

    Parameters
    ----------
    body : object
        A discretised body, a line of elements (:class:`core.geometry.bodies.Cylinder`
        on a grid, :class:`core.geometry.bodies.LineGrid`) or a patch
        (:class:`core.geometry.patch.PatchGrid`): see the protocol in the module docstring.
    operator : object
        Elastic operator on the body's grid (:mod:`core.elastic.operators` for a line,
        :func:`make_operator` builds the form the solver needs; the windowed
        half-space operator for a patch).
    history : Schedule
        The steps.
    solver : str
        A name of :data:`STEP_SOLVERS` valid for the grid's shape, or ``"auto"``
        (see :func:`select_solver`).
    tol, maxiter, detect_periodic, shakedown_rtol, params, time_budget, cancel, progress, chunk :
        As in :func:`core.solve_schedule` (validated there). ``maxiter`` None:
        the solver's ``default_maxiter(n)``.
    kernel, u0 :
        Recorded on the result.
    solver_options : dict, optional
        Keyword options of the per-step solver (a patch: ``angle``,
        ``periodic_tol``, the body's ``solver_options``).

    Returns
    -------
    CycleResult
    """
    if not isinstance(history, Schedule):
        raise ValueError(f"history must be a core.Schedule, got {type(history).__name__}")
    t0 = time.perf_counter()
    n = operator.size
    if tuple(body.shape) != tuple(operator.shape):
        raise ValueError(f"the operator's shape {tuple(operator.shape)} differs from the body's grid {body.shape}")
    shape = grid_shape(body)
    cls = select_solver(solver, n, shape)
    maxiter = cls.default_maxiter(n) if maxiter is None else maxiter
    announce_compile(*getattr(cls, "kernels", ()))  # once per process, before a first run's minute of compiling
    element_size = body.dx if shape == "line" else body.dx * body.dy  # a patch's elements may be rectangles (a cone)
    options = dict(solver_options or {})
    coupled = bool(getattr(cls, "coupled", False))
    if coupled:  # it solves the pressure on the body's grid, from the body's profile
        options["grid"] = body
    step_solver = cls(operator, element_size=element_size, tol=tol, maxiter=maxiter, **options)
    if hasattr(step_solver, "start"):
        step_solver.start(history)
    steps = len(history)
    out = cls.trajectory(history, body.shape)
    periodic = bool(detect_periodic) and history.is_periodic()
    load_scale = float(body.load_target(1.0))
    # the bound of every step, kept for the result: a line grid fills the rows of one array; a patch grid returns
    # one (ny, nx) array per step (shared between the steps with the same centre and load)
    line_bounds = None if shape != "line" else (_StepBounds if coupled else _LineBounds)(body, history)
    patch_bounds = [] if shape == "patch" else None
    # mu p_min of the last period: tracked over the history's last block as it is marched (or, when the march
    # stops at a repeated period, over that period's bounds at the end)
    lowest, last_block = _Lowest(), int(history.period[-1])
    done, periodic_from = 0, -1
    budget_end = None if time_budget is None else t0 + time_budget
    while done < steps:
        k1 = min(steps, done + chunk)
        bounds = (body.bounds(history.xc[done:k1], history.P[done:k1]) if line_bounds is None
                  else line_bounds.rows(done, k1))
        reached, periodic_from, failed = step_solver.march(bounds, history.Q, history.period, load_scale, done, k1,
                                                           periodic, out)
        lowest.add(bounds, history.period[done:reached], last_block)
        if patch_bounds is not None:
            patch_bounds.extend(bounds[:reached - done])
        if failed >= 0:
            res = max(step_solver.residuals.values())
            reason = getattr(step_solver, "failure", "") or (
                "the active set did not settle" if np.isfinite(res) else "no feasible active set")
            raise SolverError(failed, history.xc[failed], res, reason)
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
    index = np.arange(steps)  # the row of the stored bounds of each step: a copied step's is its source's
    if done < steps:
        _repeat_last_period(history.period, done, periodic_from, out)
        block = np.flatnonzero(history.period == periodic_from)
        m = block.size
        index[done:] = block[0] + (np.arange(done, steps) - done) % m
        rows = (line_bounds.rows(block[0], block[-1] + 1) if line_bounds is not None
                else [patch_bounds[k] for k in block])
        lowest.add(rows, history.period[block], periodic_from)
    pressures, pressure_index = _stored_bounds(line_bounds, patch_bounds, index)
    if progress is not None:
        progress(1.0)
    now = pressures[pressure_index[-1]] if steps else None
    if coupled and steps:  # Melan's limit of the uncoupled contact, the reference (it does not hold with coupling)
        last = np.flatnonzero(history.period == history.period[-1])
        uncoupled = body.bounds(history.xc[last], history.P[last])
        reference, now = uncoupled.min(axis=0), uncoupled[-1]
    else:
        reference = lowest.value
    return CycleResult(
        edges=body.edges, xc=history.xc, P=history.P, Q=history.Q, period=history.period, kernel=kernel, u0=u0,
        periodic_from=None if periodic_from < 0 else int(periodic_from), params=dict(params or {}), tol=tol,
        shakedown_rtol=shakedown_rtol, runtime=time.perf_counter() - t0, body=body.body_spec,
        solver=step_solver.name, residuals=out.residuals(), lowest_pressure=lowest.value,
        pressures=pressures, pressure_index=pressure_index,
        melan_limit=melan_limit(body, history, reference, now, params or {}),
        beta=float(options.get("beta", 0.0)) if coupled else 0.0, mu=options.get("mu") if coupled else None,
        y_edges=getattr(body, "y_edges", None) if shape == "patch" else None,
        nu=operator.nu if shape == "patch" else None, angle=float(getattr(step_solver, "angle", 0.0)),
        **out.result_fields())


class _LineBounds:
    """The bounds of a line grid, one row per distinct (centre, load) of the history, computed the first time a
    chunk of steps needs them: a rocking history visits the same centres every period, so the rows a result keeps
    are about one period's, not a row per step (12321 x 1418 floats at a/400), and the march's chunks are copies of
    them. A step's bound depends on its (xc, P) alone: equal keys give equal rows, to the bit."""

    def __init__(self, body, history):
        self.body = body
        keys = np.stack([history.xc, history.P], axis=1)
        self.keys, inverse = np.unique(keys, axis=0, return_inverse=True)
        self.index = inverse.reshape(-1)  # the row of each step
        self.table = np.empty((len(self.keys), body.shape[0]))  # untouched rows cost no memory
        self.ready = np.zeros(len(self.keys), dtype=bool)

    def rows(self, k0, k1):
        """The bounds of steps ``k0:k1``, shape (k1 - k0, n) (a new array)."""
        ids = self.index[k0:k1]
        need = np.unique(ids[~self.ready[ids]])
        if need.size:
            self.table[need] = self.body.bounds(self.keys[need, 0], self.keys[need, 1])
            self.ready[need] = True
        return self.table[ids]

    def stored(self, index):
        """``(pressures, pressure_index)``: the rows that the steps' sources ``index`` use, each once."""
        used, of_step = np.unique(self.index[index], return_inverse=True)
        return self.table[used], of_step.reshape(-1)


class _StepBounds:
    """The bounds of a line grid, a row per step, for a per-step solver that writes its own pressure into them (the
    coupled solver, :class:`core.solvers.coupled.CoupledSolver`): each chunk's rows are a view of one (steps, n) array,
    filled with the body's bounds before the solver overwrites them, and kept as they were solved."""

    def __init__(self, body, history):
        self.body, self.xc, self.P = body, history.xc, history.P
        self.table = np.empty((len(history), body.shape[0]))
        self.filled = 0

    def rows(self, k0, k1):
        """The rows of steps ``k0:k1`` (a view: what the solver writes is kept); those not solved yet are the
        body's bounds."""
        if k1 > self.filled:
            start = max(k0, self.filled)
            self.body.bounds(self.xc[start:k1], self.P[start:k1], out=self.table[start:k1])
            self.filled = k1
        return self.table[k0:k1]

    def stored(self, index):
        """``(pressures, pressure_index)``: the rows of the steps solved (a copied step's index is its source's)."""
        solved = int(index.max()) + 1 if index.size else 0
        return (self.table if solved == len(self.table) else self.table[:solved].copy()), index


def _stored_bounds(line_bounds, patch_bounds, index):
    """The bounds a result keeps: ``(pressures, pressure_index)``, the distinct bounds the march used (a line's
    distinct (centre, load) rows; on a patch each shared array once) and the row of each step (a copied step's is
    its source's)."""
    if line_bounds is not None:
        return line_bounds.stored(index)
    rows, first = {}, []
    for field in patch_bounds:
        if id(field) not in rows:
            rows[id(field)] = len(first)
            first.append(field)
    of_solved = np.array([rows[id(field)] for field in patch_bounds], dtype=np.int64)
    return np.stack(first), of_solved[index]


def melan_limit(body, history, lowest, now, params):
    """Melan's limit of a run's discrete problem: ``(lo, hi)`` of the tangential load [the unit of ``Q``] below which
    it shakes down and above which it ratchets, or None (:attr:`core.CycleResult.melan_limit`).

    Uncoupled contact satisfies Melan's theorem (Klarbring, Ciavarella and
    Barber 2007): the run shakes down if and only if a fixed traction within
    ``mu`` times the lowest pressure of the last period (``lowest``) carries the
    load. With no moment to balance, that is ``sum mu p_min dA`` over the
    pressure ``now`` of the last step (``lo = hi``, :func:`core.pressure.melan.grid_limit`),
    reached by tractions along the load; a body free to turn about the normal
    (the cone) solves its linear programme (:meth:`core.Cone.grid_limit`, the
    Coulomb disk between two polygons). The normal load may vary over the
    period (``p_min`` is then also the lowest over the load); the tangential one
    may not: None when it does, or for a body free to turn that has no programme.

    Parameters
    ----------
    body : object
        The discretised body of the run (its ``body_spec`` and ``dx``).
    history : Schedule
        The steps run.
    lowest, now : ndarray
        The lowest bound of each element over the last period and the bound at the last step [mu p0].
    params : dict
        The run's inputs (a body free to turn reads ``w``, ``dW`` and ``history``).
    """
    if len(history) == 0 or history.periods == 0:
        return None
    last = history.period == history.period[-1]
    Q, P = history.Q[last], history.P[last]
    if np.ptp(Q) > 1e-12 * max(1.0, float(np.abs(Q).max())):
        return None
    spec = body.body_spec
    if getattr(spec, "twist_centre", None) is not None:
        if (not hasattr(spec, "grid_limit") or params.get("history", "rocking") != "rocking"
                or np.ptp(P) > 1e-12 * float(P.max())):
            return None
        lim = spec.grid_limit(params["w"], dx=float(body.edges[1] - body.edges[0]), dW=params.get("dW"))
        return float(lim["lo"] * P[-1]), float(lim["hi"] * P[-1])
    limit = melan.grid_limit(lowest, now, P[-1])  # the one place Melan's limit is computed
    return None if limit is None else (limit, limit)


class _Lowest:
    """The lowest bound of each element over one block of steps (a period): ``mu p_min`` of the last period."""

    def __init__(self):
        self.value = None

    def add(self, bounds, period, block):
        """Take the rows of ``bounds`` (an array, or a list of arrays) whose steps are in ``block`` (their
        periods are ``period``, one per row; the block's rows are contiguous)."""
        rows = np.flatnonzero(period == block)
        if rows.size == 0:
            return
        i0, i1 = int(rows[0]), int(rows[-1]) + 1
        if isinstance(bounds, np.ndarray):
            low = bounds[i0:i1].min(axis=0)
        else:
            low = functools.reduce(np.minimum, bounds[i0 + 1:i1], bounds[i0].copy())
        if self.value is None:
            self.value = low
        else:
            np.minimum(self.value, low, out=self.value)


def _repeat_last_period(period, done, p, out):
    """Fill steps ``done:`` by repeating period ``p``: every per-step array of ``out.copied()`` is copied, those of
    ``out.advancing()`` (the displacement, a scalar or a vector per step; a patch's rotation) advance by the
    period's increment each time, iterations are 0."""
    block = np.flatnonzero(period == p)
    m = block.size
    start = block[0]
    rest = np.arange(done, period.size)
    src = start + (rest - done) % m
    repeats = 1 + (rest - done) // m
    for arr in out.copied():
        arr[rest] = arr[src]
    for arr in getattr(out, "advancing", lambda: [out.displacement])():
        before = arr[start - 1] if start > 0 else 0.0
        increment = arr[block[-1]] - before
        arr[rest] = arr[src] + repeats.reshape((-1,) + (1,) * (arr.ndim - 1)) * increment
    out.iterations[rest] = 0
    out.cg_iterations[rest] = 0
    if hasattr(out, "repeat_snapshots"):
        out.repeat_snapshots(done, rest, src)
