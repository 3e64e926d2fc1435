"""Operator limits of the served explorer, read once from the environment.

Every bound on the work one browser session can ask of the server is here,
with its environment variable and default, so an operator can see and set them
in one place (README: "Serving it to a class"). A malformed value stops the
server at start-up with a message naming the variable, rather than being
silently replaced by the default.

================================  =======  =================================================
variable                          default  what it bounds
================================  =======  =================================================
SHAKEDOWN_MAX_PERIODS             200      periods of one solve (the Periods input's upper bound)
SHAKEDOWN_MAX_RESOLUTION          400      elements per half-width a (the grid's upper bound)
SHAKEDOWN_SOLVE_BUDGET_S          20       wall time of one solve [s]; past it the solve is cancelled
SHAKEDOWN_SOLVER_THREADS          2        threads that run solves for all sessions together
SHAKEDOWN_CACHE_ITEMS             32       solver results kept (shared by all sessions)
SHAKEDOWN_CACHE_MB                512      memory of the kept results [MiB]
SHAKEDOWN_MAP_WORKERS             2        processes of one numerical-map sweep
SHAKEDOWN_MAP_BUDGET_S            300      wall time of one numerical-map sweep [s]
SHAKEDOWN_MAP_MAX_POINTS          40       points per axis of a numerical map (one map at a time)
SHAKEDOWN_MAX_QUEUED_PER_SESSION  3        solves one session may have waiting or running at once
SHAKEDOWN_SCHEDULER               (unset)  Dask scheduler (tcp://host:8786) that runs the solves and the
                                           map sweeps; unset: threads and processes of the web server
SHAKEDOWN_LOOP_WATCH_MS           (unset)  log how late the server's event loop runs a periodic check
                                           (benchmarks/loadtest.py reads it); unset: no check
================================  =======  =================================================

With ``SHAKEDOWN_SCHEDULER`` set, ``SHAKEDOWN_SOLVER_THREADS`` and
``SHAKEDOWN_MAP_WORKERS`` no longer apply: the cluster's workers run the work
(start them with ``--nthreads 1``, one process per core, this package installed).
"""

from __future__ import annotations

import os

from core.base._validate import env_int

__all__ = ["env_int", "env_scheduler", "MAX_PERIODS", "MAX_RESOLUTION", "SOLVE_BUDGET_S", "SOLVER_THREADS",
           "CACHE_ITEMS", "CACHE_MB", "MAP_WORKERS", "MAP_BUDGET_S", "MAP_MAX_POINTS", "MAX_QUEUED_PER_SESSION",
           "SCHEDULER", "LOOP_WATCH_MS"]


MAX_PERIODS = env_int("SHAKEDOWN_MAX_PERIODS", 200, 1, 10_000)
MAX_RESOLUTION = env_int("SHAKEDOWN_MAX_RESOLUTION", 400, 5, 2_000)
SOLVE_BUDGET_S = float(env_int("SHAKEDOWN_SOLVE_BUDGET_S", 20, 1, 3600))
SOLVER_THREADS = env_int("SHAKEDOWN_SOLVER_THREADS", 2, 1, 64)
CACHE_ITEMS = env_int("SHAKEDOWN_CACHE_ITEMS", 32, 1, 10_000)
CACHE_MB = env_int("SHAKEDOWN_CACHE_MB", 512, 1, 1_000_000)
MAP_WORKERS = env_int("SHAKEDOWN_MAP_WORKERS", 2, 1, 256)
MAP_BUDGET_S = float(env_int("SHAKEDOWN_MAP_BUDGET_S", 300, 1, 86_400))
MAP_MAX_POINTS = env_int("SHAKEDOWN_MAP_MAX_POINTS", 40, 2, 400)
MAX_QUEUED_PER_SESSION = env_int("SHAKEDOWN_MAX_QUEUED_PER_SESSION", 3, 1, 1000)
LOOP_WATCH_MS = env_int("SHAKEDOWN_LOOP_WATCH_MS", 0, 0, 60_000)


def env_scheduler(name: str = "SHAKEDOWN_SCHEDULER") -> str | None:
    """The Dask scheduler address in environment variable ``name``, or None if unset or empty.

    Raises
    ------
    ValueError
        If the value is not an address of the form ``scheme://host:port``
        (tcp, tls, ws, wss; at most 300 characters); the message names the variable.
    """
    raw = os.environ.get(name, "").strip()
    if not raw:
        return None
    scheme, sep, location = raw.partition("://")
    host, colon, port = location.rpartition(":")
    if (len(raw) > 300 or not sep or scheme not in ("tcp", "tls", "ws", "wss") or not colon or not host
            or not port.isdigit() or not 0 < int(port) < 65536):
        raise ValueError(f"{name} must be a Dask scheduler address such as tcp://host:8786, got {raw!r:.60}")
    return raw


SCHEDULER = env_scheduler()
