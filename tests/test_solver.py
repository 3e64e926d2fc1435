"""The cycle solver against closed forms, its invariants, and its own consistency."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

import core
from core import Schedule, SolverError, simulate_cycles, solve_schedule
from core.theory.analytical import _ellipse_primitive
from core.api.solver import shakedown_state


# ---------------------------------------------------------------------------
# Cattaneo-Mindlin: the first validation of any tangential solver
# ---------------------------------------------------------------------------
SOLVERS = ["dense", "fft"]  # the validations below run on both per-step solvers (the slow ones on one case)


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("dx", [1 / 40, 1 / 100])
@pytest.mark.parametrize("ft", [0.1, 0.4, 0.8])
def test_cattaneo_stick_zone_and_traction(ft, dx, solver):
    r = simulate_cycles(ft, 0.0, periods=1, dx=dx, solver=solver)
    c = float(core.cattaneo_stick_halfwidth(ft))
    assert abs(r.stick_halfwidth - c) <= dx, f"c = {r.stick_halfwidth} vs {c} (dx = {dx})"
    # element means of the closed form: exact for piecewise-constant tractions
    edges = r.edges
    mean_full = np.diff(_ellipse_primitive(edges)) / dx
    mean_stick = c * np.diff(_ellipse_primitive(edges / c) * c) / dx
    exact = mean_full - mean_stick
    err = np.abs(r.traction[0] - exact)
    assert err.sum() * dx < 2.0 * dx, f"L1 error {err.sum() * dx:.3g}"
    far = np.abs(np.abs(r.x) - c) > 3 * dx  # away from the stick edge, where the slope is infinite
    assert err[far].max() < 0.05 * np.sqrt(dx / (1 / 40)), err[far].max()


# ---------------------------------------------------------------------------
# invariants at every step
# ---------------------------------------------------------------------------
CASES = [
    dict(ft=0.08, w=0.77),                      # Fig 6, shakedown
    dict(ft=0.58, w=0.77),                      # Fig 7, ratcheting
    dict(ft=0.58, w=0.26, shape="sine"),
    dict(ft=-0.3, w=0.5, load_steps=5),
    dict(ft=0.3, w=0.4, kernel="strip", L_over_a=50.0, nu=0.3),
]


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("case", CASES, ids=lambda c: ",".join(f"{k}={v}" for k, v in c.items()))
def test_invariants_at_every_step(case, check_invariants, solver):
    r = simulate_cycles(periods=6, dx=1 / 30, solver=solver, **case)
    check_invariants(r)


@pytest.mark.parametrize("solver", SOLVERS)
def test_mirrored_schedule_gives_mirrored_result(solver):
    s = core.rocking_schedule(0.45, 0.5, periods=4, dW=1 / 30, load_steps=3)
    m = Schedule(xc=-s.xc, P=s.P, Q=-s.Q, period=s.period)
    a = solve_schedule(s, dx=1 / 30, detect_periodic=False, solver=solver)
    b = solve_schedule(m, dx=1 / 30, detect_periodic=False, solver=solver)
    assert_allclose(b.traction, -a.traction[:, ::-1], atol=1e-9)
    assert_allclose(b.displacement, -a.displacement, atol=1e-9)
    mirrored_state = a.state[:, ::-1].copy()
    mirrored_state[a.state[:, ::-1] == 2] = 3
    mirrored_state[a.state[:, ::-1] == 3] = 2
    assert np.array_equal(b.state, mirrored_state)


@pytest.mark.parametrize("solver", SOLVERS)
def test_periodic_detection_changes_nothing(solver):
    for ft, w in [(0.58, 0.52), (0.08, 0.26)]:
        a = simulate_cycles(ft, w, periods=10, dx=1 / 30, solver=solver)
        b = simulate_cycles(ft, w, periods=10, dx=1 / 30, detect_periodic=False, solver=solver)
        assert a.periodic_from is not None, "the steady state should have been detected"
        assert b.periodic_from is None
        assert_allclose(a.traction, b.traction, atol=1e-9)
        assert_allclose(a.displacement, b.displacement, atol=1e-9)
        assert_allclose(a.increment_per_period, b.increment_per_period, atol=1e-9)
        assert a.regime == b.regime


# ---------------------------------------------------------------------------
# convergence and agreement with the analysis
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("ft, w, solver", [(0.58, 0.77, "dense"), (0.58, 0.52, "dense"), (0.58, 0.52, "fft")])
def test_increment_per_period_converges_with_the_grid(ft, w, solver):
    inc = [simulate_cycles(ft, w, periods=6, dx=dx, solver=solver).increment_per_period[-1]
           for dx in (1 / 20, 1 / 40, 1 / 80)]
    d1, d2 = abs(inc[1] - inc[0]), abs(inc[2] - inc[1])
    assert d2 < 0.75 * d1, inc                 # converging
    assert d2 / abs(inc[2]) < 0.005, inc        # the default dx = 1/40 is within about 0.5 %


@pytest.mark.parametrize("w, solver", [(0.26, "dense"), (0.52, "dense"), (0.77, "dense"), (0.26, "fft")])
def test_numerical_limit_brackets_eq35(w, solver):
    lim = float(core.ft_limit(w))
    below = simulate_cycles(lim - 0.03, w, periods=12, solver=solver)
    above = simulate_cycles(lim + 0.03, w, periods=12, solver=solver)
    assert below.regime == "shakedown", below.increment_per_period
    assert above.regime == "ratcheting", above.increment_per_period
    assert above.increment_per_period[-1] > 0  # walks along Ft


@pytest.mark.parametrize("ft, w", [(0.08, 0.77), (0.2, 0.3), (0.5, 0.3), (0.6, 0.26)])
def test_direct_shakedown_state_matches_transient(ft, w):
    """The shaken-down traction is one static partial-slip solution with the bound
    mu * (lowest pressure over the period), the bound of the paper's slip zone (eq 22)."""
    dx = 1 / 40
    r = simulate_cycles(ft, w, periods=30, dx=dx)
    assert r.regime == "shakedown"
    sd = shakedown_state(ft, w, dx)
    assert sd.traction.shape == r.traction[-1].shape
    assert_allclose(r.traction[-1], sd.traction, atol=1e-8)
    assert sd.stick_halfwidth == pytest.approx(r.stick_halfwidth)
    assert_allclose(sd.bound, r.lowest_pressure, atol=1e-12)


@pytest.mark.parametrize("w", [0.26, 0.52, 0.77])
@pytest.mark.parametrize("frac", [0.2, 0.5, 0.8, 0.95])
def test_closure_against_numerical_shakedown_state(w, frac):
    """The paper's ansatz (eq 30) against the numerics: c_sd within 0.005 a, the
    traction within 0.01 mu p0 at the centre and 0.003 mu p0 a in L1. It is close,
    not exact: the centre error grows towards the limit (0.007 at 0.95 ft_lim) and
    does not shrink with dx (benchmarks/closure_vs_numerics.py prints the table)."""
    ft = frac * float(core.ft_limit(w))
    dx = 1 / 400
    sd = shakedown_state(ft, w, dx)
    x, q, c = sd.x, sd.traction, sd.stick_halfwidth
    c_closure = float(core.shakedown_stick_halfwidth(ft, w))
    assert abs(c - c_closure) < 0.005, (c, c_closure)
    tau = core.shakedown_traction(x, ft, w)
    assert abs(tau[np.argmin(np.abs(x))] - q[np.argmin(np.abs(x))]) < 0.01
    assert np.abs(tau - q).sum() * dx < 0.003


def test_stick_halfwidth_definition_in_a_shaken_down_run():
    r = simulate_cycles(0.2, 0.3, periods=10)
    assert r.regime == "shakedown"
    # at the end nothing slips any more, yet the paper's stick zone is a strict subset
    assert np.all(r.state[-1][r.state[-1] > 0] == 1)
    assert 0 < r.stick_halfwidth < 1 - 0.3
    assert abs(r.stick_halfwidth - float(core.shakedown_stick_halfwidth(0.2, 0.3))) < 2 * r.dx


def test_ratcheting_has_no_stick_zone_and_constant_increment():
    r = simulate_cycles(0.58, 0.77, periods=10)
    assert r.regime == "ratcheting" and r.shakedown_period is None
    inc = r.increment_per_period
    assert_allclose(inc[-3:], inc[-1], rtol=1e-6)
    assert r.stick_halfwidth < 0.1


def test_strip_kernel_in_physical_units():
    c = core.PAPER_SIMULATION.replace(ft=0.08, w=0.26)
    r = core.simulate_contact(c, periods=8)
    assert r.kernel == "strip" and r.u0 == pytest.approx(core.strip_u0(c.L / c.a, 2.0))
    assert r.regime == "shakedown"
    u_sd = r.u[-1]
    # eq 34 (a regression of the paper) within 5 %
    assert u_sd == pytest.approx(core.theory.approximations.shakedown_displacement_approx(0.08, 0.26), rel=0.05)
    # static value after loading within 5 % of eq 13
    assert r.u[0] == pytest.approx(core.theory.approximations.static_displacement_approx(0.08), rel=0.05)


def test_oscillating_normal_load_is_just_another_schedule(check_invariants):
    steps = 200
    t = np.arange(steps) / 50
    s = Schedule(xc=np.zeros(steps), P=1 + 0.2 * np.sin(2 * np.pi * t), Q=np.full(steps, 0.3),
                 period=np.repeat(np.arange(4), 50))
    r = solve_schedule(s, dx=1 / 30)
    check_invariants(r)


# ---------------------------------------------------------------------------
# failure is loud, inputs are checked
# ---------------------------------------------------------------------------
def test_unsolvable_step_raises_naming_step_xc_and_residual():
    with pytest.raises(SolverError, match=r"step \d+ \(xc = .*KKT residual"):
        solve_schedule(core.rocking_schedule(0.58, 0.77, periods=2, dW=1 / 20), dx=1 / 20, maxiter=1)


@pytest.mark.parametrize(
    "kw, name",
    [(dict(ft=1.0), "ft"), (dict(ft=np.nan), "ft"), (dict(w=1.0), "w"), (dict(w=-0.1), "w"),
     (dict(periods=0), "periods"), (dict(periods=2.5), "periods"), (dict(dx=0.0), "dx"), (dict(dx=np.inf), "dx"),
     (dict(kernel="fem"), "kernel"), (dict(kernel="strip"), "L_over_a"), (dict(shape="square"), "shape"),
     (dict(dW=-1.0), "dW"), (dict(tol=1.0), "tol"), (dict(dx=1e-4), "elements")],
)
def test_bad_inputs_raise_value_error_naming_parameter(kw, name):
    args = dict(ft=0.2, w=0.3, periods=2)
    args.update(kw)
    with pytest.raises(ValueError, match=name):
        simulate_cycles(**args)


def test_result_is_frozen_and_its_arrays_read_only():
    import dataclasses

    r = simulate_cycles(0.2, 0.3, periods=2)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.tol = 1.0  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.traction = np.zeros_like(r.traction)  # type: ignore[misc]
    for name in ("edges", "xc", "P", "Q", "period", "traction", "state", "displacement", "dissipation",
                 "iterations", "kkt_residual", "x", "pressures", "increment_per_period", "lowest_pressure",
                 "final_zones"):
        arr = getattr(r, name)
        with pytest.raises(ValueError, match="read-only"):
            arr[...] = 0
    with pytest.raises(TypeError, match="does not support item assignment"):
        r.pressure[0] = 0  # the per-step view of the stored bounds
    with pytest.raises(ValueError, match="read-only"):
        r.pressure[0][...] = 0
    strip = core.simulate_contact(core.PAPER_SIMULATION.replace(ft=0.1, w=0.2), periods=1)
    with pytest.raises(ValueError, match="read-only"):
        strip.u[0] = 1.0


# ---------------------------------------------------------------------------
# bounded work: cancellation, time budget, progress, size caps
# ---------------------------------------------------------------------------
def test_cancel_stops_the_solve_between_chunks():
    calls = []

    def cancel():
        calls.append(1)
        return len(calls) >= 2

    with pytest.raises(core.SolveCancelled, match="cancelled after"):
        simulate_cycles(0.58, 0.77, periods=10, dx=1 / 60, detect_periodic=False, cancel=cancel)
    assert len(calls) == 2


def test_time_budget_stops_the_solve_with_a_message():
    with pytest.raises(core.SolveCancelled, match="time budget"):
        simulate_cycles(0.3, 0.77, periods=200, dx=1 / 100, detect_periodic=False, time_budget=1e-3)


def test_progress_reports_increasing_fractions_and_chunks_change_nothing():
    seen = []
    a = simulate_cycles(0.58, 0.52, periods=5, dx=1 / 40, detect_periodic=False, progress=seen.append)
    assert seen == sorted(seen) and seen[-1] == 1.0 and len(seen) >= 2
    s = core.rocking_schedule(0.58, 0.52, periods=5, dW=1 / 40)
    b = solve_schedule(s, dx=1 / 40, detect_periodic=False, chunk=7)
    assert_allclose(a.traction, b.traction, atol=0)
    assert_allclose(a.displacement, b.displacement, atol=0)


def test_stored_size_is_capped():
    with pytest.raises(ValueError, match="stored values"):
        simulate_cycles(0.3, 0.9, periods=2000, dx=1 / 200)
    with pytest.raises(ValueError, match="steps"):
        simulate_cycles(0.3, 0.9, periods=10_000, dx=1 / 200)
