"""Compare the paper's shakedown closure (eqs 22-30) with the numerical shakedown state.

The numerical state is the static partial-slip solution with the bound
mu * p_min (core.api.solver.shakedown_state), which equals the end state of the
transient (tests/test_solver.py). Prints a Markdown table of the errors.

Run: python benchmarks/closure_vs_numerics.py [dx]
"""

import sys
from fractions import Fraction

import numpy as np

import core
from core.api.solver import shakedown_state


def main(dx: float = 1 / 400) -> None:
    print(f"Closure (eq 30) against the numerical shakedown state, plane strain, dx = a/{1 / dx:.0f}\n")
    print("| w | ft/ft_lim | ft | c_sd closure | c_sd numerical | diff [a] | centre traction diff [mu p0] | L1 traction diff [mu p0 a] | max traction diff [mu p0] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for w in (0.26, 0.52, 0.77):
        for frac in (0.2, 0.5, 0.8, 0.95):
            ft = frac * float(core.ft_limit(w))
            sd = shakedown_state(ft, w, dx)
            x, q, c = sd.x, sd.traction, sd.stick_halfwidth
            cc = float(core.shakedown_stick_halfwidth(ft, w))
            tau = core.shakedown_traction(x, ft, w)
            i0 = int(np.argmin(np.abs(x)))
            d = tau - q
            print(f"| {w:.2f} | {frac:.2f} | {ft:.4f} | {cc:.4f} | {c:.4f} | {c - cc:+.4f} | {d[i0]:+.4f} | "
                  f"{np.abs(d).sum() * dx:.4f} | {np.abs(d).max():.3f} |")


if __name__ == "__main__":
    main(float(Fraction(sys.argv[1])) if len(sys.argv) > 1 else 1 / 400)  # e.g. 1/800
