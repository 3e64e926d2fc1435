"""
The rocking cone, cycle by cycle: it walks and it turns
=======================================================

Beyond the paper: the frustum ``inner = r1/r2 = 0.5`` (a tapered roller, :class:`core.Cone`, contact length
``L = 10 a_m``) lying on its side and rocking about the vertical axis through its apex, run on the 3D
solver. The contact line turns by ``theta = xc / r_m`` about the apex, so a point at the distance ``r``
moves ``r theta`` across it; ``w = W_m / a_m`` is measured at the mid-length ``r_m``. The traction bound
is the slice model's pressure (Hertz line contacts of half-width ``a_m sqrt(r / r_m)`` under a uniform
line load) rotated about the apex; ``Ft`` acts across the contact line at the mid-length, and the body
is free to translate and to turn about the normal: each step has three rigid unknowns, the two
translations of the load point and the rotation about the normal, the last held by the condition that
the tractions have no moment about the line of action of ``Ft``.

Two runs at ``w = 0.3``, 10 % either side of Melan's limit on the run's grid (``Cone.grid_limit``: the
lowest pressure of the run's own positions; 0.6086 to 0.6116 at ``a/10``, the slice formula's 0.6050): below it the
increments of the load point's displacement and of the rotation die out (shakedown); above it both settle
to constants: the roller walks along ``Ft`` by about 0.009 ``mu Fn/(E* a_m)`` a period and turns by about
-0.0018 ``mu Fn/(E* a_m^2)`` rad, towards the apex (the outer end, which rocks relatively more, slips
more). The right panel: the final state of the contact of the ratcheting run (stick, slip forward or
backward) on the grid, the apex below.

How it compares: the paper has no cone; it names cones as future work. A frustum far from its apex is
the cylinder (its limit tends to eq 35, ``core.geometry.cone``); here the limit is bracketed by runs, as the
paper's solver brackets eq 35 for the cylinder.
"""

import matplotlib.pyplot as plt
import numpy as np

import core

cone = core.Cone(inner=0.5)
w, dx = 0.3, 0.1
lim = cone.grid_limit(w, dx=dx)
runs = {"0.9 x limit": core.simulate_cycles(0.9 * lim["lo"], w, periods=30, dx=dx, body=cone),
        "1.1 x limit": core.simulate_cycles(1.1 * lim["hi"], w, periods=12, dx=dx, body=cone)}
print(f"Melan on the grid: [{lim['lo']:.4f}, {lim['hi']:.4f}] (q_y = 0: {lim['along']:.4f}); slice formula "
      f"{cone.ft_limit(w):.4f}")

fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(11, 3.8), layout="constrained",
                                    gridspec_kw={"width_ratios": [1, 1, 0.55]})
for (label, r), color in zip(runs.items(), ("#0072B2", "#D55E00")):
    n = np.arange(1, r.increment_per_period.size + 1)
    ax1.semilogy(n, np.abs(r.increment_per_period), color=color, marker=".", label=f"{label}: {r.regime}")
    ax2.semilogy(n, np.abs(r.twist_per_period), color=color, marker=".", label=label)
    print(f"{label} (ft = {r.params['ft']:.4f}): {r.regime}; last period: displacement "
          f"{r.increment_per_period[-1]:.3g} mu Fn/(E* a_m), twist {r.twist_per_period[-1]:.3g} mu Fn/(E* a_m^2) rad")
ax1.set(xlabel="period", ylabel="|increment| per period [mu Fn/(E* a_m)]", title="Load point, along Ft")
ax2.set(xlabel="period", ylabel="|twist| per period [mu Fn/(E* a_m^2) rad]", title="Rotation about the normal")
ax1.legend(fontsize=8)
ax2.legend(fontsize=8)
r = runs["1.1 x limit"]
ax3.imshow(r.final_state, origin="lower", cmap="viridis", vmin=0, vmax=3, aspect="equal", interpolation="nearest",
           extent=(r.x_edges[0], r.x_edges[-1], r.y_edges[0], r.y_edges[-1]))
ax3.set(xlabel="x [a_m]", ylabel="y [a_m] (apex at -r_m)", title="Final state, 1.1 x limit\n(0 out, 1 stick, 2/3 slip)")
plt.show()
