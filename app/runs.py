"""Solver runs for the explorer: a shared read-only result cache, where solves run, and stale-run guards.

Results are shared by every session of the served app (they depend only on
their inputs); their arrays are made read-only before they are shared. The
cache is bounded both in the number of runs and in bytes.

Where the work runs:

* by default, in a pool of ``SHAKEDOWN_SOLVER_THREADS`` threads of the web
  server (solves) and a local process pool (map sweeps, one at a time);
* with ``SHAKEDOWN_SCHEDULER=tcp://host:8786``, on that Dask cluster: solves
  and map sweeps are sent to its workers (which need this package, ``core``,
  installed) and the web process only builds pages. One
  ``distributed.Client`` per server process, made on first use with
  ``set_as_default=False`` and always passed explicitly.

Either way a session may have at most ``SHAKEDOWN_MAX_QUEUED_PER_SESSION``
solves waiting or running: a request beyond that first drops the session's
own superseded requests, and is refused if that is not enough, so one user
cannot starve the rest.

The server warms the solver once at start (:func:`start_warm_up`): numba
loads its compiled code from the disk cache, or compiles it on a fresh
install; :func:`readiness` says how far that is (``/liveness`` reports it).
"""

from __future__ import annotations

import functools
import logging
import sys
import threading
import time
from collections import OrderedDict
from concurrent.futures import Executor, Future, ThreadPoolExecutor
from dataclasses import fields

import numpy as np

import core

from .limits import (CACHE_ITEMS, CACHE_MB, MAP_BUDGET_S, MAP_MAX_POINTS, MAP_WORKERS,  # noqa: F401
                     MAX_QUEUED_PER_SESSION, SCHEDULER, SOLVE_BUDGET_S, SOLVER_THREADS)

__all__ = ["ResultCache", "RESULTS", "SOLVE_BUDGET_S", "SOLVE_TASK", "run_key", "solve", "submit", "Generation",
           "MAP_WORKERS", "MAP_BUDGET_S", "MAP_MAX_POINTS", "MAP_SLOT", "submit_map", "map_scheduler",
           "SolveQueueFull", "freeze", "readiness", "solves_in_flight", "ready", "on_ready", "start_warm_up", "backend",
           "warming_seconds", "warmed", "on_warm", "call_in_session", "session_loop", "LimitCurves", "LIMIT_CURVES", "LIMIT_CURVE_GRID"]

log = logging.getLogger(__name__)


class SolveQueueFull(ValueError):
    """A session asked for more solves at once than ``SHAKEDOWN_MAX_QUEUED_PER_SESSION`` allows."""


def freeze(result: core.CycleResult) -> core.CycleResult:
    """Make every array of ``result`` read-only (also its per-step pressure), so sessions cannot alter a shared run."""
    for value in (getattr(result, f.name) for f in fields(result)):
        if isinstance(value, np.ndarray):
            value.setflags(write=False)
    return result


def result_nbytes(result: core.CycleResult) -> int:
    """Approximate memory held by a result [bytes]: its arrays (the per-step pressure is a view of its stored
    distinct rows, ``pressures``, and caches nothing)."""
    return int(sum(getattr(result, f.name).nbytes for f in fields(result)
                   if isinstance(getattr(result, f.name), np.ndarray)))


class ResultCache:
    """Least-recently-used cache of solver results, bounded in items and in bytes.

    Parameters
    ----------
    max_items : int
        Largest number of results kept, >= 1.
    max_bytes : int
        Largest total size of the kept results [bytes], >= 1. A single result
        larger than this is returned but not kept.
    """

    def __init__(self, max_items: int = 32, max_bytes: int = 512 * 2**20):
        if int(max_items) < 1 or int(max_bytes) < 1:
            raise ValueError(f"max_items and max_bytes must be >= 1, got {max_items}, {max_bytes}")
        self.max_items, self.max_bytes = int(max_items), int(max_bytes)
        self._data: OrderedDict = OrderedDict()
        self._sizes: dict = {}
        self._lock = threading.Lock()
        self.hits = self.misses = 0

    def __len__(self) -> int:
        return len(self._data)

    def __contains__(self, key) -> bool:
        return key in self._data

    @property
    def nbytes(self) -> int:
        """Total size of the kept results [bytes]."""
        return sum(self._sizes.values())

    def get(self, key):
        """The cached result for ``key`` (marking it recently used), or None."""
        with self._lock:
            if key in self._data:
                self._data.move_to_end(key)
                self.hits += 1
                return self._data[key]
            self.misses += 1
            return None

    def put(self, key, result) -> None:
        """Keep ``result`` under ``key`` (read-only, see :func:`freeze`), evicting the least recently used."""
        freeze(result)
        size = result_nbytes(result)
        with self._lock:
            if size > self.max_bytes:
                return
            self._data[key] = result
            self._sizes[key] = size
            self._data.move_to_end(key)
            while len(self._data) > self.max_items or sum(self._sizes.values()) > self.max_bytes:
                old, _ = self._data.popitem(last=False)
                self._sizes.pop(old, None)

    def clear(self) -> None:
        with self._lock:
            self._data.clear()
            self._sizes.clear()


#: The results shared by all sessions (bounds: SHAKEDOWN_CACHE_ITEMS, SHAKEDOWN_CACHE_MB).
RESULTS = ResultCache(CACHE_ITEMS, CACHE_MB * 2**20)


def run_key(contact, options: dict) -> tuple:
    """A hashable key of everything a run depends on (a line body's :class:`core.Contact` or a
    point :class:`core.Contact`, and the options; a body object by its ``repr``: its name and parameters, a height
    map's data digest). Not μ, for an uncoupled contact (Dundurs β = 0): the normalised run does not depend on it
    (tests/test_app_teacher_numbers.py checks that the arrays are the same)."""
    if contact.is_point:
        inputs = {"point_contact": True, **contact.summary()}
    else:
        inputs = contact.summary()
    if getattr(contact, "beta", 0.0) == 0.0:
        # μ is not part of an uncoupled run: in its units (tractions in μ p0, loads in μ P or μ Fn, displacements
        # in μ P/E*) the run is the same for every μ, so moving μ only rescales the physical figures
        inputs = {k: v for k, v in inputs.items() if k not in ("mu", "Ft")}
        inputs["ft"] = round(float(contact.ft), 12)
    opts = {k: (f"{type(v).__name__}:{v!r}" if k == "body" else v) for k, v in options.items()}
    return tuple(sorted(inputs.items())) + tuple(sorted(opts.items()))


#: The name of a solve's tasks on a Dask cluster (the prefix of their keys: the run's function,
#: :meth:`core.Contact.simulate`): what the cluster's tests and ``benchmarks/loadtest.py`` count.
SOLVE_TASK = "simulate"


def _compute(contact, options, cancel=None, time_budget=SOLVE_BUDGET_S):
    return contact.simulate(**options, cancel=cancel, time_budget=time_budget)


#: The warm-up runs: one small run per kernel loads (or compiles) all the solver's numba code. The explorer's
#: first page (the strip kernel, app.state) first: a visitor's first run waits for no other body's compiling.
_WARM_RUNS = (*(functools.partial(core.simulate_cycles, 0.1, 0.2, periods=1, dx=0.25, kernel=kernel,
                                  L_over_a=10.0 if kernel == "strip" else None) for kernel in ("strip", "plane")),
              # the point contacts' compiled 3D loop (about a minute to compile cold): warmed before the server
              # says it is ready, so the first sphere visitor does not freeze the server while numba compiles
              functools.partial(core.simulate_cycles, 0.1, 0.2, periods=1, dx=0.25, body="sphere"),
              # the coupled line solver (dissimilar materials, Dundurs beta != 0: its own kernels, about half a
              # minute to compile cold), last: the first page's line solver and the sphere's are ready as before
              functools.partial(core.simulate_cycles, 0.1, 0.2, periods=1, dx=0.25, beta=0.1, mu=0.3))
#: Which solver each warm-up run makes ready (a session's solve waits for its own: :func:`on_warm`): ``"line"``
#: the uncoupled line contacts', ``"point"`` the point contacts', ``"coupled"`` a coupled line contact's.
_WARM_GROUPS = ("line", "line", "point", "coupled")


class _Local:
    """Solves in ``SHAKEDOWN_SOLVER_THREADS`` threads of this process; maps in a local process pool."""

    name = "local"

    def __init__(self, threads: int):
        self._pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="solver")

    def run(self, contact, options, cancel, time_budget) -> core.CycleResult:
        return _compute(contact, options, cancel, time_budget)

    def warm(self) -> None:
        for group, run in zip(_WARM_GROUPS, _WARM_RUNS):
            run()
            _warmed(group)

    def submit(self, contact, options, cancel, cache) -> Future:
        return self._pool.submit(solve, contact, options, cache, cancel)

    def map_scheduler(self):
        return None  # core.sweep's default: a local process pool

    def close(self):
        self._pool.shutdown(wait=False, cancel_futures=True)


class _ClusterExecutor(Executor):
    """A ``concurrent.futures.Executor`` on the cluster's client, for :func:`core.sweep`.

    It reports the cluster's worker threads as ``_max_workers``, which
    :func:`core.sweep` reads to split a map into one chunk of runs per worker
    (``distributed.ClientExecutor`` has no such attribute: a map would run as one chunk).
    """

    def __init__(self, cluster: "_Cluster"):
        self._cluster = cluster

    @property
    def _max_workers(self) -> int:
        return max(1, sum(self._cluster.client().nthreads().values()))

    def submit(self, fn, /, *args, **kwargs) -> Future:
        return self._cluster.executor().submit(fn, *args, **kwargs)

    def shutdown(self, wait=True, *, cancel_futures=False):
        pass  # the client lives as long as the server


class _Cluster:
    """Solves and maps on the Dask scheduler at ``address``; the client is made on first use."""

    def __init__(self, address: str):
        self.address = address
        self.name = f"dask({address})"
        self._client = self._executor = None
        self._lock = threading.Lock()

    def client(self):
        """The process's ``distributed.Client`` (``set_as_default=False``: nothing else picks it up)."""
        with self._lock:
            if self._client is None:
                try:
                    import distributed
                except ImportError as e:
                    raise ValueError("SHAKEDOWN_SCHEDULER needs dask.distributed: pip install 'dask[distributed]'") from e
                try:
                    self._client = distributed.Client(self.address, set_as_default=False, timeout="10s")
                except (OSError, TimeoutError) as e:
                    raise ValueError(f"cannot reach the Dask scheduler SHAKEDOWN_SCHEDULER={self.address}: {e}") from e
                self._executor = self._client.get_executor(pure=False)
                log.info("solves and maps go to the Dask scheduler %s", self.address)
            return self._client

    def executor(self):
        self.client()
        return self._executor

    def _remote(self, contact, options, time_budget) -> Future:
        # core's own run function, so that the workers need only ``core``; no cancel() across processes
        return self.executor().submit(contact.simulate, time_budget=time_budget, **options)

    def run(self, contact, options, cancel, time_budget) -> core.CycleResult:
        future = self._remote(contact, options, time_budget)
        while True:  # wait in slices so that a cancel() is honoured
            try:
                result = future.result(timeout=0.25)
                break
            except TimeoutError:
                if cancel is not None and cancel():
                    future.cancel()
                    raise core.SolveCancelled("solve cancelled while it waited for the cluster") from None
        return result

    def warm(self) -> None:
        """Warm every worker connected now (a worker that joins later warms itself on its first run)."""
        client = self.client()
        client.wait_for_workers(1, timeout=120)
        for group, run in zip(_WARM_GROUPS, _WARM_RUNS):
            client.run(run)
            _warmed(group)

    def submit(self, contact, options, cancel, cache) -> Future:
        out: Future = Future()
        try:
            remote = self._remote(contact, options, SOLVE_BUDGET_S)
        except ValueError as e:
            out.set_exception(e)
            return out
        out.remote = remote  # cancelled with the request when it is superseded (see _Sessions)

        def landed(f):  # in the client's thread
            if out.done():
                return
            if f.cancelled():
                out.set_exception(core.SolveCancelled("solve cancelled: a newer request replaced it"))
                return
            exc = f.exception()
            if exc is not None:
                out.set_exception(exc)
                return
            result = f.result()
            cache.put(run_key(contact, options), result)
            out.set_result(result)

        remote.add_done_callback(landed)
        return out

    def map_scheduler(self):
        return _ClusterExecutor(self)

    def close(self):
        with self._lock:
            if self._client is not None:
                self._client.close()
                self._client = None


_BACKEND = _Cluster(SCHEDULER) if SCHEDULER else _Local(SOLVER_THREADS)


def backend():
    """Where solves run: the local pool, or the Dask cluster of ``SHAKEDOWN_SCHEDULER``."""
    return _BACKEND


def map_scheduler():
    """What to pass to :func:`core.sweep` as ``scheduler`` for the explorer's numerical map.

    None (a local process pool) without ``SHAKEDOWN_SCHEDULER``; with it, an
    executor on the Dask cluster's client.
    """
    return _BACKEND.map_scheduler()


#: One numerical map at a time on the whole server.
MAP_SLOT = threading.Semaphore(1)
_MAP_POOL = ThreadPoolExecutor(max_workers=1, thread_name_prefix="map")


def submit_map(fn) -> Future:
    """Run a map computation ``fn()`` off the UI thread (one at a time)."""
    return _MAP_POOL.submit(fn)


def solve(contact: core.Contact, options: dict, cache: ResultCache = RESULTS, cancel=None,
          time_budget: float | None = SOLVE_BUDGET_S) -> core.CycleResult:
    """Run (or fetch from ``cache``) :func:`core.simulate_contact` for ``contact`` and ``options``.

    The run happens where :func:`backend` says (here, or on the Dask cluster,
    waiting for it). ``cancel()`` returning True, or the time budget [s]
    running out, stops the solve with :class:`core.SolveCancelled`. The result
    is read-only (:func:`freeze`).
    """
    key = run_key(contact, options)
    result = cache.get(key)
    if result is None:
        result = _BACKEND.run(contact, options, cancel, time_budget)
        cache.put(key, result)
    return result


class _Sessions:
    """Solves each session has waiting or running, at most ``limit`` each."""

    def __init__(self, limit: int):
        self.limit = limit
        self._pending: dict = {}  # owner -> [(future, cancel)], only owners with pending solves
        self.ended = 0  # solves that ended (a result, an error or cancelled), since the start
        self._lock = threading.Lock()

    def pending(self, owner) -> int:
        with self._lock:
            return len(self._pending.get(owner, ()))

    def total(self) -> int:
        """Solves waiting or running, of every owner."""
        with self._lock:
            return sum(map(len, self._pending.values()))

    def admit(self, owner, cancel) -> bool:
        """Make room for one more solve of ``owner``: drop its superseded ones; False if still full."""
        with self._lock:
            entries = self._pending.get(owner, [])
            for future, stale in list(entries):
                if stale is not None and stale():
                    # not future.cancel(): its owner's callback expects a result or SolveCancelled. A local solve
                    # stops at its next cancel() check; a cluster solve is cancelled there (see _Cluster.submit)
                    remote = getattr(future, "remote", None)
                    if remote is not None:
                        remote.cancel()
                    entries.remove((future, stale))
            return len(entries) < self.limit

    def add(self, owner, future, cancel) -> None:
        with self._lock:
            self._pending.setdefault(owner, []).append((future, cancel))

        def forget(f):
            with self._lock:
                self.ended += 1
                entries = self._pending.get(owner, [])
                for item in [e for e in entries if e[0] is f]:
                    entries.remove(item)
                if not entries:
                    self._pending.pop(owner, None)

        future.add_done_callback(forget)


_SESSIONS = _Sessions(MAX_QUEUED_PER_SESSION)


def session_loop():
    """The event loop of the thread this is called in (a served session's, when called as the session is built):
    the loop :func:`call_in_session` hands that session's callbacks to. None outside a served session."""
    from tornado import ioloop

    return ioloop.IOLoop.current(instance=False)


def call_in_session(doc, loop, fn) -> None:
    """Run ``fn()`` in a callback of the served session of ``doc`` (its document locked), from any thread.

    Only the session's event loop ``loop`` (:func:`session_loop`) touches the document: from another thread the
    call is handed to the loop (tornado's ``add_callback``, thread-safe), which adds the document's next-tick
    callback. A Bokeh document is not thread-safe. ``doc.add_next_tick_callback`` called from a solver or curve
    thread raced the loop's own holds of the document (Panel's ``hold``/``unlocked`` copy and reset its held
    events, and patch the current document on a process-wide stack), and now and then a session's callbacks were
    never run: its coupled limit curve stayed at "computing… 1 of 5 amplitudes" in 1 of 24 pages, and once a CI
    run's page, 300 s after the curve was done.
    """
    def add():
        try:
            doc.add_next_tick_callback(fn)
        except Exception:  # noqa: BLE001 - a session that ended meanwhile: nothing to show it in
            log.debug("a callback for a session that ended was dropped", exc_info=True)

    if loop is None or session_loop() is loop:
        add()
    else:
        loop.add_callback(add)


def _current_session():
    """The Bokeh document of the session being served in this thread, or None (headless)."""
    pn = sys.modules.get("panel")
    return pn.state.curdoc if pn is not None else None


def submit(contact: core.Contact, options: dict, cancel=None, owner=None) -> Future:
    """Solve off the UI thread (local pool or Dask cluster); returns a future of the (read-only) result.

    Parameters
    ----------
    contact, options :
        As for :func:`solve`.
    cancel : callable, optional
        Returns True once the request is superseded: the solve stops (or, on
        the cluster, is dropped) and frees its place in the session's queue.
    owner : hashable, optional
        Whose solve it is (default: the session served in this thread). An
        owner may have at most ``SHAKEDOWN_MAX_QUEUED_PER_SESSION`` solves
        waiting or running; beyond that the future fails with :class:`SolveQueueFull`.
    """
    owner = _current_session() if owner is None else owner
    if not _SESSIONS.admit(owner, cancel):
        refused: Future = Future()
        refused.set_exception(SolveQueueFull(
            f"this session already has {_SESSIONS.limit} solves waiting or running "
            "(SHAKEDOWN_MAX_QUEUED_PER_SESSION); try again when they finish"))
        return refused
    future = _BACKEND.submit(contact, options, cancel, RESULTS)
    _SESSIONS.add(owner, future, cancel)
    return future


# ---------------------------------------------------------------------- warm-up and readiness
_READY = threading.Event()
_STATE = {"stage": "not started", "error": None, "seconds": None}
_STARTED: list = []  # time.monotonic() when the warm-up started
_READY_CALLBACKS: list = []
_WARM_LOCK = threading.Lock()


def _warm_up(also=(), first=()):
    """``first``; then load (or, on a fresh install, compile) the solver for both kernels, here or on the cluster;
    then ``also``."""
    t0 = time.perf_counter()
    try:
        for step in first:
            _STATE["stage"] = getattr(step, "__doc__", None) or step.__name__
            step()
        _STATE["stage"] = f"preparing the solver ({_BACKEND.name})"
        _BACKEND.warm()
        for step in also:
            _STATE["stage"] = getattr(step, "__doc__", None) or step.__name__
            step()
    except Exception as e:  # noqa: BLE001 - reported by /liveness, and the server keeps serving
        _STATE.update(stage="warm-up failed", error=f"{type(e).__name__}: {e}")
        log.exception("warming the solver failed")
        return
    finally:  # sessions waiting for a solver try their solve now (a failed warm-up: the solve says why)
        for group in set(_WARM_GROUPS):
            if not warmed(group):
                _warmed(group, done=True)
    _STATE.update(stage="ready", seconds=round(time.perf_counter() - t0, 2))
    log.info("solver ready after %.1f s", _STATE["seconds"])
    _READY.set()
    with _WARM_LOCK:
        callbacks, _READY_CALLBACKS[:] = list(_READY_CALLBACKS), []
    for fn in callbacks:
        try:
            fn()
        except Exception:  # noqa: BLE001 - e.g. a session that closed meanwhile; the others still get theirs
            log.exception("a callback waiting for the solver failed")


def start_warm_up(also=(), first=()) -> None:
    """Start warming the solver in a thread of its own (once per process; later calls do nothing).

    ``first``: callables run in that thread before the solver is warmed (what
    the first page needs and the solver does not: importing the explorer's
    modules, seconds, which the first session would otherwise pay for in the
    event loop while the solver compiles). ``also``: further callables run
    once the solver is warm and before :func:`ready` turns True.
    """
    with _WARM_LOCK:
        if _STATE["stage"] != "not started":
            return
        _STATE["stage"] = "starting"
        _STARTED.append(time.monotonic())
    threading.Thread(target=_warm_up, args=(tuple(also), tuple(first)), name="solver-warm-up", daemon=True).start()


def ready() -> bool:
    """True once the solver is warm (see :func:`start_warm_up`)."""
    return _READY.is_set()


def on_ready(fn) -> None:
    """Call ``fn()`` once the solver is warm: now if it is, else from the warm-up thread."""
    with _WARM_LOCK:
        if not _READY.is_set():
            _READY_CALLBACKS.append(fn)
            return
    fn()


_WARM: dict = {}  # group -> threading.Event, set once the warm-up has run the group's runs
_WARM_CALLBACKS: dict = {}  # group -> callables waiting for it


def _event(group: str) -> threading.Event:
    with _WARM_LOCK:
        return _WARM.setdefault(group, threading.Event())


def _warmed(group: str, done: bool = False) -> None:
    """One warm-up run of ``group`` is over (``done``: the warm-up ended, or failed: the group is released);
    after its last one, whoever waits for the group's solver is called."""
    with _WARM_LOCK:
        _WARM_COUNTS[group] = _WARM_COUNTS.get(group, 0) + 1
        if not done and _WARM_COUNTS[group] < _WARM_GROUPS.count(group):
            return
        _WARM.setdefault(group, threading.Event()).set()
        callbacks = _WARM_CALLBACKS.pop(group, [])
    for fn in callbacks:
        try:
            fn()
        except Exception:  # noqa: BLE001 - e.g. a session that closed meanwhile; the others still get theirs
            log.exception("a callback waiting for the %s solver failed", group)


_WARM_COUNTS: dict = {}  # group -> warm-up runs of it done


def warmed(group: str) -> bool:
    """Whether the solver of ``group`` (``"line"``, ``"point"`` or ``"coupled"``) is compiled (or loaded) by the
    warm-up; True where no warm-up was started (a notebook, a test: nothing to wait for)."""
    return not _STARTED or _event(group).is_set()


def on_warm(group: str, fn) -> None:
    """Call ``fn()`` once the solver of ``group`` is warm: now if it is, else from the warm-up thread (also if the
    warm-up fails: the solve then says why)."""
    with _WARM_LOCK:
        if _STARTED and not _WARM.setdefault(group, threading.Event()).is_set():
            _WARM_CALLBACKS.setdefault(group, []).append(fn)
            return
    fn()


def warming_seconds() -> float | None:
    """Seconds since the warm-up started, while the solver is not ready yet (None once it is, or before)."""
    return None if _READY.is_set() or not _STARTED else time.monotonic() - _STARTED[0]


def readiness() -> dict:
    """``ready``, the warm-up ``stage``, its ``error`` if it failed, its ``seconds``, the ``backend``, and
    ``solves``: the sessions' solves waiting or running now (:func:`solves_in_flight`), ``solves_ended``: those
    ended since the start."""
    return {"ready": ready(), **_STATE, "backend": _BACKEND.name, "solves": solves_in_flight(),
            "solves_ended": _SESSIONS.ended}


def solves_in_flight() -> int:
    """The sessions' solves (:func:`submit`) waiting or running on this server now, that their sessions still
    wait for (a solve a newer one of its session superseded is dropped from the count when the newer one is
    asked for, and stops at its next check). 0: the server is idle. An operator reads it on ``/liveness``, beside
    ``solves_ended``, the solves ended since the start (with a result, an error or cancelled; their sessions'
    callbacks are scheduled as they end); the tests wait on both for solves to end."""
    return _SESSIONS.total()


class Generation:
    """A counter that tells whether a request is still the newest one.

    ``token = gen.next()`` when a request starts; ``gen.is_current(token)``
    when it ends: a stale request must not overwrite a newer one.
    """

    def __init__(self):
        self._n = 0
        self._lock = threading.Lock()

    def next(self) -> int:
        with self._lock:
            self._n += 1
            return self._n

    def is_current(self, token: int) -> bool:
        return token == self._n


#: The grid of the coupled limit curves the explorer draws (:func:`core.coupled_limit_curve`): coarse (a/20), five
#: amplitudes, brackets 2 % of eq 35 wide: about 35 coupled runs, seconds of CPU time
#: (``benchmarks/coupled_limit_curve.py``).
LIMIT_CURVE_GRID = dict(w=(0.1, 0.3, 0.5, 0.7, 0.9), dx=1 / 20, tol=0.02, periods=20)


class LimitCurves:
    """The coupled limit curves of the served app, shared by every session, cached per ``(beta, mu)`` and grid.

    A curve is computed in one thread of its own (one curve at a time on the server, a run's numba code releases
    the GIL), each amplitude's bracket handed to the sessions that asked for it as it is found. A curve no session
    waits for any more (its sessions moved to another contact) is stopped at its next run.

    Parameters
    ----------
    items : int
        Complete curves kept (the oldest dropped first).
    grid : dict
        Keyword arguments of :func:`core.coupled_limit_curve` besides ``beta`` and ``mu``.
    """

    def __init__(self, items: int = 32, grid: dict | None = None):
        self.grid = dict(LIMIT_CURVE_GRID if grid is None else grid)
        self._done: OrderedDict = OrderedDict()
        self._running: dict = {}  # key -> [points so far, {listener}]
        self._lock = threading.Lock()
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="limit-curve")
        self.items = items

    def key(self, beta: float, mu: float) -> tuple:
        """The cache key: ``beta`` and ``mu`` to 1e-4 (the curve is computed at these), and the grid."""
        return (round(float(beta), 4), round(float(mu), 4), tuple(sorted((k, str(v)) for k, v in self.grid.items())))

    def request(self, beta: float, mu: float, listener) -> tuple:
        """Ask for the curve of ``(beta, mu)``: ``listener(curve, done, error)`` is called with the curve so far
        (a :class:`core.CoupledLimitCurve`) after each amplitude, with ``done`` True at the end (``error``: why it
        stopped, or ""), from the curve's thread; a cached curve is returned at once, not sent.

        Returns
        -------
        (key, curve or None)
            The key (to :meth:`cancel` with) and the complete curve if it is cached.
        """
        key = self.key(beta, mu)
        with self._lock:
            if key in self._done:
                self._done.move_to_end(key)
                return key, self._done[key]
            entry = self._running.get(key)
            if entry is not None:
                entry[1].add(listener)
                return key, None
            entry = self._running[key] = [[], {listener}]
        self._pool.submit(self._compute, key, entry)
        return key, None

    def cached(self, key: tuple):
        """The complete curve ``key`` if it is cached, else None."""
        with self._lock:
            return self._done.get(key)

    def running(self, key: tuple) -> bool:
        """Whether curve ``key`` is being computed (or waits for the curve before it)."""
        with self._lock:
            return key in self._running

    def cancel(self, key: tuple, listener) -> None:
        """``listener`` no longer waits for curve ``key`` (a curve nobody waits for stops at its next run)."""
        with self._lock:
            entry = self._running.get(key)
            if entry is not None:
                entry[1].discard(listener)

    def _partial(self, key, points) -> core.CoupledLimitCurve:
        beta, mu, _ = key
        return core.CoupledLimitCurve(beta, mu, float(self.grid["dx"]), float(self.grid["tol"]),
                                      int(self.grid["periods"]), tuple(points))

    def _send(self, entry, curve, done, error="") -> None:
        with self._lock:
            listeners = list(entry[1])
        for listener in listeners:
            try:
                listener(curve, done, error)
            except Exception:  # pragma: no cover - one session's failure must not stop the others' curve
                log.exception("a coupled limit curve's listener failed")

    def _compute(self, key, entry) -> None:
        beta, mu, _ = key

        def on_point(point):
            entry[0].append(point)
            self._send(entry, self._partial(key, entry[0]), False)

        def nobody():
            return not entry[1]

        error, curve = "", None
        try:
            if not nobody():
                curve = core.coupled_limit_curve(beta, mu, **self.grid, cancel=nobody, on_point=on_point)
        except core.SolveCancelled:
            error = "stopped: no session waits for it"
        except (ValueError, RuntimeError, core.SolverError) as e:
            error = f"not computed: {e}"
        except Exception as e:  # noqa: BLE001 - anything else would end this thread silently, every session's
            # curve after it waiting for ever: said in the log and to the sessions
            log.exception("the coupled limit curve (beta %s, mu %s) failed", beta, mu)
            error = f"not computed: {type(e).__name__}: {e}"
        with self._lock:
            self._running.pop(key, None)
            if curve is not None:
                self._done[key] = curve
                while len(self._done) > self.items:
                    self._done.popitem(last=False)
        self._send(entry, curve if curve is not None else self._partial(key, entry[0]), True, error)


#: The served app's coupled limit curves.
LIMIT_CURVES = LimitCurves()
