"""
Fig 16: the ratcheting increment per period
===========================================

The paper's Fig 16: the displacement increment per period of a ratcheting contact, ``du``, against
``ft`` for ``w = 0.26, 0.52, 0.77``, with the paper's regression eq 38, ``du = 0.64 ft (w - w_lim)``.

How it compares: the solver's increments (markers: the last of twenty periods, the paper's strip
model, grid ``a/40``, six loads per amplitude from just above the limit) against eq 38 (dashed).
The regression has the right size but not the right shape: its largest relative error is printed.
Treat eq 38 as rough and use the solver.
"""

import matplotlib.pyplot as plt

from core.maps import paper_figures

data = paper_figures.ratchet_increment_curves(points=6, dx=1 / 40, periods=20)
fig, ax = plt.subplots(figsize=(6.4, 4), layout="constrained")
for curve, color in zip(data["curves"], ("#0072B2", "#E69F00", "#009E73")):
    ax.plot(curve["ft"], curve["solver"], "o", color=color, label=f"solver, w = {curve['w']}")
    ax.plot(curve["ft"], curve["eq38"], color=color, ls="--", lw=1.2)
ax.set(xlabel="ft", ylabel="du per period (u = U / U0)", title="Fig 16: ratcheting increment (dashed: eq 38)")
ax.legend(fontsize=8)
print(f"largest |eq 38 - solver| = {data['max_difference']:.4f}, relative {100 * data['max_relative_difference']:.0f} %")
plt.show()
