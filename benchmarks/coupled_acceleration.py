"""Does the coupled alternation accelerate? Passes per step with Anderson mixing or a relaxation factor.

The coupled solver (:mod:`core.solvers.coupled`) alternates the normal and the tangential solves until neither field
changes by more than the KKT tolerance: about 8.6 passes a step at ``|beta| = 0.25``, 6.1 at 0.1 (rocking
cylinder, ``w = 0.6``, ``ft`` at eq 35, ``a/40``, 20 periods, ``mu = 0.3``), each pass narrowing the change by
0.02-0.07. This replays the run through the Python alternation (``CoupledSolver._solve_general``'s passes: the
normal solve, the tangential solve with the pressure's slip, the change), mixing the next tractions by

* Anderson's method with the last ``m`` passes (``--anderson m``, 0: the plain alternation), or
* a relaxation factor ``omega``: ``q <- (1 - omega) q + omega T(q)`` (``--omega``), or from
* another first guess of a step's tractions (``--guess``),

and prints the mean passes a step, their histogram, the last period's increment and energy (the same to the
tolerance: the fixed point does not depend on the mixing) and the worst residual. Few passes saved means the
error of the alternation spreads over many modes (no dominant one for a secant step to remove).

Run: python benchmarks/coupled_acceleration.py --anderson 3 ; python benchmarks/coupled_acceleration.py --omega 0.97
"""

from __future__ import annotations

import argparse

import numpy as np


def install(anderson: int, omega: float, counts: list, guess: str = "extrapolated") -> None:
    """Replace the coupled solver's march by a Python one over the mixed alternation (this process only)."""
    from core.solvers import _pdas
    from core.solvers import coupled as cc

    def solve(self, k, target):
        st = self.inner.state
        q_true = st.q_prev.copy()
        gap0 = self.profile(self.x - self.xc[k])
        load = self.load_factor * float(self.P[k])
        p = self.p_prev if self.p_prev.any() else None
        # ---- the first guess of the tractions (the solver's: the last increment repeated)
        move = int(np.rint((self.xc[k] - self.xc[k - 1]) / self.dx)) if k > 0 else 0
        q = {"extrapolated": q_true + self._dq_last, "previous": q_true.copy(),
             "moved": np.roll(q_true, move), "moved-extrapolated": np.roll(q_true + self._dq_last, move)}[guess]
        F, G = [], []
        lam, ok, change, it = 0.0, False, np.inf, 0
        try:
            for it in range(1, self.max_alternations + 1):
                p_new = self._normal(gap0, load, q, p)
                st.q_prev[:] = q_true + self._shift(p_new - self.p_prev)
                lam, ok = _pdas.solve_step(self.K, p_new, float(target), self.dx, self.tol, self.maxiter, st)
                if not ok:
                    break
                g = st.q.copy()
                f = g - q
                change = max(float(np.abs(p_new - p).max()) if p is not None else np.inf, float(np.abs(f).max()))
                p = p_new
                if change <= self.tol:
                    break
                F, G = (F + [f])[-(anderson + 1):], (G + [g])[-(anderson + 1):]
                q = (1 - omega) * q + omega * g
                if anderson and len(F) > 1:
                    dF = np.array([b - a for a, b in zip(F, F[1:])]).T
                    dG = np.array([b - a for a, b in zip(G, G[1:])]).T
                    q = g - dG @ np.linalg.lstsq(dF, f, rcond=None)[0]
        finally:
            st.q_prev[:] = q_true
        counts.append(it)
        return lam, p, ok and change <= self.tol, it, change

    def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out):
        st = self.inner.state
        for k in range(k0, k1):
            lam, p, ok, passes, change = solve(self, k, Q[k] * load_scale)
            if not ok or not self._record(k, k0, lam, p, change, passes, bounds, out):
                return k, -1, k
            if k + 1 < Q.size and period[k + 1] != period[k]:
                if _pdas.block_repeats(st.q, st.q_block_end, self.tol) and detect_periodic and period[k] >= 0:
                    return k + 1, int(period[k]), -1
        return k1, -1, -1

    cc.CoupledSolver.march = march


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--anderson", type=int, default=0, help="passes Anderson's mixing remembers (0: none)")
    ap.add_argument("--omega", type=float, default=1.0, help="relaxation factor of the plain alternation")
    ap.add_argument("--guess", default="extrapolated",
                    choices=("extrapolated", "previous", "moved", "moved-extrapolated"),
                    help="first guess of a step's tractions: the last increment repeated (the solver's), the previous "
                         "tractions, or either moved with the centre")
    args = ap.parse_args(argv)
    import core

    counts: list = []
    install(args.anderson, args.omega, counts, args.guess)
    ft = float(core.ft_limit(0.6))
    for beta in (0.25, 0.1):
        counts.clear()
        r = core.simulate_cycles(ft, 0.6, periods=20, beta=beta, mu=0.3)
        print(f"anderson {args.anderson} omega {args.omega} guess {args.guess} beta {beta}: {len(counts)} steps, "
              f"{np.mean(counts):.2f} passes a step, histogram {np.bincount(counts).tolist()}, "
              f"increment {r.increment_per_period[-1]:.12g}, energy {r.summary()['energy_last_period']:.12g}, "
              f"worst residual {max(r.residuals.values()):.2e}", flush=True)


if __name__ == "__main__":
    main()
