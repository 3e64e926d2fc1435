"""Solver runs for the explorer: a bounded LRU cache, a bounded worker pool, and stale-run guards.

Results are shared by every session of the served app (they depend only on
their inputs) and are treated as read-only. The cache is bounded both in the
number of runs and in bytes; the pool is bounded in threads, so one session
cannot queue unbounded work.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import fields

import numpy as np

import core

from .limits import (CACHE_ITEMS, CACHE_MB, MAP_BUDGET_S, MAP_MAX_POINTS, MAP_WORKERS,  # noqa: F401
                     SOLVE_BUDGET_S, SOLVER_THREADS)

__all__ = ["ResultCache", "RESULTS", "SOLVE_BUDGET_S", "run_key", "solve", "submit", "Generation",
           "MAP_WORKERS", "MAP_BUDGET_S", "MAP_MAX_POINTS", "MAP_SLOT", "submit_map"]




def result_nbytes(result: core.CycleResult) -> int:
    """Approximate memory held by a result [bytes] (its arrays, and the per-step pressure it will cache)."""
    total = sum(getattr(result, f.name).nbytes for f in fields(result)
                if isinstance(getattr(result, f.name), np.ndarray))
    return int(total + result.traction.nbytes)  # + the cached per-step pressure


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
        """Keep ``result`` under ``key``, evicting the least recently used beyond the bounds."""
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
#: Threads that run solves for all sessions (SHAKEDOWN_SOLVER_THREADS).
_POOL = ThreadPoolExecutor(max_workers=SOLVER_THREADS, thread_name_prefix="solver")


def _warm_up():
    """Load the solver's compiled code (numba's disk cache) before the first user asks for a run."""
    for kernel in ("plane", "strip"):
        core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25, kernel=kernel,
                             L_over_a=10.0 if kernel == "strip" else None)


_WARM = _POOL.submit(_warm_up)


#: One numerical map at a time on the whole server.
MAP_SLOT = threading.Semaphore(1)
_MAP_POOL = ThreadPoolExecutor(max_workers=1, thread_name_prefix="map")


def submit_map(fn) -> Future:
    """Run a map computation ``fn()`` off the UI thread (one at a time)."""
    return _MAP_POOL.submit(fn)


def run_key(contact: core.Contact, options: dict) -> tuple:
    """A hashable key of everything a run depends on."""
    return tuple(sorted(contact.summary().items())) + tuple(sorted(options.items()))


def solve(contact: core.Contact, options: dict, cache: ResultCache = RESULTS, cancel=None,
          time_budget: float | None = SOLVE_BUDGET_S) -> core.CycleResult:
    """Run (or fetch from ``cache``) :func:`core.simulate_contact` for ``contact`` and ``options``.

    ``cancel()`` returning True, or the time budget [s] running out, stops the
    solve with :class:`core.SolveCancelled`.
    """
    key = run_key(contact, options)
    result = cache.get(key)
    if result is None:
        result = core.simulate_contact(contact, **options, cancel=cancel, time_budget=time_budget)
        result.pressure  # noqa: B018 - computed once here, off the UI thread
        cache.put(key, result)
    return result


def submit(contact: core.Contact, options: dict, cancel=None) -> Future:
    """Solve in the shared worker pool; returns a future of the result."""
    return _POOL.submit(solve, contact, options, RESULTS, cancel)


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
