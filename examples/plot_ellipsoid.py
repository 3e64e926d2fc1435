"""
The ellipsoid: an elliptical point contact
==========================================

Beyond the paper: a body with two principal radii (``Ry = 2 Rx``), rocked along its ``x`` axis.
Its contact is an ellipse, and its exact shakedown limit (Melan's theorem) is the sphere's,
``(1 - w)^2 (2 + w) / 2``, for every axis ratio (:func:`core.theory.point_contact.ft_limit_point`), with
``w = W / a`` and ``a`` the semi-axis along the rocking.

How it compares: the 3D solver (a coarse grid of ``a/10``, twelve periods) is run just below and
above that limit at ``w = 0.3`` for the sphere and the ellipsoid; both shake down below and keep
walking above, as printed. The figure draws the final traction of the run below the limit on the
ellipse's grid.
"""

import matplotlib.pyplot as plt
import numpy as np

import core

w = 0.3
ft_lim = float(core.ft_limit(w, body="ellipsoid"))
print(f"exact limit at w = {w}: ft_lim = {ft_lim:.4f} (sphere: {float(core.ft_limit(w, body='sphere')):.4f})")
runs = {}
for body, ratio in (("sphere", None), ("ellipsoid", 2.0)):
    for ft in (0.8 * ft_lim, min(0.95, 1.3 * ft_lim)):
        r = core.simulate_point_contact(ft, w, periods=12, dx=1 / 10, body=body, ratio=ratio)
        runs[body, round(ft, 3)] = r
        print(f"{body:9s} ft = {ft:.3f}: {r.regime:12s} last increments "
              f"{', '.join(f'{v:.1e}' for v in r.increment_per_period[-3:])}")

r = runs["ellipsoid", round(0.8 * ft_lim, 3)]
q = np.asarray(r.final_traction)
qx = q[0] if q.ndim == 3 else q
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
mesh = ax.pcolormesh(r.x_edges, r.y_edges, qx, cmap="viridis", shading="flat")
fig.colorbar(mesh, label="q_x / (mu p0)")
ax.set_aspect("equal")
ax.set(xlabel="x / a", ylabel="y / a", title=f"Ellipsoid (Ry = 2 Rx), ft = {0.8 * ft_lim:.3f}, w = {w}: final traction")
plt.show()
