"""Time the cycle solver: the paper's heaviest case, and how the time grows with the grid.

Prints the compile/cache-load time separately from warm runs, and the step and
iteration counts beside every wall time, so that an algorithmic regression can
be told from machine noise. Both per-step solvers are timed: the dense
stick-set inverse (``solver="dense"``) and the matrix-free one
(``solver="fft"``, :mod:`core.matrix_free`), with their active-set and CG
iterations per step, the fitted exponent of each, and the crossover that
``solver="auto"`` uses (``core.matrix_free.FFT_CROSSOVER``), checked at every
size printed.

Run: python benchmarks/solver.py [--quick] [--solvers-only]
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


# --------------------------------------------------------------------------
# the two per-step solvers: dense stick-set inverse and matrix-free (FFT + CG)
# --------------------------------------------------------------------------
def _heavy_schedule(dx, periods=10, rocking_steps=None):
    """The heaviest case's schedule at element width dx (dW = dx), optionally cut after some rocking steps."""
    import core

    s = core.rocking_schedule(HEAVY["ft"], HEAVY["w"], periods=periods, dW=dx)
    if rocking_steps is None:
        return s
    k = 1 + rocking_steps
    return core.Schedule(xc=s.xc[:k], P=s.P[:k], Q=s.Q[:k], period=s.period[:k])


def _fft_march(schedule, dx, n=None, detect_periodic=True):
    """Run the matrix-free march over a schedule; return (wall [s], steps solved, its FFTMarch, per-step arrays)."""
    from core.matrix_free import FFTMarch
    from core.solver import make_grid

    if n is None:
        edges = make_grid(schedule.reach, dx)
    else:  # any size, beyond the grid cap of the dense solver
        edges = dx * (np.arange(n + 1) - n // 2)
    n = edges.size - 1
    steps = len(schedule)
    out = (np.empty((steps, n)), np.empty((steps, n), np.int8), np.empty(steps), np.empty(steps),
           np.empty(steps, np.int64), np.empty(steps))
    t = time.perf_counter()
    march = FFTMarch(n, dx)
    done, _, failed, res = march.run(edges, schedule.xc, schedule.P, schedule.Q, schedule.period,
                                     detect_periodic and schedule.is_periodic(), 0, steps, *out)
    wall = time.perf_counter() - t
    if failed >= 0:
        raise RuntimeError(f"matrix-free step {failed} failed (residual {res:.2g})")
    return wall, done, march, out


def _fft_line(wall, done, march, out):
    iters = out[4][:done]
    cg = np.array(march.cg_iterations, float)
    pr = np.array(march.products, float)
    return (f"{wall:8.3f} s  {done} steps solved, per step: {iters.mean():.2f} active-set, {cg.mean():.1f} CG "
            f"iterations, {pr.mean():.1f} FFT products; worst KKT residual {out[5][:done].max():.1e}")


def _steady_cost(schedule, dx, solver, first=8):
    """Wall time per step [s] after the first ``first`` steps (the dense solver builds its inverse in step 0)."""
    import core

    marks = []
    r = core.solve_schedule(schedule, dx, solver=solver, detect_periodic=False, chunk=first,
                            progress=lambda f: marks.append(time.perf_counter()))
    return (marks[-1] - marks[0]) / (len(schedule) - first), r


def solvers(quick: bool = False) -> None:
    import core
    from core.matrix_free import FFT_CROSSOVER, choose_solver

    reps = 2 if quick else 3
    print("\n=== per-step solvers: dense stick-set inverse vs matrix-free (active set + PCG, FFT products) ===")
    # (a) the paper's heaviest case
    s = _heavy_schedule(HEAVY["dx"])
    auto = min(_timed(lambda: core.simulate_cycles(**HEAVY)) for _ in range(reps))
    dense = min(_timed(lambda: core.simulate_cycles(**HEAVY, solver="dense")) for _ in range(reps))
    runs = [_fft_march(s, HEAVY["dx"]) for _ in range(reps)]
    best = min(runs, key=lambda x: x[0])
    n = core.solver.make_grid(s.reach, HEAVY["dx"]).size - 1
    print(f"(a) heaviest case, dx = a/{1 / HEAVY['dx']:.2f}, {n} elements, {len(s)} steps: "
          f"auto ({choose_solver('auto', n)}) {auto * 1e3:.1f} ms (target <= 100 ms), dense {dense * 1e3:.1f} ms")
    print(f"    fft: {_fft_line(*best)}")
    # (b) dx = a/400 on the same case
    dx = 1 / 400
    s = _heavy_schedule(dx)
    n = core.solver.make_grid(s.reach, dx).size - 1
    auto = _timed(lambda: core.simulate_cycles(**{**HEAVY, "dx": dx}))
    r = core.simulate_cycles(**{**HEAVY, "dx": dx}, solver="dense")
    print(f"(b) heaviest case, dx = a/400, {n} elements, {len(s)} steps: auto ({choose_solver('auto', n)}) "
          f"{auto:.2f} s (target <= 4 s), dense {r.runtime:.2f} s ({r.iterations.mean():.2f} active-set "
          f"iterations per step)")
    if quick:
        print("    fft: skipped with --quick")
    else:
        print(f"    fft: {_fft_line(*_fft_march(s, dx))}")
    # (c) the matrix-free solver's cost per step against n
    sizes = [500, 1000, 2000, 4000] if quick else [500, 1000, 2000, 4000, 8000]
    print("(c) matrix-free cost per step (heaviest case, dW = dx, 40 rocking steps after the loading)")
    print("  elements  window   us/step  active-set/step  CG/step  FFT products/step")
    rows = []
    for n in sizes:
        dx = 2 * 1.77 / n
        sched = _heavy_schedule(dx, periods=1, rocking_steps=40)
        per = []
        for _ in range(reps):
            wall, done, march, out = _fft_march(sched, dx, n=n, detect_periodic=False)
            per.append(wall / done)
        cg, pr = np.mean(march.cg_iterations), np.mean(march.products)
        window = int(np.ceil(2 * np.sqrt(sched.P.max()) / dx))
        rows.append((n, min(per)))
        print(f"  {n:8d} {window:7d} {min(per) * 1e6:9.0f} {out[4][:done].mean():16.2f} {cg:8.1f} {pr:12.1f}")
    ns, cost = np.array(rows).T
    k = np.polyfit(np.log(ns), np.log(cost), 1)[0]
    k_ref = np.polyfit(np.log(ns), np.log(ns * np.log(ns)), 1)[0]
    print(f"  fitted exponent: cost per step ~ n^{k:.2f} (n log n over this range would be n^{k_ref:.2f}; "
          f"the dense solver's is n^2 per step)")
    # (d) the crossover of the automatic choice
    sizes = [250, 1000, 2000, 3900] if quick else [250, 500, 1000, 1400, 2000, 2800, 3900]
    print(f"(d) steady cost per rocking step, both solvers (200 steps after 8 warm-up steps); "
          f"auto switches to fft from FFT_CROSSOVER = {FFT_CROSSOVER} elements")
    print("  elements  dense us/step  fft us/step  faster  auto picks")
    rows, ok = [], True
    for target in sizes:
        dx = 2 * 1.77 / target
        sched = _heavy_schedule(dx, periods=1, rocking_steps=208)
        n = core.solver.make_grid(sched.reach, dx).size - 1
        d = min(_steady_cost(sched, dx, "dense")[0] for _ in range(reps))
        f = min(_steady_cost(sched, dx, "fft")[0] for _ in range(reps))
        faster = "dense" if d <= f else "fft"
        pick = choose_solver("auto", n)
        ok &= pick == faster
        rows.append((n, d, f))
        print(f"  {n:8d} {d * 1e6:14.0f} {f * 1e6:12.0f}  {faster:6s}  {pick}{'' if pick == faster else '  <-- WRONG'}")
    n, d, f = np.array(rows).T
    kd = np.polyfit(np.log(n), np.log(d), 1)[0]
    kf = np.polyfit(np.log(n), np.log(f), 1)[0]
    ratio = np.log(d / f)
    cross = None
    for i in range(len(n) - 1):
        if ratio[i] <= 0 < ratio[i + 1]:
            t = -ratio[i] / (ratio[i + 1] - ratio[i])
            cross = float(np.exp(np.log(n[i]) + t * (np.log(n[i + 1]) - np.log(n[i]))))
    print(f"  fitted exponents of the cost per step: dense n^{kd:.2f}, fft n^{kf:.2f}")
    print("  measured crossover: " + (f"{cross:.0f} elements" if cross is not None else
                                      ("none in range: dense is faster at every size" if ratio[-1] <= 0 else
                                       "none in range: fft is faster at every size")))
    print(f"  auto picks the faster solver at every size printed: {ok}")


def _timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    if "--solvers-only" not in sys.argv:
        main(quick=quick)
    solvers(quick=quick)
