"""Point contacts' runs and static solves: a patch of elements from any schedule to a result.

:func:`solve_point_schedule` builds a point body's grid (:class:`core.geometry.patch.PatchGrid`),
the half-space operator's window and the patch solver (:class:`core.solvers.solver3d.PatchSolver`)
and runs them through :func:`core.march.engine.run`, the one march of every body;
:func:`core.simulate_cycles` calls it for every point body and history. The
static solves (Mindlin's partial slip, the shaken-down state under ``mu p_min``)
are one step of the same per-step solver, through :func:`core.march.engine.solve_step` as a line's are.
"""

from __future__ import annotations

import math

import numpy as np

from ..base._validate import check_int, check_range, check_scalar
from ..march.engine import check_solver, run, solve_step
from ..geometry.patch import MAX_GRID_ELEMENTS, PatchGrid, _grid, _normal_mode, _pressure
from ..theory.point_contact import Ellipsoid
from ..geometry.registry import point_body
from ..geometry.resolution import GRID_DEFAULTS
from ..records.result import StaticResult
from ..loading.schedule import Schedule
from ..solvers.solver3d import PERIODIC_TOL, TOL_3D, _Window

__all__ = ["solve_point_schedule", "solve_static_patch", "solve_static_3d", "mindlin_state", "shakedown_state_3d",
           "StaticResult3D"]


def solve_point_schedule(schedule, dx, body, *, nu=0.5, angle=0.0, tol=TOL_3D, detect_periodic=True,
                         periodic_tol=PERIODIC_TOL, shakedown_rtol=1e-3, params=None, time_budget=None, cancel=None,
                         progress=None, chunk=GRID_DEFAULTS["patch"].chunk, normal="auto", solver="auto"):
    """Solve a loading :class:`~core.loading.schedule.Schedule` for a point contact, step by step.

    Parameters
    ----------
    schedule : Schedule
        Steps (``xc`` [a], ``P`` [nominal Fn], ``Q = Ft/(mu Fn0)``, period).
    dx : float
        Element side [a], in [0.005, 0.5].
    body : Ellipsoid or core.geometry.heightmap.HeightMap
        The body (a height map runs on its own grid: ``dx`` its spacing).
    nu : float
        Substrate's Poisson ratio, in [0, 0.5].
    angle : float
        Angle of Ft to the rocking direction x [rad].
    tol : float
        KKT tolerance of every step.
    detect_periodic : bool
        When the traction at the end of a period repeats the previous one to
        ``periodic_tol`` [mu p0], copy the remaining periods (same steps every
        period only; a shaken-down period repeats exactly, a ratcheting one
        converges geometrically to its periodic state).
    shakedown_rtol : float
        Relative size of the last increment for the shakedown verdict.
    params : dict, optional
        Recorded on the result.
    time_budget, cancel, progress, chunk :
        As in :func:`core.api.solver.solve_schedule`.
    normal : {"auto", "exact", "numerical"}
        The traction bound's pressure: ``"numerical"`` (and ``"auto"``, the
        default) the discrete normal problem on the run's grid, solved by
        :func:`core.pressure.normal.solve_normal` (CONTACT's bound); ``"exact"`` the
        element means of Hertz's closed form. A height map has no closed form:
        ``"exact"`` is refused for it.
    solver : {"auto", "pcg3d"}
        The per-step solver (:data:`core.march.engine.STEP_SOLVERS`): a patch of
        elements runs :class:`PatchSolver`; the line solvers are refused.

    Returns
    -------
    CycleResult
        On a patch of elements (``is_patch``).

    Raises
    ------
    SolverError
        If a step does not settle (names the step, ``xc`` and the residual).
    SolveCancelled
        On request or when the time budget ran out.
    """
    if not isinstance(schedule, Schedule):
        raise ValueError(f"schedule must be a core.Schedule, got {type(schedule).__name__}")
    if not (isinstance(body, Ellipsoid) or hasattr(body, "grid_pressure")):
        raise ValueError(f"body must be a point body: a core.Ellipsoid, a core.geometry.heightmap.HeightMap or an object with "
                         f"run_grid and grid_pressure (the patch protocol of core.march.engine), got {type(body).__name__}")
    dx = check_scalar("dx", dx, GRID_DEFAULTS["patch"].min_dx, 0.5)
    nu = check_scalar("nu", nu, 0.0, 0.5)
    angle = check_scalar("angle", angle, -math.pi, math.pi)
    tol = check_scalar("tol", tol, 1e-13, 1e-4)
    periodic_tol = check_scalar("periodic_tol", periodic_tol, 0.0, 1e-2)
    chunk = check_int("chunk", chunk, 1, 10**7)
    normal = _normal_mode(normal, body)
    params = dict(params or {}, normal=normal)
    check_solver(solver, "patch", body)
    grid = PatchGrid.for_history(body, schedule, dx, normal)
    operator = _Window(*grid.shape, dx, nu, body.kernel_scale, hy=None if grid.dy == grid.dx else grid.dy)
    return run(grid, operator, schedule, solver=solver, tol=tol, detect_periodic=detect_periodic,
               shakedown_rtol=shakedown_rtol, params=params, time_budget=time_budget, cancel=cancel,
               progress=progress, chunk=chunk, kernel="halfspace",
               solver_options=dict(grid.solver_options, angle=angle, periodic_tol=periodic_tol))


# --------------------------------------------------------------------------
# static references: Mindlin and the shaken-down state
# --------------------------------------------------------------------------
#: The former name of :class:`core.records.result.StaticResult` on a patch.
StaticResult3D = StaticResult


def solve_static_patch(bound, ft, dx, *, body=None, nu=0.5, angle=0.0, tol=TOL_3D, solver="auto"):
    """Static partial slip on a patch of elements centred on the origin: :func:`core.solve_static`'s patch case.

    Parameters
    ----------
    bound : array_like, shape (ny, nx)
        Traction bound [mu p0], >= 0, on square elements of side ``dx`` centred on ``(0, 0)`` (odd counts).
    ft : float
        ``Ft / (mu Fn)``, below what the bound carries.
    dx : float
        Element side [a], in [0.005, 0.5].
    body : object, optional
        The point body (its ``total_load`` and ``kernel_scale``; default the sphere).
    nu, angle, tol :
        As in :func:`solve_point_schedule`.
    solver : {"auto", "pcg3d"}
        The patch solver; the line solvers are refused.

    Returns
    -------
    core.records.result.StaticResult
    """
    check_solver(solver, "patch", body)
    bound = check_range("bound", bound, 0.0, None)
    if bound.ndim != 2 or bound.shape[0] % 2 == 0 or bound.shape[1] % 2 == 0:
        raise ValueError(f"bound must be a 2-D array of odd sizes (a patch centred on 0), got shape {bound.shape}")
    if bound.size > MAX_GRID_ELEMENTS:
        raise ValueError(f"bound has {bound.size} elements (> {MAX_GRID_ELEMENTS}): use a larger dx")
    dx = check_scalar("dx", dx, 0.005, 0.5)
    body = point_body("sphere" if body is None else body)
    ny, nx = bound.shape
    return _static_patch(bound, ft, dx * (np.arange(nx + 1) - nx / 2), dx * (np.arange(ny + 1) - ny / 2), body,
                         nu=nu, angle=angle, tol=tol)


def solve_static_3d(bound, ft, x_edges, y_edges, body, *, nu=0.5, angle=0.0, tol=TOL_3D):
    """Static partial slip under a traction bound on the grid ``x_edges``, ``y_edges`` (see :func:`core.solve_static`).

    With ``bound = mu p`` it is Mindlin's problem; with ``mu p_min`` the
    shaken-down state of a rocking contact. The former name of the patch case
    of :func:`core.solve_static`, for a grid given by its edges.

    Parameters
    ----------
    bound : ndarray, shape (ny, nx)
        Traction bound [mu p0], >= 0.
    ft : float
        ``Ft / (mu Fn)``, below what the bound carries.
    x_edges, y_edges : ndarray
        The grid (square elements).
    body : Ellipsoid
    nu, angle, tol :
        As in :func:`solve_point_schedule`.

    Returns
    -------
    core.records.result.StaticResult
    """
    return _static_patch(bound, ft, x_edges, y_edges, body, nu=nu, angle=angle, tol=tol)


def _static_patch(bound, ft, x_edges, y_edges, body, *, nu=0.5, angle=0.0, tol=TOL_3D):
    h = float(x_edges[1] - x_edges[0])
    hy = float(y_edges[1] - y_edges[0]) if len(y_edges) > 1 else h
    hy = h if abs(hy - h) <= 1e-9 * h else hy  # square elements exactly; rectangular ones on a cone's grid
    dA = h * hy
    carried = float(bound.sum()) * dA / body.total_load
    ft = check_scalar("ft", ft, 0.0, carried, hi_closed=False)
    operator = _Window(y_edges.size - 1, x_edges.size - 1, h, nu, body.kernel_scale, hy=hy)
    target = ft * body.total_load * np.array([math.cos(angle), math.sin(angle)])
    step = solve_step(operator, np.ascontiguousarray(bound, dtype=float), target, solver="pcg3d", element_size=dA,
                      tol=tol)
    return StaticResult(traction=step.traction, displacement=step.displacement, residuals=step.residuals,
                        bound=bound, edges=x_edges, y_edges=y_edges,  # its states from the bound (StaticResult)
                        iterations=step.iterations)


def mindlin_state(ft, dx=0.05, body="sphere", *, ratio=None, nu=0.5, angle=0.0, tol=TOL_3D):
    """Mindlin's partial slip of a point contact loaded from rest to ``ft`` (numerical, on the grid).

    Mindlin's solution (exact for ``nu = 0``) has ``c/a = (1 - ft)^(1/3)``; for
    ``nu > 0`` the x-y coupling adds a small ``q_y`` and a slightly
    non-circular stick zone, which this solution contains.

    Returns
    -------
    core.records.result.StaticResult
    """
    body = point_body(body, ratio)
    dx = check_scalar("dx", dx, 0.005, 0.5)
    xe, ye = _grid(body, 1.0, 1.0, dx)
    return solve_static_3d(_pressure(xe, ye, 0.0, body), ft, xe, ye, body, nu=nu, angle=angle, tol=tol)


def shakedown_state_3d(ft, w, dx=0.05, body="sphere", *, ratio=None, nu=0.5, angle=0.0, tol=TOL_3D):
    """The shaken-down state of a rocking point contact, computed directly as one static problem.

    The bound is ``mu p_min``, the lowest pressure of a period (that of the
    farther turning point); below the exact limit
    (:func:`core.theory.point_contact.ft_limit_point`) the transient's end state
    equals it (``tests/test_solver3d.py``).

    Returns
    -------
    core.records.result.StaticResult
    """
    body = point_body(body, ratio)
    dx = check_scalar("dx", dx, 0.005, 0.5)
    w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
    xe, ye = _grid(body, 1.0 + w, 1.0, dx)
    pmin = np.minimum(_pressure(xe, ye, -w, body), _pressure(xe, ye, w, body))
    return solve_static_3d(pmin, ft, xe, ye, body, nu=nu, angle=angle, tol=tol)
