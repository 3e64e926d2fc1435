"""The physical-units contact: derived quantities and validation."""

import math

import pytest
from numpy.testing import assert_allclose

import core
from core import Contact, PAPER_EXPERIMENT, PAPER_SIMULATION


def test_table1_indentation_and_width():
    c = PAPER_EXPERIMENT
    # Table 1 prints d = 0.26 mm: eq 6 gives 0.2589 mm
    assert round(c.d * 1e3, 2) == 0.26
    # Table 1 prints 2a = 4.2 mm; Hertz with Table 1's inputs gives 4.133 mm
    # (rounds to 4.1: the printed width is most likely the measured one). Within 2 %:
    assert_allclose(2 * c.a * 1e3, 4.2, rtol=0.02)
    assert abs(c.beta) < 1e-4 and c.warnings == ()


def test_eq17_simulation_case():
    c = PAPER_SIMULATION
    assert_allclose(c.a * 1e3, 1.709, atol=5e-4)  # PHYSICS.md: a = 1.709 mm
    assert_allclose(c.E_star, 6.8e6, rtol=1e-12)
    assert_allclose(c.G_star, 4.5e6, rtol=0.01)  # paper prints 4.5 N/mm^2
    assert c.beta == 0.0 and c.nu == 0.5


def test_hertz_identities():
    c = Contact(R1=0.01, L=0.02, Fn=100.0, mu=0.5, E2=210e9, nu2=0.3, E1=210e9, nu1=0.3)
    assert_allclose(c.p0, math.sqrt(c.P * c.E_star / (math.pi * c.R)), rtol=1e-12)
    assert_allclose(math.pi * c.a * c.p0 / 2, c.P, rtol=1e-12)
    assert c.beta == pytest.approx(0.0, abs=1e-15)  # identical materials
    assert c.G == pytest.approx(210e9 / (2 * 1.3) / 2)


def test_beta_warning_for_rigid_on_compressible():
    c = Contact(R1=0.01, L=0.05, Fn=100.0, mu=0.5, E2=1e9, nu2=0.2)
    assert c.beta == pytest.approx((1 - 2 * 0.2) / (2 * (1 - 0.2)))  # body 1 (rigid) on body 2: beta > 0
    assert any("beta" in w for w in c.warnings)


def test_ft_and_W_both_forms():
    base = dict(R1=0.04, L=0.5, Fn=195.0, mu=0.58, E2=5.1e6, nu2=0.5)
    a = Contact(**base, ft=0.3, w=0.5)
    b = Contact(**base, Ft=0.3 * 0.58 * 195.0, W=0.5 * a.a)
    assert_allclose([a.ft, a.w, a.Ft, a.W], [b.ft, b.w, b.Ft, b.W], rtol=1e-12)
    assert a.replace(ft=0.1).ft == 0.1 and a.replace(Ft=1.0).Ft == 1.0


@pytest.mark.parametrize(
    "kw, name",
    [
        (dict(R1=0.0), "R1"), (dict(R1=-1.0), "R1"), (dict(L=math.nan), "L"), (dict(Fn=-5.0), "Fn"),
        (dict(mu=0.0), "mu"), (dict(E2=0.0), "E2"), (dict(E2=math.inf), "E2"), (dict(nu2=0.6), "nu2"),
        (dict(nu1=-0.1), "nu1"), (dict(ft=1.0), "ft"), (dict(w=1.0), "w"), (dict(Ft=1e6), "Ft"),
        (dict(W=1.0), "W"), (dict(R1="big"), "R1"), (dict(L=1e-6), "L"),
    ],
)
def test_invalid_fields_name_themselves(kw, name):
    base = dict(R1=0.04, L=0.5, Fn=195.0, mu=0.58, E2=5.1e6, nu2=0.5)
    base.update(kw)
    with pytest.raises(ValueError, match=name):
        Contact(**base)


def test_frozen():
    with pytest.raises(Exception):
        PAPER_SIMULATION.Fn = 1.0  # type: ignore[misc]


def test_summary_round_trip():
    s = PAPER_SIMULATION.summary()
    assert s["a"] == PAPER_SIMULATION.a and set(s) >= {"ft", "w", "beta", "E_star"}
    assert core.Contact(**{k: s[k] for k in ("R1", "L", "Fn", "mu", "E2", "nu2", "R2", "E1", "nu1")}) == PAPER_SIMULATION


def test_one_class_holds_a_line_or_a_point_contact_and_runs_its_body():
    """core.Contact is the one physical-units class: a line (R1, L) or a point (Rx, Ry) contact, with any body of
    its kind at its scales; its run is that body's under its normalised loads."""
    import numpy as np
    line = PAPER_EXPERIMENT.replace(ft=0.3, w=0.4, body=core.Punch(flat=0.5))
    point = Contact(Rx=0.01, Ry=0.02, Fn=10.0, mu=0.5, E2=3e6, nu2=0.4, Ft=1.0, W=2e-4)
    assert not line.is_point and point.is_point and point.body == core.Ellipsoid(2.0)
    assert line.b is None and line.P == line.Fn / line.L and point.P is None and point.b > point.a
    r = line.simulate(periods=2, dx=0.1, kernel="plane")
    ref = core.simulate_cycles(line.ft, line.w, periods=2, dx=0.1, body=core.Punch(flat=0.5))
    assert r.body == core.Punch(flat=0.5) and np.array_equal(r.increment_per_period, ref.increment_per_period)
    s = core.simulate_contact(point, periods=1, dx=0.25)
    assert s.is_patch and s.nu == pytest.approx(0.4) and s.params["ft"] == pytest.approx(point.ft)
    # the point contact's kernel Poisson ratio is the line's strip-kernel one for the same materials
    mixed = PAPER_EXPERIMENT.replace(nu2=0.4)  # a steel cylinder: elastic on both sides
    steel_ball = Contact(Rx=0.01, Ry=0.01, Fn=mixed.Fn, mu=mixed.mu, E2=mixed.E2, nu2=0.4, E1=mixed.E1, nu1=mixed.nu1)
    assert steel_ball.kernel_nu == pytest.approx(core.strip_options(mixed)["nu"], rel=1e-12) and 0.39 < mixed.kernel_nu < 0.4
    with pytest.raises(ValueError, match="not both"):
        Contact(R1=0.04, L=0.08, Fn=1.0, mu=0.5, E2=1e6, nu2=0.5, Rx=0.01, Ry=0.01)
    with pytest.raises(ValueError, match="line core.Contact"):
        core.strip_options(point)
    with pytest.raises(ValueError, match="kernel"):
        core.simulate_contact(point, periods=1, kernel="plane")


def test_point_contact_is_a_deprecated_name_of_contact():
    with pytest.warns(DeprecationWarning, match="PointContact is Contact"):
        old = core.PointContact(Rx=0.01, Ry=0.01, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4)
    new = Contact(Rx=0.01, Ry=0.01, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4)
    assert type(old) is Contact and old == new and round(old.a * 1e3, 3) == 2.657
    assert isinstance(new, core.PointContact) and not isinstance(PAPER_EXPERIMENT, core.PointContact)
