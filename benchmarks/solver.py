"""Time the cycle solver: the paper's heaviest case, and how the time grows with the grid.

Prints the compile/cache-load time separately from warm runs, and the step and
iteration counts beside every wall time, so that an algorithmic regression can
be told from machine noise.

Run: python benchmarks/solver.py [--quick]
"""

import os
import subprocess
import sys
import time

import numpy as np

HEAVY = dict(ft=0.08, w=0.77, periods=10, dx=0.02 / 1.709082)  # dx = dW = 0.02 mm, a = 1.709 mm (eq 17)


def _first_call_in_fresh_process() -> float:
    code = ("import time; t=time.perf_counter(); import core; "
            "core.simulate_cycles(0.2, 0.3, periods=1, dx=0.1); print(time.perf_counter()-t)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.strip())


def main(quick: bool = False) -> None:
    import core

    print(f"threads: OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS')}, cores={os.cpu_count()}")
    t0 = time.perf_counter()
    core.simulate_cycles(0.2, 0.3, periods=1, dx=0.1)
    print(f"first call in this process (numba compile or cache load): {time.perf_counter() - t0:.2f} s")
    print(f"first call in a fresh process, import included (cache warm): {_first_call_in_fresh_process():.2f} s")

    # the paper's heaviest case
    times = []
    for _ in range(3 if quick else 10):
        t = time.perf_counter()
        r = core.simulate_cycles(**HEAVY)
        times.append(time.perf_counter() - t)
    n = r.edges.size - 1
    print(f"\nheaviest case ft=0.08 w=0.77, dx=dW=a/{1 / HEAVY['dx']:.2f}, 10 periods: {n} elements, "
          f"{r.xc.size} steps, {int(r.iterations.sum())} active-set iterations "
          f"(max {int(r.iterations.max())}/step), worst KKT residual {r.max_kkt_residual:.1e}")
    print(f"  warm wall time: best {min(times) * 1e3:.1f} ms, median {np.median(times) * 1e3:.1f} ms "
          f"(target <= 100 ms; the paper's CONTACT needs about 3 s)  regime={r.regime}")
    no_skip = core.simulate_cycles(**HEAVY, detect_periodic=False)
    print(f"  periodic steady state detected from period: {r.periodic_from} "
          f"(time without detection {no_skip.runtime * 1e3:.1f} ms)")
    rat = core.simulate_cycles(0.58, 0.77, periods=10, dx=HEAVY["dx"])
    rat2 = core.simulate_cycles(0.58, 0.77, periods=10, dx=HEAVY["dx"], detect_periodic=False)
    print(f"  ratcheting ft=0.58 w=0.77: {rat.runtime * 1e3:.1f} ms with periodic detection (from period "
          f"{rat.periodic_from}), {rat2.runtime * 1e3:.1f} ms without")

    # scaling with the number of elements, 10 periods, w = 0.77 (steps grow like n too)
    sizes = [100, 200, 400, 800] if quick else [100, 200, 400, 800, 1600]
    rows = []
    print("\nelements  steps   iterations  wall [s]   us/step")
    for target in sizes:
        dx = 2 * 1.77 / target
        t = time.perf_counter()
        r = core.simulate_cycles(0.08, 0.77, periods=10, dx=dx)
        wall = time.perf_counter() - t
        n = r.edges.size - 1
        rows.append((n, wall))
        print(f"{n:8d} {r.xc.size:7d} {int(r.iterations.sum()):10d} {wall:9.3f} {wall / r.xc.size * 1e6:9.1f}")
    n, wall = np.array(rows).T
    k = np.polyfit(np.log(n), np.log(wall), 1)[0]
    k_hi = np.polyfit(np.log(n[-3:]), np.log(wall[-3:]), 1)[0]
    print(f"fitted exponent: time ~ n^{k:.2f} overall, n^{k_hi:.2f} over the largest three "
          f"(steps ~ n and each step is O(m^2) rank-one updates, so n^3 is the asymptote)")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
