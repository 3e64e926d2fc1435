"""The server's health endpoint and start-up warm-up: ``panel serve app/main.py --plugins app.health``.

Loaded by ``panel serve`` as a plugin (its :data:`ROUTES` are added to the
server), so it runs once per server process, before the first session:

* it starts warming the solver (:func:`app.runs.start_warm_up`), in a thread,
  while the server already answers: it imports the explorer's modules first
  (the page, served at once, needs them and no solver), then numba loads the
  compiled code from its disk cache, or compiles it on a fresh install
  (minutes on a busy machine; sessions' first runs wait for it, their pages
  do not), then it renders the figures' templates, which the first session
  would otherwise do in the event loop, and sets the
  start-up objects aside from the garbage collector (then each session's,
  :mod:`app.heap`);
* ``GET /liveness`` answers 503 until that is done and 200 after, with a JSON
  body: ``ready``, the warm-up ``stage`` and ``seconds``, the solver
  ``backend`` (local, or the Dask scheduler), ``solves``: the sessions' solves
  waiting or running now (:func:`app.runs.solves_in_flight`), ``solves_ended``:
  those ended since the start, and, when
  ``SHAKEDOWN_LOOP_WATCH_MS`` is set, ``loop_max_lag_ms``: the longest the
  server's event loop was busy (blocked) since the last ``?reset=1``, and
  ``loop_max_callback_ms``: the longest single callback it ran meanwhile, and
  ``gc_max_ms``: the longest pass of the garbage collector, ``watch_late_ms``:
  how late the watching thread itself woke at most (its resolution), and the heap's
  counts (:meth:`app.heap.Heap.report`: sessions open, objects frozen,
  reclaims of ended sessions' objects and the longest).

Panel's own ``--liveness`` answers 200 as soon as the process listens, which
says nothing about the solver; this endpoint replaces it (do not pass both).

A read-only container: numba needs a writable cache directory. If
``SHAKEDOWN_NUMBA_CACHE_SEED`` names a directory of precompiled code (the
Docker image's, filled at build time for the installed package) and
``NUMBA_CACHE_DIR`` (a tmpfs) lacks it, it is copied there before the solver
is imported, so the solver loads instead of compiling.
"""

from __future__ import annotations

import gc
import json
import os
import shutil
import threading
import time


def seed_numba_cache() -> bool:
    """Copy ``SHAKEDOWN_NUMBA_CACHE_SEED`` into ``NUMBA_CACHE_DIR`` (before numba is imported); True if copied."""
    seed, target = os.environ.get("SHAKEDOWN_NUMBA_CACHE_SEED"), os.environ.get("NUMBA_CACHE_DIR")
    if not seed or not target or not os.path.isdir(seed) or os.path.abspath(seed) == os.path.abspath(target):
        return False
    # files only, not the seed's owner or modes: the copy must be writable by this user (numba checks that)
    for folder, _, files in os.walk(seed):
        into = os.path.join(target, os.path.relpath(folder, seed))
        os.makedirs(into, mode=0o700, exist_ok=True)
        for name in files:
            shutil.copyfile(os.path.join(folder, name), os.path.join(into, name))
    return True


seed_numba_cache()

from tornado import ioloop, web  # noqa: E402

from app import runs  # noqa: E402 - after the cache is seeded: this imports the solver
from app.heap import HEAP, set_aside_sessions  # noqa: E402
from app.limits import LOOP_WATCH_MS  # noqa: E402
from app.loop import quiet_closed_sockets, take_turns  # noqa: E402

#: The garbage collector's thresholds in the server (Python's default: 700, 10, 10), see _freeze_the_heap
GC_THRESHOLDS = (10_000, 10, 10)

__all__ = ["ROUTES", "LivenessHandler", "LoopWatch", "watch_loop", "seed_numba_cache"]


class LoopWatch:
    """Measures how long the event loop is blocked: a thread asks it to run a no-op every ``interval_ms``.

    The time from asking to running is how long the loop was busy with
    something else (one session's build or callback, or several queued one
    after another: when many arrive together the loop runs them all before
    the no-op). Also times each callback the loop runs (``max_callback``):
    the longest single one. Keeps the largest of both since :meth:`reset`.
    """

    def __init__(self, loop: ioloop.IOLoop, interval_ms: int):
        self.loop, self.interval = loop, interval_ms / 1e3
        self.max_lag = self.max_callback = self.max_collection = self.max_late = 0.0
        self.samples = 0
        self._lock = threading.Lock()
        self._time_callbacks()
        self._collecting = 0.0
        gc.callbacks.append(self._collection)
        self._thread = threading.Thread(target=self._run, name="loop-watch", daemon=True)
        self._thread.start()

    def _time_callbacks(self) -> None:
        """Time every callback the server's asyncio loop runs (a handle's run; a session's build is one step of
        its task, one handle)."""
        import asyncio.events

        handle = asyncio.events.Handle
        if getattr(handle._run, "_timed", False):
            return
        run = handle._run

        server = threading.get_ident()  # (made on the server's loop: other threads' loops are not timed)

        def timed(h, _run=run, _clock=time.perf_counter, _thread=threading.get_ident):
            t0 = _clock()
            try:
                return _run(h)
            finally:
                spent = _clock() - t0
                if spent > self.max_callback and _thread() == server:
                    self.max_callback = spent

        timed._timed = True
        handle._run = timed

    def _collection(self, phase: str, info: dict) -> None:
        """Time the garbage collector's passes (it stops every thread, the loop's too)."""
        if phase == "start":
            self._collecting = time.perf_counter()
        elif self._collecting:
            self.max_collection = max(self.max_collection, time.perf_counter() - self._collecting)

    def _mark(self, sent: float) -> None:
        lag = time.perf_counter() - sent
        with self._lock:
            self.max_lag = max(self.max_lag, lag)
            self.samples += 1

    def _run(self) -> None:
        while True:
            sent = time.perf_counter()
            self.loop.add_callback(self._mark, sent)
            time.sleep(self.interval)
            # how late this thread itself woke (the OS, or the GIL held by the loop): the watch's resolution
            late = time.perf_counter() - sent - self.interval
            with self._lock:
                self.max_late = max(self.max_late, late)

    def reset(self) -> tuple[float, float, float, float]:
        """Start a new window; returns the largest lag, the longest callback, the longest garbage collection and
        how late the watch's own thread woke at most, of the old one [s].

        The lag under-reads a callback by at most the interval plus that lateness: a no-op asked for just after
        a callback started waits for the rest of it, and the next is asked for an interval (and the lateness)
        later.
        """
        with self._lock:
            old = (self.max_lag, self.max_callback, self.max_collection, self.max_late)
            self.max_lag = self.max_callback = self.max_collection = self.max_late = 0.0
            return old


_WATCH: list[LoopWatch] = []


def watch_loop() -> LoopWatch | None:
    """Start watching this thread's event loop (once per process) if ``SHAKEDOWN_LOOP_WATCH_MS`` is set."""
    if LOOP_WATCH_MS and not _WATCH:
        _WATCH.append(LoopWatch(ioloop.IOLoop.current(), LOOP_WATCH_MS))
    return _WATCH[0] if _WATCH else None


class LivenessHandler(web.RequestHandler):
    """``/liveness``: 200 once the solver is warm, 503 (with the stage) before; JSON either way."""

    def get(self):
        watch = watch_loop()
        body = runs.readiness()
        if watch is not None:
            times = watch.reset() if self.get_argument("reset", "") else (watch.max_lag, watch.max_callback,
                                                                          watch.max_collection, watch.max_late)
            for key, seconds in zip(("loop_max_lag_ms", "loop_max_callback_ms", "gc_max_ms", "watch_late_ms"),
                                    times):
                body[key] = round(1e3 * seconds, 1)
            body["loop_samples"], body["loop_watch_interval_ms"] = watch.samples, round(1e3 * watch.interval, 1)
            body.update(HEAP.report())
        self.set_header("Content-Type", "application/json")
        self.set_header("Cache-Control", "no-store")
        self.set_status(200 if body["ready"] else 503)
        self.write(json.dumps(body))


take_turns(after=HEAP.built)  # sessions' builds take turns with the rest of the event loop, and are frozen
quiet_closed_sockets()  # a tab closed mid-update leaves no "Task exception was never retrieved" in the log
set_aside_sessions()  # ended sessions' frozen objects are reclaimed

if "BOKEH_VALIDATE_DOC" not in os.environ:
    # Bokeh checks every page's model graph for layout mistakes (warnings in the log) when it is sent: 30 ms of
    # a page's 0.58 s of server CPU. The pages are the same every time, so the server skips it; the test suite
    # sets BOKEH_VALIDATE_DOC=true (tests/conftest.py) and keeps the checks.
    from bokeh.settings import settings as _bokeh_settings

    _bokeh_settings.perform_document_validation.set_value(False)

#: Routes ``panel serve --plugins app.health`` adds to the server.
ROUTES = [(r"/liveness", LivenessHandler)]

def _import_the_explorer():
    """importing the explorer"""
    # the first session would otherwise import HoloViews and the explorer (seconds) in the event loop
    import app.explorer  # noqa: F401


def _draw_the_figures():
    """drawing the page once"""
    # the first session would otherwise have HoloViews render each figure's template (about 0.5 s for the
    # first one, in the event loop; every session then draws a copy, app.live.LiveFigure) and pay for what
    # Panel and Bokeh do once per process (their models' first use); a page built into a document no one sees
    from bokeh.document import Document
    from panel.io.state import set_curdoc

    from app.explorer import Explorer

    try:
        Explorer().figures()
        doc = Document()
        with set_curdoc(doc):
            explorer = Explorer()
            with doc.models.freeze():
                explorer.template().server_doc(doc)
            doc.to_json()
    except Exception:  # noqa: BLE001 - only a head start for the first session: the server serves without it
        runs.log.exception("building a page at start-up failed; the first session will pay for it")


def _freeze_the_heap():
    """setting the server's start-up objects aside"""
    # What the process holds from its start (modules, HoloViews, the compiled solver: about 400 000 objects) is
    # never garbage: kept out of the collector's passes. A session's build allocates some 100 000 objects (about
    # 24 000 live as long as the session, app/heap.py): with
    # Python's default thresholds (a young collection every 700 allocations) the collector ran about 150 times
    # per page and a full pass scanned every live session's objects. Measured in-process (16
    # pages built and kept alive, each with its first figure): 567 ms a page, 46 ms of it collecting; with both
    # changes 545 ms, 10 ms collecting.
    gc.collect()
    gc.freeze()
    HEAP.frozen = gc.get_freeze_count()
    gc.set_threshold(*GC_THRESHOLDS)


# the explorer's modules first: its page needs no solver, and is served while the solver compiles (app/main.py)
runs.start_warm_up(first=(_import_the_explorer,), also=(_draw_the_figures, _freeze_the_heap))
