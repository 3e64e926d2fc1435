"""
The sphere against the cylinder
===============================

Beyond the paper: the rocking sphere (a point contact, solved in 3D on the half-space) beside the
cylinder. Both exact limits follow from Melan's theorem, ``ft_lim = (1/P) * integral of p_min``:
eq 35 for the cylinder and ``(1 - w)^2 (2 + w) / 2`` for the sphere.

How it compares: the paper states that at the same amplitude the cylinder bears a lower tangential
force than the sphere. The exact limits say the opposite: the sphere's lies below the cylinder's at
every amplitude. The 3D solver (:func:`core.simulate_point_contact`, a coarse grid of ``a/10`` and
twelve periods) checks it at ``w = 0.3``: a load below the sphere's limit shakes down, one between the
two limits, where the cylinder still shakes down, does not (its increments per period are printed).
"""

import matplotlib.pyplot as plt
import numpy as np

import core

w_grid = np.linspace(0, 1, 201)
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(9, 3.8), layout="constrained")
ax.plot(core.ft_limit(w_grid), w_grid, color="#0072B2", lw=2, label="cylinder, eq 35")
ax.plot(core.ft_limit(w_grid, body="sphere"), w_grid, color="#009E73", lw=2, ls="-.", label="sphere")
ax.set(xlabel="ft_lim", ylabel="w_lim", title="Exact shakedown limits", xlim=(0, 1), ylim=(0, 1))

w = 0.3
ft_sphere, ft_cyl = float(core.ft_limit(w, body="sphere")), float(core.ft_limit(w))
print(f"w = {w}: ft_lim sphere {ft_sphere:.4f}, cylinder {ft_cyl:.4f}")
for ft, marker, color in ((0.8 * ft_sphere, "o", "#009E73"), (0.5 * (ft_sphere + ft_cyl), "^", "#D55E00")):
    sphere = core.simulate_point_contact(ft, w, periods=12, dx=1 / 10)
    cylinder = core.simulate_cycles(ft, w, periods=12, dx=1 / 40)
    print(f"ft = {ft:.3f}: sphere {sphere.regime} (increments {', '.join(f'{v:.1e}' for v in sphere.increment_per_period[-3:])}), "
          f"cylinder {cylinder.regime}")
    ax.plot(ft, w, marker, color=color, ms=8, label=f"ft = {ft:.3f}: sphere {sphere.regime}")
    inc = np.abs(sphere.increment_per_period)
    ax2.semilogy(np.arange(1, inc.size + 1), inc, marker + "-", color=color, label=f"sphere, ft = {ft:.3f}")
ax.legend(fontsize=7, loc="upper right")
ax2.set(xlabel="period", ylabel="|increment| per period [mu Fn / (E* a)]", title=f"Sphere at w = {w}")
ax2.legend(fontsize=7)
plt.show()
