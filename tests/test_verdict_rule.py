"""One verdict rule for every body: the cylinder's and the point contacts' results classify the same way."""

import numpy as np

import core
from core.result import SETTLED_RATIO, classify_increments


def test_rule_on_increment_sequences():
    assert classify_increments([1.0, 0.1, 1e-4], 1e-3)[:2] == (2, "shakedown")
    assert classify_increments([1.0, 1e-4, 1e-5], 1e-3)[:2] == (1, "shakedown")
    assert classify_increments([1e-12, 3e-12], 1e-3, floor=1e-9)[:2] == (0, "shakedown")  # solver noise
    assert classify_increments([1.0, 0.5, 0.5 * SETTLED_RATIO], 1e-3)[1] == "ratcheting"
    assert classify_increments([1.0, 0.5, 0.2], 1e-3)[1] == "undetermined"
    assert classify_increments([1.0, 0.5, 0.2], 1e-3, periodic_from=2)[1] == "ratcheting"
    assert classify_increments([0.3], 1e-3)[1] == "undetermined"
    assert classify_increments([], 1e-3)[1] == "undetermined"


def test_both_results_use_the_rule():
    for r in (core.simulate_cycles(0.4, 0.6, periods=3, dx=0.1),
              core.simulate_cycles(0.4, 0.6, periods=3, dx=0.25, body="sphere")):
        period, regime, reason = classify_increments(r.increment_per_period, r.shakedown_rtol, r.periodic_from,
                                                     floor=10 * r.tol)
        assert (r.shakedown_period, r.regime) == (period, regime)
        assert r.regime_reason.split(" mu ")[0] == reason.split(" mu ")[0]
    assert r.regime == "ratcheting" and np.all(r.increment_per_period > 0)


def test_tol_reaches_point_contacts():
    r = core.simulate_cycles(0.4, 0.3, periods=1, dx=0.25, body="sphere", tol=1e-6)
    assert r.tol == 1e-6
    assert core.simulate_cycles(0.4, 0.3, periods=1, dx=0.25, body="sphere").tol == core.solver3d.TOL_3D
