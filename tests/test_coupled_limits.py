"""The coupled limit curve ft_lim(w) of dissimilar materials (issue 32): core.coupled_limit, core.coupled_limit_curve."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import core
from core.maps.coupled_limits import CoupledLimit, CoupledLimitCurve

#: benchmarks/results/coupled_limits.txt: beta = +-0.25, mu = 0.3, w = 0.6 at a/40: the limit in [0.735, 0.741] x eq 35
A40_BRACKET = (0.735, 0.741)


@pytest.mark.parametrize("kwargs, name", [
    (dict(beta=0.5), "beta"), (dict(beta=-0.6), "beta"), (dict(mu=0.0), "mu"), (dict(mu=11.0), "mu"),
    (dict(w=[0.3, 1.0]), "w"), (dict(w=[0.0]), "w"), (dict(w=[]), "w"), (dict(w=np.linspace(0.1, 0.9, 21)), "w"),
    (dict(dx=0.5), "dx"), (dict(tol=0.0), "tol"), (dict(periods=1), "periods"), (dict(lo=1.0), "lo"),
    (dict(lo=0.6, hi=0.5), "hi"),
])
def test_bad_inputs_name_the_parameter(kwargs, name):
    args = {**dict(beta=0.25, mu=0.3, w=[0.5]), **kwargs}
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        core.coupled_limit_curve(**args)


def test_the_coupled_limit_at_w_06_agrees_with_the_finer_grids_bracket_and_lies_below_eq_35():
    seen = []
    curve = core.coupled_limit_curve(0.25, 0.3, w=[0.6], on_point=seen.append)
    (point,) = curve.points
    assert seen == [point] and point.converged, point.message
    eq35 = float(core.ft_limit(0.6))
    assert point.ft_eq35 == pytest.approx(eq35, rel=1e-12)
    lo, hi = point.ft_shakedown / eq35, point.ft_ratcheting / eq35
    assert hi - lo <= 0.02 + 1e-12, (lo, hi)
    # a/20 against a/40: within 3 % of eq 35 of the finer grid's bracket, and well below eq 35 (a fall of ~25 %)
    assert A40_BRACKET[0] - 0.03 <= lo and hi <= A40_BRACKET[1] + 0.03, (lo, hi)
    assert point.fall == pytest.approx(1 - 0.5 * (lo + hi)) and point.fall > 0.2
    # every run is recorded once, each at its own ft, the lower end not ratcheting and the upper one ratcheting
    fts = [r[0] for r in point.runs]
    assert len(set(fts)) == len(fts) == curve.runs
    regimes = dict((r[0], r[1]) for r in point.runs)
    assert regimes[point.ft_shakedown] in core.maps.coupled_limits.NOT_RATCHETING
    assert regimes[point.ft_ratcheting] == "ratcheting"
    with pytest.raises(dataclasses.FrozenInstanceError):
        curve.beta = 0.1


def test_a_starting_bracket_on_the_wrong_side_is_widened_without_running_an_end_twice():
    point = core.coupled_limit(0.6, beta=-0.25, mu=0.3, lo=0.9, hi=1.0, tol=0.05)
    eq35 = point.ft_eq35
    assert point.converged, point.message
    assert point.ft_shakedown / eq35 < 0.9  # below the starting bracket: its lower end ratcheted
    assert A40_BRACKET[0] - 0.06 <= point.ft_shakedown / eq35 <= point.ft_ratcheting / eq35 <= A40_BRACKET[1] + 0.06
    fts = [r[0] for r in point.runs]
    assert len(set(fts)) == len(fts), fts


def test_uncoupled_the_bracket_holds_eq_35():
    """beta = 0: the same search finds Melan's limit (eq 35) within its bracket and the a/20 grid's error."""
    point = core.coupled_limit(0.5, beta=0.0, mu=0.3, tol=0.04)
    assert point.converged, point.message
    assert point.ft_shakedown / point.ft_eq35 - 0.02 <= 1.0 <= point.ft_ratcheting / point.ft_eq35 + 0.02, point


def test_the_limit_between_the_curves_amplitudes_follows_eq_35_scaled_by_the_interpolated_ratio():
    eq35 = {w: float(core.ft_limit(w)) for w in (0.3, 0.5, 0.4)}
    pts = (CoupledLimit(0.3, 0.90 * eq35[0.3], 0.92 * eq35[0.3], eq35[0.3], True, ()),
           CoupledLimit(0.5, 0.80 * eq35[0.5], 0.82 * eq35[0.5], eq35[0.5], True, ()),
           CoupledLimit(0.7, math.nan, math.nan, float(core.ft_limit(0.7)), False, ()))
    curve = CoupledLimitCurve(0.25, 0.3, 0.05, 0.02, 20, pts)
    assert curve.ft_limit_at(0.3) == pytest.approx(0.91 * eq35[0.3], rel=1e-12)
    assert curve.ft_limit_at(0.4) == pytest.approx(0.86 * eq35[0.4], rel=1e-12)
    assert math.isnan(curve.ft_limit_at(0.6)) and math.isnan(curve.ft_limit_at(0.2))  # no extrapolation
    assert np.isnan(curve.ft_limit[2]) and curve.at(0.5) is pts[1] and curve.at(0.55) is None
    with pytest.raises(ValueError, match="^w"):
        curve.ft_limit_at(1.0)
