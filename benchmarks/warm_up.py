"""Time the server's warm-up runs (app.runs._WARM_RUNS), each in turn as the warm-up thread runs them.

Usage: python benchmarks/warm_up.py [--cold]

Runs in a fresh process per call. ``--cold``: ``NUMBA_CACHE_DIR`` a new empty directory, as a fresh install (numba
compiles every kernel); without it, numba's cache as it is (a restart: the kernels are loaded from disk). Prints
for each run its group (the sessions that wait for it: ``line``, ``point``, ``coupled``), its CPU time and wall
time, the time at which each group is warm (what a session of that group waits for) and the whole warm-up, with
the load average before and after (2 cores shared: the wall time grows with the load, the CPU time less).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

_CHILD = """
import resource, sys, time
t_import = time.perf_counter()
from app import runs
print(f"import app.runs: {time.perf_counter() - t_import:.2f} s wall")
groups = {}
cpu0, wall0 = time.process_time(), time.perf_counter()
for group, run in zip(runs._WARM_GROUPS, runs._WARM_RUNS):
    c, w = time.process_time(), time.perf_counter()
    r = run()
    c, w = time.process_time() - c, time.perf_counter() - w
    kind = "coupled" if getattr(r, "coupled", False) else r.body_name
    print(f"  {group:8s} {kind:9s} {r.kernel:6s} CPU {c:7.2f} s  wall {w:7.2f} s")
    groups[group] = time.perf_counter() - wall0
for group, t in groups.items():
    print(f"group {group!r} warm after {t:.2f} s wall")
print(f"whole warm-up: CPU {time.process_time() - cpu0:.2f} s, wall {time.perf_counter() - wall0:.2f} s")
"""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cold", action="store_true", help="an empty numba cache (a fresh install)")
    args = ap.parse_args(argv)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    with tempfile.TemporaryDirectory(prefix="numba-cold-") as cache:
        if args.cold:
            env["NUMBA_CACHE_DIR"] = cache
        print(f"{'cold (empty numba cache)' if args.cold else 'warm (numba cache as it is)'}; "
              f"load average before: {os.getloadavg()[0]:.2f}")
        p = subprocess.run([sys.executable, "-c", _CHILD], env=env, cwd=ROOT, text=True, capture_output=True)
        print(p.stdout, end="")
        if p.returncode:
            print(p.stderr[-3000:], file=sys.stderr)
        print(f"load average after: {os.getloadavg()[0]:.2f}")
    return p.returncode


if __name__ == "__main__":
    sys.exit(main())
