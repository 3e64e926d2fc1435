"""The parts of a run: the dense per-step solver, the solver choice, the run function, the read-only install."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import core
from core.geometry.bodies import Cylinder
from core.solvers.dense import RESIDUALS, DenseSolver, Trajectory
from core.march.engine import AUTO_CROSSOVER, run, select_solver
from core.solvers.matrix_free import FFTSolver
from core.elastic.operators import DenseOperator, FFTOperator
from core.base.states import State


def _solver(n=40, dx=1 / 20, tol=1e-10):
    return DenseSolver(DenseOperator(n, dx), element_size=dx, tol=tol, maxiter=200)


def test_dense_step_reports_named_residuals_and_cattaneo():
    body = Cylinder.for_reach(1.0, 1 / 20)
    s = _solver(body.size, body.dx)
    g = body.bounds([0.0], [1.0])[0]
    step = s.step(g, float(body.load_target(0.5)))
    assert step.converged and step.iterations > 0
    assert set(step.residuals) == set(RESIDUALS) and step.kkt_residual <= 1e-10
    # load balance and Coulomb, by hand
    assert step.traction.sum() * body.dx == pytest.approx(0.5 * np.pi * 0.5, abs=1e-10)
    assert np.all(np.abs(step.traction) <= g + 1e-10)
    # the stick zone is Cattaneo's c = sqrt(1 - ft) to a cell
    stick = (step.state == State.STICK) & (np.abs(step.traction) < g - 1e-7)
    c = 0.5 * (body.edges[np.flatnonzero(stick)[-1] + 1] - body.edges[np.flatnonzero(stick)[0]])
    assert abs(c - np.sqrt(0.5)) <= body.dx
    # the same load again: the zero increment, no iteration
    again = s.step(g, float(body.load_target(0.5)))
    assert again.iterations == 0 and again.displacement == 0.0
    assert_allclose(again.traction, step.traction, atol=0)
    with pytest.raises(ValueError, match="read-only"):
        step.traction[0] = 1.0


def test_dense_step_that_cannot_settle_says_so():
    body = Cylinder.for_reach(1.0, 1 / 20)
    s = DenseSolver(DenseOperator(body.size, body.dx), element_size=body.dx, tol=1e-10, maxiter=1)
    step = s.step(body.bounds([0.0], [1.0])[0], float(body.load_target(0.9)))
    assert not step.converged and step.kkt_residual > 1e-10
    assert not s.traction.any()  # a failed step does not advance


def test_solver_choice():
    assert select_solver("dense", 100) is DenseSolver and select_solver("fft", 10) is FFTSolver
    assert select_solver("auto", AUTO_CROSSOVER) is DenseSolver
    assert select_solver("auto", AUTO_CROSSOVER + 1) is FFTSolver
    with pytest.raises(ValueError, match="solver must be one of"):
        select_solver("cholesky", 10)
    with pytest.raises(ValueError, match="solver"):
        core.simulate_cycles(0.2, 0.3, periods=1, solver="magic")


def test_each_solver_gets_the_operator_form_it_needs():
    """Dense matrix only for "dense"; the FFT form (no n x n matrix) for "fft"."""
    dense = core.march.engine.make_operator(DenseSolver, 40, 0.05)
    fft = core.march.engine.make_operator(FFTSolver, 40, 0.05)
    assert isinstance(dense, DenseOperator) and isinstance(fft, FFTOperator)
    assert not any(isinstance(v, np.ndarray) and v.ndim == 2 for v in vars(fft).values())
    with pytest.raises(ValueError, match="operator"):
        FFTSolver(object(), element_size=0.05, tol=1e-10, maxiter=10)


def test_entry_points_are_the_run_function_on_the_parts():
    s = core.rocking_schedule(0.58, 0.52, periods=3, dW=1 / 30)
    body = Cylinder.for_history(s, 1 / 30)
    direct = run(body, DenseOperator(body.size, body.dx), s, solver="dense", tol=1e-10)
    via = core.simulate_cycles(0.58, 0.52, periods=3, dx=1 / 30, solver="dense")
    auto = core.simulate_cycles(0.58, 0.52, periods=3, dx=1 / 30)
    for r in (via, auto):
        assert np.array_equal(r.traction, direct.traction) and np.array_equal(r.displacement, direct.displacement)
    assert direct.solver == "dense" and direct.body_name == "cylinder" and not direct.cg_iterations.any()
    assert set(direct.residuals) == set(RESIDUALS) and max(direct.residuals.values()) <= direct.tol
    assert direct.max_kkt_residual == pytest.approx(max(direct.residuals.values()))
    with pytest.raises(ValueError, match="shape"):
        run(body, DenseOperator(body.size + 2, body.dx), s, tol=1e-10)


def test_import_on_a_read_only_install_without_a_numba_cache(tmp_path):
    """numba cannot cache next to a read-only source or in an unusable home: `import core` must still work."""
    root = tmp_path / "site"
    shutil.copytree(Path(core.__file__).parent, root / "core", ignore=shutil.ignore_patterns("__pycache__"))
    for package in [root / "core", *(p.parent for p in (root / "core").glob("*/__init__.py"))]:
        (package / "__pycache__").write_text("")  # a file: no cache directory can be made there (even as root)
    for path in sorted(root.rglob("*"), reverse=True) + [root]:
        path.chmod(0o555 if path.is_dir() else 0o444)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "XDG_", "PYTHON"))}
    env.update(HOME="/dev/null", PYTHONPATH=str(root), PYTHONDONTWRITEBYTECODE="1")
    # a small kernel, compiled without a cache (a whole run would compile every kernel: ~40 s)
    code = ("import core, core.base._jit; p = core.hertz_pressure_element_mean([-1.0, -0.3, 0.2, 1.0], 0.1); "
            "print(core.__file__, core.base._jit.CACHING, repr(float(p.sum())))")
    try:
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300,
                             cwd=tmp_path)
    finally:
        for path in [root] + sorted(root.rglob("*")):
            path.chmod(0o755 if path.is_dir() else 0o644)
    assert out.returncode == 0, out.stderr[-2000:]
    here = core.hertz_pressure_element_mean([-1.0, -0.3, 0.2, 1.0], 0.1).sum()
    assert out.stdout.split() == [str(root / "core" / "__init__.py"), "False", repr(float(here))]


class _MatrixOnly:
    """A dense operator that does not say it is Toeplitz: the dense solver keeps the classical stick-set inverse."""

    def __init__(self, op):
        self._op = op
        self.shape, self.size = op.shape, op.size

    def matrix(self):
        return self._op.matrix()


@pytest.mark.parametrize("history", [
    core.loading.histories.rocking(0.58, 0.52, periods=3, dW=1 / 40),                # ratcheting: large slip zones
    core.loading.histories.rocking(0.3, 0.5, periods=3, dW=1 / 60, normal_amplitude=0.3, normal_phase=0.7),
    core.loading.histories.rocking(0.08, 0.77, periods=2, dW=1 / 50, shape="sine"),
])
def test_dense_interval_inverses_equal_the_stick_set_inverse(history):
    """The Toeplitz path (inverses of K on the contact interval, core.solvers._pdas) and the classical rank-one
    updates solve the same KKT conditions: same iterations, increments equal to round-off, also when the
    contact width changes every step (oscillating normal force) and when it switches between the two."""
    dx = 1 / 60
    body = Cylinder.for_history(history, dx)
    op = DenseOperator(body.size, body.dx)
    fast = run(body, op, history, solver="dense", tol=1e-10, detect_periodic=False)
    slow_solver = DenseSolver(_MatrixOnly(op), element_size=dx, tol=1e-10, maxiter=500)
    assert DenseSolver(op, element_size=dx, tol=1e-10, maxiter=10).state.kfull.size > 0
    assert slow_solver.state.kfull.size == 0
    out = Trajectory(len(history), body.size)
    bounds = body.bounds(history.xc, history.P)
    done, _, failed = slow_solver.march(bounds, history.Q, history.period, float(body.load_target(1.0)), 0,
                                        len(history), False, out)
    assert failed < 0 and done == len(history)
    assert_allclose(fast.iterations, out.iterations, atol=0)
    assert_allclose(fast.displacement, out.displacement, rtol=1e-9, atol=1e-12)
    assert_allclose(fast.traction, out.traction, rtol=0, atol=1e-9)
    assert fast.max_kkt_residual <= 1e-10


def test_grid_caps_by_solver():
    """The dense solver's grid cap (MAX_ELEMENTS, its n x n matrices) is lifted for the matrix-free one up to
    MAX_FFT_ELEMENTS; both refusals name dx and the smallest it may be."""
    from core.geometry.bodies import MAX_ELEMENTS, MAX_FFT_ELEMENTS

    dx = 2.0 / (MAX_ELEMENTS + 100)
    assert Cylinder.for_reach(1.0, dx, MAX_FFT_ELEMENTS).size > MAX_ELEMENTS
    with pytest.raises(ValueError, match=r"dx = .* needs \d+ elements \(> 4000\): dx must be >= .*solver='fft'"):
        core.simulate_cycles(0.2, 0.0, periods=1, dx=dx, solver="dense")
    with pytest.raises(ValueError, match=rf"dx = .* \(> {MAX_FFT_ELEMENTS}\): dx must be >= "):
        core.simulate_cycles(0.2, 0.5, periods=1, dx=1e-4)


# ---- one engine for lines and patches -----------------------------------------------------------------------
def test_one_set_of_residual_names_and_state_codes_for_every_grid():
    from core.solvers.solver3d import _state_codes
    from core.base.states import RESIDUAL_NAMES
    # every solver's run reports the one set of residuals, by the names of core.base.states
    line = core.simulate_cycles(0.2, 0.3, periods=1, dx=0.25)
    patch = core.simulate_cycles(0.2, 0.3, periods=1, dx=0.25, body="sphere")
    assert tuple(line.residuals) == tuple(patch.residuals) == tuple(RESIDUAL_NAMES)
    # a patch's states: released where p = 0, stick, slip forward/backward by the slip's x component
    g = np.array([[0.0, 1.0, 1.0, 1.0]])
    s = np.zeros((2, 1, 4))
    s[0, 0, 2], s[0, 0, 3], s[1, 0, 1] = 1e-3, -1e-3, 0.0
    codes = _state_codes(np.zeros((2, 1, 4)), s, g, 1e-8)
    assert codes.tolist() == [[State.RELEASED, State.STICK, State.SLIP_FORWARD, State.SLIP_BACKWARD]]


def test_every_step_solver_is_registered_for_one_grid_shape():
    from core.march.engine import STEP_SOLVERS, SOLVER_CHOICES_BY_GRID
    from core.solvers.solver3d import PatchSolver
    assert STEP_SOLVERS["pcg3d"] is PatchSolver
    for name, cls in STEP_SOLVERS.items():
        assert name in SOLVER_CHOICES_BY_GRID[cls.grid] and cls.name == name
    assert select_solver("auto", 10**6, "patch") is PatchSolver
    with pytest.raises(ValueError, match=r"\('auto', 'pcg3d'\).*'dense'"):
        select_solver("dense", 100, "patch")


def test_a_patch_runs_through_the_same_loop_with_its_period_repeated():
    """A sphere that shakes down: the march stops at the repeated period and run copies it, as for a line."""
    calls = []
    r = core.simulate_cycles(0.2, 0.3, periods=12, dx=0.2, body="sphere", progress=calls.append)
    assert r.solver == "pcg3d" and r.periodic_from is not None and calls[-1] == 1.0
    full = core.simulate_cycles(0.2, 0.3, periods=12, dx=0.2, body="sphere", detect_periodic=False)
    assert full.periodic_from is None
    assert_allclose(r.increment_per_period, full.increment_per_period, atol=1e-6)
    copied = r.period > r.periodic_from
    assert not r.iterations[copied].any() and full.iterations[copied].any()


def test_a_patch_run_can_be_cancelled_between_chunks():
    from core.records.result import SolveCancelled
    from core.loading.schedule import rocking_schedule
    from core.api.point_runs import solve_point_schedule
    from core.theory.point_contact import Ellipsoid
    with pytest.raises(SolveCancelled, match="cancelled after 10 of"):
        solve_point_schedule(rocking_schedule(0.3, 0.3, periods=4, dW=0.2), 0.2, Ellipsoid(1.0), chunk=10,
                             cancel=lambda: True)


def test_one_result_type_keeps_the_body_object_for_both_shapes():
    line = core.simulate_cycles(0.2, 0.3, periods=4, dx=0.1, body=core.Punch(flat=0.5))
    patch = core.simulate_cycles(0.2, 0.3, periods=4, dx=0.2, body="ellipsoid", ratio=2.0)
    for r, body, name in ((line, core.Punch(flat=0.5), "punch"), (patch, core.Ellipsoid(2.0), "ellipsoid")):
        assert type(r) is core.CycleResult and r.body == body and r.body_name == name and r.body_spec is r.body
        assert set(r.residuals) == set(core.RESIDUAL_NAMES) and r.max_kkt_residual <= 10 * r.tol
        assert r.increment_per_period.size == 4 and r.summary()["regime"] == r.regime
        assert r.lowest_pressure.shape == r.pressure_at(0).shape == r.final_state.shape
    assert not line.is_patch and line.y_edges is None and line.increment_unit == "mu P/E*"
    assert patch.is_patch and patch.traction.shape == (len(patch.xc), 2, patch.x.size)
    assert patch.increment_unit == "mu Fn/(E* a)" and patch.kernel == "halfspace" and patch.solver == "pcg3d"
    # the former names keep working: the point-contact alias tells a patch run from a line run
    assert isinstance(patch, core.PointContactResult) and not isinstance(line, core.PointContactResult)
    assert isinstance(line, core.LineResult) and not isinstance(patch, core.LineResult)
    assert patch.traction_cut is patch.traction and patch.x_edges is patch.edges
    # the per-step pressure is the same kind of thing on both grids: indexed by step, a step's the grid's shape
    for r in (line, patch):
        assert type(r.pressure) is core.PerStep and len(r.pressure) == r.xc.size
        assert r.pressure.shape == (r.xc.size, *r.final_state.shape) == np.asarray(r.pressure).shape
        assert_array_equal(r.pressure[3], r.pressure(3))
        assert_array_equal(r.pressure[3], r.pressure_at(3))
        assert_array_equal(np.asarray(r.pressure)[2:5], r.pressure[2:5])
        assert not r.pressure[3].flags.writeable and not r.pressure[2:5].flags.writeable
    assert line.pressure.shape == line.traction.shape
    # one summary layout: the same keys in the same order on both grids
    inputs = {*line.params, *patch.params}
    assert [k for k in line.summary() if k not in inputs] == [k for k in patch.summary() if k not in inputs]
    assert line.summary()["twist_last_period"] is None and patch.summary()["u0"] is None


@pytest.mark.parametrize("body, dx", [(core.Punch(flat=0.5), 0.1), (core.Ellipsoid(2.0), 0.2)])
def test_a_result_keeps_the_bounds_and_the_limit_the_run_used(body, dx):
    """The engine stores each step's bound and the grid's Melan limit when the run ends: they are the grid's own,
    recomputed here, and a copied period's steps share the rows of the period they repeat."""
    from core.pressure import melan
    from core.geometry.patch import PatchGrid
    r = core.simulate_cycles(0.2, 0.3, periods=12, dx=dx, body=body)
    assert r.periodic_from is not None and r.periodic_from < r.periods - 1  # the march stopped: periods copied
    grid = (PatchGrid(r.body, r.edges, r.y_edges, r.params["normal"]) if r.is_patch
            else r.body.on_grid(r.edges, r.params["normal"]))
    fresh = grid.bounds(r.xc, r.P, out=None)
    for k in range(r.xc.size):
        assert_allclose(r.pressure_at(k), fresh[k], rtol=0, atol=1e-13, err_msg=f"step {k}")
    assert r.pressures.shape[0] < r.xc.size and r.pressure_index.shape == r.xc.shape
    last = r.period == r.period[-1]
    lowest = np.min([fresh[k] for k in np.flatnonzero(last)], axis=0)
    assert_allclose(r.lowest_pressure, lowest, rtol=0, atol=1e-13)
    expected = melan.grid_limit(lowest, fresh[-1], r.P[-1])
    assert r.melan_limit == (pytest.approx(expected, rel=1e-12),) * 2


def test_result_module_computes_nothing_through_the_registry_or_a_solver():
    """core/records/result.py is a record: no import of the registry, the bodies' grids, Melan's limit or a solver."""
    import ast
    tree = ast.parse(Path(core.records.result.__file__).read_text())
    # a module by its last name (``from ..base.states import`` is ``states``), so a move between layers shows
    imported = {(node.module or "").rpartition(".")[2] for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    imported |= {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names}
    assert imported <= {"__future__", "math", "warnings", "dataclasses", "functools", "typing", "numpy", "states",
                        "verdict", "static_result", "_validate"}, imported
    r = core.simulate_cycles(0.2, 0.3, periods=2, dx=0.2)
    with pytest.raises(ValueError, match="body must be a body object"):
        core.CycleResult(**{**{f: getattr(r, f) for f in r.__dataclass_fields__}, "body": "cylinder"})


@pytest.mark.parametrize("body, solver, valid", [("sphere", "dense", "'pcg3d'"), ("sphere", "fft", "'pcg3d'"),
                                                 ("cylinder", "pcg3d", "'dense', 'fft'"),
                                                 ("punch", "pcg3d", "'dense', 'fft'")])
def test_solver_is_honoured_or_refused_naming_the_choices_for_every_body(body, solver, valid):
    with pytest.raises(ValueError, match=rf"solver must be one of .*{valid}"):
        core.simulate_cycles(0.2, 0.3, periods=1, dx=0.25, body=body, solver=solver)


def test_the_patch_solver_can_be_named_and_the_line_solvers_agree():
    """solver= is honoured on both grids; on a line the two solvers (dense inverses, FFT-preconditioned CG: two
    algorithms) give the same increments to their tolerance."""
    r = core.simulate_cycles(0.2, 0.3, periods=2, dx=0.25, body="sphere", solver="pcg3d")
    assert r.solver == "pcg3d" and r.is_patch
    dense = core.simulate_cycles(0.3, 0.5, periods=3, dx=1 / 20, solver="dense")
    fft = core.simulate_cycles(0.3, 0.5, periods=3, dx=1 / 20, solver="fft")
    assert (dense.solver, fft.solver) == ("dense", "fft")
    assert_allclose(fft.increment_per_period, dense.increment_per_period, rtol=0, atol=1e-9)


def test_one_static_solve_for_a_line_and_a_patch():
    """core.solve_static dispatches on the bound's shape, one step of each grid's solver: under mu p it is
    Cattaneo's stick zone on a line (c = sqrt(1 - Q), eq 7) and Mindlin's on a patch (c = (1 - ft)^(1/3) at nu = 0);
    shakedown_state takes a point body."""
    from core.geometry.patch import _grid, _pressure
    body = core.Ellipsoid(1.0)
    xe, ye = _grid(body, 1.0, 1.0, 0.05)
    p = _pressure(xe, ye, 0.0, body, normal="exact")
    patch = core.solve_static(p, 0.5, 0.05, nu=0.0)
    assert_allclose(patch.x_edges, xe)
    assert patch.stick_halfwidth == pytest.approx(0.5 ** (1 / 3), abs=1.5 * 0.05)
    line = core.solve_static(Cylinder.for_reach(1.0, 0.01).bounds([0.0], [1.0])[0], 0.5, 0.01)
    assert line.traction.ndim == 1 and max(line.residuals.values()) <= 1e-10
    assert line.stick_halfwidth == pytest.approx(np.sqrt(0.5), abs=0.02)
    assert_allclose(line.traction, core.cattaneo_traction(line.x, 0.5), atol=0.02)
    sd = core.shakedown_state(0.3, 0.3, 0.1, body="sphere")
    assert sd.is_patch and sd.bound.shape == sd.traction.shape[1:]
    with pytest.raises(ValueError, match=r"\('auto', 'pcg3d'\)"):
        core.solve_static(p, 0.5, 0.1, solver="dense")


def test_one_static_result_for_a_line_and_a_patch():
    """solve_static, shakedown_state and mindlin_state return one type on either grid (the three former names are
    aliases of it), read-only, with the bound, states, edges and stick half-widths."""
    line = core.shakedown_state(0.3, 0.3, dx=1 / 20)
    patch = core.shakedown_state(0.3, 0.3, 0.1, body="sphere")
    mindlin = core.mindlin_state(0.5, 0.1)
    for res in (line, patch, mindlin):
        assert type(res) is core.StaticResult
        for arr in (res.traction, res.bound, res.state, res.edges):
            with pytest.raises(ValueError):
                arr[0] = 0
    assert not line.is_patch and line.y is None and line.cut_row is None and line.stick_halfwidth_y is None
    assert line.stick_halfwidth == 0.5 and line.x.size == line.traction.size == line.state.size
    assert set(np.unique(line.state)) <= {0, 1, 2} and np.all((line.state == 0) == (line.bound == 0))
    assert patch.is_patch and patch.traction.shape == (2, *patch.bound.shape) and patch.displacement.shape == (2,)
    assert patch.iterations > 0 and mindlin.stick_halfwidth == pytest.approx(0.5 ** (1 / 3), abs=0.1)
    bound = Cylinder.for_reach(1.0, 0.05).bounds([0.0], [1.0])[0]
    centred = core.solve_static(bound, 0.5, 0.05)
    shifted = core.solve_static(bound, 0.5, 0.05, edges=centred.edges + 0.2)
    assert_allclose(shifted.traction, centred.traction, rtol=0, atol=0)
    assert shifted.x == pytest.approx(centred.x + 0.2) and centred.x.mean() == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(ValueError, match="edges must be"):
        core.solve_static(bound, 0.5, 0.05, edges=centred.edges[:-1])


class _TabulatedSphere:  # noqa: D101
    """A point body written against the patch protocol alone (its own grid and pressure, a solver option)."""

    name = "tabulated sphere"
    solver_options = {"cg_maxiter": 400}

    def __init__(self):
        self.sphere = core.Ellipsoid(1.0)
        self.total_load, self.kernel_scale = self.sphere.total_load, self.sphere.kernel_scale

    def run_grid(self, reach_x, scale, h):
        from core.geometry.patch import _grid
        return _grid(self.sphere, reach_x + scale, scale, h)

    def grid_pressure(self, x_edges, y_edges, xc, scale):
        from core.geometry.patch import _pressure
        return _pressure(x_edges, y_edges, xc, self.sphere, scale)


def test_a_point_body_plugs_into_the_engine_through_its_hooks():
    body = _TabulatedSphere()
    r = core.simulate_cycles(0.5, 0.3, periods=3, dx=0.2, body=body)
    ref = core.simulate_cycles(0.5, 0.3, periods=3, dx=0.2, body="sphere")
    assert r.is_patch and r.body is body and r.body_name == "tabulated sphere" and r.solver == "pcg3d"
    assert_allclose(r.increment_per_period, ref.increment_per_period, rtol=1e-12)
    assert_allclose(r.pressure_at(5), ref.pressure_at(5), rtol=0, atol=0)
    # a hook changes the run: free to turn about the normal through a point off the load's line, the body turns
    turning = _TabulatedSphere()
    turning.twist_centre = (0.0, 0.5)
    t = core.simulate_cycles(0.5, 0.3, periods=1, dx=0.2, body=turning)
    assert r.rotation is None and t.rotation is not None and np.abs(t.rotation).max() > 1e-3


def test_building_a_point_contact_result_builds_the_one_result_with_a_warning():
    r = core.simulate_cycles(0.2, 0.3, periods=2, dx=0.25, body="sphere")
    with pytest.warns(DeprecationWarning, match="PointContactResult is CycleResult"):
        old = core.PointContactResult(
            body=r.body, nu=r.nu, angle=r.angle, x_edges=r.edges, y_edges=r.y_edges, xc=r.xc, P=r.P, Q=r.Q,
            period=r.period, displacement=r.displacement, traction_cut=r.traction, state_cut=r.state,
            snapshot_steps=r.snapshot_steps, traction_snapshots=r.traction_snapshots,
            state_snapshots=r.state_snapshots, lowest_pressure=r.lowest_pressure, dissipation=r.dissipation,
            iterations=r.iterations, cg_iterations=r.cg_iterations, residuals=r.step_residuals,
            periodic_from=r.periodic_from, params=r.params, tol=r.tol)
    assert type(old) is core.CycleResult and isinstance(old, core.PointContactResult)
    assert_allclose(old.increment_per_period, r.increment_per_period, rtol=0, atol=0)
    assert old.max_kkt_residual == r.max_kkt_residual and old.regime == r.regime
