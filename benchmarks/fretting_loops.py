"""The energy dissipated per cycle against the closed forms of Cattaneo-Mindlin with Masing's rule (issue 30).

Prints, for the cylinder (plane strain, :func:`core.simulate_cycles` with ``history="tangential"``) and the rigid
sphere on a nu = 0.5 half-space (:func:`core.api.point_runs.solve_point_schedule` with the same schedule), the energy of
the last period and the area of its fretting loop at several amplitudes and two grids, beside
:func:`core.fretting_energy`, with the grid error (the difference between the two grids), the verdict and the run
time. Run: ``PYTHONPATH=. python benchmarks/fretting_loops.py`` (about a minute on a quiet core).
"""

import time

import core
from core.loading import histories
from core.api.point_runs import solve_point_schedule

PERIODS = 6


def row(body, A, dx, r, seconds):
    exact = float(core.fretting_energy(A, body))
    E = float(r.dissipation_per_period[-1])
    loop = r.fretting_loop().work
    print(f"| {body} | {A:.2f} | a/{1 / dx:.0f} | {E:.6f} | {loop:.6f} | {exact:.6f} | {100 * (E / exact - 1):+.2f} % "
          f"| {100 * (loop / exact - 1):+.2f} % | {r.regime} | {r.xc.size} | {seconds:.1f} s |", flush=True)
    return E


def main():
    print("| body | A | dx | E (dissipation) | loop area | closed form | E error | loop error | verdict | steps "
          "| time |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    grid_errors = []
    for A in (0.2, 0.5, 0.8):
        energies = []
        for dx in (0.05, 0.025):
            t = time.perf_counter()
            r = core.simulate_cycles(0.0, 0.0, periods=PERIODS, history="tangential", amplitude=A, dx=dx)
            energies.append(row("cylinder", A, dx, r, time.perf_counter() - t))
        grid_errors.append(("cylinder", A, energies[1] - energies[0]))
    for A in (0.2, 0.35, 0.6):
        energies = []
        for dx in (0.1, 0.05):
            t = time.perf_counter()
            r = solve_point_schedule(histories.tangential(0.0, A, periods=PERIODS), dx, core.Sphere(), nu=0.5)
            energies.append(row("sphere", A, dx, r, time.perf_counter() - t))
        grid_errors.append(("sphere", A, energies[1] - energies[0]))
    print()
    for body, A, d in grid_errors:
        exact = float(core.fretting_energy(A, body))
        print(f"grid error (fine - coarse) {body} A = {A}: {d:+.2e} ({100 * d / exact:+.2f} % of the closed form)")


if __name__ == "__main__":
    main()
