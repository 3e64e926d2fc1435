"""The 3D point-contact solver: Mindlin, invariants at every step, symmetry, the exact limit bracketed."""

import math

import numpy as np
import pytest

import core
from core.theory.point_contact import hertz_element_means, w_limit_point
from core.api.point_runs import mindlin_state, shakedown_state_3d
from core.solvers.solver3d import RESIDUAL_NAMES


@pytest.mark.parametrize("ft", [0.3, 0.6])
def test_mindlin_nu0(ft):
    """nu = 0: c/a = (1 - ft)^(1/3), q = sqrt(1 - r^2) - sqrt(c^2 - r^2), U = (3/4)(1 - (1 - ft)^(2/3))."""
    dx = 0.05
    r = mindlin_state(ft, dx=dx, nu=0.0)
    c = (1 - ft) ** (1 / 3)
    assert abs(r.stick_halfwidth - c) <= 1.5 * dx, (r.stick_halfwidth, c)
    assert abs(r.stick_halfwidth_y - c) <= 1.5 * dx
    x = r.x
    row = r.traction[0][r.y.size // 2]
    exact = np.sqrt(np.clip(1 - x**2, 0, None)) - np.sqrt(np.clip(c * c - x**2, 0, None))
    inner = np.abs(x) < 0.9  # the edge elements hold means of a square-root profile
    np.testing.assert_allclose(row[inner], exact[inner], atol=0.01, err_msg="Mindlin traction on y = 0")
    assert np.abs(r.traction[1]).max() == 0.0  # no coupling at nu = 0
    np.testing.assert_allclose(r.displacement[0], 0.75 * (1 - (1 - ft) ** (2 / 3)), rtol=5e-3)
    assert max(r.residuals.values()) <= 1e-8


def test_mindlin_nu_coupling_is_small():
    """nu = 0.5: a small q_y (< 0.1 mu p0), the displacement within 1 % of Mindlin's 3(2 - nu)/(8(1 - nu))."""
    ft, nu = 0.6, 0.5
    r = mindlin_state(ft, dx=0.1, nu=nu)
    qy = np.abs(r.traction[1]).max()
    assert 0.01 < qy < 0.1, qy
    np.testing.assert_allclose(r.displacement[0], 3 * (2 - nu) / (8 * (1 - nu)) * (1 - (1 - ft) ** (2 / 3)), rtol=0.01)
    assert abs(r.displacement[1]) < 1e-9
    # mirror symmetry: q_x even, q_y odd in y
    np.testing.assert_allclose(r.traction[0], r.traction[0][::-1], atol=1e-7)
    np.testing.assert_allclose(r.traction[1], -r.traction[1][::-1], atol=1e-7)


def _check_run(r, ft, tol_factor=10.0):
    """Invariants at every step (residuals of the full fields, the cut), and on the stored full fields."""
    tol = tol_factor * r.tol
    for name in RESIDUAL_NAMES:
        assert r.residuals[name].max() <= tol, f"{name} residual {r.residuals[name].max():.3g}"
    assert r.dissipation.min() >= -tol
    row = r.cut_row
    direction = np.array([math.cos(r.angle), math.sin(r.angle)])
    target = ft * r.body.total_load * direction
    dA = r.dx**2
    for k in range(r.xc.size):
        p = r.pressure(k)
        q = r.traction_cut[k]
        mag = np.hypot(q[0], q[1])
        assert np.all(mag <= p[row] + tol), f"|q| > mu p on the cut at step {k}"
        assert np.all(q[:, p[row] <= 0] == 0.0), f"traction out of contact at step {k}"
        assert np.all((r.state_cut[k] == 0) == (p[row] <= 0))
        slipping = r.state_cut[k] >= 2
        assert np.all(np.abs(mag[slipping] - p[row][slipping]) <= tol), "slip below the bound"
    for i, k in enumerate(r.snapshot_steps):
        q, p = r.traction_snapshots[i], r.pressure(k)
        assert np.all(np.hypot(q[0], q[1]) <= p + tol)
        assert np.all(q[:, p <= 0] == 0.0)
        np.testing.assert_allclose(q.sum(axis=(1, 2)) * dA, target, atol=tol, err_msg=f"force balance, step {k}")


@pytest.fixture(scope="module")
def bracket():
    """The sphere at ft = 0.4 (w_lim = 0.4257) a bit below and a bit above its exact limit."""
    ft = 0.4
    below = core.simulate_cycles(ft, 0.25, periods=8, dx=0.2, body="sphere")
    above = core.simulate_cycles(ft, 0.6, periods=5, dx=0.2, body="sphere")
    return ft, below, above


def test_limit_bracketed_by_solver(bracket):
    ft, below, above = bracket
    assert 0.25 < w_limit_point(ft) < 0.6
    assert below.regime == "shakedown", below.regime_reason
    assert above.regime == "ratcheting", above.regime_reason
    assert above.increment_per_period[-1] > 0.05  # positive along Ft
    assert below.stick_halfwidth > 0 and above.stick_halfwidth == 0.0


def test_invariants_every_step(bracket):
    ft, below, above = bracket
    _check_run(below, ft)
    _check_run(above, ft)


def test_mirror_symmetry_in_y(bracket):
    _, below, above = bracket
    for r in (below, above):
        q = r.traction_snapshots
        np.testing.assert_allclose(q[:, 0], q[:, 0, ::-1], atol=1e-6)
        np.testing.assert_allclose(q[:, 1], -q[:, 1, ::-1], atol=1e-6)
        np.testing.assert_allclose(r.displacement[:, 1], 0.0, atol=1e-7)


def test_direct_shakedown_state_matches_transient(bracket):
    """One static solve with the bound mu p_min gives the transient's end state: exactly for nu = 0; for
    nu = 0.5 q_x to 1e-3, while q_y keeps a history dependence of a few per cent of mu p0 (measured 0.004)."""
    ft, below, _ = bracket
    direct = shakedown_state_3d(ft, 0.25, dx=0.2)
    np.testing.assert_array_equal(direct.x_edges, below.x_edges)
    np.testing.assert_allclose(below.final_traction[0], direct.traction[0], atol=2e-3)
    assert np.abs(below.final_traction[1] - direct.traction[1]).max() < 0.01
    assert direct.stick_halfwidth == below.stick_halfwidth
    r0 = core.simulate_cycles(ft, 0.25, periods=8, dx=0.2, body="sphere", nu=0.0)
    direct0 = shakedown_state_3d(ft, 0.25, dx=0.2, nu=0.0)
    np.testing.assert_allclose(r0.final_traction, direct0.traction, atol=1e-4)


def test_result_is_read_only(bracket):
    _, below, _ = bracket
    with pytest.raises(ValueError):
        below.traction_cut[0, 0, 0] = 1.0
    with pytest.raises(ValueError):
        below.step_residuals["bound"][0] = 1.0


def test_force_at_right_angle_and_ellipsoid():
    """Ft perpendicular to the rocking, on an ellipsoid: balances hold, the increment is along Ft."""
    ft = 0.5
    r = core.simulate_cycles(ft, 0.3, periods=2, dx=0.2, body="ellipsoid", ratio=2.0, angle=math.pi / 2)
    assert r.body.kappa > 1
    _check_run(r, ft)
    assert r.increment_per_period[0] > 0


def test_bad_inputs():
    with pytest.raises(ValueError, match="dx"):
        core.simulate_cycles(0.2, 0.2, dx=0.001, body="sphere")
    with pytest.raises(ValueError, match="body"):
        core.simulate_cycles(0.2, 0.2, dx=0.1, body="torus")
    with pytest.raises(ValueError, match="ft"):
        mindlin_state(1.5)


def test_cylinder_shakes_down_where_sphere_ratchets():
    """The paper says the cylinder bears less than the sphere at the same amplitude; the solvers say the
    opposite, as the exact limits do: at w = 0.45, ft = 0.43 (cylinder limit 0.447, sphere limit 0.371; 0.377
    on the sphere's coarse grid)."""
    ft, w = 0.43, 0.45
    assert core.ft_limit(w, body="sphere") < ft < core.ft_limit(w)
    cylinder = core.simulate_cycles(ft, w, periods=10, dx=1 / 40)
    sphere = core.simulate_cycles(ft, w, periods=8, dx=0.2, body="sphere")
    assert cylinder.regime == "shakedown"
    assert sphere.regime == "ratcheting", sphere.regime_reason


def test_grid_convergence_of_the_increment():
    """The increment per period of a ratcheting sphere converges with the element size: each halving cuts the
    change by more than 3 (measured 0.00374 then 0.00116 at ft = 0.4, w = 0.6 with the bound from the discrete
    normal problem; 0.0142 then 0.0039 with element means of Hertz's pressure), a/20 within 3 % of a/10."""
    inc = [core.simulate_cycles(0.4, 0.6, periods=3, dx=dx, body="sphere").increment_per_period[-1]
           for dx in (0.2, 0.1, 0.05)]
    first, second = inc[1] - inc[0], inc[2] - inc[1]
    assert first > 0 and 0 < second < first / 3, inc
    assert second < 0.03 * inc[2]


def test_window_solve_equals_whole_grid():
    """A step solved on the rectangle carrying traction (core.solvers.solver3d._Window) equals the whole grid's solve."""
    from core.elastic.halfspace import HalfSpaceOperator
    from core.solvers.solver3d import TOL_3D, _Window, _WarmStart, solve_increment

    r = core.simulate_cycles(0.5, 0.4, periods=1, dx=0.1, body="sphere")
    k = int(r.snapshot_steps[1])  # a turning point: the next step moves back
    q_prev, g = r.traction_snapshots[1], r.pressure(k + 1)
    ny, nx = g.shape
    target = np.array([0.5 * r.body.total_load, 0.0])
    whole = solve_increment(HalfSpaceOperator(ny, nx, r.dx, r.nu, r.body.kernel_scale), g, q_prev, target,
                            r.dx**2, _WarmStart.empty(g.shape), TOL_3D)
    window = _Window(ny, nx, r.dx, r.nu, r.body.kernel_scale)
    part = window.solve(g, q_prev, target, r.dx**2, _WarmStart.empty(g.shape), TOL_3D)
    assert all(shape != (ny, nx) for shape in window.ops)  # every product on a grid smaller than the whole
    np.testing.assert_allclose(part[0], whole[0], atol=1e-7)
    np.testing.assert_allclose(part[2], whole[2], atol=1e-7)


def test_mirror_solve_equals_full_solve(monkeypatch):
    """Ft along x: the increments solved as mirror-symmetric in y (half-cost products) are the full solver's,
    to its tolerance (measured: displacements 1e-9, tractions 2e-8 apart)."""
    from core.solvers import solver3d

    fast = core.simulate_cycles(0.4, 0.6, periods=3, dx=0.2, body="sphere")
    monkeypatch.setattr(solver3d, "_MIRROR", False)
    full = core.simulate_cycles(0.4, 0.6, periods=3, dx=0.2, body="sphere")
    assert abs(full.displacement[:, 1]).max() > 0.0  # the full solver computed lam_y, not the mirror path
    assert (fast.displacement[:, 1] == 0.0).all()  # the fast one took the mirror path (no lam_y)
    np.testing.assert_allclose(fast.displacement, full.displacement, rtol=0, atol=10 * fast.tol)
    np.testing.assert_allclose(fast.traction_snapshots, full.traction_snapshots, rtol=0, atol=1e-6)
    np.testing.assert_allclose(fast.increment_per_period, full.increment_per_period, rtol=0, atol=10 * fast.tol)


@pytest.mark.parametrize("ratio", [1.0, 0.25, 4.0])
def test_discrete_normal_pressure(ratio):
    """The traction bound's pressure (the discrete normal problem on the grid): the body's gap, the exact load,
    symmetric, a translate for aligned centres, Hertz's up to the discretization (peak -> p0, means off by a few %
    only in the edge elements)."""
    from core.geometry.patch import _gap_curvatures, _grid, _pressure

    body = core.Ellipsoid(ratio)
    A, B = _gap_curvatures(body.kappa)
    np.testing.assert_allclose(B / A, 1.0 / ratio, rtol=1e-12)  # A x^2 + B y^2 = x^2/(2 Rx) + y^2/(2 Ry), scaled
    peaks, diffs = [], []
    for dx in (0.1, 0.05):
        xe, ye = _grid(body, 1.6, 1.0, dx)
        p = _pressure(xe, ye, 0.3, body)
        np.testing.assert_allclose(p.sum() * dx * dx, body.total_load, rtol=1e-12)
        np.testing.assert_array_equal(p, p[::-1])
        shifted = _pressure(xe, ye, 0.3 + 2 * dx, body)
        np.testing.assert_allclose(shifted[:, 2:], p[:, :-2], atol=1e-14)
        means = hertz_element_means(xe, ye, 0.3, body.kappa)
        diffs.append(np.abs(p - means)[means > 0.6].max())
        peaks.append(p.max())
    assert diffs[1] < diffs[0] < 0.04, diffs  # measured at a/10, a/20: 0.004, 0.001 (sphere); 0.035, 0.006 (kappa 0.4)
    assert abs(peaks[1] - 1.0) < abs(peaks[0] - 1.0) < 5e-3
    scaled = _pressure(*_grid(body, 1.6, 1.3, 0.05), 0.0, body, 1.3)
    np.testing.assert_allclose(scaled.sum() * 0.05**2, body.total_load * 1.3**3, rtol=1e-12)


def _vanishing_residual_inputs():
    """A 5 x 5 patch: the centre element sticks, the others slip along x with the Newton curvature of a
    vanishing bound (1e300: a tiny numerically solved pressure), and a residual of 1e-175, so that r.z
    underflows to exactly 0 while p A p > 0 (the curvature): rz == 0 with the residual above tol."""
    from core.elastic.halfspace import HalfSpaceOperator

    n = 5
    spec = HalfSpaceOperator(n, n, 0.2, 0.5, 1.5 / math.pi**2).spectra()
    stick = np.zeros((n, n), np.bool_)
    stick[2, 2] = True
    pxx, pyy, pxy = np.zeros((n, n)), np.ones((n, n)), np.zeros((n, n))  # slip: d = x, correction along y
    pxx[2, 2] = 1.0
    m = np.array([[pxx.sum(), 0.0], [0.0, pyy.sum()]])
    minv = np.linalg.inv(m)
    curv = np.where(stick, 0.0, 1e300)
    slip_diag = 1.0 / (curv + 1.0)
    x = np.zeros((2, n, n))
    kdq = 1e-175 * np.random.default_rng(3).standard_normal((2, n, n))
    return spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x, kdq


def test_pcg_stops_on_zero_rz():
    """rz == 0 (zero preconditioned residual) stops the projected CG instead of dividing by it (numba raised
    ZeroDivisionError at beta = rz_new / rz on these inputs): x and K dq are left as they were."""
    from core.solvers.solver3d import _pcg_kernel

    spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x, kdq = _vanishing_residual_inputs()
    kdq0 = kdq.copy()
    # tv=None as the solver passes it: the kernel's compiled signature, not one more for an omitted argument
    its, rmax = _pcg_kernel(spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x, kdq, 1e-300, 50, False, None)
    assert its == 0 and 1e-176 < rmax < 1e-173  # the residual is there, but CG cannot reduce it
    assert (x == 0).all() and (kdq == kdq0).all()
    # the same kernel in plain Python, without the guard, divides by zero on these inputs
    with pytest.raises(ZeroDivisionError):
        _pcg_unguarded(spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x, kdq, 1e-300, 50)


def _pcg_unguarded(spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x, Kdq, tol, maxiter):
    """The loop of core.solvers.solver3d._pcg_kernel before the rz == 0 guard (vectorised, pure Python)."""
    from core.solvers.solver3d import _convolve, _precondition, _project

    r, z, Ap = (np.zeros_like(x) for _ in range(3))
    _project.py_func(pxx, pyy, pxy, minv, -Kdq - curv * x, r, False)
    _precondition.py_func(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, False)
    p, rz, rmax, its = z.copy(), float(np.sum(r * z)), np.abs(r).max(), 0
    while its < maxiter and rmax > tol:
        its += 1
        Kp = _convolve(p, *spec[:5], False)
        _project.py_func(pxx, pyy, pxy, minv, Kp + curv * p, Ap, False)
        pAp = float(np.sum(p * Ap))
        if not pAp > 0.0:
            break
        alpha = rz / pAp
        x += alpha * p
        r -= alpha * Ap
        rmax = np.abs(r).max()
        _precondition.py_func(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, False)
        rz_new = float(np.sum(r * z))
        p = z + (rz_new / rz) * p
        rz = rz_new
    return its, rmax


def test_point_contact_normal_modes():
    """normal= for a point contact: "auto" is "numerical" (the discrete normal problem on the grid, the default
    bound), "exact" the element means of Hertz's pressure. Measured (ft 0.4, w 0.6, 4 periods): increments
    0.17417 vs 0.15888 at a/5 (9.6 % apart), 0.17788 vs 0.17313 at a/10 (2.7 %): they differ by the grid's
    accuracy and converge to each other; the pressures are Hertz's to 0.075 p0 and 0.048 p0 (the rim elements)."""
    runs = {(dx, n): core.simulate_cycles(0.4, 0.6, periods=4, dx=dx, body="sphere", normal=n)
            for dx in (0.2, 0.1) for n in ("auto", "numerical", "exact")}
    gaps, pdiff = [], []
    for dx in (0.2, 0.1):
        auto, num, exact = (runs[dx, n] for n in ("auto", "numerical", "exact"))
        assert auto.params["normal"] == num.params["normal"] == "numerical" and exact.params["normal"] == "exact"
        np.testing.assert_array_equal(auto.increment_per_period, num.increment_per_period)
        a, e = num.increment_per_period[-1], exact.increment_per_period[-1]
        gaps.append(abs(a - e) / e)
        np.testing.assert_allclose(exact.pressure(0), hertz_element_means(exact.x_edges, exact.y_edges, 0.0),
                                   atol=1e-12)
        pdiff.append(abs(num.pressure(0) - exact.pressure(0)).max())
        assert abs(num.pressure(0).sum() - exact.pressure(0).sum()) * dx * dx < 1e-9  # the same load
    assert gaps[0] < 0.12 and gaps[1] < 0.035 and gaps[1] < gaps[0] / 2.5, gaps
    assert pdiff[0] < 0.09 and pdiff[1] < 0.06 and pdiff[1] < pdiff[0], pdiff
    with pytest.raises(ValueError, match="normal"):
        core.simulate_cycles(0.4, 0.6, periods=2, dx=0.2, body="sphere", normal="closed")
