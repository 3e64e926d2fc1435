"""
Dissimilar materials: the coupled limit against eq 35
=====================================================

With dissimilar materials (Dundurs' ``beta != 0``) the normal and tangential problems are coupled and
Melan's theorem no longer gives the limit: eq 35 is then only the uncoupled reference. The coupled
limit ``ft_lim(w)`` is the solver's: at each ``w`` a bisection in ``ft`` on the coupled cycle
solver's verdict (:func:`core.coupled_limit_curve`; brackets 2 % of eq 35 wide, ``dx = a/20``,
20 periods, ``mu = 0.3``).

The curves for ``beta = +-0.1`` and ``+-0.25`` take minutes of CPU time (140 coupled runs), too long
for the documentation build: they are read from the table ``benchmarks/results/coupled_limit_curve.csv``,
which ``python benchmarks/coupled_limit_curve.py --parts table`` computed and committed. One point,
``beta = 0.25`` at ``w = 0.6`` with a coarser bracket, is computed live below and drawn on the table's
curve.

How it compares: the coupled limit lies below eq 35 at every amplitude, and the further the larger
``|beta|`` and ``w``; the sign of ``beta`` does not change it (open markers: ``-beta``, on the same
brackets). At ``w = 0.6`` the fall is 26 % at ``|beta| = 0.25`` and 5 % at 0.1 on this coarse grid,
against about 25 % and 4 % in the issue's CONTACT runs and 26.2 % and 4.3 % at ``a/40``
(``benchmarks/results/coupled_limits.txt``). At ``w = 0.9`` only ``0.1 a`` on either side of the
centre stays in contact, four elements of ``a/20``: that point is the grid's roughest. The paper
(``beta = 0``) has no coupled limit to compare with.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import core

TABLE = Path("benchmarks") / "results" / "coupled_limit_curve.csv"
here = [Path(__file__).resolve().parents[1]] if "__file__" in globals() else []  # (pasted into a console: none)
ROOT = next(p for p in [*here, Path.cwd(), Path.cwd().parent] if (p / TABLE).exists())  # the repository
table = pd.read_csv(ROOT / TABLE, comment="#")

fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
w = np.linspace(0.0, 0.999, 300)
ax.plot(core.ft_limit(w), w, color="black", lw=2, ls="--", label="eq 35 (uncoupled reference)")
styles = {0.1: ("#0072B2", "o"), 0.25: ("#D55E00", "^")}
for size in (0.1, 0.25):
    color, marker = styles[size]
    plus, minus = (table[np.isclose(table["beta"], b)].sort_values("w") for b in (size, -size))
    ax.plot(plus["ft_limit"], plus["w"], color=color, marker=marker, lw=1.5, label=f"coupled, β = +{size:g}")
    ax.plot(minus["ft_limit"], minus["w"], color=color, marker=marker, ms=12, mfc="none", ls="none",
            label=f"coupled, β = −{size:g}")
    ax.hlines(plus["w"], plus["ft_shakedown"], plus["ft_ratcheting"], color=color, lw=5, alpha=0.5)
    same = np.allclose(plus[["ft_shakedown", "ft_ratcheting"]].to_numpy(), minus[["ft_shakedown", "ft_ratcheting"]])
    print(f"|beta| = {size:g}: the two signs give {'the same' if same else 'different'} brackets")
    for r in plus.itertuples():
        print(f"|beta| = {size:g}, w = {r.w:.1f}: ft_lim in [{r.ft_shakedown:.4f}, {r.ft_ratcheting:.4f}], "
              f"eq 35 = {r.ft_eq35:.4f}, {r.fall:.1%} below it")

# one point live: beta = 0.25 at w = 0.6, a bracket 10 % of eq 35 wide (a few runs)
live = core.coupled_limit(0.6, beta=0.25, mu=0.3, tol=0.1)
ax.errorbar(live.ft_limit, live.w, xerr=0.5 * (live.ft_ratcheting - live.ft_shakedown), color="black", marker="D",
            ms=7, mfc="white", capsize=4, ls="none", label="computed now (β = 0.25, ±½ bracket)")
row = table[(table["beta"] == 0.25) & np.isclose(table["w"], 0.6)]
print(f"live: beta = 0.25, w = 0.6: ft_lim in [{live.ft_shakedown:.4f}, {live.ft_ratcheting:.4f}] in "
      f"{len(live.runs)} runs ({live.cpu_s:.1f} s cpu); the table: "
      + (f"[{row['ft_shakedown'].iloc[0]:.4f}, {row['ft_ratcheting'].iloc[0]:.4f}]" if len(row) else "(no row at 0.6)"))
ax.set(xlabel="ft = Ft / (μ Fn)", ylabel="w = W / a", xlim=(0, 1), ylim=(0, 1),
       title="Coupled shakedown limit (μ = 0.3, a/20)")
ax.legend(fontsize=8)
plt.show()
