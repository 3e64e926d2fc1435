"""
Sampled surfaces: a wavy cylinder and a worn sphere
===================================================

Beyond the paper: bodies given by their sampled gap, as a designed or measured surface would be
(``core.geometry.heightmap``; a profilometer file is read with SurfaceTopography through
``HeightProfile.from_topography`` and ``HeightMap.from_topography``).

* :class:`core.HeightProfile` is a line body (plane strain) on the 1D engine: here the cylinder,
  ``(2/pi) x^2`` in ``P/E*``, with a waviness ``A (1 - cos(2 pi x / 0.25))`` sampled every ``a/200``.
  Its pressure comes from the numerical normal solve and its exact limit from Melan's theorem
  (``core.ft_limit(w, body=profile)``). With ``A = 0`` the sampled cylinder gives eq 35 (0.6238 at
  ``w = 0.3``); a waviness of ``A = 0.01`` lowers the limit to 0.517 and ``A = 0.03`` to 0.188: the
  pressure ripples with the waviness, so its lowest value over the stroke, and with it the traction
  the contact can hold at every point, falls.
* :class:`core.HeightMap` is a rigid surface on a square grid, rocked along x like the sphere: here
  the sphere ``(3/8) r^2`` in ``P/(E* a)`` (``a`` the sphere's Hertz radius) worn flat over a disc of
  radius ``b``, on a 64 x 64 grid of step ``a/20``. Its limit is Melan's ``integral p_min / integral
  p`` (``w`` rounded to whole grid steps). The unworn map gives the sphere's closed form
  ``(1 - w)^2 (2 + w) / 2`` to 0.0002 (0.7038 and 0.3123 at ``w = 0.2`` and 0.5, against 0.7040 and
  0.3125); worn flat to ``b = 0.6`` its pressure spreads over a wider disc (5.32 a^2 against 3.18)
  with a lower peak (0.51 p0), and at the same ``W`` its limit rises from 0.312 to 0.433 (``w = 0.5``).

How it compares: there is no such figure in the paper; the unworn surfaces reproduce its cylinder
and the sphere's closed form. Height maps give limits only: the 3D cycle-by-cycle solver takes
Hertz's pressure.
"""

import matplotlib.pyplot as plt
import numpy as np

import core
from core.geometry.heightmap import HeightMap, HeightProfile

fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(11, 3.6), layout="constrained")

# a wavy cylinder: a line profile on the 1D engine
x = np.linspace(-2, 2, 801)
w_grid = np.linspace(0.0, 0.9, 10)
ax1.plot(core.ft_limit(w_grid), w_grid, color="0.3", lw=2, label="cylinder, eq 35")
for amp, color in zip((0.0, 0.01, 0.03), ("#009E73", "#0072B2", "#D55E00")):
    profile = HeightProfile((2 / np.pi) * x**2 + amp * (1 - np.cos(2 * np.pi * x / 0.25)), x[1] - x[0])
    ax1.plot([float(core.ft_limit(w, body=profile)) for w in w_grid], w_grid, color=color, lw=1.5, ls="--",
             marker=".", label=f"waviness A = {amp}")
    print(f"wavy cylinder, A = {amp}: ft_lim(w = 0.3) = {float(core.ft_limit(0.3, body=profile)):.4f}")
ax1.set(xlabel="ft_lim", ylabel="w_lim", title="Line profile: exact limits", xlim=(0, 1), ylim=(0, 1))
ax1.legend(fontsize=8)

# a worn sphere: a height map
h = 0.05
xs = (np.arange(64) + 0.5) * h - 1.6
X, Y = np.meshgrid(xs, xs)
r = np.hypot(X, Y)
w_map = np.arange(0.0, 0.95, 0.1)
ax3.plot(1 - 1.5 * w_map + 0.5 * w_map**3, w_map, color="0.3", lw=2, label="sphere, closed form")
for b, color in zip((0.0, 0.4, 0.6), ("#009E73", "#0072B2", "#D55E00")):
    surface = HeightMap(0.375 * np.maximum(r - b, 0.0) ** 2, h)
    sol = surface.solve()
    row = sol.pressure.shape[0] // 2  # the cut nearest y = 0
    ax2.step(xs, sol.pressure[row], where="mid", color=color, lw=1.5, label=f"worn flat to b = {b}")
    ax3.plot([surface.ft_limit(w) for w in w_map], w_map, color=color, lw=1.5, ls="--", marker=".",
             label=f"b = {b}")
    print(f"worn sphere, b = {b}: contact area {sol.area:.2f} a^2, peak pressure {sol.pressure.max():.3f} p0, "
          f"ft_lim(w = 0.2, 0.5) = {surface.ft_limit(0.2):.4f}, {surface.ft_limit(0.5):.4f}")
print(f"sphere's closed form: ft_lim(w = 0.2, 0.5) = {1 - 1.5 * 0.2 + 0.5 * 0.2**3:.4f}, "
      f"{1 - 1.5 * 0.5 + 0.5 * 0.5**3:.4f}")
ax2.set(xlabel="x / a (y = 0)", ylabel="p / p0", title="Height map: pressure")
ax2.legend(fontsize=8)
ax3.set(xlabel="ft_lim", ylabel="w_lim = W / a", title="Height map: exact limits", xlim=(0, 1), ylim=(0, 1))
ax3.legend(fontsize=8)
plt.show()
