"""
Fig 11: the traction after shakedown at w = 0.26
================================================

The paper's Fig 11: the tangential traction after shakedown at ``w = 0.26`` for
``ft = 0.22, 0.44, 0.66``. The stick zone in the middle shrinks as the load grows; outside it the
traction sits at the bound ``mu p_min``.

How it compares: the solver's shaken-down state (solid, the paper's strip model, grid ``a/100``)
against the paper's ansatz (dashed, eqs 22-26 with ``c_sd`` of eq 30). They agree outside the stick
zone exactly (both at the bound) and inside it to the difference printed (about 0.01 ``mu p0`` on
this grid, largest at the stick edge where both profiles are steep): the ansatz is close, not exact.
"""

import matplotlib.pyplot as plt

from core.maps import paper_figures

data = paper_figures.traction_profiles(paper_figures.FIG11_CASES, dx=1 / 100)
fig, ax = plt.subplots(figsize=(6.4, 4), layout="constrained")
for curve, color in zip(data["curves"], ("#0072B2", "#E69F00", "#009E73")):
    ax.plot(curve["x"], curve["solver"], color=color, lw=1.5, label=f"ft = {curve['ft']}")
    ax.plot(curve["x"], curve["ansatz"], color=color, lw=1.2, ls="--")
    print(f"ft = {curve['ft']}: c_sd solver {curve['c_solver']:.3f} a, eq 30 {curve['c_eq30']:.3f} a, "
          f"largest traction difference {curve['max_difference']:.3f} mu p0")
ax.set(xlabel="x / a", ylabel="q / (mu p0)", title="Fig 11: traction after shakedown, w = 0.26 (dashed: ansatz)")
ax.legend(fontsize=8)
plt.show()
