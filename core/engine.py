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

from .dense import DenseSolver, Trajectory
from .kernels import influence_matrix
from .result import CycleResult, SolveCancelled, SolverError
from .schedule import Schedule

__all__ = ["run", "STEP_SOLVERS", "SOLVER_CHOICES", "AUTO_CROSSOVER", "select_solver", "KernelOperator"]

#: The per-step solvers by name: each is built as ``cls(operator, element_size=, tol=, maxiter=)`` and
#: has ``march`` and ``step`` (see :class:`core.dense.DenseSolver`). The matrix-free "fft" solver registers here.
STEP_SOLVERS = {"dense": DenseSolver}
#: The values of the ``solver`` keyword.
SOLVER_CHOICES = ("auto", "dense", "fft")
#: Elements above which ``solver="auto"`` picks "fft" (None: "dense" at every size until "fft" is registered).
AUTO_CROSSOVER = None


def select_solver(solver, n):
    """The per-step solver class for ``solver`` (``"dense"``, ``"fft"`` or ``"auto"``) on ``n`` unknowns.

    Raises
    ------
    ValueError
        If ``solver`` is not one of :data:`SOLVER_CHOICES`.
    NotImplementedError
        If the named solver is not available in this build (``"fft"`` before the matrix-free solver is added).
    """
    if solver not in SOLVER_CHOICES:
        raise ValueError(f"solver must be one of {SOLVER_CHOICES}, got {solver!r:.60}")
    if solver == "auto":
        solver = "fft" if AUTO_CROSSOVER is not None and n > AUTO_CROSSOVER and "fft" in STEP_SOLVERS else "dense"
    if solver not in STEP_SOLVERS:
        raise NotImplementedError(f"solver={solver!r} is not available yet: use solver='dense' or 'auto'")
    return STEP_SOLVERS[solver]


class KernelOperator:
    """The dense influence operator of a 1D kernel (:func:`core.kernels.influence_matrix`) on a body's grid.

    Parameters
    ----------
    n : int
        Elements.
    dx : float
        Element width [a].
    kernel : str
        Name in :data:`core.kernels.KERNELS`.
    **options
        The kernel's options.
    """

    def __init__(self, n, dx, kernel="plane", **options):
        self.kernel = kernel
        self.shape = (int(n),)
        self.size = int(n)
        self._K = influence_matrix(n, dx, kernel, **options)

    def matrix(self) -> np.ndarray:
        """The dense influence matrix [mu P/E* per mu p0]."""
        return self._K

    def apply(self, q) -> np.ndarray:
        """Displacements of the traction field ``q``."""
        return self._K @ np.asarray(q, dtype=float)


def run(body, operator, history, *, solver="auto", tol, maxiter=None, detect_periodic=True, shakedown_rtol=1e-3,
        params=None, time_budget=None, cancel=None, progress=None, chunk=256, kernel="plane", u0=None):
    """March a loading history on a body with an elastic operator and a per-step solver.

    Parameters
    ----------
    body : object
        A discretised body (e.g. :class:`core.bodies.Cylinder`): ``bounds``,
        ``load_target``, ``edges``, ``dx``, ``name``.
    operator : object
        Elastic operator on the body's grid (``shape``, ``size``, ``apply``, ``matrix``).
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
        iterations=out.iterations, kkt_residual=out.kkt_residual, kernel=kernel, u0=u0,
        periodic_from=None if periodic_from < 0 else int(periodic_from),
        params=dict(params or {}), tol=tol, shakedown_rtol=shakedown_rtol,
        runtime=time.perf_counter() - t0, body=body.name, solver=step_solver.name, residuals=out.residuals(),
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
    out.kkt_residual[rest] = out.kkt_residual[src]
