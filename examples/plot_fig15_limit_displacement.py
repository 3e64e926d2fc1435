"""
Fig 15: the largest shakedown displacement
==========================================

The paper's Fig 15: ``u_lim``, the largest displacement at which the contact still shakes down,
against the amplitude (at the limit ``ft = ft_lim(w)`` of eq 35).

How it compares: at the limit the stick zone has shrunk to the centre and the whole contact
carries ``mu p_min``, so the solver's ``u_lim`` is the centre displacement of that traction over
``U0`` (the paper's strip model, grid ``a/100``). The paper's formula for it (eq 37) is unreadable
in the text; the nearest readable formula, eq 34 at ``(ft_lim(w), w)``, is drawn instead, and the
largest difference printed.
"""

import matplotlib.pyplot as plt
import numpy as np

from core.maps import paper_figures

data = paper_figures.limit_displacement_curve(w_values=tuple(np.round(np.linspace(0.0, 0.9, 10), 6)), dx=1 / 100)
fig, ax = plt.subplots(figsize=(6.4, 4), layout="constrained")
ax.plot(data["w"], data["eq34_at_limit"], color="#0072B2", lw=1.5, label="eq 34 at (ft_lim(w), w)")
ax.plot(data["w"], data["solver"], "^", color="#D55E00", label="solver")
ax.set(xlabel="w", ylabel="u_lim = U_lim / U0", title="Fig 15: the largest shakedown displacement")
ax.legend(fontsize=8)
print(f"largest |solver - eq 34 at the limit| = {data['max_difference']:.4f}")
plt.show()
