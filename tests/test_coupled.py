"""The coupled per-step solver (core/solvers/coupled.py) in the one engine: beta = 0 reproduces today's runs, the coupled
solver at beta = 0 reproduces the dense solver on its own pressures to round-off, Spence's stick zone under a
growing normal load, the refusals (point contacts, bad beta or mu), and a coupled result's Melan reference."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

import core
from core.loading import histories
from core.geometry.bodies import Cylinder
from core.march.engine import make_operator, run, select_solver
from core.theory.materials import spence_stick_ratio


def test_beta_zero_is_today_s_run_and_mu_is_irrelevant():
    today = core.simulate_cycles(0.4, 0.5, periods=4)
    for mu in (None, 0.2, 3.0):
        r = core.simulate_cycles(0.4, 0.5, periods=4, beta=0.0, mu=mu)
        assert r.solver == today.solver and not r.coupled and r.mu is None
        assert np.array_equal(r.displacement, today.displacement)
        assert np.array_equal(r.traction, today.traction)
        assert r.params == today.params and r.melan_limit == today.melan_limit


class _Replay(Cylinder):
    """A cylinder's grid whose bounds are given pressures by centre and load (the coupled run's own)."""

    def __init__(self, edges, rows):
        super().__init__(edges)
        self.rows = rows

    def bounds(self, xc, P, out=None):
        out = np.empty((len(xc), self.size)) if out is None else out
        for i, key in enumerate(zip(np.round(xc, 12), np.round(P, 12))):
            out[i] = self.rows[key]
        return out


def test_coupled_solver_at_beta_zero_is_the_dense_solver_to_round_off():
    """At beta = 0 the alternation is one pass: the dense solver's increment on the numerically solved pressure.
    Replaying that pressure through the dense solver gives the same steps to round-off."""
    ft, w, periods, dx = 0.45, 0.4, 3, 1 / 40
    coupled = core.simulate_cycles(ft, w, periods=periods, dx=dx, solver="coupled", mu=0.5)
    assert coupled.solver == "coupled" and coupled.residuals["alternation"] == 0.0
    schedule = histories.for_run("rocking", ft, w, periods=periods, dW=dx)
    rows = {(round(float(x), 12), round(float(P), 12)): coupled.pressures[coupled.pressure_index[k]]
            for k, (x, P) in enumerate(zip(schedule.xc, schedule.P))}
    grid = _Replay(coupled.edges, rows)
    cls = select_solver("dense", grid.size)
    dense = run(grid, make_operator(cls, grid.size, grid.dx), schedule, solver="dense", tol=1e-10)
    assert_allclose(dense.displacement, coupled.displacement, rtol=0, atol=1e-12)
    assert_allclose(dense.traction, coupled.traction, rtol=0, atol=1e-12)
    assert np.array_equal(dense.state, coupled.state)
    # and the numerical pressure is Hertz's to the discretisation: the increments agree with today's run to 0.1 %
    today = core.simulate_cycles(ft, w, periods=periods, dx=dx)
    assert_allclose(coupled.increment_per_period, today.increment_per_period, rtol=2e-3)


@pytest.mark.parametrize("beta, mu", [(0.1, 0.1), (-0.15, 0.1), (0.05, 0.1)])
def test_spence_stick_zone_under_growing_normal_load(beta, mu):
    """Pressed from 2 % to the full load in 60 steps with no tangential load, the contact keeps a central stick
    zone of Spence's c/a (a function of |beta|/mu; here beta mu <= 0.015, so the traction's effect on the pressure,
    which the closed form neglects, is small) within 1.5 elements; the edges slip outwards on the substrate for
    beta > 0 (q = mu p sign(x)) and inwards for beta < 0."""
    dx = 1 / 80
    P = np.linspace(0.02, 1.0, 60)
    r = core.simulate_cycles(0.0, 0.0, history=dict(xc=np.zeros(P.size), P=P, Q=np.zeros(P.size)), dx=dx,
                             beta=beta, mu=mu)
    x, q, p = r.x, r.traction[-1], r.pressures[r.pressure_index[-1]]
    contact = p > 0
    a = x[contact].max() + dx / 2
    c = np.abs(x[contact & (np.abs(q) < p - 1e-9)]).max() + dx / 2
    assert abs(c - spence_stick_ratio(abs(beta) / mu) * a) <= 1.5 * dx, (c, a)
    edge = contact & (np.abs(x) > c + dx)
    assert_allclose(q[edge], np.sign(beta) * np.sign(x[edge]) * p[edge], atol=1e-9)
    assert max(r.residuals.values()) < 1e-7


def test_refusals_name_the_input():
    with pytest.raises(ValueError, match="line contacts only"):
        core.simulate_cycles(0.2, 0.3, periods=2, body="sphere", beta=0.1, mu=0.3)
    with pytest.raises(ValueError, match="beta"):
        core.simulate_cycles(0.2, 0.3, periods=2, beta=0.5, mu=0.3)
    with pytest.raises(ValueError, match="mu is required"):
        core.simulate_cycles(0.2, 0.3, periods=2, beta=0.1)
    with pytest.raises(ValueError, match="mu"):
        core.simulate_cycles(0.2, 0.3, periods=2, beta=0.1, mu=-1.0)
    with pytest.raises(ValueError, match="kernel='plane'"):
        core.simulate_cycles(0.2, 0.3, periods=2, beta=0.1, mu=0.3, kernel="strip", L_over_a=50)
    with pytest.raises(ValueError, match="coupled solver"):
        core.simulate_cycles(0.2, 0.3, periods=2, beta=0.1, mu=0.3, solver="fft")


def test_a_coupled_run_keeps_melan_as_the_uncoupled_reference():
    r = core.simulate_cycles(0.5, 0.3, periods=6, beta=0.25, mu=0.3)
    today = core.simulate_cycles(0.5, 0.3, periods=6)
    assert r.coupled and r.solver == "coupled" and r.beta == 0.25 and r.mu == 0.3
    assert r.params["beta"] == 0.25 and r.params["mu"] == 0.3
    assert r.melan_limit == pytest.approx(today.melan_limit, rel=1e-12)  # the uncoupled contact's
    assert "Melan" not in r.regime_reason
    assert set(r.residuals) >= {"gap", "pressure", "alternation", "stick_slip", "bound"}
    assert max(r.residuals.values()) < 1e-7
    # the coupled pressure is not Hertz's: the lowest pressure differs
    common = np.isin(np.round(r.x, 9), np.round(today.x, 9))  # the coupled grid is wider
    assert common.sum() == today.x.size
    assert np.abs(r.lowest_pressure[common] - today.lowest_pressure).max() > 1e-2
    # and the result keeps that pressure, step by step: the last period's lowest is the stored steps' lowest
    last = r.period == r.period[-1]
    np.testing.assert_array_equal(np.asarray(r.pressure)[last].min(axis=0), r.lowest_pressure)


def test_a_coupled_contact_below_its_limit_that_repeats_dissipating_is_cyclic_slip():
    """At beta = +-0.1, w = 0.3 and 0.6 times eq 35 the coupled cylinder stops walking and its state repeats from
    period 9-10 with a steady dissipation of 2.8e-5 mu^2 P^2/E* a period (7e-4 of the first period's): that is
    cyclic slip (the verdict once called it shakedown, the energy being below 1e-3 of the largest); the uncoupled
    contact dissipates nothing once it repeats, and shakes down."""
    ft = 0.6 * float(core.ft_limit(0.3))
    for beta in (0.1, -0.1):
        r = core.simulate_cycles(ft, 0.3, periods=20, beta=beta, mu=0.3)
        assert r.periodic_from is not None and r.dissipation_per_period[-1] > 1e-5
        assert r.regime == "cyclic slip", r.regime_reason
        assert "repeats" in r.regime_reason
    r = core.simulate_cycles(ft, 0.3, periods=20)
    assert r.periodic_from is not None and r.dissipation_per_period[-1] == 0.0
    assert r.regime == "shakedown", r.regime_reason


def test_a_contact_of_two_intervals_takes_the_general_normal_solve():
    """Two bumps: the contact is two intervals, which the compiled alternation hands to the Python one (the general
    normal solve, core.pressure.normal.solve_line): solved to the tolerance with every named residual."""
    from core.geometry.heightmap import HeightProfile

    x = np.linspace(-3, 3, 1201)
    body = HeightProfile(4 * (x ** 2 - 0.5) ** 2, 0.005)
    r = core.simulate_cycles(0.3, 0.2, periods=2, dx=1 / 20, body=body, beta=0.2, mu=0.4)
    p = r.pressures[r.pressure_index[-1]]
    assert np.count_nonzero(np.diff((p > 0).astype(int)) == 1) == 2
    assert r.coupled and max(r.residuals.values()) < 1e-7
    assert np.all(np.abs(r.traction) <= r.pressures[r.pressure_index] + 1e-9)


def test_a_physical_contact_runs_coupled_unless_it_names_its_kernel():
    """Contact.simulate() of a coupled pair (|beta| >= 1e-3) runs coupled on the plane kernel with its own beta and
    mu; a run that names its kernel without beta (the explorer's) stays the uncoupled model it was."""
    c = core.Contact(R1=0.02, L=0.1, Fn=1e3, mu=0.3, materials="steel/aluminium", ft=0.4, w=0.3)
    assert c.coupled and not core.Contact(R1=0.02, L=0.1, Fn=1e3, mu=0.3, materials="steel/rubber").coupled
    r = c.simulate(periods=2, dx=0.1)
    assert r.coupled and r.kernel == "plane" and r.beta == pytest.approx(c.beta) and r.mu == 0.3
    u = c.simulate(periods=2, dx=0.1, kernel="strip")
    assert not u.coupled and u.kernel == "strip"


def test_the_compiled_march_is_the_python_alternation(monkeypatch):
    """The compiled march (core.solvers._coupled.march) and the Python alternation with the general normal solve
    (CoupledSolver._solve_general, taken for every step when the kernel hands each step back) solve the same
    coupled steps: the same states, increments and tractions to the alternation's tolerance."""
    from core.solvers import _coupled

    kw = dict(periods=2, dx=1 / 20, beta=0.25, mu=0.3)
    compiled = core.simulate_cycles(0.2, 0.6, **kw)

    def every_step_general(*args):
        return args[9], -1, -1, _coupled.STATUS_GENERAL  # reached = k0: this step to the general solve

    monkeypatch.setattr(_coupled, "march", every_step_general)
    general = core.simulate_cycles(0.2, 0.6, **kw)
    assert compiled.coupled and general.coupled and len(compiled.xc) == len(general.xc)
    assert max(general.residuals.values()) <= 1e3 * 1e-10 and max(compiled.residuals.values()) <= 1e3 * 1e-10
    assert np.array_equal(compiled.state, general.state)
    assert_allclose(compiled.displacement, general.displacement, rtol=0, atol=1e-8)
    assert_allclose(compiled.traction, general.traction, rtol=0, atol=1e-8)
    assert_allclose(np.asarray(compiled.pressure), np.asarray(general.pressure), rtol=0, atol=1e-8)


def _hertz_problem(n=120, dx=1 / 40):
    """A tangential step on a Hertz bound: ``K`` (Toeplitz), the bound, previous tractions and a target."""
    from core.elastic.kernels import influence_matrix

    K = np.ascontiguousarray(influence_matrix(n, dx))
    x = (np.arange(n) - (n - 1) / 2) * dx
    g = np.sqrt(np.clip(1 - x ** 2, 0, None))
    return K, g, dx


def test_the_settled_passes_stick_solve_is_solve_step_on_the_same_set():
    """core.solvers._pdas.fixed_set_stick (the coupled alternation's passes once its sets have settled) gives
    solve_step's tractions and rigid increment when the set is right, to round-off, and declines a state
    without the Toeplitz inverses."""
    import copy

    from core.solvers import _pdas

    K, g, dx = _hertz_problem()
    n = g.size
    st = _pdas.with_capacity(_pdas.new_state(n, K[:, 0]), n)
    target = 0.3 * g.sum()
    lam0, ok = _pdas.solve_step(K, g, target, dx, 1e-12, 200, st)
    assert ok and (st.kind == _pdas.UPPER).any() and (st.kind == _pdas.FREE).any()  # partial slip
    st.q_prev[:] = st.q
    # the next step: a slightly larger load on a slightly moved bound, from the converged set
    g1 = np.roll(g, 1) * (1 + 1e-3)
    checked = copy.deepcopy(st)
    lam, ok = _pdas.solve_step(K, g1, 1.001 * target, dx, 1e-12, 200, checked)
    assert ok and checked.counters[_pdas.ITERATIONS] >= 1
    settled = copy.deepcopy(st)
    settled.kind[:] = checked.kind  # the set solve_step found
    lam_s, ok_s = _pdas.fixed_set_stick(g1, 1.001 * target, settled)
    assert ok_s
    assert_allclose(lam_s, lam, rtol=0, atol=1e-12)
    assert_allclose(settled.q, checked.q, rtol=0, atol=1e-12)
    # no Toeplitz inverses (a K that is not Toeplitz): the full solve's work
    plain = _pdas.new_state(n)
    plain.kind[:] = checked.kind
    plain.q_prev[:] = st.q_prev
    assert _pdas.fixed_set_stick(g1, 1.001 * target, plain) == (0.0, False)


def test_the_interval_inverses_are_k_inverted_and_kept_a_few_widths_at_a_time():
    from core.solvers import _coupled

    K, _, _ = _hertz_problem(n=60)
    C, ok = _coupled.cholesky(K)
    CT = np.ascontiguousarray(C.T)
    inv = _coupled.new_inverses(K)
    slots = {}
    for L in (20, 21, 19, 20, 22):
        slot = _coupled.inverse(inv, C, CT, L)
        A = inv.A[slot, :L, :L]
        assert_allclose(A @ K[:L, :L], np.eye(L), rtol=0, atol=1e-10)
        assert_allclose(inv.ones[slot, :L], A.sum(axis=1), rtol=1e-13)
        slots.setdefault(L, slot)
        assert slot == slots[L]  # a width met again is found, not recomputed elsewhere
    # a fifth width replaces the least recently used (21): the other widths stay
    slot = _coupled.inverse(inv, C, CT, 30)
    assert slot == slots[21] and sorted(inv.length.tolist()) == [19, 20, 22, 30]


def _counting(monkeypatch):
    """Record each march's passes, full tangential solves and direct solves per solved step."""
    import core.solvers.coupled as cc

    seen = []
    march = cc.CoupledSolver.march

    def counting(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out):
        done = march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out)
        seen.append(np.stack([out.alternations[k0:done[0]], out.full_solves[k0:done[0]],
                              out.direct_solves[k0:done[0]]]))
        return done

    monkeypatch.setattr(cc.CoupledSolver, "march", counting)
    return seen


def test_the_alternation_alone_keeps_its_sets_on_most_passes(monkeypatch):
    """Without the direct solve the alternation makes the full tangential solve (with its checks) on the first
    pass and on the last, and keeps the settled sets in between: counted per step, the same regime and residuals
    within the tolerance."""
    import core.solvers.coupled as cc

    monkeypatch.setattr(cc.CoupledSolver, "direct", False)
    seen = _counting(monkeypatch)
    r = core.simulate_cycles(float(core.ft_limit(0.6)), 0.6, periods=3, beta=0.25, mu=0.3)
    passes, full, direct = np.concatenate(seen, axis=1)
    assert passes.size and (full >= 1).all() and (full <= passes).all() and not direct.any()
    assert full.sum() < 0.5 * passes.sum()
    assert max(r.residuals.values()) <= 1e3 * 1e-10


def test_most_coupled_steps_are_one_direct_solve_and_agree_with_the_alternation(monkeypatch):
    """With the direct solve (the default) most steps are solved at once from the last step's sets, with no
    pass; the result is the alternation's: the same states, and increments, tractions and pressures within the
    alternation's tolerance, both at beta 0.25 and 0.1."""
    import core.solvers.coupled as cc

    for beta, ft in ((0.25, float(core.ft_limit(0.6))), (-0.1, 0.8 * float(core.ft_limit(0.6)))):
        seen = _counting(monkeypatch)
        kw = dict(periods=3, beta=beta, mu=0.3)
        fast = core.simulate_cycles(ft, 0.6, **kw)
        passes, full, direct = np.concatenate(seen, axis=1)
        assert (passes == 0).mean() > 0.9 and (direct >= 1).mean() > 0.95
        assert direct.sum() < 1.5 * passes.size  # most first guesses are right
        monkeypatch.setattr(cc.CoupledSolver, "direct", False)
        slow = core.simulate_cycles(ft, 0.6, **kw)
        monkeypatch.setattr(cc.CoupledSolver, "direct", True)
        assert fast.regime == slow.regime and np.array_equal(fast.state, slow.state)
        assert_allclose(fast.displacement, slow.displacement, rtol=0, atol=1e-8)
        assert_allclose(fast.traction, slow.traction, rtol=0, atol=1e-8)
        assert_allclose(np.asarray(fast.pressure), np.asarray(slow.pressure), rtol=0, atol=1e-8)
        assert max(fast.residuals.values()) <= 1e-10


def _window_system(K, S, cn, ct, Lw):
    """The coupled system of a window in full stick, written out (core.solvers._coupled.window_inverse's)."""
    N = 2 * Lw + 2
    M = np.zeros((N, N))
    M[:Lw, :Lw], M[:Lw, Lw:2 * Lw], M[:Lw, 2 * Lw] = K[:Lw, :Lw], cn * S[:Lw, :Lw], -1
    M[Lw:2 * Lw, :Lw], M[Lw:2 * Lw, Lw:2 * Lw], M[Lw:2 * Lw, 2 * Lw + 1] = -ct * S[:Lw, :Lw], K[:Lw, :Lw], -1
    M[2 * Lw, :Lw] = M[2 * Lw + 1, Lw:2 * Lw] = 1
    return M


def test_the_direct_solve_is_the_coupled_system_with_its_sets_fixed():
    """core.solvers._coupled.direct (the window's inverse and a Sherman-Morrison-Woodbury correction for the rows of
    the elements that do not stick) gives the solution of the coupled step's linear system with the sets fixed,
    assembled here on the contact alone and solved by LAPACK, to round-off, and so does its increment form from the
    last solution (the march's); its window inverse is the inverse of the system in full stick; a contact wider
    than the window is declined."""
    from core.elastic.coupling import coupling_factors, cross_matrix
    from core.solvers import _coupled, _pdas

    K, g, dx = _hertz_problem(n=120)
    n = g.size
    S = cross_matrix(n, dx)
    cn, ct = coupling_factors(0.25, 0.3)
    Lw = 90
    WT = _coupled.window_inverse(K, dx, cn, ct, Lw)  # the inverse's transpose, then its prefix sums
    N = 2 * Lw + 2
    assert WT.shape == (N + 2 * (Lw + 1), N)
    assert_allclose(WT[:N].T @ _window_system(K, S, cn, ct, Lw), np.eye(N), rtol=0, atol=1e-10)
    ones, ramp = _coupled._prefix_sums(WT)
    for a in (0, 1, 37, Lw):  # the sums of W's first a normal columns, plain and weighted by their index
        assert_allclose(ones[a], WT[:a].sum(axis=0), rtol=0, atol=1e-12)
        assert_allclose(ramp[a], (np.arange(a)[:, None] * WT[:a]).sum(axis=0), rtol=0, atol=1e-10)

    x = (np.arange(n) - (n - 1) / 2) * dx
    gap0 = (2 / np.pi) * (x - 0.05) ** 2
    i0, i1 = 21, 101  # 80 elements
    kind = np.full(n, _pdas.OUT, dtype=np.int8)
    kind[i0:i1] = _pdas.FREE
    kind[i0:i0 + 4] = _pdas.LOWER
    kind[i1 - 6:i1] = _pdas.UPPER
    rng = np.random.default_rng(3)
    p_old = np.where((x > -1) & (x < 1), np.sqrt(np.clip(1 - x ** 2, 0, None)), 0.0) * (1 + 0.01 * rng.random(n))
    q_old = 0.3 * p_old * np.tanh(4 * x)
    load, target = 0.5 * np.pi, 0.4 * p_old.sum()
    q, p, scratch = np.zeros(n), np.zeros(n), np.zeros(n)
    ok, lam, delta = _coupled.direct(WT, K, gap0, load, dx, ct, target, q_old, p_old, i0, i1, kind, q, p, scratch)
    assert ok

    # the same system on the contact: unknowns (p, q, delta, lam), written row by row
    L = i1 - i0
    C = slice(i0, i1)
    M = np.zeros((2 * L + 2, 2 * L + 2))
    b = np.zeros(2 * L + 2)
    M[:L, :L], M[:L, L:2 * L], M[:L, 2 * L] = K[C, C], cn * S[C, C], -1
    b[:L] = -gap0[C]
    M[2 * L, :L], b[2 * L] = 1, load / dx
    M[2 * L + 1, L:2 * L], b[2 * L + 1] = 1, target
    for r, i in enumerate(range(i0, i1)):
        if kind[i] == _pdas.FREE:  # no slip: K q - ct S p - lam = K q_old - ct S p_old
            M[L + r, :L], M[L + r, L:2 * L], M[L + r, 2 * L + 1] = -ct * S[i, C], K[i, C], -1
            b[L + r] = K[i] @ q_old - ct * S[i] @ p_old
        else:  # at the bound: q = +-p
            M[L + r, L + r], M[L + r, r] = 1, -1.0 if kind[i] == _pdas.UPPER else 1.0
    ref = np.linalg.solve(M, b)
    assert_allclose(p[C], ref[:L], rtol=0, atol=1e-11)
    assert_allclose(q[C], ref[L:2 * L], rtol=0, atol=1e-11)
    assert_allclose([delta, lam], ref[2 * L:], rtol=0, atol=1e-11)
    assert not p[:i0].any() and not p[i1:].any() and not q[:i0].any() and not q[i1:].any()
    # the same solve for the increment from (p_old, q_old), as a step of the march makes it: the same solution
    b, y, q2, p2 = np.empty(N), np.empty(N), np.zeros(n), np.zeros(n)
    kp_old = np.where(p_old != 0, K @ p_old, -1e30)  # the march keeps K p_old on the last contact only
    w0 = _coupled.direct_rhs_step(WT, K, gap0, load, dx, cn, target, q_old, p_old, kp_old, i0, i1, scratch, b, y)
    assert w0 >= 0
    ok, lam2, delta2 = _coupled.direct_sets(WT, i0, i1, w0, kind, b, y, q2, p2, q_old, p_old, True)
    assert ok
    assert_allclose(p2, p, rtol=0, atol=1e-11)
    assert_allclose(q2, q, rtol=0, atol=1e-11)
    assert_allclose([delta2, lam2], [delta, lam], rtol=0, atol=1e-11)
    # a contact wider than the window: declined, nothing written
    q[:] = p[:] = 7.0
    ok, _, _ = _coupled.direct(WT, K, gap0, load, dx, ct, target, q_old, p_old, 10, 10 + Lw + 1, kind, q, p, scratch)
    assert not ok and (q == 7.0).all() and (p == 7.0).all()


def test_a_step_after_a_solved_one_needs_no_column_of_the_windows_inverse_for_a_parabolic_body():
    """core.solvers._coupled.direct_rhs_step: from the last step's solution, the next step's right-hand side on the
    contact of a parabolic body that moved is affine in the element (the profile's change less the last approach),
    and W b is made from the prefix sums of W's columns alone: with every normal column of W spoiled it is the same
    product. A body that is not parabolic, or an element that joins the contact, takes the columns it needs, and
    gives W b as well."""
    from core.elastic.coupling import coupling_factors
    from core.solvers import _coupled, _pdas

    K, g, dx = _hertz_problem(n=120)
    n = g.size
    cn, ct = coupling_factors(0.25, 0.3)
    Lw = 90
    WT = _coupled.window_inverse(K, dx, cn, ct, Lw)
    N = 2 * Lw + 2
    x = (np.arange(n) - (n - 1) / 2) * dx
    i0, i1 = 21, 101
    kind = np.full(n, _pdas.OUT, dtype=np.int8)
    kind[i0:i1] = _pdas.FREE
    kind[i0:i0 + 4] = _pdas.LOWER
    kind[i1 - 6:i1] = _pdas.UPPER
    load = 0.5 * np.pi
    scratch = np.zeros(n)

    def solved(gap0, q_old, p_old, target):  # a step's solution with these sets: a march's last step
        q, p = np.zeros(n), np.zeros(n)
        ok, lam, delta = _coupled.direct(WT, K, gap0, load, dx, ct, target, q_old, p_old, i0, i1, kind, q, p,
                                         scratch)
        assert ok
        return q, p

    def step_rhs(WT_used, gap0, q_old, p_old, target):
        b, y = np.empty(N), np.empty(N)
        kp_old = np.where(p_old != 0, K @ p_old, -1e30)
        w0 = _coupled.direct_rhs_step(WT_used, K, gap0, load, dx, cn, target, q_old, p_old, kp_old, i0, i1,
                                      scratch, b, y)
        assert w0 >= 0
        return b, y, w0

    parabola = (2 / np.pi) * (x - 0.05) ** 2
    q0, p0 = np.zeros(n), np.where((x > -1) & (x < 1), np.sqrt(np.clip(1 - x ** 2, 0, None)), 0.0)
    q_old, p_old = solved(parabola, q0, p0, 0.2 * load / dx)
    moved = (2 / np.pi) * (x - 0.075) ** 2  # the body moved by half an element
    b, y, w0 = step_rhs(WT, moved, q_old, p_old, 0.25 * load / dx)
    assert_allclose(y, WT[:N].T @ b, rtol=0, atol=1e-10 * np.abs(WT[:N].T @ b).max())
    spoiled = WT.copy()
    spoiled[:Lw] = 1e6  # every normal column of W: a product that reads one is off by millions
    b2, y2, _ = step_rhs(spoiled, moved, q_old, p_old, 0.25 * load / dx)
    assert_allclose(y2, y, rtol=0, atol=1e-10 * np.abs(y).max())
    # a profile that is not parabolic, and a contact that gained an element: the columns, the same W b
    bumpy = moved + 0.01 * np.cos(7 * x)
    b, y, w0 = step_rhs(WT, bumpy, q_old, p_old, 0.25 * load / dx)
    assert_allclose(y, WT[:N].T @ b, rtol=0, atol=1e-10 * np.abs(y).max())
    b2, y2, _ = step_rhs(spoiled, bumpy, q_old, p_old, 0.25 * load / dx)
    assert np.abs(y2 - y).max() > 1.0
    p_short = p_old.copy()
    p_short[i1 - 1] = 0.0  # the last contact one element shorter: that row's K p_old is made, not read
    b, y, w0 = step_rhs(WT, moved, q_old, p_short, 0.25 * load / dx)
    shift = np.zeros(n)
    _coupled.cross(q_old, dx, shift)
    assert_allclose(b[i1 - 1 - w0], -moved[i1 - 1] - K[i1 - 1] @ p_short - cn * shift[i1 - 1], rtol=0, atol=1e-12)
    assert_allclose(y, WT[:N].T @ b, rtol=0, atol=1e-10 * np.abs(y).max())


def test_the_gap_off_the_contact_is_bounded_where_it_is_open_and_made_where_it_may_close():
    """core.solvers._coupled.off_contact: on the rows off the contact, K p is made exactly near the contact's ends
    and replaced by Jensen's lower bound (the pressure's sum times the kernel at its centroid) where that bound
    already leaves the gap open; the kernel of the plane is convex at every distance. The bound never exceeds K p,
    the rows it keeps are open, and the march's penetration test and gap residual read the same from it as from
    K p made everywhere, also for a pressure and profile that penetrate."""
    from core.solvers import _coupled

    K, g, dx = _hertz_problem(n=160)
    n = g.size
    assert _coupled.convex_reach(K) == n - 1
    x = (np.arange(n) - (n - 1) / 2) * dx
    rng = np.random.default_rng(11)
    for case in range(40):
        L = int(rng.integers(20, 90))
        i0 = int(rng.integers(1, n - L - 1))
        i1 = i0 + L
        p = np.zeros(n)
        p[i0:i1] = rng.random(L) ** (1 + case % 3) + (0.0 if case % 4 else 0.5)
        exact = K @ p
        profile = (2 / np.pi) * (x - x[(i0 + i1) // 2]) ** 2 / (L * dx) ** 2  # a body's gap, opening outwards
        profile -= (0.0 if case % 5 else 0.3) * np.exp(-((x - x[(i1 + n) // 2]) / 0.3) ** 2)  # some: a dip
        delta = float(np.mean(exact[i0:i1] + profile[i0:i1]))
        profile[i0:i1] = delta - exact[i0:i1]  # closed on the contact
        kp = np.where((np.arange(n) >= i0) & (np.arange(n) < i1), exact, np.nan)
        made = _coupled.off_contact(K, p, i0, i1, profile, delta, kp, _coupled.convex_reach(K))
        off = np.ones(n, bool)
        off[i0:i1] = False
        assert not np.isnan(kp).any()
        assert (kp[off] <= exact[off] + 1e-12).all()
        bounded = off & ~np.isclose(kp, exact, rtol=1e-12, atol=1e-14)  # (a bound as tight as round-off counts as made)
        assert (profile[bounded] + kp[bounded] - delta > 0).all()
        assert made <= off.sum() - bounded.sum()
        assert bounded.sum() > 0 or _coupled.penetrates(profile, exact, delta, i0, i1)
        assert _coupled.penetrates(profile, kp, delta, i0, i1) == _coupled.penetrates(profile, exact, delta, i0, i1)
        q = np.zeros(n)
        work = np.zeros(n)
        assert _coupled._gap_residual_from(profile, p, q, kp, 0.0, dx, work) == pytest.approx(
            _coupled._gap_residual_from(profile, p, q, exact, 0.0, dx, work), rel=0, abs=1e-13)


def test_the_windows_inverse_is_made_once_for_the_runs_of_a_contact(monkeypatch):
    """core.solvers.coupled.window_inverse keeps the last few windows' inverses: a second run of the same contact
    (another ft) makes none; another beta makes its own."""
    import core.solvers.coupled as cc
    from core.solvers import _coupled

    made = []
    make = _coupled.window_inverse

    def counting(*args):
        made.append(args[1:])
        return make(*args)

    monkeypatch.setattr(_coupled, "window_inverse", counting)
    monkeypatch.setattr(cc, "_windows", type(cc._windows)())
    kw = dict(periods=1, dx=1 / 20, mu=0.3)
    core.simulate_cycles(0.2, 0.6, beta=0.25, **kw)
    assert len(made) == 1
    core.simulate_cycles(0.3, 0.6, beta=0.25, **kw)
    assert len(made) == 1
    core.simulate_cycles(0.3, 0.6, beta=0.1, **kw)
    assert len(made) == 2 and made[0][1:3] != made[1][1:3]
