"""
Other loading histories: an oscillating normal force, fretting
==============================================================

Beyond the paper's rocking (its outlook names oscillating normal forces): the same cylinder under
three histories of :mod:`core.loading.histories`, at ``ft = 0.3``:

* ``rocking``: the paper's, ``w = 0.5`` under constant loads (below the limit ``ft_lim(0.5) = 0.39``);
* ``normal``: the same rocking with the normal force oscillating by 20 % in phase with the motion;
* ``tangential``: a fixed centre under a tangential force oscillating by 0.2 about its mean
  (fretting, Mindlin's hysteresis loop).

How it compares: there is no figure of the paper to compare with. The printed verdicts say which
histories shake down, and the final displacements how far each walked before it stopped: the
oscillating normal force lowers the lowest pressure of the period, the bound ``mu p_min`` of the
shaken-down state.
"""

import matplotlib.pyplot as plt
import numpy as np

import core

FT, W = 0.3, 0.5
runs = {
    "rocking": core.simulate_cycles(FT, W, periods=8, dx=1 / 25),
    "normal, A = 0.2": core.simulate_cycles(FT, W, periods=8, dx=1 / 25, history="normal", amplitude=0.2),
    "tangential, amplitude 0.2": core.simulate_cycles(FT, 0.0, periods=8, dx=1 / 25, history="tangential", amplitude=0.2),
}
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
for (name, r), color in zip(runs.items(), ("#0072B2", "#D55E00", "#009E73")):
    t = np.arange(r.displacement.size)
    ax.plot(t, r.displacement, color=color, lw=1.2, label=name)
    inc = np.abs(r.increment_per_period)
    ax2.semilogy(np.arange(1, inc.size + 1), np.maximum(inc, 1e-16), "o-", color=color, label=name)
    print(f"{name:26s} {r.regime:12s} final displacement {r.displacement[-1]:.4f}, "
          f"last increment {r.increment_per_period[-1]:.2e} mu P/E*")
ax.set(xlabel="step", ylabel="rigid-body displacement [mu P/E*]", title=f"ft = {FT}")
ax2.set(xlabel="period", ylabel="|increment| per period", title="increment per period")
ax.legend(fontsize=7)
plt.show()
