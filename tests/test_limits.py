"""Operator limits of the served app (issue 6, item 2): read from the environment, checked, applied."""

import subprocess
import sys

import pytest

from app import limits


def test_env_int_reads_checks_and_defaults(monkeypatch):
    monkeypatch.delenv("SHAKEDOWN_TEST_X", raising=False)
    assert limits.env_int("SHAKEDOWN_TEST_X", 7) == 7
    monkeypatch.setenv("SHAKEDOWN_TEST_X", " 12 ")
    assert limits.env_int("SHAKEDOWN_TEST_X", 7, 1, 100) == 12
    for bad in ("lots", "1e3", "0", "101", "-5"):
        monkeypatch.setenv("SHAKEDOWN_TEST_X", bad)
        with pytest.raises(ValueError, match="SHAKEDOWN_TEST_X must be an integer in \\[1, 100\\]"):
            limits.env_int("SHAKEDOWN_TEST_X", 7, 1, 100)


def _bounds_in_fresh_process(env):
    code = "from app.state import ExplorerState as S; print(S.param.periods.bounds[1], S.param.resolution.bounds[1])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    return out


def test_caps_reach_the_state_and_a_bad_cap_stops_start_up(monkeypatch):
    import os

    env = {**os.environ, "SHAKEDOWN_MAX_PERIODS": "12", "SHAKEDOWN_MAX_RESOLUTION": "60"}
    out = _bounds_in_fresh_process(env)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["12", "60"]
    out = _bounds_in_fresh_process({**os.environ, "SHAKEDOWN_MAX_RESOLUTION": "huge"})
    assert out.returncode != 0 and "SHAKEDOWN_MAX_RESOLUTION must be an integer" in out.stderr


def test_state_refuses_work_beyond_the_caps():
    from app.state import ExplorerState

    s = ExplorerState()
    with pytest.raises(ValueError):
        s.periods = limits.MAX_PERIODS + 1
    with pytest.raises(ValueError):
        s.resolution = limits.MAX_RESOLUTION + 1
