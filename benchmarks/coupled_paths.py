"""The history dependence of a coupled contact (issue 32 item 4): ten loading paths, one steady state?

Melan's theorem does not hold with coupling (Dundurs ``beta != 0``): whether a contact shakes down may depend on
the loading history (Klarbring, Ciavarella & Barber 2007). CONTACT's rocking cylinder showed no difference in
the long-run regime or the steady increment within 1 % brackets of the limit over ten loading paths; this
script asks the same of the project's coupled solver. The rocking cylinder at ``w = 0.6``, ``dx = a/40``,
``mu = 0.3``, 20 periods (the periods the limits were bisected with), ``beta = 0, +-0.1, +-0.25``, at ``ft``
0.7, 0.99, 1.01 and 1.3 times the coupled limit (the middle of the bracket in
``benchmarks/results/coupled_limits.txt``; eq 35 at ``beta = 0``), under the ten paths of :data:`PATHS`
(:class:`core.loading.paths.LoadingPath`; every step of a path is in the loading block, so the increments and energies
are those of the 20 periods after it).

Printed per run: the regime, the increment and the energy of the last period (the steady ones when a period
repeats: ``periodic`` gives the period from which it did), the extrapolated ``D_inf``, the CPU time. Then per
``(beta, ft)``: the regimes seen over the paths and the spread of the steady increment and energy (largest minus
smallest over the largest). A second table runs the coupled cases below the limit (0.7 and 0.99 times it) for
:data:`LONG` periods, long enough for most states to repeat: whether the energy of the cyclic micro-slip settles
to one value whatever the path.

Run: python benchmarks/coupled_paths.py [--quick]  (writes benchmarks/results/coupled_paths.txt unless --quick)
"""

from __future__ import annotations

import argparse
import io
import os
import re
import sys
import time
from contextlib import redirect_stdout
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).resolve().parent / "results"
MU, W, PERIODS, DX = 0.3, 0.6, 20, 1 / 40
#: Periods of the second table (below the limit: the micro-slip's energy settled or not).
LONG = 60
BETAS = (0.0, 0.1, -0.1, 0.25, -0.25)
FRACTIONS = (0.7, 0.99, 1.01, 1.3)
#: The ten paths: (name, the path's text or a function of ft giving it).
PATHS = (
    ("P with Q (default)", "default"),
    ("P then Q (P in 10)", "ramp=10"),
    ("together in 10", "order=together,ramp=10"),
    ("together in 40", "order=together,ramp=40"),
    ("first towards -W", "first=-1"),
    ("loaded at +W", "start=+W"),
    ("loaded at -W", "start=-W"),
    ("at +W, first -W", "start=+W,first=-1"),
    ("5 periods at 0.5 ft", lambda ft: f"preload={0.5 * ft:.6g}:{W:g}:5"),
    ("5 periods at 1.2 ft, w 0.3", lambda ft: f"preload={1.2 * ft:.6g}:{W:g}:5+{ft:.6g}:0.3:5"),
)


def coupled_limits(path=RESULTS / "coupled_limits.txt") -> dict:
    """``{(beta, w): (lo, hi)}`` of ``limit / eq 35`` from the limits benchmark's table."""
    rows = re.findall(r"^\s*(-?\d\.\d+)\s+(\d\.\d+)\s+\d\.\d+\s+\[(\d\.\d+), (\d\.\d+)\]", path.read_text(), re.M)
    return {(float(b), float(w)): (float(lo), float(hi)) for b, w, lo, hi in rows}


class _Tee(io.StringIO):
    """Keep what is printed and show it as it comes (a long run's progress)."""

    def write(self, text):
        sys.__stdout__.write(text)
        sys.__stdout__.flush()
        return super().write(text)


def _table(core, limits, eq35, betas, fractions, paths, periods) -> None:
    """One run per (beta, ft, path), printed as it ends, then the summary per (beta, ft)."""
    print(f"{'beta':>6} {'ft/lim':>6} {'ft':>7}  {'path':<28} {'regime':<12} {'increment':>11} {'energy':>11} "
          f"{'D_inf':>11} {'periodic':>8} {'cpu[s]':>6}")
    groups = {}
    for beta in betas:
        lo, hi = limits.get((beta, W), (1.0, 1.0)) if beta else (1.0, 1.0)
        limit = eq35 * 0.5 * (lo + hi)
        for fraction in fractions:
            ft = fraction * limit
            rows = []
            for name, path in paths:
                text = path(ft) if callable(path) else path
                t0 = time.process_time()
                r = core.simulate_cycles(ft, W, periods=periods, dx=DX, beta=beta, mu=MU, path=text)
                cpu = time.process_time() - t0
                inc, energy = float(r.increment_per_period[-1]), float(r.dissipation_per_period[-1])
                rows.append((r.regime, inc, energy, r.periodic_from is not None))
                periodic = "-" if r.periodic_from is None else str(r.periodic_from)
                print(f"{beta:6.2f} {fraction:6.2f} {ft:7.4f}  {name:<28} {r.regime:<12} {inc:11.4e} "
                      f"{energy:11.4e} {r.D_inf:11.4e} {periodic:>8} {cpu:6.1f}", flush=True)
            groups[(beta, fraction)] = rows
    print()
    print(f"per (beta, ft), {periods} periods: the regimes over the paths (how many of each), how many runs reached "
          "a repeating state, and the spread of the last period's increment and energy over the paths, "
          "(max - min) / max; 'of repeated': the energy's spread over the runs whose state repeated (a steady "
          "state, not a transient still decaying)")
    print(f"{'beta':>6} {'ft/lim':>6}  {'regimes':<30} {'repeated':>8} {'increment min..max':>23} {'spread':>7} "
          f"{'energy min..max':>23} {'spread':>7} {'of repeated':>11}")
    for (beta, fraction), rows in groups.items():
        regimes = {}
        for regime, *_ in rows:
            regimes[regime] = regimes.get(regime, 0) + 1
        inc = np.array([abs(r[1]) for r in rows])
        en = np.array([r[2] for r in rows])
        steady = np.array([r[2] for r in rows if r[3]])
        spread = lambda a: (a.max() - a.min()) / a.max() if a.size and a.max() > 0 else 0.0  # noqa: E731
        text = ", ".join(f"{k} x{v}" for k, v in regimes.items())
        repeated = f"{steady.size}/{len(rows)}"
        of_steady = f"{spread(steady):11.1e}" if steady.size > 1 else f"{'-':>11}"
        print(f"{beta:6.2f} {fraction:6.2f}  {text:<30} {repeated:>8} {inc.min():11.3e}..{inc.max():10.3e} "
              f"{spread(inc):7.1e} {en.min():11.3e}..{en.max():10.3e} {spread(en):7.1e} {of_steady}")
    print()


def run(quick=False) -> str:
    import core

    limits = coupled_limits()
    eq35 = float(core.ft_limit(W))
    out = _Tee()
    with redirect_stdout(out):
        load = os.getloadavg()
        print(f"# benchmarks/coupled_paths.py: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
              f"cores={os.cpu_count()}, load {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}")
        print(f"the rocking cylinder, w = {W}, dx = a/{round(1 / DX)}, mu = {MU}, {PERIODS} periods after the path; "
              f"ft in multiples of the coupled limit (coupled_limits.txt, the middle of its bracket; eq 35 = "
              f"{eq35:.4f} at beta = 0); increments [mu P/E*], energies [mu^2 P^2/E*] of the last period")
        paths = PATHS[:3] if quick else PATHS
        _table(core, limits, eq35, (0.0, 0.25) if quick else BETAS, (0.99, 1.01) if quick else FRACTIONS, paths,
               PERIODS)
        print(f"below the limit, {LONG} periods: does the energy per period of the coupled micro-slip settle to one "
              "value whatever the path, or to one per path?")
        _table(core, limits, eq35, (0.25,) if quick else (0.1, 0.25), (0.7,) if quick else (0.7, 0.99), paths, LONG)
        load = os.getloadavg()
        print(f"# done {time.strftime('%H:%M UTC', time.gmtime())}, load {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}")
    return out.getvalue()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a few runs, nothing written")
    args = parser.parse_args(argv)
    text = run(quick=args.quick)
    if not args.quick:
        (RESULTS / "coupled_paths.txt").write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
