"""The coupled limit curve ft_lim(w) (issue 32): what one costs, and the table the docs gallery draws.

Two parts, printed and written to ``benchmarks/results/``:

* ``cost``: one curve of the explorer's grid (:data:`app.runs.LIMIT_CURVE_GRID`'s values: five ``w`` from 0.1 to
  0.9, ``dx = a/20``, brackets 2 % of eq 35, 20 periods) at ``beta = 0.25``, ``mu = 0.3``, and the same at
  ``a/40``: CPU time, wall time, runs, the most periods a run needed
  (``coupled_limit_curve_cost.txt``);
* ``table``: the curves for ``beta = +-0.1, +-0.25`` (``mu = 0.3``) at ``w = 0.1, 0.3, 0.5, 0.6, 0.7, 0.9``, ``a/20``,
  brackets 2 % of eq 35: one row per ``(beta, w)`` with the bracket, eq 35 and the runs
  (``coupled_limit_curve.csv``, read by ``examples/plot_coupled_limit.py``: computing it takes minutes, the
  docs build seconds).

CPU time (``time.process_time``) is the steady figure on shared cores; the load average is printed beside it.

Run: python benchmarks/coupled_limit_curve.py [--parts cost,table] [--no-write]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
MU = 0.3
BETAS = (0.1, -0.1, 0.25, -0.25)
AMPLITUDES = (0.1, 0.3, 0.5, 0.6, 0.7, 0.9)
GRID = dict(dx=1 / 20, tol=0.02, periods=20)
#: The explorer's curve (app.runs.LIMIT_CURVE_GRID): five amplitudes.
EXPLORER_W = (0.1, 0.3, 0.5, 0.7, 0.9)


def _load() -> str:
    return "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg())


def cost(write: bool) -> None:
    import core

    core.simulate_cycles(0.2, 0.5, periods=2, dx=1 / 20, beta=0.25, mu=MU, kernel="plane")  # compiled, warm
    lines = [f"# benchmarks/coupled_limit_curve.py cost: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
             f"cores={os.cpu_count()}",
             f"one coupled limit curve, beta = 0.25, mu = {MU}, w = {EXPLORER_W}, brackets 2 % of eq 35, 20 periods",
             f"{'dx':>6} {'cpu [s]':>8} {'wall [s]':>9} {'runs':>5} {'most periods':>13} {'cpu/run [s]':>12}  load"]
    print("\n".join(lines), flush=True)
    for dx in (1 / 20, 1 / 40):
        load = _load()
        c0, w0 = time.process_time(), time.perf_counter()
        curve = core.coupled_limit_curve(0.25, MU, EXPLORER_W, **{**GRID, "dx": dx})
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        most = max(r[2] for p in curve.points for r in p.runs)
        line = (f"  a/{round(1 / dx):<3} {cpu:>8.2f} {wall:>9.2f} {curve.runs:>5} {most:>13} "
                f"{cpu / curve.runs:>12.3f}  {load} -> {_load()}")
        lines.append(line)
        print(line, flush=True)
        for p in curve.points:
            line = (f"      w = {p.w:.1f}: ft_lim in [{p.ft_shakedown:.4f}, {p.ft_ratcheting:.4f}], eq 35 "
                    f"{p.ft_eq35:.4f}, fall {p.fall:6.1%}, {len(p.runs)} runs, {p.cpu_s:.2f} s cpu")
            lines.append(line)
            print(line, flush=True)
    if write:
        (RESULTS / "coupled_limit_curve_cost.txt").write_text("\n".join(lines) + "\n")


def table(write: bool) -> None:
    import pandas as pd

    import core

    rows = []
    c0 = time.process_time()
    for beta in BETAS:
        curve = core.coupled_limit_curve(beta, MU, AMPLITUDES, **GRID)
        for p in curve.points:
            rows.append(dict(beta=beta, mu=MU, w=p.w, ft_shakedown=p.ft_shakedown, ft_ratcheting=p.ft_ratcheting,
                             ft_limit=p.ft_limit, ft_eq35=p.ft_eq35, fall=p.fall, converged=p.converged,
                             runs=len(p.runs), most_periods=max(r[2] for r in p.runs), cpu_s=round(p.cpu_s, 3),
                             dx=GRID["dx"], tol=GRID["tol"], periods=GRID["periods"]))
            print(f"beta {beta:+.2f} w {p.w:.1f}: [{p.ft_shakedown:.4f}, {p.ft_ratcheting:.4f}] eq 35 "
                  f"{p.ft_eq35:.4f} fall {p.fall:6.1%} ({len(p.runs)} runs, {p.cpu_s:.1f} s)", flush=True)
    print(f"table: {len(rows)} limits, {time.process_time() - c0:.1f} s cpu, {_load()}")
    if write:
        df = pd.DataFrame(rows)
        out = RESULTS / "coupled_limit_curve.csv"
        with out.open("w") as f:
            f.write(f"# benchmarks/coupled_limit_curve.py table: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}"
                    f"; the coupled limit ft_lim(w) by core.coupled_limit_curve, bracket 2 % of eq 35, a/20\n")
            df.to_csv(f, index=False, float_format="%.6g")


PARTS = {"cost": cost, "table": table}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parts", default="cost,table", help="comma-separated parts (cost, table)")
    ap.add_argument("--no-write", action="store_true", help="print only")
    args = ap.parse_args(argv)
    for part in args.parts.split(","):
        PARTS[part](not args.no_write)


if __name__ == "__main__":
    main()
