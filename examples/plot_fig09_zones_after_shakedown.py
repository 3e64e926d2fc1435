"""
Fig 9: traction and zones after shakedown
=========================================

The paper's Fig 9: the traction after shakedown with its three zones: stick ``|x| < c_sd``, slip at
the bound ``mu p_min`` for ``c_sd < |x| < b``, and no traction where the contact is released once
per period (``b < |x| < a``).

How it compares: the solver's shaken-down state (:func:`core.shakedown_state`, one static
partial-slip problem with the bound ``mu p_min``, which equals the end of the transient) is drawn
with the paper's ansatz (eqs 22-26 with ``c_sd`` of eq 30) and the zones of the closure
(:func:`core.shakedown_zones`); plane-strain kernel, grid ``a/100``, ``ft = 0.3``, ``w = 0.3``.
The two ``c_sd`` agree to within an element.
"""

import matplotlib.pyplot as plt
import numpy as np

import core

ft, w = 0.3, 0.3
sd = core.shakedown_state(ft, w, dx=1 / 100)
c_eq30 = float(core.shakedown_stick_halfwidth(ft, w))
x = np.linspace(-1.05, 1.05, 841)

fig, ax = plt.subplots(figsize=(6.4, 3.8), layout="constrained")
ax.step(sd.x, sd.traction, where="mid", color="#0072B2", lw=1.5, label="solver (shaken-down state)")
ax.plot(x, core.shakedown_traction(x, ft, w), color="#D55E00", ls="--", lw=1.5, label="ansatz, eqs 22-26")
ax.plot(x, core.lowest_pressure(x, w), color="0.5", lw=1, label="mu p_min")
zones = core.shakedown_zones(x, ft, w)
colors = {core.ZONE_STICK: "#009E73", core.ZONE_SLIP: "#E69F00", core.ZONE_RELEASED: "#CC79A7"}
names = {core.ZONE_STICK: "stick", core.ZONE_SLIP: "slip", core.ZONE_RELEASED: "released"}
for code, color in colors.items():
    ax.fill_between(x, -0.08, -0.02, where=zones == code, color=color, label=names[code])
ax.set(xlabel="x / a", ylabel="q / (mu p0)", title=f"Fig 9: after shakedown, ft = {ft}, w = {w}")
ax.legend(fontsize=8, loc="upper right")
print(f"c_sd: solver {sd.stick_halfwidth:.3f} a, eq 30 {c_eq30:.3f} a (element {1 / 100} a)")
plt.show()
