"""Issue 12, item 6: the short load test runs in the suite and fails on any error.

``benchmarks/loadtest.py`` serves the app and the yardstick page on loopback
and drives sessions through Bokeh's client protocol (no browser): sessions
opened one after another for the CPU per session, a burst opened at once
while ``/liveness`` is timed, then sessions that drag and release sliders
(every release is a new solve). Any session that fails to open, unfinished
round trip, failed liveness request, or traceback in the server log is an
error. The figures' goals are checked by the benchmark at full size, not here.
"""

import importlib.util
from pathlib import Path

import pytest

pytestmark = [pytest.mark.browser, pytest.mark.timeout(900)]

ROOT = Path(__file__).resolve().parent.parent


def _loadtest():
    spec = importlib.util.spec_from_file_location("loadtest", ROOT / "benchmarks" / "loadtest.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_few_sessions_for_a_few_seconds_without_an_error(fresh_thread):
    lt = _loadtest()
    stats = fresh_thread(lt.run_load, sessions=3, open_over=2, seconds=8, burst=2, cpu_sessions=1)
    print(lt.report(stats))
    assert stats["errors"] == [], lt.report(stats)
    assert len(stats["loads"]) == 3 and len(stats["loads_burst"]) == 2, "every session opened"
    assert len(stats["latencies"]) >= 3, "the sessions solved"
    assert stats["cpu_explorer_s"] > 0 and stats["cpu_yardstick_s"] > 0, "the server's CPU time was read"
    assert stats["loop_lag_class_ms"] > 0, "the event loop was watched"
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


def _builds(wrap):
    """What Bokeh does for three pages requested at once: await the session hook, then build synchronously.
    While each build runs, a request arrives (``/liveness``, another session's slider): the order things ran."""
    import asyncio

    async def scenario():
        log, loop = [], asyncio.get_running_loop()

        async def hook(k):
            log.append(f"hook {k}")

        hooked = wrap(hook)

        async def page(k):
            await hooked(k)
            log.append(f"build {k}")
            loop.call_soon(log.append, f"request during build {k}")

        await asyncio.gather(*(page(k) for k in (1, 2, 3)))
        await asyncio.sleep(0)
        return log

    return asyncio.run(scenario())


def test_session_builds_take_turns_with_the_event_loop():
    """Without turns the three builds run back to back before the requests that arrived meanwhile (the loop was
    blocked for 44-53 s while 60 sessions opened); with them, what arrived during a build runs before the next."""
    from app.loop import in_turns

    alone = _builds(lambda hook: hook)
    assert alone.index("build 3") < alone.index("request during build 1")
    turns = _builds(in_turns)
    assert turns.index("request during build 1") < turns.index("build 2")
    assert turns.index("request during build 2") < turns.index("build 3")
    assert [e for e in turns if e.startswith("build")] == ["build 1", "build 2", "build 3"]
