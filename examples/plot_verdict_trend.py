"""
The verdict near the limit: D_inf and r
=======================================

Close to its shakedown limit a run's increment per period decays, or settles, slowly, and a short
run cannot tell which. The verdict (:doc:`/guide/verdicts`) fits the tail of the increments with
``D_n = D_inf + C r^n`` and says "undetermined" until the fit decides: ``result.D_inf`` (with
``result.D_inf_error``), ``result.decay_ratio`` (``r``) and ``result.periods_to_decide`` are on every
result.

Here the rounded flat punch (``core.Punch(flat=0.5)``, whose pressure minimum does not sit at a
turning point, so it approaches its limit slowly) rocks at ``w = 0.3``, 0.2 % below and above its
exact limit ``ft_lim = 0.5527``, on a grid of ``a/40``. After 12 periods both runs are undetermined:
the fits extrapolate to ``D_inf = 2.5e-4`` and ``3.0e-4`` mu P/E* (``r = 0.67`` and ``0.69``), above
the shakedown tolerance, but the part still changing at period 12 is 0.9 times ``D_inf``, and the fit
asks for about 4 more periods. After 40 periods the run below the limit has shaken down (its
increment fell below 0.001 of its largest from period 18) and the one above ratchets at 2.8e-4 mu
P/E* per period: the 12-period fit of the first was an extrapolation of a decay still slowing down,
which is why the verdict did not call it ratcheting. The dashed lines are the 12-period fits.

How it compares: the paper reads its verdicts off the figures. The punch's limit from Melan's theorem
is exact, so runs this close to it are where a verdict rule matters.
"""

import matplotlib.pyplot as plt
import numpy as np

import core

w, body = 0.3, core.Punch(flat=0.5)
ft_lim = float(core.ft_limit(w, body=body))
print(f"punch, flat = 0.5, w = {w}: ft_lim = {ft_lim:.4f}")
fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
for factor, color in ((0.998, "#0072B2"), (1.002, "#D55E00")):
    ft = factor * ft_lim
    short = core.simulate_cycles(ft, w, periods=12, dx=1 / 40, body=body)
    long = core.simulate_cycles(ft, w, periods=40, dx=1 / 40, body=body)
    n = np.arange(1, long.periods + 1)
    ax.semilogy(n, np.abs(long.increment_per_period), color=color, marker=".", lw=1,
                label=f"ft = {factor} ft_lim: {long.regime} after 40")
    t = short.trend
    m = np.arange(short.periods - t.periods_fitted + 1, 41)
    ax.semilogy(m, np.abs(t.D_inf + t.transient * t.ratio ** (m - short.periods)), color=color, ls="--", lw=1,
                label=f"fit after 12: D_inf = {t.D_inf:.2g}, r = {t.ratio:.2f}")
    print(f"ft = {factor} ft_lim, 12 periods: {short.regime}, D_inf = {short.D_inf:.3g} +- {short.D_inf_error:.2g}, "
          f"r = {short.decay_ratio:.4f}, periods to decide ~ {short.periods_to_decide}")
    print(f"ft = {factor} ft_lim, 40 periods: {long.regime} ({long.regime_reason})")
ax.axvline(12, color="0.6", lw=0.8)
ax.set(xlabel="period", ylabel="increment per period [mu P/E*]", ylim=(1e-7, 1),
       title="Rounded flat punch near its limit (w = 0.3)")
ax.legend(fontsize=8)
plt.show()
