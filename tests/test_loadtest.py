"""Issue 6, item 3: the short load test (5 sessions, 15 s) runs in the suite and fails on any error.

``benchmarks/loadtest.py`` serves the app on loopback and drives concurrent
Chromium sessions that drag and release sliders (every release is a new
solve). Any console or page error, unfinished round trip, liveness failure,
or traceback of the app in the server log is an error.
"""

import importlib.util
from pathlib import Path

import pytest

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parent.parent


def _loadtest():
    spec = importlib.util.spec_from_file_location("loadtest", ROOT / "benchmarks" / "loadtest.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_five_sessions_for_fifteen_seconds_without_an_error():
    lt = _loadtest()
    stats = lt.run_load(sessions=5, seconds=15)
    print(lt.report(stats))
    assert stats["errors"] == [], lt.report(stats)
    assert len(stats["loads"]) == 5, "every session opened"
    assert len(stats["latencies"]) >= 5, "the sessions solved"
    assert stats["liveness"] and max(stats["liveness"]) < 5000, "liveness answered while solves ran"
    # no growth beyond the bound of the shared result cache (plus the sessions' own state)
    assert stats["rss_after_mb"] - stats["rss_before_mb"] < stats["cache_mb"] + 200
    assert stats["returncode"] == 0, "the server shut down cleanly on SIGTERM"


def test_server_log_classifier_keeps_app_errors():
    lt = _loadtest()
    noise = ("2026-01-01 00:00:00,000 Task exception was never retrieved\nTraceback (most recent call last):\n"
             "tornado.websocket.WebSocketClosedError\n")
    app_error = ("2026-01-01 00:00:01,000 error handling message\nTraceback (most recent call last):\n"
                 '  File "/srv/app/explorer.py", line 3\nValueError: boom\n')
    errors, skipped = lt.classify_server_log(noise + app_error)
    assert len(errors) == 1 and "boom" in errors[0]
    assert len(skipped) == 1
