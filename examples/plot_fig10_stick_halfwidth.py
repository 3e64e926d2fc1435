"""
Fig 10: the stick half-width after shakedown
============================================

The paper's Fig 10: the half-width of the stick zone after shakedown, ``c_sd / a``, against
``ft`` for several amplitudes ``w`` (``w = 0`` is Cattaneo's static ``sqrt(1 - ft)``). It shrinks
to zero at the limit ``ft_lim(w)`` of eq 35.

How it compares: the solver's direct shaken-down states (:func:`core.maps.paper_figures.stick_halfwidth_curves`,
the paper's strip model) are drawn as markers on the paper's closure eq 30 (lines). Here on a grid of
``a/100`` and eight loads per amplitude (the explorer's shipped data uses ``a/400`` and sixteen);
the largest difference printed is within about one element, so the closure is right to the
resolution of the grid.
"""

import matplotlib.pyplot as plt

from core.maps import paper_figures

data = paper_figures.stick_halfwidth_curves(points=8, dx=1 / 100)
fig, ax = plt.subplots(figsize=(6.4, 4), layout="constrained")
for curve, color in zip(data["curves"], ("0.3", "#0072B2", "#E69F00", "#009E73")):
    ax.plot(curve["ft"], curve["eq30"], color=color, lw=1.5, label=f"eq 30, w = {curve['w']}")
    ax.plot(curve["ft"], curve["solver"], "o", color=color, ms=5)
ax.set(xlabel="ft = Ft / (mu Fn)", ylabel="c_sd / a", title="Fig 10: stick half-width after shakedown (o: solver)")
ax.legend(fontsize=8)
print(f"largest |solver - eq 30| = {data['max_difference']:.4f} a at dx = a/100")
plt.show()
