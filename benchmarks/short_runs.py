"""Short runs against long ones: how often does a run of 4 to 12 periods give the regime of the same run at 30?

The explorer runs 6 to 10 periods; the verdict of a short run must not contradict what more periods say. For the
rocking cylinder (a/20; uncoupled, and coupled at ``beta = +-0.1, +-0.25`` with ``mu = 0.3``), five amplitudes and
``ft`` from 0.5 to 1.05 times eq 35, and for the sphere and the cone (``--point``), each case is run at 4, 5, 6, 8,
10, 12 and 30 periods. Prints, per group, the short runs whose regime is the 30-period run's; ``--jsonl FILE``
keeps every run's regime (``--against FILE``: another tree's, to list the verdicts that changed).

Run: python benchmarks/short_runs.py [--groups 0,0.1,-0.1,0.25,-0.25,point] [--jsonl F] [--against F]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

PERIODS = (4, 5, 6, 8, 10, 12)
LONG = 30
AMPLITUDES = (0.1, 0.3, 0.5, 0.7, 0.9)
LOADS = (0.5, 0.8, 0.9, 0.95, 0.99, 1.01, 1.05)


def cases(group: str):
    """(group, w, ft / limit, keyword arguments of simulate_cycles, the limit's keyword arguments)."""
    if group == "point":
        for body in ("sphere", "cone"):
            for w in (0.3, 0.6):
                for k in (0.8, 0.95, 1.05):
                    yield body, w, k, dict(body=body), dict(body=body)
        return
    beta = float(group)
    run = dict(dx=1 / 20, beta=beta, mu=0.3) if beta else dict(dx=1 / 20)
    for w in AMPLITUDES:
        for k in LOADS:
            yield group, w, k, run, {}


def main(argv=None) -> int:
    import core

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--groups", default="0,0.1,-0.1,0.25,-0.25")
    ap.add_argument("--jsonl", type=Path)
    ap.add_argument("--against", type=Path)
    args = ap.parse_args(argv)
    rows = []
    for group in args.groups.split(","):
        agree = total = 0
        for g, w, k, run, limit in cases(group):
            ft = k * float(core.ft_limit(w, **limit))
            regimes = {n: core.simulate_cycles(ft, w, periods=n, **run).regime for n in (*PERIODS, LONG)}
            for n in PERIODS:
                rows.append(dict(group=g, w=w, k=k, periods=n, regime=regimes[n], long=regimes[LONG]))
                agree += regimes[n] == regimes[LONG]
                total += 1
        print(f"{group}: {agree} of {total} short runs give the {LONG}-period regime", flush=True)
    if args.jsonl:
        args.jsonl.write_text("".join(json.dumps(r) + "\n" for r in rows))
    if args.against:
        before = {(r["group"], r["w"], r["k"], r["periods"]): r for r in map(json.loads, args.against.open())}
        changed = [(before[key], r) for r in rows if (key := (r["group"], r["w"], r["k"], r["periods"])) in before
                   and before[key]["regime"] != r["regime"]]
        print(f"{len(changed)} verdicts changed against {args.against.name}")
        for old, new in changed:
            print(f"  {new['group']} w {new['w']} ft {new['k']} eq 35, {new['periods']} periods: {old['regime']} -> "
                  f"{new['regime']} ({LONG} periods: {new['long']})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
