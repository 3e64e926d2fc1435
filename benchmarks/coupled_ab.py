"""Interleaved A/B timing of the coupled solver: two source trees of ``core``, the same runs, taking turns.

Two worker processes, one per tree (``--before DIR``, ``--after DIR``: each a directory holding a ``core``
package, e.g. ``git archive <commit> core | tar -x -C DIR``), compile and warm their kernels, then run the same
rocking-cylinder runs (``a/40``, 20 periods, ``mu = 0.3``) in turn, the order swapped on every pair (AB, BA, ...)
so that a change of the machine's load falls on both. Each run reports its CPU time (``time.process_time``), the
CPU of building its record (``record``: ``CycleResult.__post_init__``, the verdict's fits and the per-period figures
made after the solve; the table gives the ratio of the solves alone too), wall
time, steps solved (a repeated period is copied), mean active-set iterations and alternations (normal/tangential
passes) per solved step, regime, last period's increment and energy, the worst residual and the load average
when it ended; one JSON line a run in ``--out``. ``--table`` formats such a file (the CPU of each run, the ratio
to the uncoupled run of the same ``w`` and ``ft`` in the same tree, the passes).

Run: python benchmarks/coupled_ab.py --before /tmp/before --after /tmp/after --out ab.jsonl
     python benchmarks/coupled_ab.py --table ab.jsonl
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time

FRACTIONS = (0.6, 0.8, 0.9, 1.0, 1.05, 1.1, 1.2)
BETAS = (0.0, 0.1, -0.1, 0.25, -0.25)


def worker() -> None:
    """Read ``ft w beta periods`` lines, run each, print one JSON line a run."""
    import numpy as np

    import core
    import core.solvers.coupled as cc

    counts, directs = [], []
    if "solve" in cc.CoupledSolver.__dict__:  # a tree whose march calls the per-step Python solve
        solve0 = cc.CoupledSolver.solve

        def solve(self, k, target):
            out = solve0(self, k, target)
            counts.append(out[3])
            return out
        cc.CoupledSolver.solve = solve
    else:  # the compiled march records the alternations in the trajectory
        march0 = cc.CoupledSolver.march

        def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out):
            done = march0(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out)
            counts.extend(out.alternations[k0:done[0]].tolist())
            if hasattr(out, "direct_solves"):
                directs.extend(out.direct_solves[k0:done[0]].tolist())
            return done
        cc.CoupledSolver.march = march
    made = []  # the CPU of building each record (its __post_init__: the verdict's fits, the per-period figures)
    post = getattr(core.CycleResult, "__post_init__", None)
    if post is not None:
        def timed(self):
            c = time.process_time()
            post(self)
            made.append(time.process_time() - c)
        core.CycleResult.__post_init__ = timed
    ft = float(core.ft_limit(0.6))
    core.simulate_cycles(ft, 0.6, periods=2, beta=0.25, mu=0.3)
    core.simulate_cycles(ft, 0.6, periods=2)
    made.clear()
    print(json.dumps({"ready": True}), flush=True)
    for line in sys.stdin:
        ft, w, beta, periods = line.split()
        ft, w, beta, periods = float(ft), float(w), float(beta), int(periods)
        counts.clear()
        directs.clear()
        c0, w0 = time.process_time(), time.perf_counter()
        r = core.simulate_cycles(ft, w, periods=periods, **(dict(beta=beta, mu=0.3) if beta else {}))
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        record = sum(made)
        made.clear()
        solved = len(r.xc) if r.periodic_from is None else int(np.flatnonzero(r.period == r.periodic_from)[-1] + 1)
        s = r.summary()
        print(json.dumps(dict(cpu=cpu, record=record, wall=wall, solved=solved, it=float(np.mean(r.iterations[:solved])),
                              alt=float(np.mean(counts)) if counts else 0.0,
                              direct=float(np.mean(directs)) if directs else 0.0, regime=r.regime,
                              inc=float(s["increment_last_period"]), energy=float(s["energy_last_period"]),
                              rep=r.periodic_from, kkt=float(s["max_kkt_residual"]))), flush=True)


def drive(before: str, after: str, out: str, repeats: int, quick: bool = False) -> None:
    """Start both workers and run every configuration on both, in turns."""
    def start(tree):
        env = dict(os.environ, PYTHONPATH=tree)
        return subprocess.Popen(["nice", "-n", "10", sys.executable, os.path.abspath(__file__), "--worker"],
                                cwd=tree, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                bufsize=1)
    workers = {"before": start(before), "after": start(after)}
    for tag, p in workers.items():
        print(tag, p.stdout.readline().strip(), time.strftime("%H:%M:%S"), flush=True)
    sys.path.insert(0, after)
    import core

    # every configuration once, then again (``repeats`` rounds): a coupled run and the uncoupled run of the same w
    # and ft are neighbours in time, so that a change of the machine's load falls on both
    grid = [(f, w, b) for w in (0.3, 0.6) for f in ((1.0,) if quick else FRACTIONS) for b in BETAS]
    i = 0
    with open(out, "w") as fh:
        for rep in range(repeats):
            for f, w, b in grid:
                cfg = f"{f * float(core.ft_limit(w))!r} {w} {b} 20\n"
                order = ("before", "after") if i % 2 == 0 else ("after", "before")
                i += 1
                for tag in order:
                    workers[tag].stdin.write(cfg)
                    workers[tag].stdin.flush()
                    res = json.loads(workers[tag].stdout.readline())
                    res.update(tag=tag, f=f, w=w, beta=b, rep=rep, order="".join(t[0] for t in order),
                               load=os.getloadavg()[0], time=time.strftime("%H:%M:%S"))
                    fh.write(json.dumps(res) + "\n")
                    fh.flush()


def table(path: str) -> None:
    """Print the runs of ``path``: before/after CPU, ratio to the uncoupled run, passes, and what moved."""
    rows = [json.loads(line) for line in open(path)]
    best = {}
    for r in rows:
        key = (r["tag"], r["w"], r["f"], r["beta"])
        if key not in best or r["cpu"] < best[key]["cpu"]:
            best[key] = r
    loads = [r["load"] for r in rows]
    print(f"{len(rows)} runs from {rows[0]['time']} to {rows[-1]['time']} UTC, load average (1 min) at the runs' "
          f"ends {min(loads):.1f}-{max(loads):.1f} (median {sorted(loads)[len(loads) // 2]:.1f}); CPU: the least of "
          "a configuration's repeats")
    print(f"{'w':>4} {'ft/eq35':>7} {'beta':>6} | {'cpu before':>10} {'x uncpl':>7} {'passes':>6} | {'cpu after':>9} "
          f"{'x uncpl':>7} {'passes':>6} {'direct':>6} {'solve x':>7} | {'speed-up':>8} {'steps':>5} {'it/step':>7} {'regime':>12} "
          f"{'d increment':>11} {'d energy':>9}")
    keys = sorted({k[1:] for k in best}, key=lambda k: (k[0], abs(k[2]) > 0, abs(k[2]), -k[2], k[1]))
    ratios = {"before": [], "after": []}
    solves = {"before": [], "after": []}  # the run less its record (the verdict's fits, the per-period figures)
    least = {}  # the least solve of each configuration
    for r in rows:
        key = (r["tag"], r["w"], r["f"], r["beta"])
        if "record" in r:
            least[key] = min(least.get(key, math.inf), r["cpu"] - r["record"])
    per_step = []
    for w, f, b in keys:
        a, z = best.get(("before", w, f, b)), best.get(("after", w, f, b))
        if a is None or z is None:
            continue
        ua, uz = best.get(("before", w, f, 0.0)), best.get(("after", w, f, 0.0))
        ra = f"{a['cpu'] / ua['cpu']:.1f}" if ua and b else "-"
        rz = f"{z['cpu'] / uz['cpu']:.1f}" if uz and b else "-"
        if b and ua and uz:
            ratios["before"].append(a["cpu"] / ua["cpu"])
            ratios["after"].append(z["cpu"] / uz["cpu"])
            per_step.append((z["cpu"] / z["solved"]) / (uz["cpu"] / uz["solved"]))
            for tag in ("before", "after"):
                if (tag, w, f, b) in least and (tag, w, f, 0.0) in least:
                    solves[tag].append(least[(tag, w, f, b)] / least[(tag, w, f, 0.0)])
        sz = (f"{least[('after', w, f, b)] / least[('after', w, f, 0.0)]:.1f}"
              if b and ("after", w, f, b) in least and ("after", w, f, 0.0) in least else "-")
        print(f"{w:>4} {f:>7.2f} {b:>6.2f} | {a['cpu']:>10.3f} {ra:>7} {a['alt']:>6.2f} | {z['cpu']:>9.3f} {rz:>7} "
              f"{z['alt']:>6.2f} {z.get('direct', 0.0):>6.2f} {sz:>7} | {a['cpu'] / z['cpu']:>8.2f} {z['solved']:>5d} "
              f"{z['it']:>7.2f} {z['regime']:>12} "
              f"{abs(a['inc'] - z['inc']):>11.1e} {abs(a['energy'] - z['energy']):>9.1e}")
    import statistics
    for tag, r in ratios.items():
        if r:
            print(f"{tag}: a coupled run costs {min(r):.1f}-{max(r):.1f} times the uncoupled run of the same w and ft "
                  f"(median {statistics.median(r):.1f}; within 3x in {sum(x <= 3 for x in r)} of {len(r)})")
    for tag, r in solves.items():
        if r:
            print(f"{tag}, the solve alone (a run less the building of its record): {min(r):.1f}-"
                  f"{max(r):.1f} times (median {statistics.median(r):.1f}; within 3x in {sum(x <= 3 for x in r)} "
                  f"of {len(r)})")
    if per_step:
        print(f"after, per solved step: {min(per_step):.1f}-{max(per_step):.1f} times the uncoupled run's "
              f"(median {statistics.median(per_step):.1f}; within 3x in {sum(x <= 3 for x in per_step)} of "
              f"{len(per_step)})")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--before")
    ap.add_argument("--after")
    ap.add_argument("--out", default="coupled_ab.jsonl")
    ap.add_argument("--repeats", type=int, default=3, help="rounds of every configuration (the least CPU is kept)")
    ap.add_argument("--table", help="format a JSON-lines file of runs")
    ap.add_argument("--quick", action="store_true", help="ft at eq 35 only")
    args = ap.parse_args(argv)
    if args.worker:
        worker()
    elif args.table:
        table(args.table)
    else:
        drive(args.before, args.after, args.out, args.repeats, args.quick)


if __name__ == "__main__":
    main()
