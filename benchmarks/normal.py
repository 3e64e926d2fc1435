"""Cost of the numerical normal solve against the closed-form pressure, for the translating line bodies.

A body that only translates carries its static pressure along, so
``normal="numerical"`` solves the normal problem once per normal load (on a
line: the direct active set of :mod:`core.pressure.normal`, on elements
:data:`core.geometry.bodies.NORMAL_REFINE` times finer than the run's) and then
shifts it: its run should cost at most 1.2x the closed form's. Every run
starts with the pressure tables cleared (``core.geometry.bodies.clear_tables``), so the
solve is inside the time; the exact and the numerical runs alternate (so
that a change of the machine's load hits both), and each figure is the
median of ``repeat`` runs. Printed per body and grid: the median wall and CPU
time of both runs, their ratios (wall, CPU), the normal solve alone (its
method, the contact sets or CG iterations of its fine level, its time, and
the time of the conjugate-gradient solve it replaces), the largest difference
of the increments per period (relative to the largest), and the last column
the wall ratio of a repeated run of an equal body, which reuses the solved
pressure (as the runs of a sweep do).

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


def _alternated(fns, repeat):
    """Median wall and CPU time of each of ``fns``, run in turn ``repeat`` times (and each output)."""
    walls = [[] for _ in fns]
    cpus = [[] for _ in fns]
    outs = [None] * len(fns)
    for _ in range(repeat):
        for k, fn in enumerate(fns):
            w0, c0 = time.perf_counter(), time.process_time()
            outs[k] = fn()
            walls[k].append(time.perf_counter() - w0)
            cpus[k].append(time.process_time() - c0)
    return [(statistics.median(w), statistics.median(c), o) for w, c, o in zip(walls, cpus, outs)]


def main(quick=False):
    import core
    from core.geometry.bodies import NORMAL_REFINE, clear_tables

    def fresh(fn):
        def call():
            clear_tables()
            return fn()
        return call

    core.simulate_cycles(0.2, 0.3, periods=1, dx=0.1)  # compile / load the cache
    repeat = 11 if quick else 9
    cases = [("cylinder", lambda: core.Cylinder()), ("punch 0.5", lambda: core.Punch(flat=0.5)),
             ("punch 0.8", lambda: core.Punch(flat=0.8))]
    grids = [1 / 40] if quick else [1 / 40, 0.02 / 1.709082, 1 / 160]  # the default, the paper's (eq 17), finer
    print(f"w = 0.3, ft = 0.9 ft_lim (shakedown) and 1.1 ft_lim (ratcheting), 10 periods, no periodic copy; "
          f"normal solve on dx/{NORMAL_REFINE}; exact and numerical runs alternated, median of {repeat}; "
          "times in ms")
    print(f"{'body':10} {'dx':>7} {'ft/lim':>6} {'steps':>6} {'exact':>7} {'num':>7} {'ratio':>6} "
          f"{'cpu ratio':>9} {'method':>7} {'it':>4} {'solve':>7} {'CG solve':>8} {'max|d inc|':>10} {'cached':>7}")
    for name, make in cases:
        lim = float(core.ft_limit(0.3, body=make()))
        for dx in grids:
            kw = dict(periods=10, dx=dx, detect_periodic=False)
            for mode in ("exact", "numerical"):  # warm: grids and kernels of this dx compiled / cached once
                core.simulate_cycles(0.9 * lim, 0.3, body=make(), normal=mode, **kw)
            for f in (0.9, 1.1):
                (te, ce, ex), (tn, cn, nu) = _alternated(
                    [fresh(lambda: core.simulate_cycles(f * lim, 0.3, body=make(), normal="exact", **kw)),
                     fresh(lambda: core.simulate_cycles(f * lim, 0.3, body=make(), normal="numerical", **kw))],
                    repeat)
                (te2, _, _), (tc, _, _) = _alternated(
                    [lambda: core.simulate_cycles(f * lim, 0.3, body=make(), normal="exact", **kw),
                     lambda: core.simulate_cycles(f * lim, 0.3, body=make(), normal="numerical", **kw)], repeat)
                ts, _, (edges, sol) = _timed(lambda: make().solve_normal(dx, refine=NORMAL_REFINE), repeat)
                tcg, _, (_, cg) = _timed(lambda: make().solve_normal(dx, refine=NORMAL_REFINE, method="cg"), repeat)
                d = np.abs(nu.increment_per_period - ex.increment_per_period).max()
                d /= np.abs(ex.increment_per_period).max()
                print(f"{name:10} {dx:7.4f} {f:6.1f} {len(ex.xc):6d} {1e3 * te:7.2f} {1e3 * tn:7.2f} {tn / te:6.2f} "
                      f"{cn / ce:9.2f} {sol.method:>7} {sol.iterations:4d} {1e3 * ts:7.2f} {1e3 * tcg:8.2f} "
                      f"{d:10.2e} {tc / te2:7.2f}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
