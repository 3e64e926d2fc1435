"""Issue 32's open question: the steady dissipation below the coupled limit (cyclic micro-slip) on finer grids.

Below its coupled limit the rocking cylinder of dissimilar materials stops walking but keeps a small energy
dissipated per period. Is it a property of the contact (converging to a non-zero value as the grid is refined) or
of the discretisation (vanishing with the element size)? This runs ``w = 0.6``, ``mu = 0.3``, ``|beta| = 0.1`` and
``0.25`` at ``ft = 0.8`` and ``0.9`` times the coupled limit found at ``a/40`` (``coupled_limits.txt``: 0.9565 and
0.738 times eq 35) on the grids ``a/20``, ``a/40``, ``a/80`` (and ``a/160``), the rocking step ``dW`` equal to the
element size (the default), and prints the energy of the last period [mu^2 P^2/E*] (steady when a period repeats:
'rep' is the period from which the state repeats), the increment, the regime and the observed order of the change
between successive grids (``log2`` of the ratio of successive differences), whether the energy is steady in time
(the last period's over the one five periods before) and the verdict's fit of the energy per period as the
periods go on (``E_inf``).

Run: python benchmarks/coupled_dissipation_grid.py [--coarsest 20] [--finest 160] [--periods 30]
[--betas 0.1,0.25] [--append]; writes benchmarks/results/coupled_dissipation_grid.txt.
"""

from __future__ import annotations

import argparse
import io
import math
import os
import sys
import time
from contextlib import redirect_stdout
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).resolve().parent / "results"
MU, W = 0.3, 0.6
#: The coupled limit at w = 0.6 and a/40 as a fraction of eq 35 (midpoints of coupled_limits.txt's brackets).
LIMIT_A40 = {0.1: 0.9565, 0.25: 0.738}
FRACTIONS = (0.8, 0.9)


def study(finest: int, periods: int, betas, coarsest: int = 20) -> None:
    import core

    eq35 = float(core.ft_limit(W))
    grids = [g for g in (20, 40, 80, 160) if coarsest <= g <= finest]
    print(f"rocking cylinder, w = {W}, mu = {MU}, dW = dx, up to {periods} periods; energy [mu^2 P^2/E*] and "
          "increment [mu P/E*] of the last period (steady when the state repeats from 'rep')")
    print(f"{'beta':>6} {'ft/lim':>7} {'ft':>7} {'a/dx':>5} {'energy':>11} {'increment':>11} {'regime':>12} "
          f"{'rep':>4} {'E(dx)-E(dx/2)':>14} {'order':>6} {'E_n/E_n-5':>10} {'E_inf fit':>10} {'cpu [s]':>8}")
    for beta in betas:
        for f in FRACTIONS:
            ft = f * LIMIT_A40[abs(beta)] * eq35
            energies = []
            for g in grids:
                c0 = time.process_time()
                r = core.simulate_cycles(ft, W, periods=periods, dx=1.0 / g, beta=beta, mu=MU)
                s = r.summary()
                energies.append(s["energy_last_period"])
                diff = order = ""
                if len(energies) >= 2:
                    diff = f"{energies[-2] - energies[-1]:.3e}"
                if len(energies) >= 3:
                    d1, d2 = energies[-3] - energies[-2], energies[-2] - energies[-1]
                    order = f"{math.log2(abs(d1 / d2)):.2f}" if d2 != 0 and d1 != 0 else "-"
                rep = "-" if r.periodic_from is None else str(r.periodic_from)
                e = np.asarray(r.dissipation_per_period, dtype=float)  # is the last period's energy steady in time?
                trend = f"{e[-1] / e[-6]:.4f}" if e.size >= 6 and e[-6] > 0 else "-"
                e_inf = "-" if s["E_inf"] is None else f"{s['E_inf']:.3e}"
                print(f"{beta:>6.2f} {f:>7.2f} {ft:>7.4f} {g:>5d} {s['energy_last_period']:>11.4e} "
                      f"{s['increment_last_period']:>11.3e} {s['regime']:>12} {rep:>4} {diff:>14} {order:>6} "
                      f"{trend:>10} "
                      f"{e_inf:>10} {time.process_time() - c0:>8.1f}", flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--finest", type=int, default=160, choices=(40, 80, 160), help="finest grid, a/FINEST")
    ap.add_argument("--coarsest", type=int, default=20, choices=(20, 40, 80, 160), help="coarsest grid, a/COARSEST")
    ap.add_argument("--periods", type=int, default=30, help="periods of every run (a repeated period stops it)")
    ap.add_argument("--betas", default="0.1,0.25,-0.25", help="comma-separated Dundurs beta values")
    ap.add_argument("--no-write", action="store_true", help="print only")
    ap.add_argument("--append", action="store_true", help="add to the results file instead of replacing it")
    args = ap.parse_args(argv)
    buf = io.StringIO()

    class Tee(io.TextIOBase):
        def write(self, s):
            sys.__stdout__.write(s)
            sys.__stdout__.flush()
            return buf.write(s)

    with redirect_stdout(Tee()):
        print(f"# benchmarks/coupled_dissipation_grid.py --coarsest {args.coarsest} --finest {args.finest} "
              f"--periods {args.periods} "
              f"--betas {args.betas}: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, cores={os.cpu_count()}, "
              f"load {os.getloadavg()[0]:.1f}")
        study(args.finest, args.periods, [float(b) for b in args.betas.split(",")], args.coarsest)
    if not args.no_write:
        RESULTS.mkdir(exist_ok=True)
        path = RESULTS / "coupled_dissipation_grid.txt"
        path.write_text((path.read_text() if args.append and path.exists() else "") + buf.getvalue())


if __name__ == "__main__":
    main()
