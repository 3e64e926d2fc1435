"""
Fig 12: the traction after shakedown at ft = 0.08
=================================================

The paper's Fig 12: the tangential traction after shakedown at ``ft = 0.08`` for
``w = 0.26, 0.52, 0.77``. The larger the amplitude, the narrower the band ``|x| < a - W`` that
stays in contact, and the narrower the stick zone inside it.

How it compares: solver (solid, the paper's strip model, grid ``a/100``) against the paper's ansatz
(dashed, eqs 22-26 with ``c_sd`` of eq 30); the differences printed are about 0.01 ``mu p0`` at
most, as in Fig 11.
"""

import matplotlib.pyplot as plt

from core.maps import paper_figures

data = paper_figures.traction_profiles(paper_figures.FIG12_CASES, dx=1 / 100)
fig, ax = plt.subplots(figsize=(6.4, 4), layout="constrained")
for curve, color in zip(data["curves"], ("#0072B2", "#E69F00", "#009E73")):
    ax.plot(curve["x"], curve["solver"], color=color, lw=1.5, label=f"w = {curve['w']}")
    ax.plot(curve["x"], curve["ansatz"], color=color, lw=1.2, ls="--")
    print(f"w = {curve['w']}: c_sd solver {curve['c_solver']:.3f} a, eq 30 {curve['c_eq30']:.3f} a, "
          f"largest traction difference {curve['max_difference']:.3f} mu p0")
ax.set(xlabel="x / a", ylabel="q / (mu p0)", title="Fig 12: traction after shakedown, ft = 0.08 (dashed: ansatz)")
ax.legend(fontsize=8)
plt.show()
