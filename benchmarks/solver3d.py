"""Time the 3D point-contact solver (rocking sphere) and print the grid convergence of its increment.

The two cases of issue 10 (targets 2.4 s and 27 s warm; the paper's program
needs about 24 s and 270 s), each with the steps computed, the periods copied
once the state repeated, and the active-set and CG iterations per step, so
that an algorithmic regression can be told from machine noise. Then the
increment per period of a ratcheting sphere on three grids.

The CPU time is printed beside the wall time: on a shared machine it is the
figure that does not depend on the other processes.

Run: python benchmarks/solver3d.py [--quick] [--no-fine]
"""

import sys
import time

import numpy as np

CASES = [
    dict(ft=0.3, w=0.6, periods=10, dx=1 / 20),  # 40 elements across the contact; paper's program ~24 s
    dict(ft=0.6, w=0.3, periods=10, dx=1 / 40),  # 80 across, ~10,000 elements; paper's program ~270 s
]


def _run(case, repeats):
    import core

    best, best_cpu, r = np.inf, np.inf, None
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        r = core.simulate_cycles(case["ft"], case["w"], periods=case["periods"], dx=case["dx"], body="sphere")
        best, best_cpu = min(best, time.perf_counter() - t), min(best_cpu, time.process_time() - c)
    computed = r.xc.size if r.periodic_from is None else int(np.flatnonzero(r.period == r.periodic_from)[-1]) + 1
    active = r.iterations[:computed]
    elements = (r.x_edges.size - 1) * (r.y_edges.size - 1)
    print(f"sphere ft={case['ft']}, w={case['w']}, dx=a/{round(1 / case['dx'])}, {case['periods']} periods: "
          f"{best:.2f} s wall, {best_cpu:.2f} s CPU (best of {repeats}), {elements} elements, {r.xc.size} steps, {computed} computed "
          f"(periodic from period {r.periodic_from}); per computed step: active-set iterations "
          f"{active.mean():.2f} (max {active.max()}), CG iterations {r.cg_iterations[:computed].mean():.1f} "
          f"(max {r.cg_iterations.max()}); regime {r.regime}, last increment {r.increment_per_period[-1]:.5f}, "
          f"worst residual {r.max_residual:.1e}")
    return r


def grid_convergence(dxs=(0.2, 0.1, 0.05), ft=0.4, w=0.6, periods=5):
    """Increment per period [mu Fn/(E* a)] of a ratcheting sphere against the element size."""
    import core

    print(f"\ngrid convergence: sphere ft={ft}, w={w} (exact limit ft_lim = {float(core.ft_limit(w, body='sphere')):.4f}),"
          f" {periods} periods, nu = 0.5")
    print(f"{'dx [a]':>8} {'elements':>9} {'increment (last period)':>24} {'change':>9} {'time [s]':>9}")
    prev = None
    for dx in dxs:
        r = core.simulate_cycles(ft, w, periods=periods, dx=dx, body="sphere")
        inc = float(r.increment_per_period[-1])
        change = "" if prev is None else f"{inc - prev:+.5f}"
        print(f"{dx:8.3f} {(r.x_edges.size - 1) * (r.y_edges.size - 1):9d} {inc:24.5f} {change:>9} {r.runtime:9.2f}")
        prev = inc


def main(quick=False, fine=True):
    import core

    t = time.perf_counter()
    core.simulate_cycles(0.2, 0.3, periods=1, dx=0.25, body="sphere")
    print(f"first call (imports, FFT plans): {time.perf_counter() - t:.2f} s")
    _run(CASES[0], 1 if quick else 2)
    if fine:
        _run(CASES[1], 1)
    grid_convergence(dxs=(0.2, 0.1) if quick else (0.2, 0.1, 0.05))


if __name__ == "__main__":
    main(quick="--quick" in sys.argv, fine="--no-fine" not in sys.argv)
