"""Loading histories as data (core.loading.histories): the recipes, their validation, and runs on them."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import core
from core import solve_schedule
from core.loading.histories import HISTORIES, from_arrays, history, rocking, tangential


def test_rocking_without_normal_oscillation_is_the_paper_schedule():
    a = rocking(0.3, 0.5, periods=3, dW=0.05, shape="sine")
    b = core.rocking_schedule(0.3, 0.5, periods=3, dW=0.05, shape="sine")
    for name in ("xc", "P", "Q", "period"):
        assert np.array_equal(getattr(a, name), getattr(b, name))


def test_rocking_with_an_oscillating_normal_force():
    s = rocking(0.3, 0.5, periods=2, dW=0.125, normal_amplitude=0.2, normal_phase=0.0)
    m = 16
    t = np.arange(1, m + 1) / m
    assert_allclose(s.P[1:1 + m], 1 + 0.2 * np.sin(2 * np.pi * t), atol=1e-15)
    assert s.P[0] == pytest.approx(1.0) and s.is_periodic()
    # the normal force peaks where the centre does (t = 1/4) at phase 0, a quarter later at phase -pi/2
    assert np.argmax(s.P[1:1 + m]) == np.argmax(s.xc[1:1 + m])
    late = rocking(0.3, 0.5, periods=2, dW=0.125, normal_amplitude=0.2, normal_phase=-np.pi / 2)
    assert np.argmax(late.P[1:1 + m]) == np.argmax(s.xc[1:1 + m]) + m // 4


def test_tangential_oscillation():
    s = tangential(0.2, 0.3, periods=3, steps_per_period=8, shape="triangle")
    assert np.all(s.xc == 0) and np.all(s.P == 1)
    assert_allclose(s.Q[1:9], 0.2 + 0.3 * np.array([0.5, 1, 0.5, 0, -0.5, -1, -0.5, 0]), atol=1e-15)
    assert s.Q[0] == 0.2 and s.is_periodic()
    sine = tangential(0.0, 0.5, periods=1, steps_per_period=8)
    assert_allclose(sine.Q[1:], 0.5 * np.sin(2 * np.pi * np.arange(1, 9) / 8), atol=1e-15)


@pytest.mark.parametrize("make, name", [
    (lambda: rocking(0.3, 0.5, normal_amplitude=1.0), "normal_amplitude"),
    (lambda: rocking(0.3, 0.5, normal_amplitude=-0.1), "normal_amplitude"),
    (lambda: rocking(0.9, 0.5, normal_amplitude=0.2), "normal_amplitude"),
    (lambda: rocking(0.3, 0.5, normal_phase=np.nan), "normal_phase"),
    (lambda: rocking(0.3, 1.2), "w"),
    (lambda: tangential(0.6, 0.4), "amplitude"),
    (lambda: tangential(1.0, 0.0), "ft"),
    (lambda: tangential(0.2, 0.1, steps_per_period=10), "steps_per_period"),
    (lambda: tangential(0.2, 0.1, shape="square"), "shape"),
    (lambda: tangential(0.2, 0.1, periods=0), "periods"),
    (lambda: from_arrays([0.0, 0.1], Q=[0.2, 1.5]), "Q"),
    (lambda: from_arrays([0.0, np.inf]), "xc"),
    (lambda: from_arrays([0.0, 0.1], P=[1.0, -1.0]), "P"),
    (lambda: from_arrays([0.0, 0.1], period=[1, 0]), "period"),
    (lambda: history("earthquake"), "history"),
])
def test_bad_inputs_name_the_parameter(make, name):
    with pytest.raises(ValueError, match=name):
        make()


def test_named_histories_run_and_keep_the_invariants(check_invariants):
    assert set(HISTORIES) == {"rocking", "tangential", "arrays"}
    runs = [
        history("rocking", ft=0.3, w=0.4, periods=3, dW=1 / 30, normal_amplitude=0.3, normal_phase=1.0),
        history("tangential", ft=0.1, amplitude=0.5, periods=3, steps_per_period=24),
        history("arrays", xc=np.linspace(-0.3, 0.3, 20), P=np.linspace(0.8, 1.2, 20), Q=np.full(20, 0.4)),
    ]
    for s in runs:
        check_invariants(solve_schedule(s, dx=1 / 30))


def test_tangential_oscillation_follows_masing_and_does_not_ratchet():
    """Cattaneo-Mindlin unloading is the loading curve scaled by 2 (Masing's rule, exact for the
    discrete problem too: it is linear in the load and the bound); the loop closes every period."""
    A = 0.6
    r = solve_schedule(tangential(0.0, A, periods=3, steps_per_period=40, shape="triangle"), dx=1 / 40)
    d = r.displacement  # index k = step k of the first period (index 0: the loading to Q = 0)
    for i in range(1, 6):
        assert d[10] - d[10 + 2 * i] == pytest.approx(2 * d[i], rel=1e-7, abs=1e-12)
    assert_allclose(r.increment_per_period[1:], 0.0, atol=1e-9)
    per_period = np.add.reduceat(r.dissipation[1:], [0, 40, 80])
    assert per_period.min() > 0 and per_period[1] == pytest.approx(per_period[2], rel=1e-9)


def test_simulate_cycles_takes_the_named_histories_and_arrays():
    """core.simulate_cycles(history=...): each name runs its recipe of core.loading.histories, a Schedule or a
    mapping of arrays runs as given, and the result records which."""
    kw = dict(periods=2, dx=1 / 30, dW=1 / 30)
    normal = core.simulate_cycles(0.3, 0.4, history="normal", amplitude=0.25, phase=1.0, **kw)
    same = solve_schedule(rocking(0.3, 0.4, periods=2, dW=1 / 30, normal_amplitude=0.25, normal_phase=1.0),
                          dx=1 / 30)
    assert_allclose(normal.displacement, same.displacement, rtol=0, atol=0)
    assert normal.params["history"] == "normal" and normal.params["amplitude"] == 0.25
    sine = core.simulate_cycles(0.3, 0.4, history="rocking", shape="sine", **kw)
    assert_allclose(sine.xc, rocking(0.3, 0.4, periods=2, dW=1 / 30, shape="sine").xc, atol=0)
    fretting = core.simulate_cycles(0.2, 0.0, history="tangential", amplitude=0.5, **kw)
    assert np.all(fretting.xc == 0) and fretting.Q.max() == pytest.approx(0.7)
    assert fretting.xc.size == 1 + 2 * 4 * math.ceil(30 / 4)  # 4 ceil(1 / (4 dW)) steps a period
    default = core.simulate_cycles(0.2, 0.0, history="tangential", **kw)
    assert default.params["amplitude"] == pytest.approx(0.4)  # (1 - |ft|) / 2
    s = tangential(0.1, 0.3, periods=2, steps_per_period=16)
    given = core.simulate_cycles(0.0, 0.0, dx=1 / 30, history=s)
    arrays = core.simulate_cycles(0.0, 0.0, dx=1 / 30, history={"xc": s.xc, "Q": s.Q, "period": s.period})
    assert_allclose(given.displacement, arrays.displacement, atol=0)
    assert given.params["history"] == "arrays" and given.params["periods"] == 2 and "w" not in given.params


@pytest.mark.parametrize("options, name", [
    (dict(history="earthquake"), "history"),
    (dict(history=3), "history"),
    (dict(history={"x": [0.0]}), "history"),
    (dict(history="normal", amplitude=1.0), "amplitude"),
    (dict(history="rocking", amplitude=0.1), "amplitude"),
    (dict(history="tangential", amplitude=0.8), "amplitude"),
    (dict(history="normal", phase=np.inf), "phase"),
])
def test_simulate_cycles_history_errors_name_the_parameter(options, name):
    with pytest.raises(ValueError, match=name):
        core.simulate_cycles(0.3, 0.4, periods=1, **options)
