"""Time (ft, w) maps at the default resolution: 5 x 5 and 40 x 40, default workers, 1 worker, 2 workers.

Run: python benchmarks/sweep.py [--n 5 40] [--workers auto 1 2]

``auto`` is the default of :func:`core.sweep` (workers chosen by the size of
the job: a small map runs in this process, a large one on every core); a
number forces that many processes. Also printed: the solver time per cell
(step x element) of the 1-worker run, the constant
``core.maps.tasks.SECONDS_PER_CELL`` that the default uses to size the job.

Prints, separately: the compile time of the solver (in a subprocess with an
empty numba cache, so the shared cache is not touched), the warm-up of this
process and of each worker (loading the cached code), and for each number of
workers the wall time of the map, the start-up of the pool, the mean wall time
per run, the mean solver time per run (``runtime`` column: the step solves
alone; the rest of a run is building its result table row) and the active-set
iterations, so that an algorithmic regression can be told from machine noise.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import core
from core.maps.grid import run_cells
from core.maps.tasks import SECONDS_PER_CELL

TARGET_S = 60.0


def compile_time() -> float:
    """Seconds of the first solve in a fresh process whose numba cache is empty (import excluded)."""
    code = ("import time, core; t = time.perf_counter(); core.simulate_cycles(0.3, 0.3, periods=1); "
            "print(time.perf_counter() - t)")
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[5, 40], help="grid points per axis (default 5 40)")
    parser.add_argument("--workers", nargs="+", default=["auto", "1", "2"],
                        help="'auto' (the default of core.sweep) or worker counts (default auto 1 2)")
    parser.add_argument("--no-compile", action="store_true", help="skip the cold-compile measurement")
    args = parser.parse_args(argv)

    print(f"maps over ft and w in [0.02, 0.95], default resolution (dx = dW = {core.api.solver.DEFAULT_DX:g} a, "
          f"10 periods), {os.cpu_count()} cores")
    if not args.no_compile:
        print(f"compile (empty numba cache, fresh process):   {compile_time():6.2f} s")
    t0 = time.perf_counter()
    core.simulate_cycles(0.3, 0.3, periods=1)
    print(f"warm-up of this process (cached code):        {time.perf_counter() - t0:6.2f} s")
    for n in args.n:
        grid = np.linspace(0.02, 0.95, n)
        cells = sum(run_cells(p) for p in core.sweep_grid(grid, grid))
        walls = {}
        for workers in args.workers:
            t0 = time.perf_counter()
            table = core.sweep(grid, grid, workers=None if workers == "auto" else int(workers))
            wall = time.perf_counter() - t0
            walls[workers] = wall
            warm = table.attrs["warmup_s"]
            warm_text = ", ".join(f"{v:.2f}" for v in warm.values())
            print(f"\n{n} x {n} map, workers={workers}: backend {table.attrs['backend']}, "
                  f"{table.attrs['chunksize']} runs per task")
            print(f"  wall time of the map:        {wall:7.2f} s" + (
                f"  (target < {TARGET_S:.0f} s: {'met' if wall < TARGET_S else 'MISSED'})" if n >= 40 else ""))
            print(f"  start-up (pool + warm-up):   {table.attrs['startup_s']:7.2f} s  (worker warm-up: {warm_text} s)")
            print(f"  wall per run:                {1e3 * wall / len(table):7.2f} ms")
            print(f"  solver time per run (mean):  {1e3 * table['runtime'].mean():7.2f} ms "
                  f"(median {1e3 * table['runtime'].median():.2f}, max {1e3 * table['runtime'].max():.1f})")
            print(f"  solver time per cell:        {table['runtime'].sum() / cells:9.3g} s "
                  f"(core.maps.tasks.SECONDS_PER_CELL = {SECONDS_PER_CELL:.3g})")
            print(f"  active-set iterations:       max {int(table['max_iterations'].max())} per step, "
                  f"{int(table['steps'].sum())} steps in all")
            counts = table["regime"].value_counts().to_dict()
            print("  regimes:                     " + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
        if "1" in walls:
            for workers, wall in walls.items():
                if workers != "1":
                    print(f"{n} x {n}: 1 worker -> workers={workers}: {walls['1'] / wall:.2f}x")


if __name__ == "__main__":
    main()
