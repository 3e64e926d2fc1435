"""Time the cycle solver: the paper's heaviest case, and how the time grows with the grid.

Prints the compile/cache-load time separately from warm runs, and the step and
iteration counts beside every wall time, so that an algorithmic regression can
be told from machine noise. Both per-step solvers of :data:`core.march.engine.STEP_SOLVERS`
are timed: the dense stick-set inverse (``solver="dense"``) and the matrix-free
one (``solver="fft"``, :mod:`core.solvers.matrix_free`), with their active-set and CG
iterations per step, the fitted exponent of each, and the crossover that
``solver="auto"`` uses (:data:`core.march.engine.AUTO_CROSSOVER`), checked at every
size printed, and the error bars of :func:`core.converged_increment` (Richardson
from a/40 and a/80 against a/400). Wall and CPU times are both printed: on
shared cores the CPU time (``time.process_time``) is the steadier figure.

Run: python benchmarks/solver.py [--quick] [--solvers-only]
"""

import math
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
    times, cpus = [], []
    for _ in range(3 if quick else 10):
        t, c = time.perf_counter(), time.process_time()
        r = core.simulate_cycles(**HEAVY)
        times.append(time.perf_counter() - t)
        cpus.append(time.process_time() - c)
    n = r.edges.size - 1
    print(f"\nheaviest case ft=0.08 w=0.77, dx=dW=a/{1 / HEAVY['dx']:.2f}, 10 periods: {n} elements, "
          f"{r.xc.size} steps, {int(r.iterations.sum())} active-set iterations "
          f"(max {int(r.iterations.max())}/step), worst KKT residual {r.max_kkt_residual:.1e}")
    print(f"  warm wall time: best {min(times) * 1e3:.1f} ms, median {np.median(times) * 1e3:.1f} ms; "
          f"CPU best {min(cpus) * 1e3:.1f} ms (target <= 100 ms; the paper's CONTACT needs about 3 s)  "
          f"solver={r.solver} regime={r.regime}")
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
          f"(steps ~ n; a step is O(L h + n log n) on the contact interval's inverse, so about n^2)")


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


def _fft_march_any_size(schedule, n, dx, first=8):
    """The engine's matrix-free solver marched over ``schedule`` on ``n`` elements (any size up to
    core.geometry.bodies.MAX_FFT_ELEMENTS). Returns (wall [s] of the steps after the first ``first``, CPU [s] of
    them, the Trajectory)."""
    from core.base._hertz import element_means
    from core.solvers.dense import Trajectory
    from core.march.engine import STEP_SOLVERS
    from core.elastic.operators import FFTOperator

    edges = dx * (np.arange(n + 1) - n // 2)
    steps = len(schedule)
    out = Trajectory(steps, n)
    a = np.sqrt(schedule.P)  # half-width and peak pressure of the Hertz contact (eq 5)
    bounds = element_means(edges, schedule.xc, a, a)
    solver = STEP_SOLVERS["fft"](FFTOperator(n, dx), element_size=dx, tol=1e-10, maxiter=50 + 2 * n)
    scale = 0.5 * np.pi / dx
    solver.march(bounds, schedule.Q, schedule.period, scale, 0, first, False, out)
    t, c = time.perf_counter(), time.process_time()
    done, _, failed = solver.march(bounds[first:], schedule.Q, schedule.period, scale, first, steps, False, out)
    wall, cpu = time.perf_counter() - t, time.process_time() - c
    if failed >= 0:
        raise RuntimeError(f"matrix-free step {failed} failed (residuals {solver.residuals})")
    return wall, cpu, out


def _line(r):
    solved = r.iterations > 0
    return (f"{r.runtime:8.3f} s  solver={r.solver}, {r.xc.size} steps ({int(solved.sum())} not settled by the "
            f"zero increment), per such step: {r.iterations[solved].mean():.2f} active-set, "
            f"{r.cg_iterations[solved].mean():.1f} CG iterations; worst KKT residual {r.max_kkt_residual:.1e}")


def _steady_cost(schedule, dx, solver, first=8):
    """CPU time per step [s] after the first ``first`` steps (the dense solver builds its inverses in step 0)."""
    import core

    marks = []
    core.solve_schedule(schedule, dx, solver=solver, detect_periodic=False, chunk=first,
                        progress=lambda f: marks.append(time.process_time()))
    return (marks[-1] - marks[0]) / (len(schedule) - first)


def _best(fn, reps):
    """The run with the smallest runtime out of ``reps`` (the machine is shared: the minimum is the figure),
    and the smallest CPU time of the runs."""
    runs, cpus = [], []
    for _ in range(reps):
        c = time.process_time()
        runs.append(fn())
        cpus.append(time.process_time() - c)
    return min(runs, key=lambda r: r.runtime), min(cpus)


def solvers(quick: bool = False) -> None:
    import core
    from core.march.engine import AUTO_CROSSOVER, select_solver

    reps = 2 if quick else 3
    print("\n=== per-step solvers: dense (interval / stick-set inverses) vs matrix-free (active set + PCG, FFT products) ===")
    # (a) the paper's heaviest case, (b) the same at dx = a/400: "auto" runs the solver it picks
    # (outside --quick both solvers run both cases, best of `reps`; (d) compares them step by step)
    for label, case, n_reps in (("(a)", HEAVY, reps), ("(b)", {**HEAVY, "dx": 1 / 400}, reps)):
        n = core.api.solver.make_grid(_heavy_schedule(case["dx"]).reach, case["dx"]).size - 1
        pick = select_solver("auto", n).name
        timed = {solver: _best(lambda: core.simulate_cycles(**case, solver=solver), n_reps)
                 for solver in (("dense", "fft") if label == "(a)" or not quick else (pick,))}
        runs = {solver: r for solver, (r, _) in timed.items()}
        auto = runs[pick]  # what solver="auto" runs at this size (the same call)
        assert label == "(b)" or core.simulate_cycles(**case).solver == pick
        target = "0.1 s" if label == "(a)" else "4 s"
        print(f"{label} heaviest case ft={case['ft']} w={case['w']} {case['periods']} periods, dx = dW = "
              f"a/{1 / case['dx']:.2f}: {n} elements, {auto.xc.size} steps, best of {n_reps}")
        print(f"    auto picks {pick}: {auto.runtime:.3f} s wall, {timed[pick][1]:.3f} s CPU (target <= {target}), "
              f"regime {auto.regime}, periodic from {auto.periodic_from}")
        for solver, r in runs.items():
            print(f"    {solver:5s} {_line(r)} (CPU {timed[solver][1]:.3f} s)")
    # (c) the matrix-free solver's cost per step against n
    sizes = [500, 1000, 2000, 4000] if quick else [500, 1000, 2000, 4000, 8000]
    print("(c) matrix-free cost per step (heaviest case, dW = dx, 40 rocking steps after the loading and 7 "
          f"warm-up steps; best of {reps}; CPU time)")
    print("  elements   us/step (CPU)  us/step (wall)  active-set/step  CG/step")
    rows = []
    for n in sizes:
        dx = 2 * 1.77 / n
        sched = _heavy_schedule(dx, periods=1, rocking_steps=40)
        runs = [_fft_march_any_size(sched, n, dx) for _ in range(reps)]
        steps = len(sched) - 8
        cpu, wall = min(r[1] for r in runs) / steps, min(r[0] for r in runs) / steps
        out = runs[0][2]
        rows.append((n, cpu))
        print(f"  {n:8d} {cpu * 1e6:14.0f} {wall * 1e6:15.0f} {out.iterations[8:].mean():16.2f} "
              f"{out.cg_iterations[8:].mean():8.1f}")
    ns, cost = np.array(rows).T
    k = np.polyfit(np.log(ns), np.log(cost), 1)[0]
    k_ref = np.polyfit(np.log(ns), np.log(ns * np.log(ns)), 1)[0]
    print(f"  fitted exponent: cost per step ~ n^{k:.2f} (n log n over this range would be n^{k_ref:.2f})")
    # (d) the crossover of the automatic choice
    sizes = [1000, 2000, 3900] if quick else [500, 1000, 1400, 2000, 2800, 3900, 5200, 6400]
    print(f"(d) steady cost per rocking step, both solvers (100 steps after 8 warm-up steps, best of {reps}; "
          f"CPU time); auto picks fft above AUTO_CROSSOVER = {AUTO_CROSSOVER} elements (the dense grid cap)")
    print("  elements  dense us/step  fft us/step  faster  auto picks")
    rows, ok = [], True
    for target in sizes:
        dx = 2 * 1.77 / target
        sched = _heavy_schedule(dx, periods=1, rocking_steps=108)
        n = core.api.solver.make_grid(sched.reach, dx, core.geometry.bodies.MAX_FFT_ELEMENTS).size - 1
        d = min(_steady_cost(sched, dx, "dense") for _ in range(reps)) if n <= core.geometry.bodies.MAX_ELEMENTS else math.inf
        f = min(_steady_cost(sched, dx, "fft") for _ in range(reps))
        faster = "dense" if d <= f else "fft"
        pick = select_solver("auto", n).name
        ok &= pick == faster
        rows.append((n, d, f))
        dense = f"{d * 1e6:14.0f}" if math.isfinite(d) else f"{'(above cap)':>14s}"
        print(f"  {n:8d} {dense} {f * 1e6:12.0f}  {faster:6s}  {pick}{'' if pick == faster else '  <-- WRONG'}")
    n, d, f = np.array(rows).T
    both = np.isfinite(d)
    kd = np.polyfit(np.log(n[both]), np.log(d[both]), 1)[0]
    kf = np.polyfit(np.log(n), np.log(f), 1)[0]
    ratio = np.log(d[both] / f[both])
    cross = None
    for i in range(int(both.sum()) - 1):
        if ratio[i] <= 0 < ratio[i + 1]:
            t = -ratio[i] / (ratio[i + 1] - ratio[i])
            cross = float(np.exp(np.log(n[i]) + t * (np.log(n[i + 1]) - np.log(n[i]))))
    print(f"  fitted exponents of the cost per step: dense n^{kd:.2f}, fft n^{kf:.2f}")
    print("  measured crossover: " + (f"{cross:.0f} elements" if cross is not None else
                                      (f"none up to the dense cap ({core.geometry.bodies.MAX_ELEMENTS}): dense is faster at every size "
                                       "it runs" if ratio[-1] <= 0 else "none in range: fft is faster at every size")))
    print(f"  auto picks the faster solver at every size printed: {ok}")


def error_bars(quick: bool = False) -> None:
    """Richardson's extrapolation from a/40 and a/80 (core.converged_increment) against a run at a/400."""
    import core

    ft, w, periods = 0.58, 0.77, 4
    print(f"\n=== error bars: increment per period at ft={ft} w={w}, {periods} periods ===")
    c = core.converged_increment(ft, w, dx=1 / 80, periods=periods)
    t = time.process_time()
    fine = core.simulate_cycles(ft, w, periods=periods, dx=1 / 400)
    cpu = time.process_time() - t
    value = fine.increment_per_period[-1]
    print(f"  a/80 {c.value:.6g}, a/40 {c.coarse:.6g}: order {c.order:.2f} (clean: {c.clean}), extrapolated "
          f"{c.extrapolated:.6g} +- {c.error:.2g} (estimate)")
    print(f"  a/400 ({fine.solver}, {cpu:.2f} s CPU): {value:.6g}; error of a/80 {abs(c.value - value):.2g}, "
          f"of the extrapolation {abs(c.extrapolated - value):.2g} "
          f"({abs(c.extrapolated - value) / abs(c.value - value):.2f} of a/80's)")

if __name__ == "__main__":
    quick = "--quick" in sys.argv
    if "--solvers-only" not in sys.argv:
        main(quick=quick)
    solvers(quick=quick)
    error_bars(quick=quick)
    if "--no-3d" not in sys.argv:  # the point contacts' two timed cases (issue 10): benchmarks/solver3d.py
        import runpy
        runpy.run_path(os.path.join(os.path.dirname(os.path.abspath(__file__)), "solver3d.py"))["timed_cases"](quick)
