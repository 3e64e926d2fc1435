"""Identities and limits of the closed-form model (core.theory.analytical)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import quad

import core
from core.theory import analytical as an


W_GRID = np.linspace(0.0, 0.95, 20)


def test_eq35_reference_values():
    # PHYSICS.md: w = 0.26 -> 0.6727; 0.52 -> 0.3691; 0.77 -> 0.1277
    assert_allclose(core.ft_limit([0.26, 0.52, 0.77]), [0.6727, 0.3691, 0.1277], atol=5e-5)


def test_ft_limit_endpoints_and_monotonic():
    assert_allclose(core.ft_limit(0.0), 1.0, atol=1e-15)
    assert_allclose(core.ft_limit(1.0), 0.0, atol=1e-15)
    w = np.linspace(0, 1, 1001)
    assert np.all(np.diff(core.ft_limit(w)) < 0)


def test_w_limit_is_exact_inverse():
    ft = np.linspace(0.0, 1.0, 401)
    assert_allclose(core.ft_limit(core.w_limit(ft)), ft, atol=1e-12)
    w = np.linspace(0.0, 1.0, 401)
    assert_allclose(core.w_limit(core.ft_limit(w)), w, atol=1e-9)


def test_scalars_in_scalars_out():
    for f in (core.ft_limit, core.w_limit, core.cattaneo_stick_halfwidth):
        assert np.ndim(f(0.3)) == 0
    assert np.ndim(core.shakedown_stick_halfwidth(0.3, 0.2)) == 0
    assert core.shakedown_stick_halfwidth(np.ones((3, 4)) * 0.2, 0.1).shape == (3, 4)


@pytest.mark.parametrize("ft", [0.0, 0.1, 0.36, 0.7, 0.99])
def test_w_zero_reduces_to_cattaneo(ft):
    assert_allclose(core.shakedown_stick_halfwidth(ft, 0.0), core.cattaneo_stick_halfwidth(ft), atol=1e-12)
    x = np.linspace(-1.2, 1.2, 241)
    assert_allclose(an.shakedown_traction(x, ft, 0.0), an.cattaneo_traction(x, ft), atol=1e-12)


def test_cattaneo_traction_integrates_to_ft():
    for ft in (0.1, 0.5, 0.9):
        total, _ = quad(lambda x: an.cattaneo_traction(x, ft), -1, 1, points=[-np.sqrt(1 - ft), np.sqrt(1 - ft)])
        assert_allclose(total / (np.pi / 2), ft, rtol=1e-8)


@pytest.mark.parametrize("w", [0.05, 0.26, 0.52, 0.77, 0.95])
def test_c_sd_vanishes_on_limit_curve(w):
    assert_allclose(core.shakedown_stick_halfwidth(core.ft_limit(w), w), 0.0, atol=1e-9)
    assert np.isnan(core.shakedown_stick_halfwidth(min(core.ft_limit(w) + 1e-6, 0.999), w))


def test_c_sd_at_zero_load_is_always_in_contact_width():
    w = np.linspace(0, 0.95, 11)
    assert_allclose(core.shakedown_stick_halfwidth(0.0, w), 1.0 - w, atol=1e-9)


@pytest.mark.parametrize("w", [0.1, 0.26, 0.52, 0.77])
@pytest.mark.parametrize("frac", [0.05, 0.3, 0.6, 0.95])
def test_shakedown_traction_integrates_to_ft(w, frac):
    ft = frac * float(core.ft_limit(w))
    c = float(core.shakedown_stick_halfwidth(ft, w))
    q = lambda x: an._traction_and_zones(np.asarray(x), c, w)[0]  # noqa: E731 (c solved once)
    assert_allclose(q(0.3), an.shakedown_traction(0.3, ft, w))
    total, _ = quad(q, -1, 1, points=[-1 + w, -c, c, 1 - w], limit=200)
    assert_allclose(total / (np.pi / 2), ft, rtol=1e-8, err_msg=f"w={w} ft={ft}")


@pytest.mark.parametrize("w", [0.1, 0.26, 0.52, 0.77])
@pytest.mark.parametrize("frac", [0.1, 0.5, 0.9])
def test_traction_continuous_at_c_sd(w, frac):
    ft = frac * float(core.ft_limit(w))
    c = float(core.shakedown_stick_halfwidth(ft, w))
    # the stick term behaves like sqrt(c - x): continuous, with infinite slope
    eps = 1e-13
    inside = an.shakedown_traction(c - eps, ft, w)
    outside = an.shakedown_traction(c + eps, ft, w)
    assert_allclose(inside, outside, atol=1e-5)
    assert_allclose(outside, an.lowest_pressure(c, w), atol=1e-6)


def test_c_sd_falls_with_ft_and_w():
    ft = np.linspace(0.0, 0.9, 91)
    for w in (0.0, 0.2, 0.5, 0.8):
        c = core.shakedown_stick_halfwidth(ft, w)
        ok = ~np.isnan(c)
        assert np.all(np.diff(c[ok]) < 0), f"w={w}"
    w = np.linspace(0.0, 0.9, 91)
    for f in (0.05, 0.2, 0.5):
        c = core.shakedown_stick_halfwidth(f, w)
        ok = ~np.isnan(c)
        assert ok.sum() > 5
        assert np.all(np.diff(c[ok]) < 0), f"ft={f}"


def test_zones_partition_the_contact():
    ft, w = 0.2, 0.3
    c = float(core.shakedown_stick_halfwidth(ft, w))
    x = np.array([0.0, c * 0.99, c * 1.01 + 0.001, 0.69, 0.71, 0.99, 1.01])
    z = an.shakedown_zones(x, ft, w)
    assert list(z) == [an.ZONE_STICK, an.ZONE_STICK, an.ZONE_SLIP, an.ZONE_SLIP,
                       an.ZONE_RELEASED, an.ZONE_RELEASED, an.ZONE_NONE]


def test_hertz_pressure_and_element_mean_conserve_load():
    x = np.linspace(-2, 2, 4001)
    p = an.hertz_pressure(x, 0.3)
    assert p.max() == pytest.approx(1.0, abs=1e-6)
    assert np.all(p[np.abs(x - 0.3) >= 1] == 0)
    edges = np.linspace(-1.7, 1.9, 37)  # coarse and off-centre on purpose
    for xc in (0.0, 0.33, -0.61):
        pm = an.hertz_pressure_element_mean(edges, xc)
        assert_allclose(np.sum(pm * np.diff(edges)), np.pi / 2, rtol=1e-13)


def test_stick_zone_ansatz_respects_the_friction_bound():
    """Finding: the paper's stick-zone traction (eqs 23-26) stays within mu * p_min.

    Checked on a dense (ft, w) grid over the whole shakedown region. If this
    ever fails, the ansatz violates Coulomb's law there: report where.
    """
    x = np.linspace(-1, 1, 2001)
    worst = -np.inf
    for w in np.linspace(0.0, 0.98, 50):
        for ft in np.linspace(0.0, float(core.ft_limit(w)), 25)[:-1]:
            q = an.shakedown_traction(x, ft, w)
            excess = np.abs(q) - an.lowest_pressure(x, w)
            worst = max(worst, float(excess.max()))
    assert worst <= 1e-12, f"ansatz exceeds mu*p_min by {worst}"


def test_classify_regime():
    r = core.classify_regime([0.1, 0.7, 1.0, 0.67], [0.26, 0.26, 0.1, 0.26])
    assert list(r) == ["shakedown", "ratcheting", "gross sliding", "shakedown"]


@pytest.mark.parametrize(
    "call",
    [
        lambda: core.ft_limit(-0.1),
        lambda: core.ft_limit(1.1),
        lambda: core.ft_limit(np.nan),
        lambda: core.w_limit(2.0),
        lambda: core.shakedown_stick_halfwidth(1.0, 0.2),
        lambda: core.shakedown_stick_halfwidth(0.2, 1.0),
        lambda: core.cattaneo_stick_halfwidth("a"),
        lambda: core.classify_regime(0.2, np.inf),
    ],
)
def test_bad_inputs_raise_value_error(call):
    with pytest.raises(ValueError):
        call()


def test_error_message_names_parameter_and_range():
    with pytest.raises(ValueError, match=r"w must be in \[0, 1\), got 1.5"):
        core.shakedown_stick_halfwidth(0.2, 1.5)
