"""
The rocking cone: a limit that falls along the contact
======================================================

Beyond the paper: a rigid cone, or a frustum (a tapered roller), lying on its side and rocking about
its apex (:class:`core.Cone`, ``inner = r1/r2``; ``inner = 0`` is the full cone). Each slice across
the contact line at the distance ``r`` from the apex is a Hertz line contact of half-width
``a(r) = a_m sqrt(r / r_m)`` rocking with the amplitude ``r Theta``, so its local ``w(r) = w sqrt(r /
r_m)`` grows towards the outer end, where contact is lost first. Melan's theorem then gives the exact
limit from the paper's eq 35 applied slice by slice, with one more condition: ``Ft`` acting at the
mid-length must leave no moment about the normal (the body is free to turn), which lowers the limit
below the sum over the slices (``restrained=True``: the turning held, an upper bound).

How it compares: there is no such figure in the paper. A frustum far from its apex (``inner =
0.999``) is the cylinder: its limit is eq 35's (printed below, 0.6238 at ``w = 0.3``). At ``w = 0.3``
the full cone's limit is 0.5746, 8 % below the cylinder's, and 0.6465 with the turning held (above
it: the slices near the apex rock less than ``w``); the frustum ``inner = 0.5`` lies between, at
0.6050 and 0.6257. The left panel
draws the exact limit for a full cone and two frusta against eq 35; the right one the local amplitude
along the contact at ``w = 0.8``: the outer end of the full cone passes 1 (it loses contact once a
period), the nearly cylindrical frustum is a point at 0.8. The cycles of the cone on the 3D solver, and runs
bracketing this limit, are in the next example (``plot_cone_cycles.py``).
"""

import matplotlib.pyplot as plt
import numpy as np

import core
from core.geometry.cone import slice_amplitude

w_grid = np.linspace(0.0, 0.99, 34)
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(9, 3.8), layout="constrained")
ax.plot(core.ft_limit(w_grid), w_grid, color="0.3", lw=2, label="cylinder, eq 35")
styles = {0.0: "#D55E00", 0.5: "#0072B2", 0.999: "#009E73"}
for inner, color in styles.items():
    cone = core.Cone(inner=inner)
    ax.plot([cone.ft_limit(w) for w in w_grid], w_grid, color=color, lw=1.5, ls="--",
            label=f"inner = {inner} (free to turn)")
    if inner == 0.5:
        ax.plot([cone.ft_limit(w, restrained=True) for w in w_grid], w_grid, color=color, lw=1, ls=":",
                label="inner = 0.5, turning held")
    r = np.linspace(max(inner, 1e-3), 1.0, 200)
    ax2.plot(r, slice_amplitude(r, 0.8, inner), color=color, lw=1.5, marker="o" if inner > 0.99 else None,
             markevery=[-1], label=f"inner = {inner}")
ax.set(xlabel="ft_lim", ylabel="w_lim (at the mid-length)", title="Exact shakedown limits",
       xlim=(0, 1), ylim=(0, 1))
ax.legend(fontsize=8)
ax2.axhline(1.0, color="0.5", lw=0.8)
ax2.set(xlabel="r / r2 (distance from the apex)", ylabel="w(r)", title="Local amplitude at w = 0.8")
ax2.legend(fontsize=8)

w = 0.3
print(f"w = {w}: cylinder (eq 35) ft_lim = {float(core.ft_limit(w)):.4f}")
for inner in styles:
    cone = core.Cone(inner=inner)
    print(f"inner = {inner}: ft_lim = {cone.ft_limit(w):.4f} (free to turn), "
          f"{cone.ft_limit(w, restrained=True):.4f} (turning held); w_lim at ft = 0.3: {cone.w_limit(0.3):.4f}")
plt.show()
