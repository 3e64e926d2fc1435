"""One run function: a body, an elastic operator, a per-step solver and a loading history give a result.

:func:`run` marches a :class:`~core.schedule.Schedule` (the loading history as
data) step by step: the body gives the traction bound of every element at
every step, the per-step solver solves the KKT conditions of each increment on
the operator, and the per-step arrays become a frozen
:class:`~core.result.CycleResult`. The public entry points
(:func:`core.simulate_cycles`, :func:`core.simulate_contact`,
:func:`core.solve_schedule`) build the parts and call it.

The per-step solvers are chosen by name in :data:`STEP_SOLVERS`, the one place
where a solver is registered.
"""

from __future__ import annotations

import time

import numpy as np

from .bodies import MAX_ELEMENTS
from .dense import DenseSolver, Trajectory
from .matrix_free import FFTSolver
from .operators import elastic_operator
from .result import CycleResult, SolveCancelled, SolverError
from .schedule import Schedule

__all__ = ["run", "STEP_SOLVERS", "SOLVER_CHOICES", "AUTO_CROSSOVER", "select_solver", "make_operator"]

#: The per-step solvers by name: each is built as ``cls(operator, element_size=, tol=, maxiter=)`` and
#: has ``name``, ``form`` (the operator form it needs), ``march``, ``step`` and ``residuals`` (see
#: :class:`core.dense.DenseSolver` and :class:`core.matrix_free.FFTSolver`).
STEP_SOLVERS = {"dense": DenseSolver, "fft": FFTSolver}
#: The values of the ``solver`` keyword.
SOLVER_CHOICES = ("auto", "dense", "fft")
#: Elements above which ``solver="auto"`` picks "fft", measured by ``benchmarks/solver.py`` (docs/dev/
#: benchmarks.md): the dense solver (interval inverses of the Toeplitz matrix, FFT residuals) is faster per
#: rocking step at every size up to its grid cap (about 5x at 3800 elements: 1.1 ms against 5.6 ms a step,
#: 2 cores shared), so "auto" runs it up to :data:`core.bodies.MAX_ELEMENTS` and the matrix-free one above,
#: up to :data:`core.bodies.MAX_FFT_ELEMENTS`.
AUTO_CROSSOVER = MAX_ELEMENTS


def select_solver(solver, n):
    """The per-step solver class for ``solver`` (``"dense"``, ``"fft"`` or ``"auto"``) on ``n`` unknowns.

    Raises
    ------
    ValueError
        If ``solver`` is not one of :data:`SOLVER_CHOICES`.
    """
    if solver not in SOLVER_CHOICES:
        raise ValueError(f"solver must be one of {SOLVER_CHOICES}, got {solver!r:.60}")
    if solver == "auto":
        solver = "fft" if n > AUTO_CROSSOVER else "dense"
    return STEP_SOLVERS[solver]


def make_operator(step_solver, n, dx, kernel="plane", **options):
    """The elastic operator (:mod:`core.operators`) in the form ``step_solver`` needs.

    The dense matrix only for the dense solver; the FFT form (the kernel's
    column and its circulant spectra, never an ``n x n`` matrix) for the
    matrix-free one.

    Parameters
    ----------
    step_solver : type
        A class of :data:`STEP_SOLVERS` (its ``form``: ``"dense"`` or ``"fft"``).
    n, dx, kernel, **options :
        As in :func:`core.operators.elastic_operator`.
    """
    return elastic_operator(n, dx, kernel, form=step_solver.form, **options)


def run(body, operator, history, *, solver="auto", tol, maxiter=None, detect_periodic=True, shakedown_rtol=1e-3,
        params=None, time_budget=None, cancel=None, progress=None, chunk=256, kernel="plane", u0=None):
    """March a loading history on a body with an elastic operator and a per-step solver.

    Parameters
    ----------
    body : object
        A discretised body (e.g. :class:`core.bodies.Cylinder`): ``bounds``,
        ``load_target``, ``edges``, ``dx``, ``name``.
    operator : object
        Elastic operator on the body's grid (:mod:`core.operators`; :func:`make_operator`
        builds the form the solver needs).
    history : Schedule
        The steps.
    solver : str
        ``"dense"``, ``"fft"`` or ``"auto"`` (see :func:`select_solver`).
    tol, maxiter, detect_periodic, shakedown_rtol, params, time_budget, cancel, progress, chunk :
        As in :func:`core.solve_schedule` (validated there).
    kernel, u0 :
        Recorded on the result.

    Returns
    -------
    CycleResult
    """
    if not isinstance(history, Schedule):
        raise ValueError(f"history must be a core.Schedule, got {type(history).__name__}")
    t0 = time.perf_counter()
    n = operator.size
    if body.shape != tuple(operator.shape):
        raise ValueError(f"the operator's shape {tuple(operator.shape)} differs from the body's grid {body.shape}")
    maxiter = 50 + 2 * n if maxiter is None else maxiter
    step_solver = select_solver(solver, n)(operator, element_size=body.dx, tol=tol, maxiter=maxiter)
    steps = len(history)
    out = Trajectory(steps, n)
    periodic = bool(detect_periodic) and history.is_periodic()
    load_scale = float(body.load_target(1.0))
    bounds = np.empty((min(chunk, steps), n))
    done, periodic_from = 0, -1
    budget_end = None if time_budget is None else t0 + time_budget
    while done < steps:
        k1 = min(steps, done + chunk)
        body.bounds(history.xc[done:k1], history.P[done:k1], out=bounds[:k1 - done])
        reached, periodic_from, failed = step_solver.march(bounds, history.Q, history.period, load_scale, done, k1,
                                                           periodic, out)
        if failed >= 0:
            res = max(step_solver.residuals.values())
            raise SolverError(failed, history.xc[failed], res,
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
        _repeat_last_period(history.period, done, periodic_from, out)
    if progress is not None:
        progress(1.0)
    return CycleResult(
        edges=body.edges, xc=history.xc, P=history.P, Q=history.Q, period=history.period,
        traction=out.traction, state=out.state, displacement=out.displacement, dissipation=out.dissipation,
        iterations=out.iterations, cg_iterations=out.cg_iterations, kkt_residual=out.kkt_residual, kernel=kernel,
        u0=u0,
        periodic_from=None if periodic_from < 0 else int(periodic_from),
        params=dict(params or {}), tol=tol, shakedown_rtol=shakedown_rtol,
        runtime=time.perf_counter() - t0, body=body.name,
        body_spec=getattr(body, "body_spec", None), solver=step_solver.name, residuals=out.residuals(),
    )


def _repeat_last_period(period, done, p, out):
    """Fill steps ``done:`` by repeating period ``p`` (its displacement advancing by its increment)."""
    block = np.flatnonzero(period == p)
    m = block.size
    start = block[0]
    disp = out.displacement
    before = disp[start - 1] if start > 0 else 0.0
    increment = disp[block[-1]] - before
    rest = np.arange(done, period.size)
    src = start + (rest - done) % m
    repeats = 1 + (rest - done) // m
    out.traction[rest] = out.traction[src]
    out.state[rest] = out.state[src]
    disp[rest] = disp[src] + repeats * increment
    out.dissipation[rest] = out.dissipation[src]
    out.iterations[rest] = 0
    out.cg_iterations[rest] = 0
    out.kkt_residual[rest] = out.kkt_residual[src]
