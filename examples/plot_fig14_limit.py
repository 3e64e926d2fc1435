"""
Fig 14: the shakedown limit
===========================

The paper's Fig 14: the largest amplitude that still shakes down, ``w_lim``, against the load
``ft_lim``: the exact limit eq 35, the paper's regression eq 36, and the paper's simulations.

How it compares: for five loads the solver brackets the limit by transients only (bisection in
``w`` from the whole range, :func:`core.numerical_limit_curve`; triangles: the last amplitude that
shook down and the first that ratcheted, to ``5e-3`` in ``w`` with twenty periods on a grid of
``a/40``). Eq 35 lies inside every bracket, as printed. The paper's regression eq 36 is off eq 35
by the amount printed (about 0.01 in ``w``). The sphere's exact limit (dash-dot) lies below the cylinder's at every
amplitude: the sphere bears the lower tangential force, the opposite of what the paper states (see
the user guide's "Cylinder versus sphere").
"""

import matplotlib.pyplot as plt

from core.maps import paper_figures

data = paper_figures.limit_curve(ft_values=(0.1, 0.3, 0.5, 0.7, 0.9), tol=5e-3, dx=1 / 40, periods=20)
line, pts = data["line"], data["points"]
fig, ax = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
ax.plot(line["ft"], line["w_eq35"], color="#0072B2", lw=2, label="eq 35 (exact)")
ax.plot(line["ft"], line["w_eq36"], color="#E69F00", lw=1.5, ls="--", label="eq 36 (paper's regression)")
ax.plot(line["ft"], line["w_sphere"], color="#009E73", lw=1.5, ls="-.", label="sphere (exact)")
ax.plot(pts["ft"], pts["w_shakedown"], "^", color="#0072B2", label="solver: last shakedown")
ax.plot(pts["ft"], pts["w_ratcheting"], "v", color="#D55E00", label="solver: first ratcheting")
ax.set(xlabel="ft_lim", ylabel="w_lim", title="Fig 14: the shakedown limit", xlim=(0, 1), ylim=(0, 1))
ax.legend(fontsize=8)
inside, total = data["eq35_in_bracket"]
print(f"eq 35 inside {inside} of {total} brackets; eq 36 - eq 35 up to {data['max_regression_difference']:.3f} in w")
for ft, lo, hi in zip(pts["ft"], pts["w_shakedown"], pts["w_ratcheting"]):
    print(f"ft = {ft}: w_lim in [{lo:.3f}, {hi:.3f}]")
plt.show()
