"""
Table 1: the experiment's contact
=================================

The paper's Table 1 lists the experiment: a steel cylinder (R = 40 mm, L = 80 mm) on silicone
rubber, Fn = 32.2 N, mu = 0.79, and the Hertz contact it gives, 2a = 4.2 mm and d = 0.26 mm.
:data:`core.PAPER_EXPERIMENT` is that contact in SI units; here its derived quantities are
printed and drawn beside the printed values.

How it compares: eq 6 gives d = 0.2589 mm, the printed 0.26 mm. The Hertz width from the table's
inputs is 2a = 4.133 mm, which rounds to 4.1 mm, not the printed 4.2 mm: the printed width is most
likely the measured one (1.6 % wider). Dundurs' beta is 6e-6: the uncoupled model (beta = 0)
applies.
"""

import matplotlib.pyplot as plt
import numpy as np

import core

c = core.PAPER_EXPERIMENT
rows = [
    ("2a [mm]", 2 * c.a * 1e3, 4.2),
    ("d [mm]", c.d * 1e3, 0.26),
]
print(f"{'quantity':10s} {'computed':>10s} {'printed':>8s}")
for name, computed, printed in rows:
    print(f"{name:10s} {computed:10.4f} {printed:8.2f}   ({100 * (computed / printed - 1):+.1f} %)")
print(f"p0 = {c.p0 / 1e3:.1f} kPa, E* = {c.E_star / 1e6:.3f} MPa, Dundurs beta = {c.beta:.2g}")

# %%
# The Hertz pressure of the experiment, with the printed and the computed contact widths.
x = np.linspace(-1.3, 1.3, 521)
fig, ax = plt.subplots(figsize=(6.4, 3.4), layout="constrained")
ax.plot(x * c.a * 1e3, core.hertz_pressure(x) * c.p0 / 1e3, color="#0072B2", lw=2, label="Hertz, Table 1 inputs")
for half, style, label in ((c.a * 1e3, "-", "computed 2a"), (2.1, "--", "printed 2a = 4.2 mm")):
    ax.axvline(-half, color="0.4", ls=style, lw=1)
    ax.axvline(half, color="0.4", ls=style, lw=1, label=label)
ax.set(xlabel="x [mm]", ylabel="p [kPa]", title="Table 1: the experiment's Hertz contact")
ax.legend(loc="upper right", fontsize=8)
plt.show()
