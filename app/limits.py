"""Operator limits of the served explorer, read once from the environment.

Every bound on the work one browser session can ask of the server is here,
with its environment variable and default, so an operator can see and set them
in one place (README: "Serving it to a class"). A malformed value stops the
server at start-up with a message naming the variable, rather than being
silently replaced by the default.

=============================  =======  =================================================
variable                       default  what it bounds
=============================  =======  =================================================
SHAKEDOWN_MAX_PERIODS          200      periods of one solve (the Periods input's upper bound)
SHAKEDOWN_MAX_RESOLUTION       400      elements per half-width a (the grid's upper bound)
SHAKEDOWN_SOLVE_BUDGET_S       20       wall time of one solve [s]; past it the solve is cancelled
SHAKEDOWN_SOLVER_THREADS       2        threads that run solves for all sessions together
SHAKEDOWN_CACHE_ITEMS          32       solver results kept (shared by all sessions)
SHAKEDOWN_CACHE_MB             512      memory of the kept results [MiB]
SHAKEDOWN_MAP_WORKERS          2        processes of one numerical-map sweep
SHAKEDOWN_MAP_BUDGET_S         300      wall time of one numerical-map sweep [s]
SHAKEDOWN_MAP_MAX_POINTS       40       points per axis of a numerical map (one map at a time)
=============================  =======  =================================================
"""

from __future__ import annotations

from core._validate import env_int

__all__ = ["env_int", "MAX_PERIODS", "MAX_RESOLUTION", "SOLVE_BUDGET_S", "SOLVER_THREADS", "CACHE_ITEMS",
           "CACHE_MB", "MAP_WORKERS", "MAP_BUDGET_S", "MAP_MAX_POINTS"]


MAX_PERIODS = env_int("SHAKEDOWN_MAX_PERIODS", 200, 1, 10_000)
MAX_RESOLUTION = env_int("SHAKEDOWN_MAX_RESOLUTION", 400, 5, 2_000)
SOLVE_BUDGET_S = float(env_int("SHAKEDOWN_SOLVE_BUDGET_S", 20, 1, 3600))
SOLVER_THREADS = env_int("SHAKEDOWN_SOLVER_THREADS", 2, 1, 64)
CACHE_ITEMS = env_int("SHAKEDOWN_CACHE_ITEMS", 32, 1, 10_000)
CACHE_MB = env_int("SHAKEDOWN_CACHE_MB", 512, 1, 1_000_000)
MAP_WORKERS = env_int("SHAKEDOWN_MAP_WORKERS", 2, 1, 256)
MAP_BUDGET_S = float(env_int("SHAKEDOWN_MAP_BUDGET_S", 300, 1, 86_400))
MAP_MAX_POINTS = env_int("SHAKEDOWN_MAP_MAX_POINTS", 40, 2, 400)
