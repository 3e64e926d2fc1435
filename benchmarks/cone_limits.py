"""The rocking cone's limit curve: the slice formula, Melan's programme on the run's grid, and runs bracketing it.

For each ``inner`` (0.5: a frustum; 0: the full cone) and ``w`` = 0.1 .. 0.6 at
``L/a_m = 10`` and the cone's default grid (a/10, ``dW = dx``), it prints

* ``slice``: :func:`core.geometry.cone.cone_ft_limit` (the slice model's limit, Ft at the mid-length) and, in brackets,
  ``restrained`` (no moment condition, the rotation about the normal held);
* ``along``, ``lo``, ``hi``: Melan's programme on the run's grid with the discrete ``p_min`` of the run's own
  positions (:meth:`core.geometry.cone.Cone.grid_limit`): ``q_y = 0`` (the slice model's programme on the grid), and the
  Coulomb disk between an inscribed and a circumscribed 32-gon;
* the runs: ``0.9 lo`` and ``1.1 hi`` (their regimes), then a bisection of ``ft`` between the highest run that
  shook down and the lowest that ratcheted (``undetermined`` runs are reported and end the bisection), of
  ``PERIODS`` periods each, run again with 4 and 16 times as many while undetermined (the periods in brackets):
  the full cone 10 % below its limit at w 0.5 and 0.6 decays by 0.977 and 0.990 a period once its stick and
  slip zones have settled, and shakes down at period 165 and 421.

Run: python benchmarks/cone_limits.py [--quick]   (quick: w = 0.3 and 0.5 only, no bisection)
"""

import sys
import time

import numpy as np

PERIODS = 40
#: A run still undetermined after PERIODS periods is run again with 4 and 16 times as many, up to these.
MOST_PERIODS = 640
BISECTIONS = 3


def _regime(body, ft, w, dx):
    """The run's regime, re-run with four times the periods (up to ``MOST_PERIODS``) while it is undetermined."""
    import core

    periods = PERIODS
    while True:
        r = core.simulate_cycles(ft, w, periods=periods, dx=dx, body=body)
        if r.regime != "undetermined" or periods >= MOST_PERIODS:
            break
        periods = min(4 * periods, MOST_PERIODS)
    return r.regime, r


def _label(regime, r):
    """The regime as printed, with the periods run when more than PERIODS."""
    return regime[:10] if r.periods <= PERIODS else f"{regime[:10]} ({r.periods})"


def curve(inner, ws, dx=0.1, bisections=BISECTIONS):
    import core
    from core.geometry.cone import cone_ft_limit

    body = core.Cone(inner=inner)
    print(f"\ninner {inner} (L/a_m = {body.length:g}, dx = a/{round(1 / dx)}, {PERIODS} periods a run, up to "
          f"{MOST_PERIODS} while undetermined):")
    print("     w   slice (restrained)   grid: along      lo      hi   runs:   0.9 lo            1.1 hi   bracket "
          "[shakedown, ratcheting]")
    for w in ws:
        t = time.perf_counter()
        lim = body.grid_limit(w, dx=dx)
        low, high = 0.9 * lim["lo"], 1.1 * lim["hi"]
        below, r_below = _regime(body, low, w, dx)
        above, r_above = _regime(body, high, w, dx)
        sd = low if below == "shakedown" else None
        rt = high if above == "ratcheting" else None
        note = ""
        for _ in range(bisections if (sd is not None and rt is not None) else 0):
            mid = 0.5 * (sd + rt)
            regime, r = _regime(body, mid, w, dx)
            if regime == "shakedown":
                sd = mid
            elif regime == "ratcheting":
                rt = mid
            else:
                note = f" (undetermined at {mid:.4f}: {r.regime_reason[:60]}...)"
                break
        bracket = f"[{sd:.4f}, {rt:.4f}]" if sd is not None and rt is not None else "-"
        print(f"  {w:4.2f}   {cone_ft_limit(w, inner):.4f} ({cone_ft_limit(w, inner, None):.4f})      "
              f"{lim['along']:.4f}  {lim['lo']:.4f}  {lim['hi']:.4f}   {_label(below, r_below):>16}  "
              f"{_label(above, r_above):>16}   {bracket}"
              f"  twist/period at 1.1 hi {r_above.twist_per_period[-1]:.3g}, increment "
              f"{r_above.increment_per_period[-1]:.3g}; {time.perf_counter() - t:.0f} s{note}")


def main(quick=False):
    ws = (0.3, 0.5) if quick else tuple(np.round(np.arange(0.1, 0.61, 0.1), 2))
    for inner in (0.5, 0.0):
        curve(inner, ws, bisections=0 if quick else BISECTIONS)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
