"""The numerical limit of every body (issue 21, item 5): the search brackets the body's exact limit.

The sphere's exact limit is ``ft = 1 - 3w/2 + w^3/2`` (:func:`core.theory.point_contact.ft_limit_point`). The
searches here run on a coarse grid (dx = 0.2 a, ten elements across the contact) to stay cheap; the
table at the default grid a/20 is in docs/guide/verdicts.md.
"""

import math
import os
import pathlib
import subprocess
import sys

import pandas as pd
import pytest

import core
from core.theory.point_contact import ft_limit_point

ROOT = pathlib.Path(__file__).parents[1]


@pytest.mark.parametrize("w", [0.3, 0.5])
def test_sphere_limit_search_brackets_the_exact_limit(w):
    ft = float(ft_limit_point(w))
    res = core.numerical_limit(ft, tol=0.01, body="sphere", dx=0.2)
    assert res.converged, res.message
    assert res.w_limit_eq35 == pytest.approx(w, abs=1e-9)  # the sphere's own exact limit, not eq 35
    assert res.exact_within_tol and res.w_ratcheting - res.w_shakedown <= 2 * 0.01, res
    assert set(res.runs["body"]) == {"sphere"} and set(res.runs["dx"]) == {0.2}


def test_ellipsoid_limit_search_brackets_the_same_exact_limit():
    """The exact limit of a point contact does not depend on the axis ratio: the ellipsoid's search brackets it."""
    res = core.numerical_limit(float(ft_limit_point(0.3)), tol=0.01, body="ellipsoid", ratio=2.0, dx=0.2)
    assert res.converged and res.exact_within_tol, res
    assert res.w_limit_eq35 == pytest.approx(0.3, abs=1e-9)


@pytest.mark.slow
def test_sphere_limit_search_at_the_default_grid_uses_a20():
    res = core.numerical_limit(float(ft_limit_point(0.5)), tol=0.05, body="sphere", periods=6)
    assert set(res.runs["dx"]) == {core.geometry.resolution.default_dx("sphere")} == {0.05}
    assert res.converged and res.exact_within_tol, res


def test_an_undetermined_midpoint_is_decided_on_either_side(monkeypatch):
    """A run that stays undetermined is close to the limit: the search decides w -+ tol/2 and stops there."""
    from core.maps import limits_search

    limit = 0.41
    calls = []

    def fake_run(point):
        calls.append(point["w"])
        if abs(point["w"] - limit) < 0.004:
            regime = "undetermined"
        else:
            regime = "shakedown" if point["w"] < limit else "ratcheting"
        return {"regime": regime, "regime_reason": "test", "runtime": 0.0}

    monkeypatch.setattr(limits_search, "run_point", fake_run)
    res = limits_search._limit_search(0.5, 0.01, {"periods": 4, "dx": 0.1})
    assert res.converged and res.w_shakedown <= limit <= res.w_ratcheting, res
    assert res.w_ratcheting - res.w_shakedown <= 2 * 0.01
    monkeypatch.setattr(limits_search, "run_point", lambda p: {"regime": "undetermined" if p["w"] > 0.2 and
                                                               p["w"] < 0.9 else ("shakedown" if p["w"] < 0.5
                                                                                   else "ratcheting"),
                                                               "regime_reason": "test", "runtime": 0.0})
    res = limits_search._limit_search(0.5, 0.01, {"periods": 4, "dx": 0.1})
    assert not res.converged and "undetermined" in res.message
    # 4, 8, 16, 32 periods were run (the message said 64, a doubling that was never run)
    assert "undetermined after 32 periods" in res.message and res.periods == 32
    assert max(res.runs["periods"]) == 32


def test_a_search_that_cannot_decide_keeps_the_bracket_of_the_runs_that_did(monkeypatch):
    """Runs within 0.02 of the limit stay undetermined (the free cone near its limit decays by 0.96-0.98 a period):
    the search does not converge to tol, but it reports the highest w that shook down and the lowest that ratcheted,
    with the limit between them, instead of no bracket at all."""
    from core.maps import limits_search

    limit = 0.384

    def fake_run(point):
        w = point["w"]
        regime = "undetermined" if abs(w - limit) < 0.02 else ("shakedown" if w < limit else "ratcheting")
        return {"regime": regime, "regime_reason": "test", "runtime": 0.0}

    monkeypatch.setattr(limits_search, "run_point", fake_run)
    res = limits_search._limit_search(0.5, 0.001, {"periods": 4, "dx": 0.1})
    assert not res.converged and "not to the tolerance" in res.message and "undetermined" in res.message
    assert res.w_shakedown <= limit - 0.02 < limit + 0.02 <= res.w_ratcheting < 0.5, res
    assert math.isnan(res.w_limit)


@pytest.mark.slow
def test_cli_limit_for_the_sphere_as_a_subprocess(tmp_path):
    """One search, its table in a CSV file and its text on stdout (the CSV on stdout, --out -: tests/test_cli.py)."""
    ft = float(ft_limit_point(0.3))
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-m", "core.command.cli", "limit", "--ft", f"{ft:.6f}", "--tol", "0.01",
                           "--body", "sphere", "--dx", "0.2", "--workers", "1", "--no-progress",
                           "--out", str(tmp_path / "limit.csv")],
                          capture_output=True, text=True, env=env, timeout=600, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    table = pd.read_csv(tmp_path / "limit.csv")
    row = table.iloc[0]
    assert bool(row["converged"]) and bool(row["exact_within_tol"]), row
    assert row["w_limit_eq35"] == pytest.approx(0.3, abs=1e-5)
    assert "of the sphere (dx = 0.2 a)" in done.stdout and "1 - 3w/2 + w^3/2" in done.stdout
    assert "exact_within_tol" in done.stdout
