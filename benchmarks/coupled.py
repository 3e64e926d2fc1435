"""Coupled contact (issue 32): the rocking cylinder of dissimilar materials, measured, and the cost of coupling.

Three parts, each printed and written to ``benchmarks/results/coupled_<part>.txt``:

* ``timing``: the rocking cylinder at ``a/40`` for 20 periods (``w = 0.6``,
  ``ft`` at eq 35), uncoupled against coupled (``beta = 0.25``, ``mu = 0.3``):
  CPU and wall time, steps solved (a repeated period is copied), active-set
  iterations, the alternations of the normal and tangential solves per step and
  the direct solves of a step with its sets fixed;
* ``runs``: ``beta = 0, +-0.1, +-0.25`` (``mu = 0.3``), ``w = 0.3, 0.6``, ``ft``
  from 0.6 to 1.2 times eq 35: the increment and the energy of the last period
  (the steady ones when a period repeats), the regime, the period from which
  the state repeated;
* ``limits``: the coupled limit in ``ft`` at ``w = 0.3`` and ``0.6``, bisected on
  the regime (shakedown or cyclic slip below, ratcheting above; an undetermined
  run is repeated with twice the periods, up to 80) and set against eq 35 and
  the issue's CONTACT figures; and the same limit found by the project's own
  search in ``w`` (:func:`core.numerical_limit`, ``shakedown limit --beta``) at
  the ``ft`` eq 35 puts at ``w = 0.6``.

Wall times on shared cores are noisy: the CPU time (``time.process_time``) is
the steadier figure, and the step and alternation counts say where it goes.

Run: python benchmarks/coupled.py [--quick] [--parts timing,runs,limits]
"""

from __future__ import annotations

import argparse
import io
import os
import sys
import time
from contextlib import redirect_stdout
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).resolve().parent / "results"
MU = 0.3
BETAS = (0.0, 0.1, -0.1, 0.25, -0.25)
AMPLITUDES = (0.3, 0.6)
FRACTIONS = (0.6, 0.8, 0.9, 1.0, 1.05, 1.1, 1.2)
#: The issue's CONTACT figures: the fall of the limit below eq 35 at (|beta|, w).
CONTACT_FALL = {(0.25, 0.6): 0.25, (0.25, 0.3): 0.08, (0.1, 0.6): 0.04, (0.1, 0.3): 0.01}


def _alternations():
    """Count the coupled solver's alternations, full tangential solves and direct solves per solved step (a wrapper
    around its ``march``, which records them in the trajectory's ``alternations``, ``full_solves`` and
    ``direct_solves``)."""
    import core.solvers.coupled as cc

    counts = []
    if not hasattr(cc.CoupledSolver, "_bench_march"):
        cc.CoupledSolver._bench_march = cc.CoupledSolver.march

        def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out):
            done = self._bench_march(bounds, Q, period, load_scale, k0, k1, detect_periodic, out)
            cc.CoupledSolver._bench_counts.extend(zip(out.alternations[k0:done[0]].tolist(),
                                                      out.full_solves[k0:done[0]].tolist(),
                                                      out.direct_solves[k0:done[0]].tolist()))
            return done
        cc.CoupledSolver.march = march
    cc.CoupledSolver._bench_counts = counts
    return counts


#: The timing's runs: the uncoupled reference first.
TIMED = (("uncoupled (dense)", {}), ("coupled beta=+0.25", dict(beta=0.25, mu=MU)),
         ("coupled beta=-0.25", dict(beta=-0.25, mu=MU)), ("coupled beta=+0.1", dict(beta=0.1, mu=MU)),
         ("coupled beta=-0.1", dict(beta=-0.1, mu=MU)))


def timing(quick: bool, repeats: int | None = None) -> None:
    import core

    repeats = repeats or (3 if quick else 9)
    ft = float(core.ft_limit(0.6))
    core.simulate_cycles(ft, 0.6, periods=2, beta=0.25, mu=MU)  # compile and warm both paths
    core.simulate_cycles(ft, 0.6, periods=2)
    print(f"rocking cylinder, w = 0.6, ft = eq 35 = {ft:.4f}, dx = a/40, 20 periods, mu = {MU}; each run {repeats} "
          f"times, interleaved (every run once, then again): the least CPU time and the median")
    print(f"{'run':<22} {'cpu min [s]':>11} {'median':>7} {'steps solved':>13} {'mean it/step':>13} "
          f"{'passes/step':>12} {'full/step':>10} {'direct/step':>12} {'regime':>11}")
    cpu = {label: [] for label, _ in TIMED}
    last = {}
    for _ in range(repeats):
        for label, kw in TIMED:
            counts = _alternations()
            c0 = time.process_time()
            r = core.simulate_cycles(ft, 0.6, periods=20, **kw)
            cpu[label].append(time.process_time() - c0)
            last[label] = (r, list(counts))
    rows = {}
    for label, _ in TIMED:
        r, counts = last[label]
        solved = len(r.xc) if r.periodic_from is None else int(np.flatnonzero(r.period == r.periodic_from)[-1] + 1)
        passes = f"{np.mean([c[0] for c in counts]):.2f}" if counts else "-"
        full = f"{np.mean([c[1] for c in counts]):.2f}" if counts else "-"
        direct = f"{np.mean([c[2] for c in counts]):.2f}" if counts else "-"
        best = min(cpu[label])
        print(f"{label:<22} {best:>11.4f} {np.median(cpu[label]):>7.4f} {solved:>13d} "
              f"{np.mean(r.iterations[:solved]):>13.2f} {passes:>12} {full:>10} {direct:>12} {r.regime:>11}")
        rows[label] = (best, float(np.median(cpu[label])), solved)
    base = rows["uncoupled (dense)"]
    for label, (best, median, solved) in rows.items():
        if label != "uncoupled (dense)":
            print(f"{label}: {best / base[0]:.2f} x the uncoupled run's least CPU time, {median / base[1]:.2f} x its "
                  f"median ({best / solved * 1e3:.3f} ms a solved step against {base[0] / base[2] * 1e3:.4f} ms; "
                  f"target <= 3 x)")


def _run(ft, w, beta, periods=20):
    import core

    kw = dict(beta=beta, mu=MU) if beta else {}
    return core.simulate_cycles(ft, w, periods=periods, **kw)


def runs(quick: bool) -> None:
    import core

    fractions = (0.8, 1.0, 1.2) if quick else FRACTIONS
    print(f"rocking cylinder, dx = a/40, 20 periods, mu = {MU}; increments [mu P/E*], energies [mu^2 P^2/E*] of the "
          "last period (steady when the state repeats from 'rep')")
    print(f"{'beta':>6} {'w':>4} {'ft/eq35':>8} {'ft':>7} {'increment':>11} {'energy':>11} {'regime':>13} "
          f"{'rep':>4} {'cpu [s]':>8}")
    for w in AMPLITUDES:
        eq35 = float(core.ft_limit(w))
        for beta in BETAS:
            for f in fractions:
                c0 = time.process_time()
                r = _run(f * eq35, w, beta)
                s = r.summary()
                rep = "-" if r.periodic_from is None else str(r.periodic_from)
                print(f"{beta:>6.2f} {w:>4.1f} {f:>8.2f} {f * eq35:>7.4f} {s['increment_last_period']:>11.4g} "
                      f"{s['energy_last_period']:>11.4g} {s['regime']:>13} {rep:>4} {time.process_time() - c0:>8.2f}",
                      flush=True)


def _ratchets(ft, w, beta, log):
    """Whether the run ratchets (an undetermined run is repeated with twice the periods, up to 80)."""
    periods = 20
    while True:
        r = _run(ft, w, beta, periods)
        if r.regime != "undetermined" or periods >= 80:
            break
        periods *= 2
    log.append((ft, r.regime, periods))
    return r.regime not in ("shakedown", "cyclic slip")


def coupled_limit(w, beta, tol=0.005, lo=0.5, hi=1.2):
    """The limit in ``ft`` at ``w``, as a fraction of eq 35, bisected on the regime: ``(lo, hi, runs)``."""
    import core

    eq35 = float(core.ft_limit(w))
    log = []
    if _ratchets(lo * eq35, w, beta, log) or not _ratchets(hi * eq35, w, beta, log):
        return float("nan"), float("nan"), log
    while hi - lo > 2 * tol:
        mid = 0.5 * (lo + hi)
        if _ratchets(mid * eq35, w, beta, log):
            hi = mid
        else:
            lo = mid
    return lo, hi, log


def limits(quick: bool) -> None:
    import core

    betas = (0.25, -0.25) if quick else BETAS
    tol = 0.02 if quick else 0.005
    print(f"the limit in ft at fixed w, bisected on the regime (tol {tol} of eq 35), dx = a/40, mu = {MU}")
    print(f"{'beta':>6} {'w':>4} {'eq 35':>7} {'limit/eq35 in':>17} {'fall':>7} {'CONTACT fall':>13} {'runs':>5} "
          f"{'most periods':>13} {'cpu [s]':>8}")
    for w in AMPLITUDES:
        for beta in betas:
            c0 = time.process_time()
            lo, hi, log = coupled_limit(w, beta, tol)
            fall = 1 - 0.5 * (lo + hi)
            contact = CONTACT_FALL.get((abs(beta), w))
            print(f"{beta:>6.2f} {w:>4.1f} {float(core.ft_limit(w)):>7.4f} {f'[{lo:.3f}, {hi:.3f}]':>17} "
                  f"{fall:>7.1%} {'-' if contact is None else f'~{contact:.0%}':>13} {len(log):>5} "
                  f"{max(p for _, _, p in log):>13} {time.process_time() - c0:>8.1f}", flush=True)
    # the project's own search (shakedown limit --beta): bisection in w at the ft of eq 35 at w = 0.6
    ft = float(core.ft_limit(0.6))
    for beta in (0.25, -0.25):
        c0 = time.process_time()
        res = core.numerical_limit(ft, tol=0.01, periods=20, beta=beta, mu=MU)
        print(f"core.numerical_limit(ft={ft:.4f}, beta={beta:+g}, mu={MU}, tol=0.01, periods=20): w in "
              f"[{res.w_shakedown:.4f}, {res.w_ratcheting:.4f}] (eq 35: {res.w_limit_eq35:.4f}, the uncoupled "
              f"reference), {len(res.runs)} runs, {time.process_time() - c0:.1f} s cpu: {res.message}", flush=True)


PARTS = {"timing": timing, "runs": runs, "limits": limits}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer points and a coarser limit tolerance")
    ap.add_argument("--parts", default="timing,runs,limits", help="comma-separated parts (timing, runs, limits)")
    ap.add_argument("--no-write", action="store_true", help="print only")
    args = ap.parse_args(argv)
    for part in args.parts.split(","):
        buf = io.StringIO()

        class Tee(io.TextIOBase):
            def write(self, s):
                sys.__stdout__.write(s)
                sys.__stdout__.flush()
                return buf.write(s)

        with redirect_stdout(Tee()):
            print(f"# benchmarks/coupled.py {part}{' --quick' if args.quick else ''}: "
                  f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, cores={os.cpu_count()}")
            PARTS[part](args.quick)
        if not args.no_write:
            RESULTS.mkdir(exist_ok=True)
            (RESULTS / f"coupled_{part}{'_quick' if args.quick else ''}.txt").write_text(buf.getvalue())


if __name__ == "__main__":
    main()
