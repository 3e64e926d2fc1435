"""
Fretting: the loop, the energy per cycle and the three regimes
==============================================================

The cylinder held at its centre under a tangential force oscillating about its mean,
``Q = 0.3 + 0.5 sin(2 pi t)`` (in mu P): the contact slips at both edges every half period, for ever,
and the body does not walk: **cyclic slip**. Its fretting loop (the force against the rigid-body
displacement) closes from the second period on; its area is the energy dissipated per cycle, which
Cattaneo-Mindlin with Masing's rule gives in closed form (:func:`core.fretting_energy`).

Beside it, two rocking runs at ``w = 0.5``:
``ft = 0.2`` shakes down (the energy per period falls to zero with the walk) and ``ft = 0.5``
ratchets (both tend to constants; under a constant force the energy per period is ``Q`` times the
walk).

How it compares: the printed energy of the last period against the closed form 0.036194 mu^2 P^2/E*
(within 0.1 % at the default grid a/40, see the user guide's page on the regimes).
"""

import matplotlib.pyplot as plt
import numpy as np

import core

fretting = core.simulate_cycles(0.3, 0.0, periods=4, history="tangential", amplitude=0.5)
exact = float(core.fretting_energy(0.5))
print(f"tangential: {fretting.regime}; energy of the last period {fretting.dissipation_per_period[-1]:.5f}, "
      f"closed form {exact:.5f} mu^2 P^2/E*")

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
for period, style in ((0, dict(color="#56B4E9", ls="--", label="first period")),
                      (-1, dict(color="#D55E00", lw=2, label="last period"))):
    loop = fretting.fretting_loop(period)
    # the hysteresis is small beside the elastic compliance: shear the loop by the secant through its tips
    k = np.polyfit(loop.Q, loop.displacement, 1)[0]
    ax.plot(loop.displacement - k * loop.Q, loop.Q, **style)
    print(f"period {loop.period}: area int Q dD = {loop.work:.5f}, dissipated {loop.energy:.5f}")
ax.set(xlabel="displacement minus its secant part, D - k Q [mu P/E*]", ylabel="Q / (mu P)",
       title=f"fretting loop: {fretting.regime}")
ax.legend(fontsize=8)

runs = {"tangential, A = 0.5": fretting,
        "rocking ft = 0.2, w = 0.5": core.simulate_cycles(0.2, 0.5, periods=8),
        "rocking ft = 0.5, w = 0.5": core.simulate_cycles(0.5, 0.5, periods=8)}
for (name, r), color in zip(runs.items(), ("#E69F00", "#0072B2", "#631E03")):
    energy = r.dissipation_per_period
    ax2.semilogy(np.arange(1, energy.size + 1), np.maximum(energy, 1e-16), "o-", color=color,
                 label=f"{name}: {r.regime}")
    print(f"{name:28s} {r.regime:12s} E_inf = {r.E_inf:.4g} +- {r.E_inf_error:.2g} mu^2 P^2/E*")
ax2.set(xlabel="period", ylabel="energy dissipated per period [mu^2 P^2/E*]", title="energy per period")
ax2.legend(fontsize=7)
plt.show()
