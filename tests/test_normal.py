"""The numerical normal solve (core/pressure/normal.py): Hertz to grid accuracy, converging with dx, and an independent code."""

import numpy as np
import pytest
from scipy.special import ellipe, ellipk

import core
from core.base._hertz import element_means
from core.pressure.normal import PatchOperator, solve_line, solve_normal, solve_patch, line_operator
from core.theory.point_contact import Ellipsoid, hertz_element_means


def _line(dx, half=1.5):
    n = int(round(2 * half / dx))
    e = np.arange(n + 1) * dx - half
    return e, 0.5 * (e[1:] + e[:-1])


def test_cylinder_equals_hertz_and_converges():
    """p = sqrt(1 - x^2) for h = (2/pi) x^2 at the nominal load: the L1 error (relative to P) falls about as
    dx^1.5 (0.2 % at dx = 0.04, 0.008 % at 0.01), the interior (|x| < 0.9) error as dx^2 (1.3e-3 -> 4e-5)."""
    l1, inner = [], []
    for dx in (0.04, 0.02, 0.01):
        e, x = _line(dx)
        s = solve_line((2 / np.pi) * x**2, dx)
        exact = element_means(e, np.zeros(1), np.ones(1), np.ones(1))[0]
        d = s.pressure - exact
        l1.append(np.abs(d).sum() * dx / (np.pi / 2))
        inner.append(np.abs(d[np.abs(x) < 0.9]).max())
        assert s.load == pytest.approx(np.pi / 2, rel=1e-12)
        assert abs(s.area - 2.0) <= 2 * dx + 1e-12
        assert s.gap_residual < 1e-8 and s.penetration == 0.0
    assert l1[0] < 3e-3 and l1[-1] < 1e-4
    assert inner[0] < 2e-3 and inner[-1] < 6e-5
    assert l1[0] / l1[-1] > 8 and inner[0] / inner[-1] > 12  # dx / 4: at least dx^1.5


def test_sphere_equals_hertz():
    """h = (3/8) r^2 in the point-contact units: the L1 error 1.3 % at h = 0.1, 0.4 % at h = 0.05."""
    errs = []
    for h in (0.1, 0.05):
        e, x = _line(h)
        X, Y = np.meshgrid(x, x)
        s = solve_patch(0.375 * (X**2 + Y**2), h)
        exact = hertz_element_means(e, e, 0.0, 1.0)
        d = s.pressure - exact
        errs.append(np.abs(d).sum() * h * h / (2 * np.pi / 3))
        assert np.abs(d[np.hypot(X, Y) < 0.9]).max() < (0.015 if h == 0.1 else 0.003)
    assert errs[0] < 0.015 and errs[1] < 0.005


def test_ellipsoid_equals_hertz():
    """Ratio Ry/Rx = 2: the profile from Hertz's elliptical solution (Johnson ch. 3: the displacement under
    p0 sqrt(1 - x^2/a^2 - y^2/b^2)); the numerical pressure matches it, L1 error 0.3 % at h = 0.05."""
    kap = Ellipsoid(2.0).kappa
    alpha, beta = kap, 1.0  # semi-major (along y), semi-minor (along x)
    m = 1 - (beta / alpha) ** 2
    K, E = ellipk(m), ellipe(m)
    Ay = beta / (m * alpha**2) * (K - E)
    Ax = beta / (m * alpha**2) * ((alpha / beta) ** 2 * E - K)
    h = 0.05
    ex = np.arange(-1.5, 1.5 + 1e-9, h)
    ey = np.arange(-1.5 * kap, 1.5 * kap + h, h)
    ey -= ey.mean()
    x, y = 0.5 * (ex[1:] + ex[:-1]), 0.5 * (ey[1:] + ey[:-1])
    Y, X = np.meshgrid(y, x, indexing="ij")
    load = 2 * np.pi * kap / 3
    s = solve_patch(Ax * X**2 + Ay * Y**2, h, load=load, scale=1 / np.pi)
    d = s.pressure - hertz_element_means(ex, ey, 0.0, kap)
    assert np.abs(d).sum() * h * h / load < 0.005
    assert np.abs(d[X**2 + (Y / kap) ** 2 < 0.81]).max() < 0.003
    assert s.area == pytest.approx(np.pi * kap, rel=0.02)


def test_cone_matches_contactmechanics():
    """A cone (non-Hertzian) on the non-periodic half-space against ContactMechanics' own Polonsky-Keer solver on
    its FreeFFTElasticHalfSpace (Johnson's piecewise-constant kernel, E* = 1): the pressures agree to 1e-8 of
    the peak. Their pixel forces are ``p dA`` and their topography is the rigid surface's height, i.e. ``-h``."""
    import ContactMechanics as cm
    from ContactMechanics.Optimization import constrained_conjugate_gradients
    n, h = 48, 3.0 / 48
    _, x = _line(h)
    X, Y = np.meshgrid(x, x, indexing="ij")
    prof = 0.4 * np.hypot(X, Y)
    mine = solve_patch(prof, h, load=1.0, scale=1 / np.pi)
    sub = cm.FreeFFTElasticHalfSpace((n, n), 1.0, (n * h, n * h))
    ref = constrained_conjugate_gradients(sub, -prof, external_force=1.0, pentol=1e-12, forcetol=1e-12)
    assert ref.success
    p_ref = ref.jac / (h * h)
    assert np.abs(p_ref - mine.pressure).max() < 1e-8 * mine.pressure.max()
    assert mine.contact.sum() == (p_ref > 0).sum()
    # the cone's pressure is not Hertz's: a log singularity at the tip, a finite slope at the edge
    assert mine.pressure.max() > 1.5 * mine.pressure[np.hypot(X, Y) < 0.5].min()


def test_patch_operator_matches_matrix():
    op = PatchOperator(5, 7, 0.2)
    p = np.random.default_rng(3).random(op.shape)
    assert np.allclose(op.apply(p).ravel(), op.matrix() @ p.ravel(), rtol=1e-12, atol=1e-14)


def test_warm_start_and_a_flat_profile():
    e, x = _line(0.02)
    h = (2 / np.pi) * x**2
    cold = solve_line(h, 0.02, method="cg")
    warm = solve_line(h, 0.02, initial=cold.pressure, method="cg")
    assert warm.iterations < cold.iterations
    assert np.allclose(warm.pressure, cold.pressure, atol=1e-8)


@pytest.mark.parametrize("kwargs, match", [
    (dict(load=0.0), "load"),
    (dict(load=np.nan), "load"),
    (dict(tol=1.0), "tol"),
    (dict(maxiter=0), "maxiter"),
    (dict(element_area=-1.0), "element_area"),
    (dict(profile=np.full(10, np.inf)), "profile"),
    (dict(profile=np.zeros(11)), "profile"),
    (dict(initial=-np.ones(10)), "initial"),
    (dict(maxiter=1, tol=1e-14), "converge"),
    (dict(method="lu"), "method"),
    (dict(method=None), "method"),
    (dict(method="direct", operator=PatchOperator(2, 5, 0.2), profile=np.zeros((2, 5))), "method='direct'"),
])
def test_bad_inputs(kwargs, match):
    args = dict(profile=np.linspace(-1, 1, 10) ** 2, load=1.0, operator=line_operator(10, 0.2), element_area=0.2,
                method="cg")
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        solve_normal(**args)


def test_bad_grids():
    with pytest.raises(ValueError, match="profile"):
        solve_line(np.zeros((3, 3)), 0.1)
    with pytest.raises(ValueError, match="dx"):
        solve_line(np.zeros(10), 0.0)
    with pytest.raises(ValueError, match="profile"):
        solve_patch(np.zeros(10), 0.1)
    with pytest.raises(ValueError, match="h"):
        solve_patch(np.zeros((4, 4)), -0.1)


def test_preconditioning_changes_the_iterations_not_the_solution():
    """The inverse-symbol preconditioner: the same pressure (to the tolerance), 3x fewer iterations at dx = a/160
    on the line (33 against 109) and about half on the patch (cone, h = 0.05: 23 against 50)."""
    dx = 1 / 160
    n = int(round(4 / dx))
    x = (np.arange(n) + 0.5) * dx - 2
    plain = solve_normal((2 / np.pi) * x**2, np.pi / 2, line_operator(n, dx), dx, precondition=False, method="cg")
    pre = solve_normal((2 / np.pi) * x**2, np.pi / 2, line_operator(n, dx), dx, method="cg")
    assert np.abs(plain.pressure - pre.pressure).max() < 1e-8
    assert 2.5 * pre.iterations < plain.iterations
    e, xp = _line(0.05)
    X, Y = np.meshgrid(xp, xp)
    plain = solve_patch(0.4 * np.hypot(X, Y), 0.05, precondition=False)
    pre = solve_patch(0.4 * np.hypot(X, Y), 0.05)
    assert np.abs(plain.pressure - pre.pressure).max() < 1e-8
    assert 1.5 * pre.iterations < plain.iterations


@pytest.mark.parametrize("ratio", [1.0, 0.5, 2.0])
def test_ellipsoid_profile_gives_its_hertz_pressure(ratio):
    """core.Ellipsoid.profile in the point-contact units (gap in Fn/(E* a), kernel_scale, total_load): the patch
    solve returns the element means of p0 sqrt(1 - x^2 - (y/kappa)^2): L1 error < 0.5 % at h = 0.05 (ratio 0.5,
    kappa = 0.63, fewer elements across: 0.66 % at h = 0.05, 0.24 % at 0.025)."""
    body = Ellipsoid(ratio)
    kap = body.kappa
    h = 0.05 if ratio >= 1 else 0.025
    ex = np.arange(-1.5, 1.5 + 1e-9, h)
    ey = np.arange(-1.5 * kap, 1.5 * kap + h, h)
    ey -= ey.mean()
    x, y = 0.5 * (ex[1:] + ex[:-1]), 0.5 * (ey[1:] + ey[:-1])
    s = solve_patch(body.profile(x[None, :], y[:, None]), h, load=body.total_load, scale=body.kernel_scale)
    d = s.pressure - hertz_element_means(ex, ey, 0.0, kap)
    assert np.abs(d).sum() * h * h / body.total_load < 0.005


# ---- the direct solve of a line (active set on the Toeplitz matrix) against the conjugate gradient ----------

def _profiles():
    from core.theory.punch import punch_profile
    return {
        "cylinder": lambda x: (2 / np.pi) * x**2,
        "punch 0.5": lambda x: punch_profile(x, 0.5),
        "punch 0.8": lambda x: punch_profile(x, 0.8),
        "two bumps": lambda x: (x**2 - 0.8) ** 2,  # non-convex: two contact intervals
    }


def _intervals(contact):
    return int(np.count_nonzero(np.diff(np.concatenate(([0], contact.astype(int), [0]))) == 1))


@pytest.mark.parametrize("name", ["cylinder", "punch 0.5", "punch 0.8", "two bumps"])
@pytest.mark.parametrize("dx", [0.04, 0.02, 0.01, 1 / 160])
def test_direct_equals_cg(name, dx):
    """method='direct' (the default on a line) against Polonsky-Keer's CG: the same pressures to 1e-8 of the
    peak (measured: 1e-9 and below), the same contact set, approach and load; the direct solution's gap
    residual is round-off (CG's is its tolerance)."""
    e, x = _line(dx, half=2.0)
    h = _profiles()[name](x)
    d = solve_line(h, dx)
    c = solve_line(h, dx, method="cg", tol=1e-12)
    assert d.method == "direct" and c.method == "cg"
    assert np.abs(d.pressure - c.pressure).max() < 1e-8 * d.pressure.max()
    assert np.array_equal(d.contact, c.contact)
    assert _intervals(d.contact) == (2 if name == "two bumps" else 1)
    assert d.approach == pytest.approx(c.approach, rel=1e-9, abs=1e-12)
    assert d.load == pytest.approx(np.pi / 2, rel=1e-12)
    assert d.gap_residual < 1e-11 and d.penetration < 1e-11
    assert np.all(d.pressure >= 0) and np.all(d.pressure[~d.contact] == 0)


@pytest.mark.parametrize("load", [0.05, 0.5, 3.0])
def test_direct_two_intervals_at_any_load(load):
    """A light load touches the two bumps apart, a heavy one closes the gap between them: the direct solve
    follows (holes in its window solved by the Schur complement) and equals the CG."""
    dx = 0.01
    _, x = _line(dx, half=2.0)
    h = (x**2 - 0.5) ** 2 + 0.05 * x  # not symmetric
    d = solve_line(h, dx, load=load)
    c = solve_line(h, dx, load=load, method="cg", tol=1e-12)
    assert d.method == "direct"
    assert np.abs(d.pressure - c.pressure).max() < 1e-8 * d.pressure.max()
    assert np.array_equal(d.contact, c.contact)
    assert _intervals(d.contact) == (1 if load == 3.0 else 2)


@pytest.mark.parametrize("make", [lambda: core.Cylinder(), lambda: core.Punch(flat=0.5), lambda: core.Punch(flat=0.8),
                                  lambda: _two_bump_body()], ids=["cylinder", "punch 0.5", "punch 0.8", "profile"])
@pytest.mark.parametrize("dx", [1 / 40, 1 / 80])
def test_body_solve_direct_equals_cg(make, dx):
    """Body.solve_normal (coarse solve, then 4x finer over the contact): both levels direct, the fine one settles
    on the refined coarse set at once; the same grid and pressures as the CG's to 1e-8."""
    body = make()
    e_d, d = body.solve_normal(dx, refine=4)
    e_c, c = body.solve_normal(dx, refine=4, method="cg", tol=1e-12)
    assert d.method == "direct" and c.method == "cg"
    assert np.array_equal(e_d, e_c)
    assert np.abs(d.pressure - c.pressure).max() < 1e-8 * d.pressure.max()
    assert np.array_equal(d.contact, c.contact)
    assert d.iterations <= 3


def _two_bump_body():
    from core.geometry.heightmap import HeightProfile
    x = np.linspace(-2.5, 2.5, 1001)
    return HeightProfile(4 * (x**2 - 0.8) ** 2, x[1] - x[0], centre=500)


def test_two_bump_body_has_two_contacts():
    _, s = _two_bump_body().solve_normal(1 / 40, refine=4)
    assert s.method == "direct" and _intervals(s.contact) == 2


def test_direct_hands_over_to_cg(monkeypatch):
    """A direct solve that does not settle (here: allowed one contact set, started from every element), or meets
    too many holes, is solved by the CG instead, and says so."""
    import core.pressure.normal as normal
    dx = 0.02
    _, x = _line(dx, half=2.0)
    h = (2 / np.pi) * x**2
    monkeypatch.setattr(normal, "ACTIVE_SET_ITERATIONS", 1)
    s = solve_line(h, dx, initial=np.ones(x.size))
    assert s.method == "cg-fallback" and s.iterations > 1
    monkeypatch.undo()
    d = solve_line(h, dx)
    assert d.method == "direct" and np.abs(s.pressure - d.pressure).max() < 1e-8
    # a contact whose dense system is above MAX_HOLES (a rough profile's islands; here two bumps and none allowed)
    bumps = (x**2 - 0.5) ** 2
    monkeypatch.setattr(normal, "MAX_HOLES", 0)
    s = solve_line(bumps, dx, load=0.5)
    monkeypatch.undo()
    d = solve_line(bumps, dx, load=0.5)
    assert s.method == "cg-fallback" and d.method == "direct" and _intervals(d.contact) == 2
    assert np.abs(s.pressure - d.pressure).max() < 1e-8 * d.pressure.max()


def test_indefinite_matrix_is_shifted():
    """A short reference length (0.5 a) makes the log kernel's matrix indefinite over a contact wider than 2 a:
    Levinson's recursion meets a non-positive leading minor, and the direct solve repeats with a constant added
    to every influence (a longer reference length: the same pressures, the approach shifted). The pressures are
    those of the default operator (4 a) and of the CG; and a contact 36 a wide (beyond 4 times the default
    reference length) is solved directly too."""
    from core.elastic.operators import elastic_operator
    dx = 0.02
    _, x = _line(dx, half=2.0)
    h = (2 / np.pi) * x**2
    op = elastic_operator(x.size, dx, "plane", form="fft", reference_length=0.5)
    assert np.linalg.eigvalsh(op.matrix())[0] < 0
    short = solve_normal(h, np.pi / 2, op, dx)
    cg = solve_normal(h, np.pi / 2, op, dx, method="cg", tol=1e-12)
    default = solve_line(h, dx)
    assert short.method == "direct" and default.method == "direct"
    assert np.abs(short.pressure - default.pressure).max() < 1e-8
    assert np.abs(short.pressure - cg.pressure).max() < 1e-8
    assert short.approach == pytest.approx(cg.approach, rel=1e-9)
    assert np.array_equal(short.contact, default.contact)
    dx, n = 0.05, 800
    xw = (np.arange(n) + 0.5) * dx - 20
    wide = solve_line(0.002 * xw**2, dx)
    ref = solve_line(0.002 * xw**2, dx, method="cg", tol=1e-12)
    assert wide.method == "direct" and wide.area > 35
    assert np.abs(wide.pressure - ref.pressure).max() < 1e-8 * wide.pressure.max()
    assert np.array_equal(wide.contact, ref.contact)


def test_methods_of_a_patch_and_of_a_large_line():
    """'auto' is the CG on a patch (no Toeplitz column) and on a line above DIRECT_MAX_ELEMENTS."""
    from core.pressure.normal import DIRECT_MAX_ELEMENTS
    e, x = _line(0.1)
    X, Y = np.meshgrid(x, x)
    assert solve_patch(0.375 * (X**2 + Y**2), 0.1).method == "cg"
    n = DIRECT_MAX_ELEMENTS + 2
    dx = 4.0 / n
    xl = (np.arange(n) + 0.5) * dx - 2.0
    assert solve_line((2 / np.pi) * xl**2, dx).method == "cg"
    assert solve_line((2 / np.pi) * xl[::2] ** 2, 2 * dx).method == "direct"


@pytest.mark.parametrize("mixed", [False, True])
def test_numerical_bounds_equal_the_interpolated_table(mixed):
    """LineGrid.bounds of a numerical body (one numba pass over the uniform table) against np.interp of the same
    cumulative pressure: equal to round-off, and zero on exactly the same elements (a 1e-17 bound out of contact
    doubled the tangential solver's iterations), for one normal load and for several."""
    body = core.Punch(flat=0.5)
    dx = 1 / 40
    grid = body.on_grid(dx * (np.arange(121) - 60), "numerical")
    rng = np.random.default_rng(1)
    xc = np.concatenate((rng.uniform(-0.4, 0.4, 200), dx / 4 * np.arange(-20, 21)))  # and shifts by whole knots
    P = np.where(np.arange(xc.size) % 3 == 0, 1.2, 0.9) if mixed else np.ones(xc.size)
    fast = grid.bounds(xc, P)
    ref = np.empty_like(fast)
    for i, (x, p) in enumerate(zip(xc, P)):
        table, _ = body._table(dx, float(p), "numerical")
        F = np.interp(grid.edges - x, table.knots, table.values)
        ref[i] = np.maximum(np.diff(F) / dx, 0.0)
    assert np.abs(fast - ref).max() < 1e-13
    assert np.array_equal(fast == 0, ref == 0)


def test_cg_restarts_when_its_direction_loses_conjugacy():
    """Found by comparing the two methods on 600 random profiles: on this wavy one the preconditioned CG's kept
    direction stopped being a descent direction once the contact set changed (r.t < 0 from iteration 16), and it
    "converged" to one element in contact with a penetration of 8 times the profile's range. It now restarts
    from the preconditioned residual there, and equals the direct solve (as on all 600)."""
    A, B, k, phase = 0.9700504332574895, 0.15511096583329428, 2.775578440186193, 4.2154334463151155
    n = 268
    dx = 4.0 / n
    x = (np.arange(n) + 0.5) * dx - 2
    h = A * x**2 + B * np.sin(k * x + phase)
    cg = solve_line(h, dx, load=2.7553374217432536, method="cg")
    direct = solve_line(h, dx, load=2.7553374217432536)
    assert cg.penetration < 1e-10 and direct.penetration == 0.0
    assert np.array_equal(cg.contact, direct.contact) and cg.contact.sum() == 134
    assert np.abs(cg.pressure - direct.pressure).max() < 1e-8 * direct.pressure.max()
