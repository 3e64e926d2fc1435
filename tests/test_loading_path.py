"""The loading path of a history (core.loading.paths.LoadingPath, issue 32 item 4): its checks, its text, the default
path's bitwise sameness, the schedule a path makes, and Melan's promise at beta = 0 (the steady state does not
depend on the path: Barber, Davies & Hills 2011)."""

import io

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings, strategies as st

import core
from core.command.cli import main
from core.loading.histories import for_run, rocking, tangential
from core.loading.paths import DEFAULT_PATH, LoadingPath, as_path
from core.loading.schedule import rocking_schedule

FAST = dict(periods=8, dx=0.05)


# --------------------------------------------------------------------------
# validation and text
# --------------------------------------------------------------------------
@pytest.mark.parametrize("fields, named", [
    (dict(order="Q-then-P"), "order"),
    (dict(ramp_steps=-1), "ramp_steps"),
    (dict(ramp_steps=10_001), "ramp_steps"),
    (dict(ramp_steps=2.5), "ramp_steps"),
    (dict(first_direction=0), "first_direction"),
    (dict(first_direction=True), "first_direction"),
    (dict(start_at=1.5), "start_at"),
    (dict(start_at=float("nan")), "start_at"),
    (dict(preload=[(1.0, 0.5, 3)]), r"preload\[0\].ft"),
    (dict(preload=[(0.2, 1.0, 3)]), r"preload\[0\].amplitude"),
    (dict(preload=[(0.2, 0.5, 3), (0.2, 0.5, 0)]), r"preload\[1\].periods"),
    (dict(preload=[(0.2, 0.5)]), r"preload\[0\]"),
    (dict(preload=5), "preload"),
    (dict(preload=[(0.1, 0.1, 1)] * 21), "preload"),
])
def test_a_field_out_of_range_is_refused_by_name(fields, named):
    with pytest.raises(ValueError, match=named):
        LoadingPath(**fields)


@pytest.mark.parametrize("text, named", [
    ("order=sideways", "order"), ("ramp=x", "ramp"), ("first=0", "first"), ("start=2", "start_at"),
    ("speed=3", "KEY"), ("ramp", "KEY"), ("ramp=1,ramp=2", "twice"), ("preload=0.1:0.2", "preload"),
])
def test_a_bad_text_is_refused_by_its_field(text, named):
    with pytest.raises(ValueError, match=named):
        LoadingPath.parse(text)


@given(order=st.sampled_from(["P-then-Q", "together"]), ramp=st.integers(0, 10_000), first=st.sampled_from([1, -1]),
       start=st.floats(-1.0, 1.0), preload=st.lists(st.tuples(st.floats(-0.99, 0.99), st.floats(0.0, 0.99),
                                                             st.integers(1, 50)), max_size=3))
@settings(max_examples=60, deadline=None)
def test_the_text_reads_back_to_the_same_path(order, ramp, first, start, preload):
    path = LoadingPath(order=order, ramp_steps=ramp, first_direction=first, start_at=start, preload=preload)
    back = LoadingPath.parse(str(path))
    assert (back.order, back.ramp_steps, back.first_direction) == (path.order, path.ramp_steps, path.first_direction)
    np.testing.assert_allclose(back.start_at, path.start_at, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(np.reshape(back.preload, (-1, 3)), np.reshape(path.preload, (-1, 3)), rtol=1e-5,
                               atol=1e-6)


def test_the_default_path_in_every_spelling():
    for spelled in (None, LoadingPath(), "default", "", {}, {"order": "P-then-Q"}):
        assert as_path(spelled) is DEFAULT_PATH or as_path(spelled) == DEFAULT_PATH
        assert as_path(spelled).is_default
    assert not LoadingPath(first_direction=-1).is_default
    with pytest.raises(ValueError, match="path"):
        as_path(3)
    with pytest.raises(ValueError, match="unknown fields"):
        as_path({"ramp": 3})


# --------------------------------------------------------------------------
# the default path is today's, bitwise
# --------------------------------------------------------------------------
@pytest.mark.parametrize("history, extra", [("rocking", {}), ("normal", dict(amplitude=0.2, phase=0.4)),
                                            ("tangential", dict(amplitude=0.3))])
def test_the_default_path_gives_the_same_schedule(history, extra):
    base = for_run(history, 0.3, 0.5, periods=3, dW=0.05, load_steps=3, **extra)
    for path in (None, LoadingPath(), "default"):
        s = for_run(history, 0.3, 0.5, periods=3, dW=0.05, load_steps=3, path=path, **extra)
        for name in ("xc", "P", "Q", "period"):
            assert np.array_equal(getattr(s, name), getattr(base, name)), (history, name)
    assert np.array_equal(for_run("rocking", 0.3, 0.5, periods=3, dW=0.05).xc,
                          rocking_schedule(0.3, 0.5, periods=3, dW=0.05).xc)


@pytest.mark.parametrize("beta", [0.0, 0.25])
def test_the_default_path_gives_bitwise_the_same_run(beta):
    kw = dict(periods=4, dx=0.05, beta=beta, mu=0.3)
    a = core.simulate_cycles(0.25, 0.6, **kw)
    for path in (LoadingPath(), "default"):
        b = core.simulate_cycles(0.25, 0.6, path=path, **kw)
        assert np.array_equal(a.traction, b.traction)
        assert np.array_equal(a.increment_per_period, b.increment_per_period)
        assert np.array_equal(a.dissipation_per_period, b.dissipation_per_period)
        assert a.params == b.params and "path" not in b.params


# --------------------------------------------------------------------------
# the schedule a path makes
# --------------------------------------------------------------------------
def test_a_path_is_all_in_the_loading_block_and_keeps_the_periods():
    base = rocking(0.3, 0.5, periods=2, dW=0.125)
    s = rocking(0.3, 0.5, periods=2, dW=0.125, path=LoadingPath(ramp_steps=4, start_at=1.0,
                                                               preload=[(0.1, 0.25, 2)]))
    periods = s.period >= 0
    assert np.all(s.period[:np.argmax(periods)] == -1) and s.periods == base.periods == 2
    for name in ("xc", "P", "Q", "period"):
        assert np.array_equal(getattr(s, name)[periods], getattr(base, name)[base.period >= 0]), name
    loading = ~periods
    # P raised first, at Q = 0, at +W; then Q to the preload's 0.1; the centre back to 0; 2 periods at w 0.25
    np.testing.assert_allclose(s.P[:4], [0.25, 0.5, 0.75, 1.0])
    assert np.all(s.Q[:4] == 0.0) and np.all(s.xc[:5] == 0.5)
    assert s.Q[4] == pytest.approx(0.1)
    np.testing.assert_allclose(s.xc[5:9], [0.375, 0.25, 0.125, 0.0])
    assert np.max(np.abs(s.xc[loading][9:])) == pytest.approx(0.25)
    assert s.Q[loading][-1] == pytest.approx(0.3) and np.all(s.P[loading][4:] == 1.0)


def test_together_keeps_q_over_p_and_first_direction_mirrors_the_periods():
    s = rocking(0.3, 0.5, periods=1, dW=0.125, path="order=together,ramp=5,first=-1")
    np.testing.assert_allclose(s.Q[:5] / s.P[:5], 0.3)
    np.testing.assert_allclose(s.P[:5], [0.2, 0.4, 0.6, 0.8, 1.0])
    base = rocking(0.3, 0.5, periods=1, dW=0.125)
    np.testing.assert_array_equal(s.xc[s.period >= 0], -base.xc[base.period >= 0])
    t = tangential(0.2, 0.3, periods=1, steps_per_period=8, path=LoadingPath(first_direction=-1))
    u = tangential(0.2, 0.3, periods=1, steps_per_period=8)
    np.testing.assert_allclose(t.Q[t.period >= 0] - 0.2, -(u.Q[u.period >= 0] - 0.2), atol=1e-15)


def test_paths_that_cannot_apply_are_refused():
    with pytest.raises(ValueError, match="start_at"):
        tangential(0.2, 0.3, path="start=+W")
    with pytest.raises(ValueError, match="path"):
        for_run(rocking(0.2, 0.3, periods=1), 0.2, 0.3, path="first=-1")
    with pytest.raises(ValueError, match="path"):
        core.simulate_cycles(0.2, 0.3, history={"xc": [0.0, 0.1]}, path="ramp=3")
    with pytest.raises(ValueError, match="preload"):  # a preload at gross sliding under the normal oscillation
        for_run("normal", 0.2, 0.3, amplitude=0.5, path="preload=0.6:0.3:1")


def test_the_verdict_reads_the_periods_after_the_path():
    r = core.simulate_cycles(0.4, 0.6, path="preload=0.1:0.3:3+0.2:0.6:2", **FAST)
    assert r.periods == 8 and r.increment_per_period.size == 8 and r.dissipation_per_period.size == 8
    assert r.params["path"] == "preload=0.1:0.3:3+0.2:0.6:2"
    assert np.count_nonzero(r.period < 0) > 5 * 4  # the preloads' periods are loading steps


def test_contact_simulate_takes_a_path():
    c = core.PAPER_SIMULATION.replace(ft=0.3, w=0.5)
    r = c.simulate(periods=4, dx=0.05, path="first=-1")
    assert r.params["path"] == "first=-1" and r.periods == 4


# --------------------------------------------------------------------------
# beta = 0: the steady state does not depend on the path (Melan; Barber, Davies & Hills 2011)
# --------------------------------------------------------------------------
def _steady(r):
    return float(r.increment_per_period[-1]), float(r.dissipation_per_period[-1])


def test_p_then_q_and_together_reach_the_same_steady_state_at_beta_0():
    for history, ft, kw in (("rocking", 0.4, {}), ("tangential", 0.2, dict(amplitude=0.4))):
        runs = [core.simulate_cycles(ft, 0.6, history=history, path=p, **FAST, **kw)
                for p in ("default", "ramp=6", "order=together,ramp=7")]
        assert len({r.regime for r in runs}) == 1, [r.regime for r in runs]
        inc, energy = zip(*map(_steady, runs))
        assert energy[0] > 1e-3  # ratcheting and cyclic slip: a steady loop that dissipates
        np.testing.assert_allclose(energy, energy[0], rtol=1e-8, err_msg=history)
        np.testing.assert_allclose(inc, inc[0], rtol=1e-8, atol=1e-12, err_msg=history)


paths = st.builds(
    LoadingPath, order=st.sampled_from(["P-then-Q", "together"]), ramp_steps=st.integers(0, 8),
    first_direction=st.sampled_from([1, -1]), start_at=st.sampled_from([0.0, 1.0, -1.0, 0.5]),
    preload=st.lists(st.tuples(st.floats(-0.5, 0.5), st.floats(0.0, 0.8), st.integers(1, 2)), max_size=2))


@given(path=paths)
@settings(max_examples=8, deadline=None)
def test_at_beta_0_no_path_changes_the_regime_or_the_steady_dissipation(path):
    # ratcheting above eq 35 (0.2848 at w = 0.6), shakedown below it: Melan decides whatever the path
    above = core.simulate_cycles(0.4, 0.6, path=path, **FAST)
    reference = core.simulate_cycles(0.4, 0.6, **FAST)
    assert above.regime == reference.regime == "ratcheting"
    np.testing.assert_allclose(_steady(above), _steady(reference), rtol=1e-8)
    below = core.simulate_cycles(0.2, 0.6, path=path, **FAST)
    assert below.regime == "shakedown", below.regime_reason


# --------------------------------------------------------------------------
# the command line
# --------------------------------------------------------------------------
def test_shakedown_run_takes_path(capsys):
    code = main(["run", "--ft", "0.4", "--w", "0.6", "--periods", "8", "--dx", "0.05",
                 "--path", "order=together,ramp=5,first=-1,start=+W,preload=0.1:0.3:2"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "loading path: order=together,ramp=5,first=-1,start=1,preload=0.1:0.3:2" in out
    r = core.simulate_cycles(0.4, 0.6, path="order=together,ramp=5,first=-1,start=+W,preload=0.1:0.3:2", **FAST)
    assert f"{r.increment_per_period[-1]:.6g} mu P/E*" in out
    code = main(["run", "--ft", "0.4", "--w", "0.6", "--path", "first=sideways"])
    out, err = capsys.readouterr()
    assert code == 2 and "--path" in err and "first" in err and "Traceback" not in err
    code = main(["run", "--help"])
    assert "--path" in capsys.readouterr().out


PATH = "order=together,ramp=5,first=-1,start=+W,preload=0.1:0.3:2"


def test_shakedown_sweep_takes_path(capsys):
    code = main(["sweep", "--ft", "0.2,0.4", "--w", "0.6", "--periods", "8", "--dx", "0.05", "--path", PATH,
                 "--out", "-", "--no-progress"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "loading path: order=together,ramp=5,first=-1,start=1,preload=0.1:0.3:2" in err
    table = core.sweep([0.2, 0.4], 0.6, path=PATH, **FAST)
    printed = pd.read_csv(io.StringIO(out))
    assert list(printed["path"]) == ["order=together,ramp=5,first=-1,start=1,preload=0.1:0.3:2"] * 2
    assert list(printed["regime"]) == list(table["regime"])
    np.testing.assert_allclose(printed["increment"], table["increment"], rtol=1e-12)


def test_shakedown_limit_takes_path(capsys):
    code = main(["limit", "--ft", "0.5", "--tol", "0.1", "--periods", "8", "--dx", "0.05", "--path", PATH,
                 "--out", "-", "--no-progress"])
    out, err = capsys.readouterr()
    assert code == 0, err
    table = core.numerical_limit_curve([0.5], tol=0.1, path=PATH, workers=1, **FAST)
    printed = pd.read_csv(io.StringIO(out))
    assert list(printed["runs"]) == list(table["runs"])
    np.testing.assert_allclose(printed[["w_shakedown", "w_ratcheting"]], table[["w_shakedown", "w_ratcheting"]],
                               rtol=1e-12)
    code = main(["limit", "--ft", "0.5", "--tol", "0.1", "--periods", "8", "--dx", "0.05", "--path", PATH,
                 "--no-progress"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "loading path: order=together,ramp=5,first=-1,start=1,preload=0.1:0.3:2" in out


@pytest.mark.parametrize("command", [["sweep", "--out", "-"], ["limit"]])
def test_sweep_and_limit_check_path_as_run_does(command, capsys):
    name, *rest = command
    base = [name, "--ft", "0.4", "--w" if name == "sweep" else "--tol", "0.6" if name == "sweep" else "0.1", *rest]
    assert main([*base, "--path", "first=sideways"]) == 2
    err = capsys.readouterr().err
    assert "--path" in err and "first" in err and "Traceback" not in err
    # a path the history cannot take reaches the solver's own check (it is passed on, not dropped)
    assert main([*base, "--history", "tangential", "--path", "start=+W"]) == 2
    err = capsys.readouterr().err
    assert "start_at" in err and "Traceback" not in err
    assert main([name, "--help"]) == 0
    assert "--path FIELDS" in capsys.readouterr().out


# --------------------------------------------------------------------------
# coupled: a mirror symmetry the path makes testable
# --------------------------------------------------------------------------
@pytest.mark.parametrize("path, mirrored", [("default", "first=-1"), ("start=+W", "start=-W,first=-1"),
                                            ("order=together,ramp=5", "order=together,ramp=5,first=-1")])
def test_minus_beta_is_beta_with_the_rocking_mirrored(path, mirrored):
    # x -> -x turns (beta, Q, xc) into (beta, -Q, -xc), and q -> -q turns (beta, Q) into (-beta, -Q): together
    # (beta, xc) runs as (-beta, -xc) under the same Q, so the path mirrored at -beta walks and dissipates the same
    kw = dict(periods=6, dx=0.05, mu=0.3)
    a = core.simulate_cycles(0.18, 0.6, beta=0.25, path=path, **kw)
    b = core.simulate_cycles(0.18, 0.6, beta=-0.25, path=mirrored, **kw)
    np.testing.assert_allclose(b.increment_per_period, a.increment_per_period, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(b.dissipation_per_period, a.dissipation_per_period, rtol=1e-6, atol=1e-9)
    assert a.regime == b.regime
    c = core.simulate_cycles(0.18, 0.6, beta=-0.25, path=path, **kw)  # not mirrored: another transient
    assert not np.allclose(c.increment_per_period, a.increment_per_period, rtol=1e-3)
