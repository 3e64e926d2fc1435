"""Load test of the served explorer: many sessions driven through Bokeh's client protocol, not browsers.

Usage: python benchmarks/loadtest.py [--sessions 60] [--open-over 30] [--seconds 60] [--cluster 2]

Serves ``app/main.py`` and the yardstick page (``benchmarks/yardstick.py``: a
template, four sliders, two HoloViews plots) from one ``panel serve`` on
127.0.0.1, and drives sessions with ``bokeh.client`` (one websocket and one
Python document per session, no browser): what is measured is what a
session costs the server. With ``--cluster N`` the solves go to a loopback
Dask cluster of N workers (``dask scheduler`` and ``dask worker`` processes
started here; ``SHAKEDOWN_SCHEDULER`` for the server).

Phases, each printed:

1. CPU per session: ``--cpu-sessions`` sessions of the explorer opened one
   after another (each closed before the next), then as many of the
   yardstick; the server process's CPU time (``/proc/<pid>/stat``, all its
   threads) per session, and the ratio (goal: at most 2).
2. Burst: ``--burst`` sessions open at once while ``/liveness`` is polled
   every 0.25 s; its worst latency (goal: under 2 s).
3. Class: ``--sessions`` sessions open, evenly spread over ``--open-over``
   seconds; each then, until ``--seconds`` after the last opening, drags the
   ft slider (every third time the w slider) through three values (no
   release: the analytical layers follow, no solve) and releases that
   slider at a value no session has used (a new solve). The *solve round trip* runs from sending the
   release to the run card's text changing in the session's document.

Printed: errors (goal 0: a session that fails to open, a round trip over
60 s, a failed or slow ``/liveness`` (over 30 s), a traceback or ERROR in the
server's log), time until all sessions are up, median and p95 of the round
trips, ``/liveness`` latency, the longest time the server's event loop was
blocked (``SHAKEDOWN_LOOP_WATCH_MS``, reported by ``/liveness``; goal
<= 0.5 s), and the server's memory (VmRSS) before and after.

Every loop is bounded in count and in time.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import itertools
import json
import math
import os
import re
import signal
import statistics
import sys
import tempfile
import threading
import time
import urllib.request
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from app import limits  # noqa: E402
from app.serving import dask_cluster, served_app, tasks_done  # noqa: E402

YARDSTICK = Path(__file__).resolve().parent / "yardstick.py"
FT_TITLE = "ft = Ft/(μ Fn)"
W_TITLE = "w = W/a"
ROUND_TRIP_TIMEOUT_S = 60.0
OPEN_TIMEOUT_S = 180.0
LIVENESS_LIMIT_S = 30.0
MAX_ROUND_TRIPS_PER_SESSION = 500
_TICK = os.sysconf("SC_CLK_TCK")

_RECORD = re.compile(r"^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d,\d{3} ", re.M)
# Bokeh/Tornado races when a client leaves mid-update: a write to the closed socket,
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


def _cpu_s(pid: int) -> float:
    """CPU time (user + system) of process ``pid`` so far [s], all its threads."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / _TICK


def _rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def _percentile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, int(round(q * (len(v) - 1))))] if v else float("nan")


def _health(base: str, reset: bool = False, timeout: float = LIVENESS_LIMIT_S) -> dict:
    with urllib.request.urlopen(f"{base}/liveness" + ("?reset=1" if reset else ""), timeout=timeout) as r:  # noqa: S310
        return json.loads(r.read())


def _lag_ms(base: str, stats: dict) -> float:
    """The longest the server's event loop was blocked since the last call [ms] (a new window starts)."""
    for attempt in range(3):  # the loop may still be busy with sessions that are being built
        try:
            return _health(base, reset=True, timeout=120).get("loop_max_lag_ms", float("nan"))
        except OSError as e:
            error = e
    stats["errors"].append(f"/liveness did not answer in 3 x 120 s: {type(error).__name__}")
    return float("nan")


class Session:
    """One session of a served page, driven through Bokeh's client protocol in a thread of its own."""

    def __init__(self, url: str, arguments: dict | None = None):
        import panel.models  # noqa: F401 - the client must know Panel's model types to read the document
        import panel.models.katex  # noqa: F401
        import panel.models.location  # noqa: F401
        from bokeh.client import pull_session
        from tornado.ioloop import IOLoop

        asyncio.set_event_loop(asyncio.new_event_loop())  # this thread's loop; the client runs it while it waits
        self.loop = IOLoop.current()
        self.session = pull_session(url=url, arguments=arguments or {}, io_loop=self.loop)

    @property
    def models(self) -> list:
        return list(self.session.document.models)

    def find(self, predicate):
        return next((m for m in self.models if predicate(m)), None)

    def slider(self, title):
        return self.find(lambda m: getattr(m, "title", None) == title and "value_throttled" in m.properties())

    def run_card(self):
        return self.find(lambda m: isinstance(getattr(m, "text", None), str) and " steps" in m.text and "el.," in m.text)

    def pump(self, until, timeout: float) -> bool:
        """Let the server's updates in until ``until()`` (True) or ``timeout`` seconds (False)."""
        from tornado.ioloop import PeriodicCallback

        conn = self.session._connection  # the public API only pumps while it waits for a reply, dropping updates
        deadline = time.monotonic() + timeout
        # a no-op request every 100 ms wakes the client's loop so that the deadline is seen without an update
        ping = PeriodicCallback(lambda: self.loop.add_callback(conn.send_message, conn._protocol.create("SERVER-INFO-REQ")), 100)
        ping.start()
        try:
            # in slices of 2 s: the client handles each message one recursion level deeper until it stops
            for _ in range(int(timeout / 2) + 2):
                end = min(deadline, time.monotonic() + 2.0)
                conn._loop_until(lambda: until() or time.monotonic() > end or not conn.connected)
                if until() or time.monotonic() > deadline or not conn.connected:
                    break
        finally:
            ping.stop()
        return bool(until())

    def set(self, model, value, release: bool) -> None:
        model.value = value
        if release:
            model.set_from_json("value_throttled", value)  # read-only in Python: what the browser sends on mouse-up

    def close(self):
        with contextlib.suppress(Exception):
            self.session.close()
        with contextlib.suppress(Exception):
            self.loop.close(all_fds=True)


def _fresh_values():
    # values never used before by any session: every release is a new solve
    ft = (round(0.05 + (0.8 * ((i * 0.618034) % 1.0)), 4) for i in itertools.count(1))
    w = (round(0.1 + (0.75 * ((i * 0.414214) % 1.0)), 4) for i in itertools.count(1))
    return {"ft": ft, "w": w, "lock": threading.Lock()}


def _next(fresh, key):
    with fresh["lock"]:
        return next(fresh[key])


def _open(url, k, stats, arguments=None) -> Session | None:
    t0 = time.monotonic()
    try:
        s = Session(url, arguments)
        stats["loads"].append(time.monotonic() - t0)
        return s
    except Exception as e:  # noqa: BLE001 - a session that did not open is an error of the run
        stats["errors"].append(f"session {k} did not open: {type(e).__name__}: {str(e)[:200]}")
        return None


def _run_text(s: Session):
    """The text of the card that describes the run shown, or None while the cards wait for a solve."""
    card = s.run_card()
    return None if card is None else card.text


def _work(s: Session, k, deadline, fresh, stats):
    """Drag and release sliders on session ``k`` until ``deadline()`` (a time.monotonic() value)."""
    ft, w = s.slider(FT_TITLE), s.slider(W_TITLE)
    if ft is None or w is None or s.run_card() is None:
        stats["errors"].append(f"session {k}: no ft/w slider or run card in the document")
        return
    for i in range(MAX_ROUND_TRIPS_PER_SESSION):
        if time.monotonic() > deadline():
            return
        # as a hand does it: drag one slider (the analytical layers follow, nothing is solved), then release
        # that same slider at a value no session has used (a new solve). The explorer waits for the release
        # of a slider being dragged before it solves, so releasing another one would not end the drag.
        slider, key = (w, "w") if i % 3 == 2 else (ft, "ft")
        for j in range(3):
            s.set(slider, round(0.1 + 0.25 * j + 0.01 * (k % 10), 4), release=False)
            s.pump(lambda: False, 0.05)
        before = _run_text(s)  # None while the cards wait for a release ('release the slider')
        t0 = time.monotonic()
        s.set(slider, _next(fresh, key), release=True)
        if s.pump(lambda: _run_text(s) not in (None, before), ROUND_TRIP_TIMEOUT_S):
            stats["latencies"].append((time.monotonic() - t0) * 1e3)
        else:
            stats["errors"].append(f"session {k}: a solve round trip did not finish in {ROUND_TRIP_TIMEOUT_S:.0f} s")
            return


def _session_thread(url, k, start_at, deadline, fresh, stats, up):
    time.sleep(max(0.0, start_at - time.monotonic()))
    s = _open(url, k, stats, {"ft": "0.3", "w": f"{0.2 + 0.02 * (k % 20):.2f}"})
    up.append(time.monotonic() if s is not None else math.nan)  # a failed session ends its opening too
    if s is None:
        return
    try:
        if deadline is not None:
            _work(s, k, deadline, fresh, stats)
    except Exception as e:  # noqa: BLE001
        stats["errors"].append(f"session {k}: {type(e).__name__}: {str(e)[:200]}")
    finally:
        s.close()


@contextlib.contextmanager
def _liveness(base, stats, key, period=0.25):
    """Poll /liveness every ``period`` s in a thread while the block runs; latencies [ms] go to ``stats[key]``."""
    stop = threading.Event()

    def poll():
        for _ in range(1_000_000):  # bounded; ends with the block
            if stop.is_set():
                return
            t0 = time.monotonic()
            try:
                _health(base)
            except Exception as e:  # noqa: BLE001
                stats["errors"].append(f"liveness ({key}) failed after {time.monotonic() - t0:.1f} s: {type(e).__name__}")
            stats[key].append((time.monotonic() - t0) * 1e3)
            stop.wait(period)

    thread = threading.Thread(target=poll, daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join(LIVENESS_LIMIT_S + 5)


def _cpu_per_session(url, pid, n, stats, arguments=None) -> float:
    """Server CPU [s] per session of ``url``: ``n`` sessions opened one after another (after one untimed)."""
    s = _open(url, -1, {"loads": [], "errors": stats["errors"]}, arguments)
    if s is not None:
        s.close()
    time.sleep(0.5)
    c0 = _cpu_s(pid)
    for k in range(n):
        s = _open(url, k, {"loads": [], "errors": stats["errors"]}, arguments)
        if s is not None:
            s.close()
    time.sleep(1.0)  # the server finishes with the closed sessions
    return (_cpu_s(pid) - c0) / n


def _run(url, base, pid, sessions, open_over, seconds, burst, cpu_sessions):
    stats = {"errors": [], "latencies": [], "liveness": [], "liveness_burst": [], "loads": []}
    yard = url.rsplit("/", 1)[0] + "/yardstick"
    # 1. CPU per session, one after another
    stats["cpu_explorer_s"] = _cpu_per_session(url, pid, cpu_sessions, stats)
    stats["cpu_yardstick_s"] = _cpu_per_session(yard, pid, cpu_sessions, stats)
    stats["loop_lag_cpu_ms"] = _lag_ms(base, stats)
    # 2. burst: sessions open at once while /liveness is polled
    up: list = []
    threads = [threading.Thread(target=_session_thread, args=(url, 1000 + k, 0.0, None, None, stats, up))
               for k in range(burst)]
    with _liveness(base, stats, "liveness_burst"):
        for t in threads:
            t.start()
        for t in threads:
            t.join(OPEN_TIMEOUT_S)
    stats["loop_lag_burst_ms"] = _lag_ms(base, stats)
    stats["loads_burst"], stats["loads"] = stats["loads"], []
    # 3. the class: sessions spread over open_over seconds, each then moves sliders until `seconds` after
    # the last one is up (or failed), so that all of them work together for that long
    time.sleep(1.0)
    stats["rss_before_mb"] = _rss_mb(pid)
    fresh = _fresh_values()
    t0 = time.monotonic()
    up = []
    hard_end = t0 + open_over + OPEN_TIMEOUT_S + seconds

    def deadline():
        if len(up) < sessions:
            return hard_end
        opened = [t for t in up if not math.isnan(t)]
        return min(hard_end, max(opened, default=t0) + seconds)

    threads = [threading.Thread(target=_session_thread,
                                args=(url, k, t0 + open_over * k / max(1, sessions - 1) if sessions > 1 else t0,
                                      deadline, fresh, stats, up), daemon=True)
               for k in range(sessions)]
    cpu0 = _cpu_s(pid)
    with _liveness(base, stats, "liveness"):
        for t in threads:
            t.start()
        for t in threads:
            t.join(max(1.0, hard_end + ROUND_TRIP_TIMEOUT_S - time.monotonic()))
    opened = [t for t in up if not math.isnan(t)]
    stats["all_up_s"] = (max(opened) - t0) if len(opened) == sessions else float("nan")
    stats["wall_s"] = time.monotonic() - t0
    stats["cpu_class_s"] = _cpu_s(pid) - cpu0
    stats["loop_lag_class_ms"] = _lag_ms(base, stats)
    time.sleep(2.0)  # let the server drop the closed sessions
    stats["rss_after_mb"] = _rss_mb(pid)
    return stats


def run_load(sessions: int = 60, open_over: float = 30.0, seconds: float = 60.0, burst: int = 10,
             cpu_sessions: int = 5, cluster: int = 0, env: dict | None = None, keep_log: str | None = None,
             serve_args: tuple[str, ...] = ()) -> dict:
    """Serve the app (and the yardstick), run the three phases; return the figures.

    Returns
    -------
    dict
        ``errors`` (list of messages), ``latencies`` (solve round trips, ms),
        ``liveness`` and ``liveness_burst`` (ms), ``loads`` and
        ``loads_burst`` (s), ``all_up_s``, ``cpu_explorer_s``,
        ``cpu_yardstick_s`` (server CPU per session), ``loop_lag_*_ms``,
        ``rss_before_mb``, ``rss_after_mb``, ``cache_mb``, ``cluster_tasks``
        (solves the Dask cluster ran) and the server's ``returncode``.
    """
    if not (1 <= sessions <= 200 and 0 <= open_over <= 600 and 1 <= seconds <= 3600 and 1 <= burst <= 100
            and 1 <= cpu_sessions <= 100 and 0 <= cluster <= 8):
        raise ValueError("sessions in [1, 200], open_over in [0, 600] s, seconds in [1, 3600], burst in [1, 100], "
                         "cpu_sessions in [1, 100], cluster in [0, 8] workers")
    env = {**(env or {}), "SHAKEDOWN_LOOP_WATCH_MS": "50"}
    with tempfile.TemporaryDirectory() as tmp, contextlib.ExitStack() as stack:
        if cluster:
            address = stack.enter_context(dask_cluster(cluster))
            env["SHAKEDOWN_SCHEDULER"] = address
        log_path = Path(tmp) / "server.log"
        info: dict = {}
        with served_app(env=env, log_path=log_path, info=info, extra_args=serve_args, extra_apps=[YARDSTICK]) as url:
            stats = _run(url, info["base"], info["pid"], sessions, open_over, seconds, burst, cpu_sessions)
            stats["cluster_tasks"] = tasks_done(env["SHAKEDOWN_SCHEDULER"], "simulate_contact") if cluster else 0
        log = log_path.read_text(errors="replace")
        if keep_log:
            Path(keep_log).write_text(log)
    bad, noise = classify_server_log(log)
    stats["server_log_errors"], stats["disconnect_noise"] = bad, len(noise)
    stats["errors"] += [f"server log: {rec.splitlines()[0][:200]} ... {rec.splitlines()[-1][:200]}" for rec in bad]
    stats["errors"] += [f"liveness took {max(v) / 1e3:.1f} s (> {LIVENESS_LIMIT_S:.0f} s)"
                        for v in (stats["liveness"], stats["liveness_burst"]) if v and max(v) > LIVENESS_LIMIT_S * 1e3]
    stats["returncode"] = info.get("returncode")
    stats["stop_s"] = info.get("stop_seconds", float("nan"))
    stats["cache_mb"] = limits.CACHE_MB
    stats.update(sessions=sessions, open_over=open_over, seconds=seconds, burst=burst, cpu_sessions=cpu_sessions,
                 cluster=cluster, serve_args=list(serve_args))
    return stats


def _summary(values, unit="ms"):
    if not values:
        return "none"
    return (f"median {statistics.median(values):.0f} {unit}, p95 {_percentile(values, 0.95):.0f} {unit}, "
            f"max {max(values):.0f} {unit}")


def _goal(ok: bool) -> str:
    return "met" if ok else "NOT met"


def report(stats: dict) -> str:
    ratio = stats["cpu_explorer_s"] / stats["cpu_yardstick_s"] if stats["cpu_yardstick_s"] > 0 else float("nan")
    burst_max = max(stats["liveness_burst"]) / 1e3 if stats["liveness_burst"] else float("nan")
    lag = max(stats["loop_lag_burst_ms"], stats["loop_lag_class_ms"]) / 1e3
    where = (f"solves on a loopback Dask cluster of {stats['cluster']} workers ({stats['cluster_tasks']} solves ran there)"
             if stats["cluster"] else "solves in the server's threads")
    lines = [
        f"server: panel serve {' '.join(stats['serve_args']) or '(default options)'}; {where}",
        f"errors: {len(stats['errors'])} (goal 0)" + "".join(f"\n  - {e}" for e in stats["errors"][:20]),
        f"server CPU per session, opened one after another ({stats['cpu_sessions']} each): explorer "
        f"{stats['cpu_explorer_s']:.2f} s, yardstick {stats['cpu_yardstick_s']:.2f} s, ratio {ratio:.1f} "
        f"(goal <= 2: {_goal(ratio <= 2)})",
        f"{stats['burst']} sessions opening at once: /liveness {_summary(stats['liveness_burst'])} "
        f"(goal < 2 s: {_goal(burst_max < 2)}); opening {_summary([x * 1e3 for x in stats['loads_burst']])}",
        f"{stats['sessions']} sessions opening over {stats['open_over']:.0f} s: all up after {stats['all_up_s']:.1f} s; "
        f"opening {_summary([x * 1e3 for x in stats['loads']])}",
        f"  then sliders for {stats['seconds']:.0f} s: {len(stats['latencies'])} solve round trips, "
        f"{_summary(stats['latencies'])}",
        f"  /liveness meanwhile: {len(stats['liveness'])} checks, {_summary(stats['liveness'])}",
        f"  server CPU over the whole phase: {stats['cpu_class_s']:.1f} s in {stats['wall_s']:.0f} s of wall time",
        f"event loop blocked at most: {stats['loop_lag_burst_ms'] / 1e3:.2f} s (burst), "
        f"{stats['loop_lag_class_ms'] / 1e3:.2f} s (class), {stats['loop_lag_cpu_ms'] / 1e3:.2f} s (one session "
        f"at a time) (goal <= 0.5 s: {_goal(lag <= 0.5)})",
        f"server memory (RSS): {stats['rss_before_mb']:.0f} MB before, {stats['rss_after_mb']:.0f} MB after "
        f"({stats['rss_after_mb'] - stats['rss_before_mb']:+.0f} MB; the result cache is bounded at {stats['cache_mb']} MB)",
        f"server stopped with exit code {stats['returncode']} in {stats['stop_s']:.1f} s; "
        f"disconnect noise in its log: {stats['disconnect_noise']} records",
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sessions", type=int, default=60)
    ap.add_argument("--open-over", type=float, default=30.0, help="seconds over which the sessions open")
    ap.add_argument("--seconds", type=float, default=60.0, help="seconds of slider activity after the last opening")
    ap.add_argument("--burst", type=int, default=10, help="sessions opened at once while /liveness is timed")
    ap.add_argument("--cpu-sessions", type=int, default=5, help="sessions per page for the CPU per session")
    ap.add_argument("--cluster", type=int, default=0, help="solve on a loopback Dask cluster of this many workers")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    ap.add_argument("--log", help="keep the server's log in this file")
    ap.add_argument("--serve-args", default="", help="further 'panel serve' options, e.g. '--num-threads 4'")
    args = ap.parse_args(argv)
    # stopped with SIGTERM: unwind, so that the server and the cluster this script started are stopped too
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    stats = run_load(args.sessions, args.open_over, args.seconds, args.burst, args.cpu_sessions, args.cluster,
                     keep_log=args.log, serve_args=tuple(args.serve_args.split()))
    print(report(stats))
    if args.json:
        Path(args.json).write_text(json.dumps(stats, indent=1))
    return 0 if not stats["errors"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
