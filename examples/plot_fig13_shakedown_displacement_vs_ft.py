"""
Fig 13: the shakedown displacement against the load
===================================================

The paper's Fig 13: the shakedown displacement ``u_sd = U_sd / U0`` against ``ft`` for several
amplitudes; rocking increases the displacement above its static value (``w = 0``, eq 13).

How it compares: the solver's direct shaken-down states (markers, the paper's strip model, the
displacement at the contact centre over ``U0``; grid ``a/100``, eight loads per amplitude) against the
paper's regression eq 34 (lines; ``w = 0``: eq 13). Diamonds are transients of ten periods at
``a/40``, which end where the direct state is. The regression follows the solver to the largest
difference printed; the paper's own 3D simulation and experiment sit in the same band.
"""

import matplotlib.pyplot as plt

from core.maps import paper_figures

data = paper_figures.shakedown_displacement_curves(points=8, dx=1 / 100, check_ft=(0.1,), check_dx=1 / 40, periods=10)
fig, ax = plt.subplots(figsize=(6.4, 4), layout="constrained")
for curve, color in zip(data["curves"], ("0.3", "#0072B2", "#E69F00", "#009E73")):
    ax.plot(curve["ft"], curve["eq34"], color=color, lw=1.5, label=f"eq 34, w = {curve['w']}")
    ax.plot(curve["ft"], curve["solver"], "o", color=color, ms=5)
    if curve["check_ft"]:
        ax.plot(curve["check_ft"], curve["check_transient"], "D", color=color, mfc="none", ms=8)
ax.set(xlabel="ft", ylabel="u_sd = U_sd / U0", title="Fig 13: shakedown displacement (o: direct state, ◇: transient)")
ax.legend(fontsize=8)
print(f"largest |solver - eq 34| = {data['max_difference']:.4f}; "
      f"transient - direct state: {data['max_transient_difference']:.2e}")
plt.show()
