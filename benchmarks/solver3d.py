"""The 3D point-contact solver (rocking sphere): timings, Mindlin's error, limit brackets, cylinder vs sphere,
grid convergence.

1. The two timed cases of issue 10 (targets 2.4 s and 27 s warm; the paper's
   program needs about 24 s and 270 s), each with the steps computed, the
   periods copied once the state repeated, and the active-set and CG
   iterations per step, so that an algorithmic regression can be told from
   machine noise. The CPU time is printed beside the wall time: on a shared
   machine it is the figure that depends least on the other processes.
   Measured back to back on 2 shared cores (load average about 3.5), warm:
   a/20 1.53 s CPU, 1.64 s wall (best of 3; 6.1 active-set and 14.8 CG
   iterations per step); a/40 18.8 s CPU, 20.5 s wall (9.5 and 27.7). Before
   the mirror-symmetric products: 2.25 s CPU, 2.58 s wall (6.2 and 16.6) and
   27.2 s CPU, 28.4 s wall (9.6 and 29.2). Issue 21 (cycle fallback, bound from the discrete normal problem),
   measured the same day before and after on the same loaded machine (load average 3.5-6): a/20 1.51 s CPU
   (6.10 and 14.8) before, 1.39-1.45 s CPU (5.46 and 14.3) after; a/40 18.9 s CPU (9.46 and 27.7) before,
   18.9 s CPU (8.54 and 26.8) after (wall times 17-38 s, set by the other processes).
2. Mindlin's static partial slip (c/a = (1 - ft)^(1/3), exact for nu = 0):
   the solver's stick half-widths along x and y, the traction on y = 0 and
   the displacement against the closed form, for nu = 0 and nu = 0.5 (the
   x-y coupling's effect).
3. The sphere's exact limit bracketed by the solver at two amplitudes.
4. Cylinder against sphere, each in its own normalisation (ft = Ft/(mu Fn),
   w = W/a with a the half-width or the radius): exact limits and solver verdicts.
5. Grid convergence of the increment per period of a ratcheting sphere.
6. The increment per period against CONTACT's (ft 0.6, w 0.3) at 20 to 80 elements across the contact, with
   the traction bound from the discrete normal problem (normal="numerical", the default) and from element means
   of Hertz's pressure (normal="exact").
7. The discrete bound's normal solve alone. Since it is core.pressure.normal.solve_normal (one normal solver, issue 21;
   preconditioned by the inverse continuous symbol), measured back to back, twice, at load average 3.4: one
   window 14.3-14.9, 69-71, 466-497 ms at a/20, a/40, a/80 with the bound's own unpreconditioned CG before,
   7.7-7.8, 30, 165-173 ms after (the same pressures to 2e-12); the timed cases of 1: a/20 1.49 s CPU before,
   1.42 s after; a/40 18.9 s and 18.4 s CPU (identical increments and iterations: the solve is a few windows
   a run).
8. A height map (a rough paraboloid; at a/20 a rougher surface, the same rms per sample) on the 3D solver: its
   pressure shifted by whole elements (dW = dx) or solved again per fractional offset (dW = 0.6 dx). A normal
   solve is 17-18 ms (35x35 map, a/10) and 29-61 ms (71x71, a/20) against 0.4-4.5 s for a 10-period run: the
   per-offset solves cost < 7 % of a run, the shift is exact (the discrete problem is translation-invariant).

9. The cone (core.Cone): a frustum (inner 0.5) and a full cone, L/a_m = 10, w = 0.3, 10 % either side of Melan's
   limit on the run's grid, at a/10 and a/20 (see cones()). Measured at load average 3.4: a/10 1.4-1.7 s CPU
   (3605 and 4429 elements, 121 steps, 8-10 active-set and 23-40 CG iterations a step), a/20 17-28 s CPU
   (13195 and 17255 elements, 241 steps). The twist option (issue 20, the cone's third rigid unknown) leaves the
   sphere's path as it was (numba prunes it): the a/20 case of 1, back to back with main after the engine merge,
   1.62 and 1.48 s CPU on main, 1.68 and 1.50 s on the cone branch (load average 5-8), the same iterations per
   step (5.46 and 14.3) and increments equal to 3e-16.

10. Issue 31 item 15: the cone's elements 2.5 times as long along its line as across it (core.geometry.cone.ASPECT). The
   explorer's first run (--defaults) on a 41 x 26 window instead of 101 x 26: 0.96 s CPU (best of 2, load 13);
   1.24 s against 2.82 s with square elements (medians of 10 interleaved runs, load 5-14,
   benchmarks/results/app_bodies_s4.txt); --convergence prints both element shapes (results:
   benchmarks/results/solver3d_cone_s4.txt). The figures of 9 are those of square elements.

Run: python benchmarks/solver3d.py [--quick] [--no-fine] [--cone (the cone's row alone)]
    [--defaults [--convergence] (sphere against cone at the explorer's grid, issue 31)]
"""

import math
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
          f"{best:.2f} s wall, {best_cpu:.2f} s CPU (best of {repeats}), {elements} elements, {r.xc.size} steps, "
          f"{computed} computed (periodic from period {r.periodic_from}); per computed step: active-set iterations "
          f"{active.mean():.2f} (max {active.max()}), CG iterations {r.cg_iterations[:computed].mean():.1f} "
          f"(max {r.cg_iterations.max()}); regime {r.regime}, last increment {r.increment_per_period[-1]:.5f}, "
          f"worst residual {r.max_residual:.1e}")
    return r


def timed_cases(quick=False, fine=True):
    """The two cases of issue 10, after a first call that loads the compiled kernels."""
    import core

    t = time.perf_counter()
    core.simulate_cycles(0.2, 0.3, periods=1, dx=0.25, body="sphere")
    print(f"\npoint contacts: first call (imports, compiled kernels): {time.perf_counter() - t:.2f} s")
    _run(CASES[0], 1 if quick else 3)
    if fine:
        _run(CASES[1], 1)


def mindlin(dx=0.05, fts=(0.3, 0.6)):
    """Mindlin's partial slip against the solver, nu = 0 (exact) and nu = 0.5 (coupled)."""
    from core.api.point_runs import mindlin_state

    print(f"\nMindlin (static, from rest), dx = a/{round(1 / dx)}: c/a exact (1 - ft)^(1/3); displacement "
          "3(2 - nu)/(8(1 - nu)) (1 - (1 - ft)^(2/3)) [mu Fn/(E* a)]")
    print(f"{'nu':>4} {'ft':>4} {'c/a':>7} {'c_x':>7} {'c_y':>7} {'max|qx-Mindlin| y=0':>20} {'max|qy|':>8} "
          f"{'U':>8} {'U Mindlin':>9} {'U error':>8}")
    for nu in (0.0, 0.5):
        for ft in fts:
            r = mindlin_state(ft, dx=dx, nu=nu)
            c = (1 - ft) ** (1 / 3)
            x = r.x
            exact = np.sqrt(np.clip(1 - x**2, 0, None)) - np.sqrt(np.clip(c * c - x**2, 0, None))
            inner = np.abs(x) < 0.9  # edge elements hold means of a square-root profile
            err = np.abs(r.traction[0][r.cut_row] - exact)[inner].max()
            u = 3 * (2 - nu) / (8 * (1 - nu)) * (1 - (1 - ft) ** (2 / 3))
            print(f"{nu:4.1f} {ft:4.1f} {c:7.4f} {r.stick_halfwidth:7.4f} {r.stick_halfwidth_y:7.4f} {err:20.4f} "
                  f"{np.abs(r.traction[1]).max():8.4f} {r.displacement[0]:8.5f} {u:9.5f} "
                  f"{(r.displacement[0] - u) / u:+8.2%}")


def brackets(ft=0.4, amplitudes=(0.3, 0.55), dx=0.1, periods=12):
    """The sphere's exact limit w_lim(ft) between a shaking-down and a ratcheting amplitude."""
    import core

    w_lim = float(core.w_limit(ft, body="sphere"))
    print(f"\nsphere limit bracket: ft = {ft}, exact w_lim = {w_lim:.4f}, dx = a/{round(1 / dx)}, {periods} periods")
    for w in amplitudes:
        r = core.simulate_cycles(ft, w, periods=periods, dx=dx, body="sphere")
        inc = np.abs(r.increment_per_period)
        print(f"  w = {w:.3f} ({'below' if w < w_lim else 'above'} the limit): {r.regime}; increments first "
              f"{inc[0]:.4f}, last {inc[-1]:.2e} ({r.regime_reason})")


def cylinder_vs_sphere(ws=(0.1, 0.3, 0.45, 0.6), check=(0.43, 0.45)):
    """Exact limits of both bodies in their own normalisation, and the two solvers at one point between them."""
    import core

    print("\ncylinder vs sphere, each in its own units (ft = Ft/(mu Fn), w = W/a; a the half-width of the strip or "
          "the radius of the circle):")
    for w in ws:
        fc, fs = float(core.ft_limit(w)), float(core.ft_limit(w, body="sphere"))
        print(f"  w = {w:.2f}: ft_lim cylinder {fc:.4f}, sphere {fs:.4f} -> the {'cylinder' if fc > fs else 'sphere'}"
              " bears more")
    ft, w = check
    cyl = core.simulate_cycles(ft, w, periods=10, dx=1 / 40)
    sph = core.simulate_cycles(ft, w, periods=10, dx=0.1, body="sphere")
    print(f"  solvers at ft = {ft}, w = {w}: cylinder {cyl.regime}, sphere {sph.regime} (limits: cylinder "
          f"{float(core.ft_limit(w)):.4f}, sphere {float(core.ft_limit(w, body='sphere')):.4f})")


def grid_convergence(dxs=(0.2, 0.1, 0.05, 0.025), ft=0.4, w=0.6, periods=5):
    """Increment per period [mu Fn/(E* a)] of a ratcheting sphere against the element size."""
    import core

    print(f"\ngrid convergence: sphere ft={ft}, w={w} (exact limit ft_lim = {float(core.ft_limit(w, body='sphere')):.4f}),"
          f" {periods} periods, nu = 0.5, dW = dx")
    print(f"{'dx [a]':>8} {'elements':>9} {'increment (last period)':>24} {'change':>9} {'time [s]':>9}")
    prev = None
    for dx in dxs:
        r = core.simulate_cycles(ft, w, periods=periods, dx=dx, body="sphere")
        inc = float(r.increment_per_period[-1])
        change = "" if prev is None else f"{inc - prev:+.5f}"
        print(f"{dx:8.3f} {(r.x_edges.size - 1) * (r.y_edges.size - 1):9d} {inc:24.5f} {change:>9} {r.runtime:9.2f}")
        prev = inc


#: CONTACT's steady increment per period [mu Fn/(E* a)] of the rocking sphere (rigid, incompressible half-space),
#: ft 0.6, w 0.3, by elements across the contact diameter (issue 21).
CONTACT_INCREMENT = {40: 2.919e-2, 60: 2.928e-2, 80: 2.933e-2}


def contact_comparison(elements=(20, 40, 60, 80), ft=0.6, w=0.3, periods=10):
    """The increment per period against CONTACT's, with the traction bound from the discrete normal problem (the
    default, as CONTACT) and from the element means of Hertz's pressure (the bound before issue 21)."""
    import core

    print(f"\nagainst CONTACT: sphere ft={ft}, w={w}, {periods} periods, nu = 0.5, dW = dx; increment per period "
          "[1e-2 mu Fn/(E* a)]")
    print(f"{'elements':>8} {'CONTACT':>8} {'discrete p':>11} {'vs CONTACT':>11} {'means of p':>11} {'vs CONTACT':>11}"
          f" {'apart':>7}")
    found = {}
    for n in elements:
        row = []
        for discrete in (True, False):
            inc = float(core.simulate_cycles(ft, w, periods, dx=2 / n, body="sphere",
                                             normal="numerical" if discrete else "exact").increment_per_period[-1])
            found[n, discrete] = inc
            ref = CONTACT_INCREMENT.get(n)
            row.append(f"{100 * inc:11.4f} {'' if ref is None else f'{(inc - ref) / ref:+.2%}':>11}")
        ref = CONTACT_INCREMENT.get(n)
        apart = (found[n, True] - found[n, False]) / found[n, False]
        print(f"{n:8d} {'' if ref is None else f'{100 * ref:.3f}':>8} {row[0]} {row[1]} {apart:+7.2%}")
    # Richardson's extrapolation from three grids halving the element: both bounds tend to one limit, and the
    # distance of each grid's increment from it is that bound's discretization error
    triple = [n for n in elements if 2 * n in elements and 4 * n in elements][:1]
    for n in triple:
        for discrete, name in ((True, "discrete p"), (False, "means of p")):
            f1, f2, f4 = (found[m, discrete] for m in (n, 2 * n, 4 * n))
            ratio = (f2 - f1) / (f4 - f2)
            limit = f4 + (f4 - f2) / (ratio - 1.0)
            errors = ", ".join(f"{m}: {(found[m, discrete] - limit) / limit:+.2%}" for m in (n, 2 * n, 4 * n))
            print(f"  {name}: extrapolated from {n}, {2 * n}, {4 * n} elements (order {math.log2(ratio):.2f}) "
                  f"{100 * limit:.4f}; each grid from it: {errors}")


def normal_solve(dxs=(1 / 20, 1 / 40, 1 / 80)):
    """The discrete bound's normal solve alone (core.geometry.patch._pressure, cache cleared): one window of the sphere."""
    import core.geometry.patch as s3
    from core.theory.point_contact import Ellipsoid

    print("\nthe sphere's discrete normal solve on one window (core.pressure.normal.solve_normal), best of 3:")
    for dx in dxs:
        xe, ye = s3._centred_edges(1.7, dx), s3._centred_edges(1.0, dx)
        best = np.inf
        for _ in range(3):
            s3._NORMAL_CACHE.clear()
            t = time.perf_counter()
            s3._pressure(xe, ye, 0.1 + 0.3 * dx, Ellipsoid(1.0))
            best = min(best, time.perf_counter() - t)
        print(f"  a/{round(1 / dx)}: {1e3 * best:.1f} ms")


def height_maps(quick=False):
    """A rough paraboloid (0.375 r^2 + 0.01 N(0, 1) per sample, P/(E* a)) on the 3D solver, 10 % above its Melan
    limit at w = 0.3: the pressure solved once and shifted (dW = dx) or solved again per fractional offset
    (dW = 0.6 dx), beside the cost of one normal solve."""
    import core
    from core.geometry.heightmap import HeightMap

    print("\nheight map (rough paraboloid), ft = 1.1 ft_lim(0.3), 10 periods:")
    for dx, n in ((0.1, 35),) if quick else ((0.1, 35), (0.05, 71)):
        x = (np.arange(n) - n // 2) * dx
        X, Y = np.meshgrid(x, x)
        heights = 0.375 * (X**2 + Y**2) + 0.01 * np.random.default_rng(7).standard_normal(X.shape)
        m = HeightMap(heights, dx)
        t = time.perf_counter()
        m.solve()
        solve = time.perf_counter() - t
        lim = m.ft_limit(0.3)
        for dW in (dx, 0.6 * dx):
            m = HeightMap(heights, dx)
            t = time.perf_counter()
            r = core.simulate_cycles(1.1 * lim, 0.3, periods=10, body=m, dW=dW)
            print(f"  a/{round(1 / dx)} ({n}x{n} map; one normal solve {1e3 * solve:.0f} ms), dW = {dW / dx:.1f} dx: "
                  f"{time.perf_counter() - t:.2f} s, {1 + len(m._shifted)} normal solves, {r.xc.size} steps, "
                  f"limit {lim:.4f}, last increment {r.increment_per_period[-1]:.5f} ({r.regime})")


def cones(quick=False):
    """The cone's row: a run of the rocking frustum (inner 0.5) and of the full cone (inner 0), L/a_m = 10, w = 0.3,
    10 % either side of Melan's limit on the run's grid, 10 periods, at a/10 and the default a/20: the wall and CPU
    time, the grid, the steps and the iterations per computed step (the twist adds a third rigid unknown)."""
    import core

    print("\ncone (L/a_m = 10, w = 0.3, 10 periods; ft = 0.9 lo and 1.1 hi of the grid's Melan limit [lo, hi]):")
    for inner in (0.5, 0.0):
        for dx in ((0.1,) if quick else (0.1, 0.05)):
            body = core.Cone(inner=inner)
            t = time.perf_counter()
            lim = body.grid_limit(0.3, dx=dx)
            lp = time.perf_counter() - t
            for f, key in ((0.9, "lo"), (1.1, "hi")):
                t, c = time.perf_counter(), time.process_time()
                r = core.simulate_cycles(f * lim[key], 0.3, periods=10, dx=dx, body=body)
                wall, cpu = time.perf_counter() - t, time.process_time() - c
                computed = r.xc.size if r.periodic_from is None else int(
                    np.flatnonzero(r.period == r.periodic_from)[-1]) + 1
                elements = (r.x_edges.size - 1) * (r.y_edges.size - 1)
                print(f"  inner {inner}, dx=a/{round(1 / dx)}: ft {f * lim[key]:.4f} ({f} {key}; limit [{lim['lo']:.4f}, "
                      f"{lim['hi']:.4f}], LP {lp:.2f} s): {wall:.2f} s wall, {cpu:.2f} s CPU, {elements} elements, "
                      f"{r.xc.size} steps, {computed} computed; per step: active-set "
                      f"{r.iterations[:computed].mean():.2f}, CG {r.cg_iterations[:computed].mean():.1f}; {r.regime}, "
                      f"last increment {r.increment_per_period[-1]:.3g} mu Fn/(E* a_m), twist "
                      f"{r.twist_per_period[-1]:.3g} mu Fn/(E* a_m^2) rad, worst residual {r.max_residual:.1e}")


def explorer_defaults(repeats=2):
    """Sphere against cone at the explorer's default grid (a/10 for every point body, ``app.state``), its first
    numerical run (ft 0.32, w 0.5, 10 periods, triangle; the cone: inner 0.5, L/a_m = 10): why the cone costs more
    on the same patch solver. Per run: the grid, the window the steps are solved on (its most frequent shape), the
    padded FFT grid of one operator product and that product's time (half-cost on the sphere: mirror-symmetric),
    the steps, the active-set and CG iterations per step and the CPU time per step (best of ``repeats``)."""
    import collections

    import core
    import core.solvers.solver3d as s3
    from core.elastic.halfspace import HalfSpaceOperator, convolve, convolve_mirror

    print("\nexplorer's default grid (a/10), ft 0.32, w 0.5, 10 periods: sphere against cone (inner 0.5, L/a_m 10)")
    for name, body in (("sphere", "sphere"), ("cone", core.Cone(inner=0.5))):
        core.simulate_cycles(0.32, 0.5, periods=1, dx=0.25, body=body)  # compiled kernels loaded
        windows = collections.Counter()
        solve = s3.solve_increment

        def counted(op, g, *args, **kwargs):
            windows[g.shape] += 1
            return solve(op, g, *args, **kwargs)

        s3.solve_increment = counted
        try:
            best, r = np.inf, None
            for _ in range(repeats):
                windows.clear()
                c = time.process_time()
                r = core.simulate_cycles(0.32, 0.5, periods=10, dx=0.1, body=body)
                best = min(best, time.process_time() - c)
        finally:
            s3.solve_increment = solve
        shape = windows.most_common(1)[0][0]
        op = HalfSpaceOperator(*shape, 0.1, 0.5, 1.0 / np.pi)
        spec = op.spectra()
        mirror = name == "sphere"
        q = np.random.default_rng(1).standard_normal((2,) + shape)
        product = convolve_mirror if mirror else convolve
        product(q, *spec[:5])
        t, n = time.perf_counter(), 300
        for _ in range(n):
            product(q, *spec[:5])
        each = (time.perf_counter() - t) / n
        steps = r.xc.size
        ny, nx = r.y_edges.size - 1, r.x_edges.size - 1
        print(f"  {name:6s}: grid {ny}x{nx} ({ny * nx} "
              f"elements), window {shape[0]}x{shape[1]} ({shape[0] * shape[1]}), FFT grid {spec[3]}x{spec[4]}"
              f"{' (half: mirror)' if mirror else ''}, one product {1e3 * each:.3f} ms; {steps} steps; per step: "
              f"active-set {r.iterations.mean():.2f}, CG {r.cg_iterations.mean():.1f}, "
              f"CPU {1e3 * best / steps:.1f} ms; "
              f"run {best:.2f} s CPU (best of {repeats}); {r.regime}, last increment {r.increment_per_period[-1]:.3g}")


def cone_convergence(ft=0.4041, w=0.5, inner=0.5, dxs=(0.2, 0.125, 0.1, 0.05), dws=(0.2, 0.125, 0.05),
                     squares=(0.1, 0.05)):
    """The cone's increment per period against the grid and the time step, at one ft (the explorer's w = 0.5,
    inner 0.5; ft 0.4041 is 1.1 times the upper Melan limit on the a/10 grid: a ratcheting cone), 10 periods:
    dx at dW = dx (the default) with the default elements (``core.geometry.cone.ASPECT`` times longer along the line than
    across), then the square elements (aspect 1, the grid before issue 31's) at ``squares``, then dW at dx = a/10."""
    import core
    import core.geometry.cone as cone_module

    body = core.Cone(inner=inner)
    default = cone_module.ASPECT
    print(f"\ncone convergence: inner {inner}, w {w}, ft {ft}, 10 periods (increment [mu Fn/(E* a_m)], twist "
          "[mu Fn/(E* a_m^2) rad], energy [(mu Fn)^2/(E* a_m)], last period)")
    rows = ([(dx, None, default) for dx in dxs] + [(dx, None, 1.0) for dx in squares]
            + [(0.1, dW, default) for dW in dws])
    try:
        for dx, dW, aspect in rows:
            cone_module.ASPECT = aspect
            cone_module._grid_limit.cache_clear()  # the run's Melan programme on this grid
            c = time.process_time()
            r = core.simulate_cycles(ft, w, periods=10, dx=dx, dW=dW, body=body)
            print(f"  dx a/{1 / dx:5.2f} x {aspect:g}, dW {dx if dW is None else dW:.4f}: {r.xc.size:4d} steps, "
                  f"{r.y_edges.size - 1:3d}x{r.x_edges.size - 1:3d} elements, {time.process_time() - c:6.2f} s CPU; "
                  f"AS {r.iterations.mean():.2f}, CG {r.cg_iterations.mean():.1f}; {r.regime}, increment "
                  f"{r.increment_per_period[-1]:.6f} (first {r.increment_per_period[0]:.6f}), twist "
                  f"{r.twist_per_period[-1]:.4e}, energy {r.dissipation_per_period[-1]:.4e}", flush=True)
    finally:
        cone_module.ASPECT = default
        cone_module._grid_limit.cache_clear()


def main(quick=False, fine=True):
    timed_cases(quick, fine)
    mindlin(dx=0.1 if quick else 0.05)
    brackets()
    cylinder_vs_sphere()
    grid_convergence(dxs=(0.2, 0.1) if quick else ((0.2, 0.1, 0.05, 0.025) if fine else (0.2, 0.1, 0.05)))
    contact_comparison(elements=(20, 40) if quick else ((20, 40, 60, 80) if fine else (20, 40, 60)))
    normal_solve()
    height_maps(quick)
    cones(quick)


if __name__ == "__main__":
    if "--cone" in sys.argv:  # the cone's row alone
        cones(quick="--quick" in sys.argv)
    elif "--defaults" in sys.argv:  # sphere against cone at the explorer's default grid, and the cone's convergence
        explorer_defaults()
        if "--convergence" in sys.argv:
            cone_convergence()
    else:
        main(quick="--quick" in sys.argv, fine="--no-fine" not in sys.argv)
