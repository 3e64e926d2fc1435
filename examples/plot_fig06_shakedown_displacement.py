"""
Fig 6: the displacement shakes down (ft = 0.08)
===============================================

The paper's Fig 6: the displacement ``u = U / U0`` of the cylinder over ten periods of rocking at
``ft = 0.08`` for the amplitudes ``w = 0.26, 0.52, 0.77``. Under this small tangential load every
amplitude shakes down: the cylinder walks a little in the first periods, then stops at a new
equilibrium, further for the larger amplitude.

How it compares: the runs use the paper's numerical model (eq 17: the truncated-3D strip of
:data:`core.PAPER_SIMULATION`, ``L/a = 292.6``, ``nu = 0.5``), on a grid of ``a/40`` instead of the
paper's ``a/85``. As in the paper, the three curves level off within a few periods, higher for the
larger amplitude; the solver's ``u_sd`` (0.078 to 0.092 on this grid) lies within 0.004 of the
paper's regression eq 34 (``u_sd = 1 - (1 - ft)^0.92 + 0.3 ft w``, dotted), printed beside it.
"""

import matplotlib.pyplot as plt

import core
from core.theory import approximations
from core.maps.paper_figures import paper_model, time_in_periods


FT = 0.08
fig, ax = plt.subplots(figsize=(6.4, 3.8), layout="constrained")
for w, color in zip((0.26, 0.52, 0.77), ("#0072B2", "#E69F00", "#009E73")):
    r = core.simulate_cycles(FT, w, periods=10, dx=1 / 40, **paper_model())
    ax.plot(time_in_periods(r), r.u, color=color, lw=1.5, label=f"w = {w} ({r.regime})")
    eq34 = float(approximations.shakedown_displacement_approx(FT, w))
    ax.axhline(eq34, color=color, ls=":", lw=1)
    print(f"w = {w}: {r.regime:10s} u_sd = {r.u[-1]:.4f} (eq 34: {eq34:.4f}), "
          f"last increment {r.increment_per_period[-1] / r.u0:.2e} U0")
ax.set(xlabel="time [periods]", ylabel="u = U / U0", title=f"Fig 6: shakedown at ft = {FT} (dotted: eq 34)")
ax.legend(fontsize=8)
plt.show()
