"""The public entry points of the cycle simulation: build the parts, run them, return a result.

:func:`simulate_cycles` (normalised inputs), :func:`simulate_contact`
(a :class:`~core.api.contact.Contact` in SI units) and :func:`solve_schedule`
(any :class:`~core.loading.schedule.Schedule`) build a body (:mod:`core.geometry.bodies`), an
elastic operator (:mod:`core.elastic.operators`), a per-step solver (``solver="dense"``,
``"fft"`` or ``"auto"``: :mod:`core.solvers.dense`, :mod:`core.solvers.matrix_free`, :data:`core.march.engine.STEP_SOLVERS`)
and a loading history (:mod:`core.loading.schedule`, :mod:`core.loading.histories`) and
hand them to :func:`core.march.engine.run`. :func:`solve_static` and
:func:`shakedown_state` solve one static partial-slip problem.

Normalised units: lengths in ``a``, tractions in ``mu p0``, loads in ``mu P``,
displacements in ``mu P / E*`` (see :mod:`core.elastic.kernels`).

References
----------
.. [1] R. Wetter, "Frictional shakedown and ratcheting of an oscillating
   cylindrical, elastic contact with Coulomb friction", Physical
   Mesomechanics 18 (2015).
"""

from __future__ import annotations

import numpy as np

from ..geometry.resolution import DEFAULT_DX_LINE, GRID_DEFAULTS, default_dW, default_dx
from ..base._validate import check_int, check_scalar
from ..geometry.bodies import MAX_ELEMENTS, MAX_FFT_ELEMENTS, NORMAL_CHOICES, Body, Cylinder, _edges_for_reach, resolve_body
from ..theory.materials import check_beta
from ..elastic.kernels import KERNELS, strip_b_coefficient, strip_u0
from ..records.result import StaticResult, read_only
from ..march.engine import check_solver, make_operator, run, select_solver, solve_step
from ..geometry.registry import kind, point_body, resolve
from ..loading import histories
from ..loading.schedule import Schedule
from ..loading.paths import as_path

__all__ = ["simulate_cycles", "solve_schedule", "solve_static", "shakedown_state",
           "simulate_point_contact", "StaticSolution", "ShakedownState", "make_grid", "DEFAULT_DX", "MAX_ELEMENTS", "MAX_FFT_ELEMENTS", "MAX_STORED_VALUES",
           "KKT_TOL"]

#: Default element width [a]: 80 elements across the contact. The increment per
#: period is then within about 1 % of the converged value (tests/test_solver.py).
DEFAULT_DX = DEFAULT_DX_LINE  # the cylinder's default grid (core/geometry/resolution.py)
#: Largest steps x elements a run may store (traction float64 + state int8: ~9 bytes each).
MAX_STORED_VALUES = 2.5e8
#: Default tolerance of the KKT residual (tractions in mu p0, slips in mu P/E*).
KKT_TOL = GRID_DEFAULTS["line"].tol


def make_grid(reach, dx, max_elements=MAX_ELEMENTS):
    """The element edges of :meth:`core.geometry.bodies.Cylinder.for_reach` (``reach`` and ``dx`` in a; ``max_elements``
    the grid cap, the dense solver's by default).

    Returns
    -------
    ndarray, shape (n + 1,)
        Uniform edges symmetric about 0 with one spare element each side; ``n`` is even.
    """
    return Cylinder.for_reach(reach, dx, max_elements).edges


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
                   time_budget=None, cancel=None, progress=None, chunk=GRID_DEFAULTS["line"].chunk, solver="auto",
                   body="cylinder",
                   normal="auto", beta=0.0, mu=None):
    """Run the incremental solver over any :class:`~core.loading.schedule.Schedule`.

    Parameters
    ----------
    schedule : Schedule
        The steps (centre, normal and tangential load, period).
    dx : float
        Element width [a], in [1e-4, 0.5].
    kernel : {"plane", "strip"}
        Influence kernel (:mod:`core.elastic.kernels`).
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
    solver : {"auto", "dense", "fft"}
        Per-step solver (:func:`core.march.engine.select_solver`): ``"dense"`` (the
        primal-dual active set on the dense matrix, :mod:`core.solvers.dense`),
        ``"fft"`` (matrix-free: active set with FFT-preconditioned conjugate
        gradients, :mod:`core.solvers.matrix_free`) or ``"auto"`` (``"fft"`` above
        :data:`core.march.engine.AUTO_CROSSOVER` elements; the default). The result
        records it (``solver``) and the CG iterations of each step (``cg_iterations``).
    body : str or core.geometry.bodies.Body
        A line-contact body: a name in :data:`core.geometry.bodies.BODIES` (``"cylinder"``,
        ``"punch"``: default parameters) or a body object (``core.Punch(flat=0.8)``,
        any :class:`core.geometry.bodies.Body`).
    normal : {"auto", "exact", "numerical"}
        The pressure: the body's closed form (``"exact"``), the numerical normal
        solve (``"numerical"``, :mod:`core.pressure.normal`, solved once per normal load:
        the body translates) or the closed form where there is one (``"auto"``).

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

    Examples
    --------
    Any :class:`~core.loading.schedule.Schedule`; here two periods of the paper's rocking:

    >>> from core import rocking_schedule
    >>> r = solve_schedule(rocking_schedule(0.3, 0.5, periods=2, dW=0.25), dx=1 / 20)
    >>> r.increment_per_period.round(3)
    array([0.137, 0.032])
    """
    if not isinstance(schedule, Schedule):
        raise ValueError(f"schedule must be a core.Schedule, got {type(schedule).__name__}")
    dx = check_scalar("dx", dx, GRID_DEFAULTS["line"].min_dx, 0.5)
    tol = check_scalar("tol", tol, 1e-14, 1e-4)
    shakedown_rtol = check_scalar("shakedown_rtol", shakedown_rtol, 0.0, 1.0)
    kernel_options = dict(kernel_options or {})
    check_solver(solver, "line", body)
    # the dense solver's grid cap, or the matrix-free one's where that solver may run
    if normal not in NORMAL_CHOICES:
        raise ValueError(f"normal must be one of {NORMAL_CHOICES}, got {normal!r:.60}")
    solver, solver_options = _coupling(beta, mu, solver, kernel)
    spec = resolve_body(body)
    body = spec.grid(schedule, dx, MAX_ELEMENTS if solver in ("dense", "coupled") else MAX_FFT_ELEMENTS, normal)
    if solver == "coupled":  # the coupled contact is wider than Hertz's and shifted: room for it
        margin = 0.1 * float(np.sqrt(np.max(schedule.P))) + 2 * body.dx
        body = spec.on_grid(_edges_for_reach(float(body.edges[-1]) - body.dx + margin, body.dx, MAX_ELEMENTS),
                            normal)
    n = body.size
    maxiter = check_int("maxiter", 50 + 2 * n if maxiter is None else maxiter, 1, 10**7)
    chunk = check_int("chunk", chunk, 1, 10**7)
    if time_budget is not None:
        time_budget = check_scalar("time_budget", time_budget, 0.0, None, lo_closed=False)
    if len(schedule) * n > MAX_STORED_VALUES:
        raise ValueError(f"{len(schedule)} steps x {n} elements exceeds {MAX_STORED_VALUES:.0e} stored values "
                         "(about 2.4 GB): use fewer periods, a larger dx or a larger dW")
    # the operator in the form the chosen solver needs: no n x n matrix for the matrix-free one
    operator = make_operator(select_solver(solver, n), n, body.dx, kernel, **kernel_options)
    u0 = strip_u0(kernel_options["L_over_a"], kernel_options["b_coefficient"]) if kernel == "strip" else None
    return run(body, operator, schedule, solver=solver, tol=tol, maxiter=maxiter, detect_periodic=detect_periodic,
               shakedown_rtol=shakedown_rtol, params=params, time_budget=time_budget, cancel=cancel,
               progress=progress, chunk=chunk, kernel=kernel, u0=u0, solver_options=solver_options)


def _coupling(beta, mu, solver, kernel):
    """``(solver, solver_options)`` of a line run with Dundurs' ``beta`` and friction ``mu`` (validated, naming
    them): the coupled solver when ``beta != 0`` or asked for by name, else ``solver`` and no options."""
    beta = check_beta(beta)
    if mu is not None:
        mu = check_scalar("mu", mu, 0.0, 10.0, lo_closed=False)
    if beta == 0.0 and solver != "coupled":
        return solver, None
    if solver not in ("auto", "dense", "coupled"):
        raise ValueError(f"beta = {beta:g} needs the coupled solver (solver 'auto', 'dense' or 'coupled'), "
                         f"got solver={solver!r:.40}")
    if kernel != "plane":
        raise ValueError(f"beta = {beta:g}: the coupled solver is plane strain (kernel='plane'), got kernel={kernel!r:.40}")
    if mu is None and beta == 0.0:  # the coupled solver by name at beta = 0: mu plays no part
        mu = 1.0
    if mu is None:
        raise ValueError(f"mu is required with beta = {beta:g} (the coupling enters as beta mu and beta / mu): "
                         "give the friction coefficient, in (0, 10]")
    return "coupled", {"beta": beta, "mu": mu}


#: The former names of :class:`core.records.result.StaticResult` (a line's static solution, its shaken-down state).
StaticSolution = ShakedownState = StaticResult


def _is_line_body(body) -> bool:
    """Whether ``body`` (a name, class or object) is a line contact (:class:`core.geometry.bodies.Body`; else a point body)."""
    if isinstance(body, type):
        return issubclass(body, Body)
    return kind(body) == "line"


def solve_static(bound, Q, dx, kernel="plane", *, kernel_options=None, tol=None, solver="auto", body=None, nu=0.5,
                 angle=0.0, edges=None):
    """Static partial slip under an arbitrary traction bound, loaded from zero in one step: a line or a patch.

    Solves ``min 1/2 q^T K q`` subject to ``|q_i| <= bound_i`` and
    ``sum q_i dx = (pi/2) Q``: with ``bound = mu p`` it is Cattaneo-Mindlin;
    with ``bound = mu`` times the lowest pressure of a rocking period it is the
    shaken-down state (:func:`shakedown_state`). A 2-D ``bound`` (or a point
    ``body``) is a patch of elements centred on the origin: the same problem
    with vector tractions on Coulomb disks, ``sum q dA = Q Fn`` along ``angle``
    (Mindlin's, or a point contact's shaken-down state), solved by the patch
    solver (:func:`core.api.point_runs.solve_static_patch`).

    Parameters
    ----------
    bound : array_like, shape (n,) or (ny, nx)
        Traction bound per element [mu p0], >= 0 (a patch: odd sizes, centred on the origin).
    Q : float
        Tangential load [mu P]; ``|Q| < (2/pi) sum(bound) dx`` (a patch: ``ft = Ft/(mu Fn)`` in [0, what the bound carries)).
    dx : float
        Element width [a].
    kernel, kernel_options, solver :
        As in :func:`solve_schedule` (a patch: ``solver`` ``"auto"`` or ``"pcg3d"``; no kernel options).
    tol : float, optional
        KKT tolerance (default :data:`KKT_TOL`; a patch: :data:`core.solvers.solver3d.TOL_3D`).
    body : object, optional
        A patch's point body (default the sphere); a line body is not needed.
    nu, angle : float
        A patch's Poisson ratio and the angle of ``Ft`` to x [rad].
    edges : array_like, optional
        A line's element edges (``n + 1`` of them, ``dx`` apart), for the result's ``x`` and
        ``stick_halfwidth``; default centred on the origin.

    Returns
    -------
    core.records.result.StaticResult
        ``traction`` [mu p0], ``displacement`` [mu P/E*; a patch mu Fn/(E* a)], the named
        ``residuals``, ``bound``, the element ``state`` and ``stick_halfwidth``, on a line or a patch.

    Examples
    --------
    Mindlin's stick radius ``(1 - ft)^(1/3)`` on a coarse patch (``dx = a/10``), to an element:

    >>> import numpy as np, core
    >>> x = 0.1 * np.arange(-12, 13)
    >>> p = np.sqrt(np.clip(1 - x[None, :] ** 2 - x[:, None] ** 2, 0, None))
    >>> s = core.solve_static(p, 0.5, 0.1)
    >>> abs(s.stick_halfwidth - 0.5 ** (1 / 3)) <= 0.1
    True
    """
    from ..base._validate import check_range

    if np.ndim(bound) == 2 or (body is not None and not _is_line_body(body)):
        from .point_runs import TOL_3D, solve_static_patch
        return solve_static_patch(bound, Q, dx, body=body, nu=nu, angle=angle, solver=solver,
                                  tol=TOL_3D if tol is None else tol)
    tol = KKT_TOL if tol is None else tol
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
    if edges is not None:
        edges = np.asarray(edges, dtype=float)
        if edges.shape != (n + 1,) or not np.allclose(np.diff(edges), dx, rtol=1e-9, atol=0.0):
            raise ValueError(f"edges must be {n + 1} edges dx = {dx:g} apart, got shape {edges.shape}")
    operator = make_operator(select_solver(solver, n), n, dx, kernel, **dict(kernel_options or {}))
    step = solve_step(operator, bound, target, solver=solver, element_size=dx, tol=tol, maxiter=50 + 2 * n)
    return StaticResult(traction=step.traction, displacement=step.displacement, residuals=step.residuals,
                        bound=bound, edges=dx * (np.arange(n + 1) - 0.5 * n) if edges is None else edges,
                        iterations=step.iterations)


def shakedown_state(ft, w, dx=None, *, kernel="plane", L_over_a=None, nu=0.5, tol=None, solver="auto",
                    body="cylinder", normal="auto", ratio=None, angle=0.0):
    """The shaken-down traction, computed directly as one static partial-slip problem.

    After shakedown nothing slips, and every element carries at most ``mu``
    times the lowest pressure it sees in a period. This computes the
    partial-slip solution with that bound, loaded once (the bound of the
    paper's slip zone, eq 22, on every element): that it equals the end state
    of the transient is checked in ``tests/test_solver.py``
    (``test_direct_shakedown_state_matches_transient``). It takes one solve
    instead of a whole transient.

    Parameters
    ----------
    ft, w, dx, kernel, L_over_a, nu, tol, body, normal, ratio, angle :
        As in :func:`simulate_cycles` (the rocking steps do not matter here).
        A line body other than the exact cylinder takes its lowest pressure over
        centres a quarter element apart (:meth:`core.geometry.bodies.LineGrid.lowest_bound`).
        A point body (``"sphere"``, ``"ellipsoid"`` with ``ratio``, an
        :class:`core.theory.point_contact.Ellipsoid`) runs
        :func:`core.api.point_runs.shakedown_state_3d` (``dx`` default 0.05, its grid).

    Returns
    -------
    core.records.result.StaticResult
        ``x`` (element centres [a]), ``traction`` [mu p0], ``bound`` (``mu p_min``
        per element [mu p0]) and ``stick_halfwidth`` (``c_sd / a``, 0 if none);
        a point body's fields are on its patch.

    Examples
    --------
    A coarse grid (``dx = a/20``) resolves ``c_sd`` to one element; eq 30 gives 0.494:

    >>> sd = shakedown_state(0.3, 0.3, dx=1 / 20)
    >>> sd.stick_halfwidth
    0.5
    >>> bool((abs(sd.traction) <= sd.bound + 1e-9).all())
    True
    """
    if not _is_line_body(body):
        from .point_runs import TOL_3D, shakedown_state_3d
        check_solver(solver, "patch", body)
        return shakedown_state_3d(ft, w, 0.05 if dx is None else dx, body, ratio=ratio, nu=nu, angle=angle,
                                  tol=TOL_3D if tol is None else tol)
    if ratio is not None or angle != 0.0:
        raise ValueError(f"ratio and angle are the point contacts', not body={body!r:.40}'s")
    tol = KKT_TOL if tol is None else tol
    dx = DEFAULT_DX if dx is None else dx
    ft = check_scalar("ft", ft, -1.0, 1.0, lo_closed=False, hi_closed=False)
    w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
    dx = check_scalar("dx", dx, 1e-4, 0.5)
    spec = resolve_body(body)
    if type(spec) is Cylinder and spec.normal_mode(normal) == "exact":
        body = Cylinder.for_reach(1.0 + w, dx)
    else:
        body = spec.grid(histories.for_run("rocking", 0.0, w, periods=1, dW=dx), dx, normal=normal)
    bound = read_only(body.lowest_bound(w))
    return solve_static(bound, ft, dx, kernel, kernel_options=_kernel_options(kernel, L_over_a, nu), tol=tol,
                        solver=solver, edges=body.edges)


def simulate_cycles(ft, w, periods=10, dx=None, dW=None, *, kernel="plane", shape="triangle",
                    load_steps=1, L_over_a=None, nu=0.5, tol=None, detect_periodic=True,
                    shakedown_rtol=1e-3, time_budget=None, cancel=None, progress=None, solver="auto",
                    body="cylinder", ratio=None, angle=0.0, history="rocking", amplitude=None, phase=0.0,
                    normal="auto", periodic_tol=None, beta=0.0, mu=None, path=None):
    """Simulate the rocking contact in normalised units (``a = 1``): loading, then ``periods`` periods.

    Parameters
    ----------
    ft : float
        ``Ft / (mu Fn)`` in [0, 1) (negative: pulled the other way).
    w : float
        Rocking amplitude ``W / a`` in [0, 1).
    periods : int
        Number of rocking periods, in [1, 10000].
    dx : float, optional
        Element width over ``a``, in [1e-4, 0.5]; default: the body's grid
        (:func:`core.geometry.resolution.default_dx`: 1/40 for the cylinder, 1/20 for
        the point contacts, where it is 0.4 % below 1/40's increment and eight
        times cheaper, see :data:`core.solvers.solver3d.DEFAULT_DX_3D`).
    dW : float, optional
        Rocking step over ``a``; defaults to ``dx`` (as in the paper), or the body's own multiple of it
        (:func:`core.geometry.resolution.default_dW`: the cone's is ``2 dx``).
    kernel : {"plane", "strip"}
        Plane strain (default) or the truncated-3D strip of length ``L``.
    shape : {"triangle", "sine"}
        Waveform of the rocking (see :func:`core.loading.schedule.rocking_schedule`).
    load_steps : int
        Steps of the initial loading.
    L_over_a : float, optional
        Strip length over ``a`` (``kernel="strip"`` only), >= 2.
    nu : float
        Poisson ratio of the substrate under a rigid cylinder (``"strip"`` only), in [0, 0.5].
    tol : float, optional
        KKT tolerance of every step; default :data:`KKT_TOL` for the cylinder,
        :data:`core.solvers.solver3d.TOL_3D` for the point contacts.
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
    solver : {"auto", "dense", "fft", "pcg3d"}
        Per-step solver (:data:`core.march.engine.STEP_SOLVERS`): ``"dense"`` or
        ``"fft"`` for a line contact (see :func:`solve_schedule`), ``"pcg3d"``
        (the 3D active-set / projected CG) for a point contact; ``"auto"`` picks
        for the grid. A solver of the other grid shape is refused (ValueError
        naming the valid choices).
    body : str or body object
        ``"cylinder"`` (default) and ``"punch"`` (:data:`core.geometry.bodies.BODIES`, or
        objects: ``core.Punch(flat=0.8)``, any :class:`core.geometry.bodies.Body`) are
        line contacts on the 1D engine; the point contacts (``"sphere"``,
        ``"ellipsoid"``, ``core.Ellipsoid``, a :class:`core.geometry.heightmap.HeightMap`
        on its own grid) run on a patch of elements through
        :func:`simulate_point_contact` (with ``ratio = Ry/Rx`` of
        an ellipsoid and ``angle`` of Ft to the rocking direction [rad]; ``dx``
        is the element side, ``nu`` the substrate's; ``kernel`` and ``L_over_a``
        are the cylinder's). Both return a :class:`CycleResult` (``is_patch``
        tells them apart) keeping the body object (``result.body``).
    history : {"rocking", "normal", "tangential"}, Schedule or mapping
        The loading history (:func:`core.loading.histories.for_run`): ``"rocking"`` (the
        paper's, the default); ``"normal"``, the same rocking under the normal force
        ``P = 1 + amplitude sin(2 pi t + phase)``; ``"tangential"``, the centre fixed and
        the tangential force ``ft + amplitude f(t)`` oscillating with ``shape``; a
        :class:`~core.loading.schedule.Schedule` (run as it is) or a mapping of per-step arrays
        ``xc``, ``P``, ``Q``, ``period`` (:func:`core.loading.histories.from_arrays`). Every body takes
        every history (a point contact: the sphere under an oscillating normal force, or
        Mindlin-Deresiewicz's oscillating tangential force with ``"tangential"``).
    amplitude : float, optional
        Amplitude of the oscillating load of ``"normal"`` (relative, in [0, 1), default 0.2)
        or ``"tangential"`` ([mu P], ``|ft| + amplitude < 1``, default ``(1 - |ft|)/2``).
    phase : float
        Phase of the normal force of ``"normal"`` [rad].
    normal : {"auto", "exact", "numerical"}
        The pressure of a line contact (see :func:`solve_schedule`): ``"auto"``
        (the default) takes the closed form where the body has one. Point
        contacts: ``"numerical"`` (and ``"auto"``, the default) bound the
        traction by the discrete normal problem on the run's grid (as CONTACT
        does), ``"exact"`` by the element means of Hertz's pressure (see
        :func:`core.api.point_runs.solve_point_schedule`).
    periodic_tol : float, optional
        The patch solver's periodic tolerance [mu p0] (point contacts only; default
        ``core.geometry.resolution.GRID_DEFAULTS["patch"].periodic_tol``).
    beta : float
        Dundurs' ``beta`` of the pair, body 1 the rocking body (:mod:`core.theory.materials`; a rigid
        cylinder on a compressible substrate has ``beta > 0``), ``|beta| < 0.5``. ``beta != 0``
        solves the normal and tangential problems together (:mod:`core.solvers.coupled`; line contacts on
        the plane-strain kernel only: a point contact refuses it); lengths stay in Hertz's ``a`` and
        increments in ``mu P/E*``. The result's ``melan_limit`` is then the uncoupled reference.
    mu : float, optional
        The friction coefficient, in (0, 10]: required with ``beta != 0`` (Spence's parameter is
        ``beta/mu``), accepted and irrelevant at ``beta = 0``.
    path : LoadingPath, str or dict, optional
        The loading path of a named history (:class:`core.loading.paths.LoadingPath`, or its text
        ``"order=together,ramp=10,first=-1,start=+W,preload=0.5:0.3:5"``): the order and steps in which ``P``
        and ``Q`` are raised, where the centre is then, the first direction of the rocking, earlier periods at
        other loads. All of it is the loading block: the increments, energies and verdict are those of the
        ``periods`` after it. Default: today's loading (``Q`` at ``xc = 0``, then ``0 -> +W``), bitwise.

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
    line = _is_line_body(body)
    if normal not in NORMAL_CHOICES:
        raise ValueError(f"normal must be one of {NORMAL_CHOICES}, got {normal!r:.60}")
    beta = check_beta(beta)
    if mu is not None:
        mu = check_scalar("mu", mu, 0.0, 10.0, lo_closed=False)
    if beta != 0.0 and not line:
        raise ValueError(f"beta = {beta:g}: coupled normal and tangential contact is solved for line contacts only "
                         f"(3D coupling does not exist yet); a point contact ({body!r:.40}) runs with beta = 0")
    if line:
        if ratio is not None or angle != 0.0:
            raise ValueError(f"ratio and angle are the point contacts' (body='ellipsoid' or 'sphere'), not "
                             f"body={body!r:.40}'s: got ratio={ratio!r}, angle={angle!r}")
        spec = resolve_body(body)
    else:
        spec = point_body(body, ratio)
    defaults = GRID_DEFAULTS["line" if line else "patch"]
    tol = defaults.tol if tol is None else tol
    dx = check_scalar("dx", default_dx(spec) if dx is None else dx, defaults.min_dx, 0.5)
    dW = default_dW(spec, dx) if dW is None else check_scalar("dW", dW, 1e-4, 1.0)
    path = as_path(path)
    schedule = histories.for_run(history, ft, w, periods=periods, dW=dW, shape=shape, load_steps=load_steps,
                                 amplitude=amplitude, phase=phase, path=path)
    if line:
        options = _kernel_options(kernel, L_over_a, nu)
        params = dict(ft=float(ft), w=float(w), periods=int(periods), dx=dx, dW=dW, kernel=kernel, shape=shape,
                      load_steps=int(load_steps))
        if spec != resolve() or normal != "auto":  # another body than the default's: its parameters
            params.update(spec.parameters, normal=spec.normal_mode(normal))
        if kernel == "strip":
            params.update(L_over_a=options["L_over_a"], nu=float(nu))
        if beta != 0.0:
            params.update(beta=beta, mu=mu)
    else:
        params = dict(ft=float(ft), w=float(w), periods=int(periods), dx=dx, dW=dW, body=spec.name,
                      ratio=getattr(spec, "ratio", None), angle=float(angle), nu=float(nu), shape=shape,
                      load_steps=int(load_steps))
    params["history"] = history if isinstance(history, str) else "arrays"
    if params["history"] == "arrays":  # the schedule's own periods; the rocking options played no part
        params["periods"] = int(schedule.periods)
        for name in ("ft", "w", "dW", "shape", "load_steps"):
            del params[name]
    if params["history"] in ("normal", "tangential"):
        params.update(amplitude=float(histories.default_amplitude(history, ft, amplitude)), phase=float(phase))
    if not path.is_default:  # its text (core.loading.paths.LoadingPath.parse reads it back)
        params["path"] = str(path)
    common = dict(tol=tol, detect_periodic=detect_periodic, shakedown_rtol=shakedown_rtol, params=params,
                  time_budget=time_budget, cancel=cancel, progress=progress, solver=solver, normal=normal)
    if line:
        return solve_schedule(schedule, dx, kernel, kernel_options=options, body=spec, beta=beta, mu=mu, **common)
    from .point_runs import solve_point_schedule
    if periodic_tol is not None:
        common["periodic_tol"] = periodic_tol
    return solve_point_schedule(schedule, dx, spec, nu=nu, angle=angle, **common)


def simulate_point_contact(ft, w, periods=10, dx=None, dW=None, *, body="sphere", ratio=None, angle=0.0, nu=0.5,
                           shape="triangle", load_steps=1, tol=None, detect_periodic=True, periodic_tol=None,
                           shakedown_rtol=1e-3, time_budget=None, cancel=None, progress=None, normal="auto",
                           solver="auto", history="rocking", amplitude=None, phase=0.0, path=None):
    """Simulate a point contact in normalised units: :func:`simulate_cycles` with a point body (the sphere by default).

    Parameters
    ----------
    ft, w, periods, dx, dW, ratio, angle, nu, shape, load_steps, tol, detect_periodic, shakedown_rtol,
    time_budget, cancel, progress, normal, solver, history, amplitude, phase, path :
        As in :func:`simulate_cycles` (``dx`` the element side, in [0.005, 0.5]; default
        :func:`core.geometry.resolution.default_dx`, 1/20).
    body : {"sphere", "ellipsoid", ...} or a point body object
        The body; ``"ellipsoid"`` takes ``ratio = Ry/Rx`` (x: the rocking direction).
    periodic_tol : float, optional
        The patch solver's periodic tolerance [mu p0] (default
        ``core.geometry.resolution.GRID_DEFAULTS["patch"].periodic_tol``).

    Returns
    -------
    CycleResult
        On a patch of elements (``is_patch``).

    Examples
    --------
    >>> import core
    >>> r = core.simulate_point_contact(0.2, 0.3, periods=6, dx=0.2)
    >>> r.regime
    'shakedown'
    """
    if _is_line_body(body):
        raise ValueError(f"body must be a point body (sphere, ellipsoid, ... or an object), got {body!r:.60}: "
                         "use core.simulate_cycles for a line body")
    return simulate_cycles(ft, w, periods, dx, dW, body=body, ratio=ratio, angle=angle, nu=nu, shape=shape,
                           load_steps=load_steps, tol=tol, detect_periodic=detect_periodic,
                           periodic_tol=periodic_tol, shakedown_rtol=shakedown_rtol, time_budget=time_budget,
                           cancel=cancel, progress=progress, normal=normal, solver=solver, history=history,
                           amplitude=amplitude, phase=phase, path=path)
