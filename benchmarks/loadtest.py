"""Load test of the served explorer: concurrent browser sessions that move sliders and trigger solves.

Usage: python benchmarks/loadtest.py [--sessions 20] [--seconds 60]

Serves ``app/main.py`` on loopback (127.0.0.1 only) and opens ``--sessions``
independent sessions at once (one Chromium browser context each, driven by
Playwright); their page loads are timed. Then, for ``--seconds``, every
session repeats:

* drag: three new values of the ft slider without releasing it (the
  analytical plots follow; no solve);
* release: ft (and every third time w) set to a value no session has used, so
  the server must solve it (no cache hit); the *solve round trip* runs from
  setting the value in the page to the run's card showing the new run.

Meanwhile ``/liveness`` is polled every 0.5 s. Counted as errors: a browser
console error or uncaught page error, a round trip that does not finish in
60 s, a liveness request that fails or takes over 5 s while the sessions work
(over 30 s, Docker's default health-check time-out, while they open: building
a session's page holds the server's event loop), and any traceback or ERROR
line in the server's log. Memory is the server process's resident set
(VmRSS) after one warm-up session and again after the load, compared with the
bound of the shared result cache (``SHAKEDOWN_CACHE_MB``).

Request loops are bounded in count and in time and stop by themselves.
"""

from __future__ import annotations

import argparse
import asyncio
import itertools
import json
import re
import statistics
import sys
import tempfile
import time
import urllib.request
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from app import limits  # noqa: E402
from app.serving import CHROMIUM, CHROMIUM_ARGS, served_app  # noqa: E402

FT_TITLE = "ft = Ft/(μ Fn)"
W_TITLE = "w = W/a"
BADGE = "[data-regime='shakedown'], [data-regime='ratcheting']"
ROUND_TRIP_TIMEOUT_S = 60.0
MAX_ROUND_TRIPS_PER_SESSION = 500  # a bound on each loop, whatever the clock says

# In the page: set a slider (dragging, or released), and for a release wait until the
# run card (the text with "el., ... steps") changes. Returns elapsed ms, or -1 on time-out.
_SET_SLIDER = """
async ([title, value, release, timeoutMs]) => {
  const models = () => { const out = []; for (const d of Bokeh.documents) for (const m of d.all_models) out.push(m); return out; };
  const slider = models().find((m) => m.title === title && typeof m.value === 'number' && 'value_throttled' in m);
  if (!slider) throw new Error('no slider titled ' + title);
  const findCard = () => models().find((m) => typeof m.text === 'string' && m.text.includes(' steps') && m.text.includes('el.,'));
  let card = findCard();
  const before = card ? card.text : null;
  const t0 = performance.now();
  slider.value = value;
  if (!release) return 0;
  slider.value_throttled = value;
  let last = t0;
  while (performance.now() - t0 < timeoutMs) {
    await new Promise((r) => setTimeout(r, 5));
    if (performance.now() - last > 250) { card = findCard(); last = performance.now(); }
    if (card && card.text !== before) return performance.now() - t0;
  }
  return -1;
}
"""


_RECORD = re.compile(r"^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d,\d{3} ", re.M)
# Bokeh/Tornado races when a browser leaves mid-update: a write to the closed socket,
# or a patch that arrives after its session was detached. Not the app's errors.
_DISCONNECT = ("WebSocketClosedError", "assert self._session is not None", "Stream is closed")


def classify_server_log(log: str) -> tuple[list[str], list[str]]:
    """Split a server log into error records and disconnect noise; returns (errors, noise)."""
    starts = [m.start() for m in _RECORD.finditer(log)] + [len(log)]
    records = [log[a:b] for a, b in zip(starts[:-1], starts[1:])] or ([log] if log.strip() else [])
    errors, noise = [], []
    for rec in records:
        if "Traceback" not in rec and " ERROR " not in rec and "error handling message" not in rec:
            continue
        if any(sig in rec for sig in _DISCONNECT) and "/app/" not in rec and "/core/" not in rec:
            noise.append(rec)
        else:
            errors.append(rec)
    return errors, noise


def _rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def _percentile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, int(round(q * (len(v) - 1))))] if v else float("nan")


async def _open(browser, url, k, stats):
    """Open session ``k`` and wait for its first verdict; returns the page (or None)."""
    context = await browser.new_context(viewport={"width": 1400, "height": 1000})
    page = await context.new_page()
    page.on("console", lambda m: m.type == "error" and stats["errors"].append(f"session {k} console: {m.text[:200]}"))
    page.on("pageerror", lambda e: stats["errors"].append(f"session {k} page error: {str(e)[:200]}"))
    t0 = time.monotonic()
    try:
        await page.goto(url + f"?ft=0.3&w={0.2 + 0.02 * (k % 20):.2f}", timeout=180_000)
        await page.locator(BADGE).first.wait_for(timeout=180_000)
        stats["loads"].append(time.monotonic() - t0)
        return page
    except Exception as e:  # noqa: BLE001 - a broken session is an error of the test, reported
        stats["errors"].append(f"session {k} did not open: {type(e).__name__}: {str(e)[:300]}")
        await context.close()
        return None


async def _work(page, deadline, k, fresh, stats):
    """Drag and release sliders on session ``k`` until ``deadline``."""
    try:
        for i in range(MAX_ROUND_TRIPS_PER_SESSION):
            if time.monotonic() > deadline:
                break
            for j in range(3):  # dragging: the analytical layers follow, nothing is solved
                await page.evaluate(_SET_SLIDER, [FT_TITLE, 0.1 + 0.25 * j + 0.01 * (k % 10), False, 0])
                await asyncio.sleep(0.05)
            if i % 3 == 2:  # release w too now and then (a solve as well)
                ms = await page.evaluate(_SET_SLIDER, [W_TITLE, next(fresh["w"]), True, ROUND_TRIP_TIMEOUT_S * 1e3])
                _record(stats, k, ms)
            ms = await page.evaluate(_SET_SLIDER, [FT_TITLE, next(fresh["ft"]), True, ROUND_TRIP_TIMEOUT_S * 1e3])
            _record(stats, k, ms)
    except Exception as e:  # noqa: BLE001
        stats["errors"].append(f"session {k}: {type(e).__name__}: {str(e)[:300]}")
    finally:
        # leave as a user does: let in-flight updates land, then close the websocket by navigating away
        await asyncio.sleep(1.0)
        try:
            await page.goto("about:blank", timeout=30_000)
        finally:
            await page.context.close()


def _record(stats, k, ms):
    if ms is None or ms < 0:
        stats["errors"].append(f"session {k}: a solve round trip did not finish in {ROUND_TRIP_TIMEOUT_S:.0f} s")
    else:
        stats["latencies"].append(ms)


async def _liveness(base, stop, stats, key, limit_s):
    """Poll /liveness every 0.5 s until ``stop``; latencies go to ``stats[key]``."""
    for _ in range(100_000):  # bounded; ends when the phase ends
        if stop.is_set():
            return
        t0 = time.monotonic()
        try:
            ok = await asyncio.to_thread(
                lambda: urllib.request.urlopen(f"{base}/liveness", timeout=limit_s).status == 200)
            if not ok:
                stats["errors"].append("liveness answered non-200")
        except Exception as e:  # noqa: BLE001
            stats["errors"].append(f"liveness ({key}) failed after {time.monotonic() - t0:.1f} s: {type(e).__name__}")
        stats[key].append((time.monotonic() - t0) * 1e3)
        await asyncio.sleep(0.5)


async def _phase(coro, base, stats, key, limit_s):
    """Run ``coro`` while polling /liveness."""
    stop = asyncio.Event()
    live = asyncio.create_task(_liveness(base, stop, stats, key, limit_s))
    try:
        return await coro
    finally:
        stop.set()
        await live


def _fresh_values():
    # values never used before by any session: every release is a new solve
    ft = (round(0.05 + (0.8 * ((i * 0.618034) % 1.0)), 4) for i in itertools.count(1))
    w = (round(0.1 + (0.75 * ((i * 0.414214) % 1.0)), 4) for i in itertools.count(1))
    return {"ft": ft, "w": w}


async def _run(url, base, pid, sessions, seconds):
    from playwright.async_api import async_playwright

    stats = {"errors": [], "latencies": [], "liveness": [], "liveness_opening": [], "loads": []}
    async with async_playwright() as pw:
        browser = await pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            # warm-up: one session so the first-import costs are not counted as growth
            warm = await browser.new_context()
            page = await warm.new_page()
            await page.goto(url, timeout=120_000)
            await page.locator(BADGE).first.wait_for(timeout=120_000)
            await warm.close()
            stats["rss_before_mb"] = _rss_mb(pid)
            # phase 1: every session opens at once
            t0 = time.monotonic()
            pages = await _phase(asyncio.gather(*(_open(browser, url, k, stats) for k in range(sessions))),
                                 base, stats, "liveness_opening", 30.0)
            stats["open_s"] = time.monotonic() - t0
            # phase 2: they all drag, release and solve
            fresh = _fresh_values()
            t0 = time.monotonic()
            deadline = t0 + seconds
            await _phase(asyncio.gather(*(_work(p, deadline, k, fresh, stats) for k, p in enumerate(pages) if p)),
                         base, stats, "liveness", 5.0)
            stats["wall_s"] = time.monotonic() - t0
            await asyncio.sleep(2.0)  # let the server drop the closed sessions
            stats["rss_after_mb"] = _rss_mb(pid)
        finally:
            await browser.close()
    return stats


def run_load(sessions: int = 20, seconds: float = 60.0, env: dict | None = None,
             keep_log: str | None = None, serve_args: tuple[str, ...] = ()) -> dict:
    """Serve the app, drive ``sessions`` concurrent sessions for ``seconds``; return the figures.

    Returns
    -------
    dict
        ``errors`` (list of messages), ``latencies`` (solve round trips, ms),
        ``liveness`` (ms), ``rss_before_mb``, ``rss_after_mb``, ``cache_mb``,
        ``wall_s``, ``server_log_errors`` and the server's ``returncode``.
    """
    if not 1 <= sessions <= 100 or not 1 <= seconds <= 3600:
        raise ValueError("sessions must be in [1, 100] and seconds in [1, 3600]")
    with tempfile.TemporaryDirectory() as tmp:
        log_path = Path(tmp) / "server.log"
        info: dict = {}
        with served_app(env=env, log_path=log_path, info=info, extra_args=serve_args) as url:
            # in a thread of its own: a caller may already run an event loop (pytest after sync Playwright)
            with ThreadPoolExecutor(1) as pool:
                stats = pool.submit(asyncio.run, _run(url, info["base"], info["pid"], sessions, seconds)).result()
        log = log_path.read_text(errors="replace")
        if keep_log:
            Path(keep_log).write_text(log)
    bad, noise = classify_server_log(log)
    stats["server_log_errors"], stats["disconnect_noise"] = bad, len(noise)
    stats["errors"] += [f"server log: {rec.splitlines()[0][:200]} ... {rec.splitlines()[-1][:200]}" for rec in bad]
    stats["returncode"] = info.get("returncode")
    stats["stop_s"] = info.get("stop_seconds", float("nan"))
    stats["cache_mb"] = limits.CACHE_MB
    stats["sessions"], stats["seconds"], stats["serve_args"] = sessions, seconds, list(serve_args)
    return stats


def _summary(values, unit="ms"):
    if not values:
        return "none"
    return (f"median {statistics.median(values):.0f} {unit}, p95 {_percentile(values, 0.95):.0f} {unit}, "
            f"max {max(values):.0f} {unit}")


def report(stats: dict) -> str:
    growth = stats["rss_after_mb"] - stats["rss_before_mb"]
    lines = [
        f"server options: {' '.join(stats['serve_args']) or '(defaults)'}\n"
        f"sessions: {stats['sessions']}, activity: {stats['seconds']:.0f} s (wall {stats['wall_s']:.1f} s)",
        f"errors: {len(stats['errors'])}" + "".join(f"\n  - {e}" for e in stats["errors"][:20]),
        f"opening all sessions at once: {stats['open_s']:.1f} s; page load per session: "
        f"{_summary([x * 1e3 for x in stats['loads']])}",
        f"  liveness while they open: {_summary(stats['liveness_opening'])}",
        f"solve round trips: {len(stats['latencies'])}; {_summary(stats['latencies'])}",
        f"  liveness while they work: {len(stats['liveness'])} checks, {_summary(stats['liveness'])}",
        f"server memory (RSS): {stats['rss_before_mb']:.0f} MB before, {stats['rss_after_mb']:.0f} MB after "
        f"({growth:+.0f} MB; the result cache is bounded at {stats['cache_mb']} MB)",
        f"server stopped with exit code {stats['returncode']} in {stats['stop_s']:.1f} s; "
        f"disconnect noise in its log (Bokeh/Tornado, pages closed mid-update): {stats['disconnect_noise']} records",
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sessions", type=int, default=20)
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--json", help="also write the figures to this JSON file")
    ap.add_argument("--log", help="keep the server's log in this file")
    ap.add_argument("--serve-args", default="", help="further 'panel serve' options, e.g. '--num-threads 4'")
    args = ap.parse_args(argv)
    stats = run_load(args.sessions, args.seconds, keep_log=args.log, serve_args=tuple(args.serve_args.split()))
    print(report(stats))
    if args.json:
        Path(args.json).write_text(json.dumps(stats, indent=1))
    return 0 if not stats["errors"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
