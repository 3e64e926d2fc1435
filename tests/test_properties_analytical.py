"""Hypothesis property tests of the analytical core over its whole domain."""

import numpy as np
from hypothesis import given, settings, strategies as st

import core
from core.theory import analytical as an

unit = st.floats(0.0, 1.0, exclude_max=True, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(ft=unit, w=unit)
def test_c_sd_defined_exactly_in_shakedown_region(ft, w):
    c = core.shakedown_stick_halfwidth(ft, w)
    if ft <= core.ft_limit(w):
        assert not np.isnan(c)
        assert -1e-12 <= c <= 1.0 - w + 1e-12
        assert abs(an.shakedown_closure(c, w) - ft) < 1e-9
    else:
        assert np.isnan(c)


@settings(max_examples=200, deadline=None)
@given(ft=unit, w=unit)
def test_regime_matches_limit(ft, w):
    r = core.classify_regime(ft, w)
    assert r == ("shakedown" if ft <= core.ft_limit(w) else "ratcheting")


@settings(max_examples=200, deadline=None)
@given(ft=unit, w=unit)
def test_traction_bounded_by_lowest_pressure(ft, w):
    x = np.linspace(-1, 1, 201)
    q = an.shakedown_traction(x, ft, w)
    if np.isnan(q).any():
        assert ft > core.ft_limit(w)
    else:
        assert np.all(np.abs(q) <= an.lowest_pressure(x, w) + 1e-12)


bad = st.one_of(
    st.floats(allow_nan=True).filter(lambda v: not (0 <= v < 1)),
    st.just(float("nan")),
    st.text(max_size=5),
)


@settings(max_examples=200, deadline=None)
@given(v=bad, other=unit)
def test_bad_inputs_raise(v, other):
    for call in (lambda: core.shakedown_stick_halfwidth(v, other), lambda: core.shakedown_stick_halfwidth(other, v)):
        try:
            call()
        except ValueError:
            pass
        else:
            raise AssertionError(f"no ValueError for {v!r}")
