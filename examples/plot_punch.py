"""
The rounded flat punch: two pressure peaks
==========================================

Beyond the paper: the fretting-fatigue indenter, a flat of half-width ``b`` with rounded edges, in
plane strain (:class:`core.Punch`, ``flat = b/a``; ``flat = 0`` is the paper's cylinder). Its
pressure (Ciavarella, Hills and Monno 1998, :func:`core.theory.punch.punch_pressure`) has two peaks near
``x = +-b`` and a dip between them, so the lowest pressure over a rocking period no longer sits at
a turning point, and its exact shakedown limit comes from Melan's theorem numerically
(``core.ft_limit(w, body=core.Punch(flat=...))``).

How it compares: there is no such figure in the paper. The left panel draws the pressure for three
flats; the right one the exact limits against the cylinder's eq 35. The solver (grid ``a/40``,
twenty periods) is run at ``flat = 0.5``, ``w = 0.3``, 10 % below and above the punch's limit: the
printed verdicts bracket it.
"""

import matplotlib.pyplot as plt
import numpy as np

import core
from core.theory.punch import punch_pressure

x = np.linspace(-1.1, 1.1, 881)
w_grid = np.linspace(0.0, 0.95, 20)
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(9, 3.8), layout="constrained")
ax2.plot(core.ft_limit(w_grid), w_grid, color="0.3", lw=2, label="cylinder, eq 35")
for flat, color in zip((0.0, 0.5, 0.8), ("0.3", "#0072B2", "#D55E00")):
    ax.plot(x, punch_pressure(x, flat=flat), color=color, lw=1.5, label=f"flat = b/a = {flat}")
    if flat:
        body = core.Punch(flat=flat)
        ax2.plot([float(core.ft_limit(w, body=body)) for w in w_grid], w_grid, color=color, lw=1.5, ls="--",
                 label=f"punch, flat = {flat} (Melan)")
ax.set(xlabel="x / a", ylabel="p / p0", title="Pressure of the rounded flat punch")
ax.legend(fontsize=8)
ax2.set(xlabel="ft_lim", ylabel="w_lim", title="Exact shakedown limits", xlim=(0, 1), ylim=(0, 1))
ax2.legend(fontsize=8)

w, body = 0.3, core.Punch(flat=0.5)
ft_lim = float(core.ft_limit(w, body=body))
print(f"flat = 0.5, w = {w}: ft_lim = {ft_lim:.4f} (cylinder: {float(core.ft_limit(w)):.4f})")
for ft in (0.9 * ft_lim, 1.1 * ft_lim):
    r = core.simulate_cycles(ft, w, periods=20, dx=1 / 40, body=body)
    print(f"ft = {ft:.4f} ({ft / ft_lim:.1f} ft_lim): {r.regime}, last increment {r.increment_per_period[-1]:.2e} mu P/E*")
plt.show()
