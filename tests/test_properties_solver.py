"""Hypothesis property tests: the solver's invariants over random valid inputs and schedules."""

import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st

import core
from core import Schedule, solve_schedule

FAST = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@FAST
@given(
    ft=st.floats(-0.95, 0.95),
    w=st.floats(0.0, 0.9),
    inv_dx=st.integers(8, 30),
    periods=st.integers(1, 4),
    shape=st.sampled_from(["triangle", "sine"]),
    load_steps=st.integers(1, 4),
    kernel=st.sampled_from(["plane", "strip"]),
)
def test_rocking_runs_keep_coulomb_balance_and_dissipation(ft, w, inv_dx, periods, shape, load_steps, kernel,
                                                           check_invariants):
    extra = dict(L_over_a=40.0, nu=0.4) if kernel == "strip" else {}
    r = core.simulate_cycles(ft, w, periods=periods, dx=1 / inv_dx, shape=shape, load_steps=load_steps,
                             kernel=kernel, **extra)
    check_invariants(r)
    assert r.regime in ("shakedown", "ratcheting", "undetermined")  # undetermined: too few periods to tell
    assert 0.0 <= r.stick_halfwidth <= 1.0
    # the body walks along the load, never against it (beyond round-off: at w ~ 0 the increment is ~1e-16)
    assert np.all(r.increment_per_period * np.sign(ft) >= -1e-12)


@st.composite
def schedules(draw):
    """Random histories: wandering centre, varying normal and tangential load."""
    steps = draw(st.integers(2, 60))
    xc = np.cumsum(draw(st.lists(st.floats(-0.08, 0.08), min_size=steps, max_size=steps)))
    xc = np.clip(xc, -0.9, 0.9)
    P = np.array(draw(st.lists(st.floats(0.6, 1.4), min_size=steps, max_size=steps)))
    frac = np.array(draw(st.lists(st.floats(-0.95, 0.95), min_size=steps, max_size=steps)))
    return Schedule(xc=xc, P=P, Q=frac * P, period=np.zeros(steps, dtype=int))


@FAST
@given(schedule=schedules(), inv_dx=st.integers(10, 30))
def test_arbitrary_schedules_keep_the_invariants(schedule, inv_dx, check_invariants):
    r = solve_schedule(schedule, dx=1 / inv_dx)
    check_invariants(r)


@FAST
@given(ft=st.floats(0.0, 0.95), w=st.floats(0.0, 0.9))
def test_more_load_never_shrinks_the_slip(ft, w):
    """Monotonicity: at a higher load the shaken-down stick zone is not larger."""
    from core.api.solver import shakedown_state

    hi = min(ft + 0.05, 0.99)
    c_lo = shakedown_state(ft, w, 1 / 40).stick_halfwidth if ft <= core.ft_limit(w) else 0.0
    c_hi = shakedown_state(hi, w, 1 / 40).stick_halfwidth if hi <= core.ft_limit(w) else 0.0
    assert c_hi <= c_lo + 1e-12
