"""
Fig 8: the pressure at the reversal points
==========================================

The paper's Fig 8: the Hertz pressure when the contact centre is at its reversal points
``xc = +W`` and ``xc = -W``, and the regions in contact. Between them lies the band
``|x| < b = a - W`` that stays in contact all the time; outside it each edge is released once per
period, and the lowest pressure a point sees over the period, ``p_min``, is the bound ``mu p_min``
that the traction must respect in the shaken-down state (eq 22).

How it compares: this figure is the model's input, not a result: the pressures are exactly
Hertz's (uncoupled contact, beta = 0), as in the paper, here for ``w = 0.52``.
"""

import matplotlib.pyplot as plt
import numpy as np

import core

w = 0.52
x = np.linspace(-1 - w - 0.1, 1 + w + 0.1, 801)
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
ax.plot(x, core.hertz_pressure(x, w), color="#0072B2", lw=2, label="xc = +W")
ax.plot(x, core.hertz_pressure(x, -w), color="#D55E00", lw=2, ls="--", label="xc = -W")
ax.fill_between(x, core.lowest_pressure(x, w), color="0.8", label="p_min over the period")
b = 1 - w
ax.axvspan(-b, b, color="#009E73", alpha=0.12, label=f"always in contact, |x| < b = {b:.2f} a")
ax.set(xlabel="x / a", ylabel="p / p0", title=f"Fig 8: pressure at the reversal points, w = {w}")
ax.legend(fontsize=8, loc="upper right")
print(f"b = a - W = {b:.2f} a; contact swept: |x| < {1 + w:.2f} a")
plt.show()
