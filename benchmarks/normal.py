"""Cost of the numerical normal solve against the closed-form pressure, for the translating line bodies.

A body that only translates carries its static pressure along, so
``normal="numerical"`` solves the normal problem once per normal load
(Polonsky-Keer constrained CG, :mod:`core.normal`, on elements
:data:`core.bodies.NORMAL_REFINE` times finer than the run's) and then
shifts it: its run should cost at most about 1.2x the closed form's. Every
run starts with the pressure tables cleared (``core.bodies.clear_tables``),
so the solve is inside the time; the last column times a repeated run of an
equal body, which reuses the solved pressure (as the runs of a sweep do). Printed per body and grid: the median
wall and CPU time of both runs, their ratio, the CG iterations and time of
the normal solve alone, and the largest difference of the increments per
period (relative to the largest).

Run: python benchmarks/normal.py [--quick]
"""

import statistics
import sys
import time

import numpy as np


def _timed(fn, repeat):
    walls, cpus, out = [], [], None
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        walls.append(time.perf_counter() - w0)
        cpus.append(time.process_time() - c0)
    return statistics.median(walls), statistics.median(cpus), out


def main(quick=False):
    import core
    from core.bodies import NORMAL_REFINE, clear_tables

    def fresh(fn):
        def call():
            clear_tables()
            return fn()
        return call

    core.simulate_cycles(0.2, 0.3, periods=1, dx=0.1)  # compile / load the cache
    repeat = 3 if quick else 5
    cases = [("cylinder", lambda: core.Cylinder()), ("punch 0.5", lambda: core.Punch(flat=0.5)),
             ("punch 0.8", lambda: core.Punch(flat=0.8))]
    grids = [1 / 40] if quick else [1 / 40, 0.02 / 1.709082, 1 / 160]  # the default, the paper's (eq 17), finer
    print(f"w = 0.3, ft = 0.9 ft_lim (shakedown) and 1.1 ft_lim (ratcheting), 10 periods, no periodic copy; "
          f"normal solve on dx/{NORMAL_REFINE}; median of {repeat}")
    print(f"{'body':10} {'dx':>7} {'ft/lim':>6} {'steps':>6} {'exact s':>8} {'num s':>8} {'ratio':>6} "
          f"{'cpu ratio':>9} {'CG it':>6} {'solve s':>8} {'max|d inc|':>10} {'cached':>7}")
    for name, make in cases:
        lim = float(core.ft_limit(0.3, body=make()))
        for dx in grids:
            for f in (0.9, 1.1):
                kw = dict(periods=10, dx=dx, detect_periodic=False)
                te, ce, ex = _timed(fresh(lambda: core.simulate_cycles(f * lim, 0.3, body=make(), normal="exact",
                                                                       **kw)), repeat)
                tn, cn, nu = _timed(fresh(lambda: core.simulate_cycles(f * lim, 0.3, body=make(), normal="numerical",
                                                                       **kw)), repeat)
                tc, _, _ = _timed(lambda: core.simulate_cycles(f * lim, 0.3, body=make(), normal="numerical", **kw),
                                  repeat)
                ts, _, (edges, sol) = _timed(lambda: make().solve_normal(dx, refine=NORMAL_REFINE), repeat)
                d = np.abs(nu.increment_per_period - ex.increment_per_period).max()
                d /= np.abs(ex.increment_per_period).max()
                print(f"{name:10} {dx:7.4f} {f:6.1f} {len(ex.xc):6d} {te:8.3f} {tn:8.3f} {tn / te:6.2f} "
                      f"{cn / ce:9.2f} {sol.iterations:6d} {ts:8.4f} {d:10.2e} {tc / te:7.2f}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
