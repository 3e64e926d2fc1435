"""One verdict rule for every body, read from the trend of the increments (issue 21, item 1).

The rule fits ``D_n = D_inf + C r^n`` to the tail of the increments per period: shakedown when ``D_inf``
is below the shakedown tolerance within its uncertainty and ``r < 1``, ratcheting when it is above it
beyond its uncertainty, undetermined otherwise (with the periods likely to decide).
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest

import core
from core.records.result import MIN_FIT_PERIODS, VERDICT_SIGMAS, classify_increments, fit_trend

NOISE = 1e-8  # the solver's tolerance, relative to the largest increment


def _sequence(D, r, periods, noise=NOISE, seed=0, C=0.1):
    """``D + C r^n`` with Gaussian noise of ``noise`` times the largest value."""
    x = D + C * r ** np.arange(periods)
    return x + noise * np.abs(x).max() * np.random.default_rng(seed).standard_normal(periods)


def test_rule_on_short_and_settled_sequences():
    assert classify_increments([1.0, 0.1, 1e-4], 1e-3)[:2] == (2, "shakedown")
    assert classify_increments([1.0, 1e-4, 1e-5], 1e-3)[:2] == (1, "shakedown")
    assert classify_increments([1e-12, 3e-12], 1e-3, floor=1e-9)[:2] == (0, "shakedown")  # solver noise
    assert classify_increments([1.0, 0.5, 0.2], 1e-3, periodic_from=2)[1] == "ratcheting"
    for short in ([1.0, 0.5, 0.5], [1.0, 0.5, 0.2], [0.3]):  # too few periods to fit a trend
        v = classify_increments(short, 1e-3)
        assert v.regime == "undetermined" and v.trend is None and "too few" in v.reason
        assert v.periods_to_decide == MIN_FIT_PERIODS - len(short)
    assert classify_increments([], 1e-3)[1] == "undetermined"


@pytest.mark.parametrize("r", [0.95, 0.99])
@pytest.mark.parametrize("periods", [12, 40, 120])
def test_geometric_decay_to_zero_is_shakedown(r, periods):
    """A steady ratio below 1 is a decay however slow (issue 21: 0.909 was called 'settled')."""
    inc = _sequence(0.0, r, periods)
    v = classify_increments(inc, 1e-3, floor=NOISE * 0.1)
    assert v.regime == "shakedown", v.reason
    assert v.shakedown_period is None and "decays geometrically" in v.reason  # the fit decided, not the tail
    assert abs(v.trend.D_inf) <= VERDICT_SIGMAS * v.trend.D_inf_error + 1e-12
    assert v.trend.ratio == pytest.approx(r, abs=1e-3)
    assert v.trend.D_inf_error < 1e-3 * 0.1  # the fit resolves D_inf well inside the tolerance


@pytest.mark.parametrize("r", [0.95, 0.99])
@pytest.mark.parametrize("periods", [12, 40, 120])
def test_convergence_to_a_constant_is_ratcheting(r, periods):
    D = 0.02  # a fifth of the first increment
    inc = _sequence(D, r, periods)
    v = classify_increments(inc, 1e-3, floor=NOISE * 0.1)
    assert v.regime == "ratcheting", v.reason
    assert "tends to a constant" in v.reason and "D_inf" in v.reason
    assert abs(v.trend.D_inf - D) <= VERDICT_SIGMAS * v.trend.D_inf_error
    assert v.trend.D_inf_error < 1e-3 * D
    assert v.trend.ratio == pytest.approx(r, abs=1e-3)


def test_negative_increments_are_read_in_their_own_direction():
    v = classify_increments(-_sequence(0.02, 0.95, 30), 1e-3, floor=1e-9)
    assert v.regime == "ratcheting" and v.trend.D_inf == pytest.approx(-0.02, rel=1e-4)


def test_settled_ratio_rule_is_gone():
    """Issue 21's case: a ratio steady at 0.909 for 15 periods, increments from 8.8e-2 to 9.2e-5 over 40."""
    inc = 8.8e-2 * 0.5 ** np.minimum(np.arange(40), 3) * 0.909 ** np.maximum(np.arange(40) - 3, 0)
    inc *= 1 + NOISE * np.random.default_rng(1).standard_normal(40)
    assert inc[-1] / inc[-2] == pytest.approx(0.909, rel=1e-6) and inc[-1] > 1e-3 * inc.max()
    assert classify_increments(inc, 1e-3, floor=1e-7).regime == "shakedown"


def test_undetermined_says_how_many_more_periods_and_they_decide():
    """Noisy increments at r = 0.99: undetermined after 20 periods; the estimate of the periods needed is right."""
    noise = 1e-4
    inc = _sequence(0.0, 0.99, 1000, noise=noise, seed=3)
    v = classify_increments(inc[:20], 1e-3, floor=noise * 0.1)
    assert v.regime == "undetermined" and v.trend is not None
    more = v.periods_to_decide
    assert more is not None and f"roughly {more} more periods" in v.reason
    assert 100 < more < 980
    assert classify_increments(inc[:20 + more], 1e-3, floor=noise * 0.1).regime == "shakedown"
    assert classify_increments(inc[:20 + more // 10], 1e-3, floor=noise * 0.1).regime == "undetermined"


#: Increments per period of the free cone (inner 0) at w 0.3, ft 0.5485 (5 % below its grid limit), a_m/10,
#: 40 periods, measured on the engine: their ratio rises from 0.94 to 0.958; 200 periods shake down (period 101).
CONE_NEAR_LIMIT = [
    0.0154944, 0.00531817, 0.00263579, 0.00188348, 0.00149531, 0.00125124, 0.00107989, 0.000954743, 0.000855401,
    0.000773957, 0.000706031, 0.00064879, 0.000599169, 0.000555979, 0.000517832, 0.000484301, 0.000454168,
    0.000428048, 0.000404241, 0.000382161, 0.000362516, 0.000343652, 0.000326033, 0.000310231, 0.000295323,
    0.000280875, 0.000267348, 0.000255299, 0.000243828, 0.000232769, 0.000222244, 0.000212179, 0.000203174,
    0.000194728, 0.000186453, 0.000178461, 0.000170792, 0.000163471, 0.000156542, 0.000150024]


#: The frustum (inner 0.5) at w 0.38243, ft 0.5, a_m/4, its first 20 periods (the limit search's run): it shakes
#: down from period 130.
CONE_20_PERIODS = [
    0.0194903, 0.0067151, 0.00291324, 0.0020736, 0.00171422, 0.00148122, 0.00130983, 0.00117693, 0.00106839,
    0.000978431, 0.000902397, 0.000836226, 0.000779731, 0.000727372, 0.000684525, 0.00064463, 0.000605995,
    0.000572435, 0.000544304, 0.000516687]


def test_twenty_periods_of_a_slow_decay_are_undetermined_and_the_search_runs_longer():
    """Tails of 16, 12, 6 periods fit 4.3e-4, 3.3e-4, 2.9e-4: each within the errors of the next, but not within
    STEADY_FRACTION: undetermined (the limit search then doubles the periods), not ratcheting."""
    v = classify_increments(CONE_20_PERIODS, 1e-3, floor=1e-9)
    assert v.regime == "undetermined" and v.periods_to_decide > 0, v.reason


def test_the_cone_slowly_shaking_down_is_not_called_ratcheting():
    """One tail's fit extrapolates these to D_inf = 6.4e-5 +- 1.2e-5 (r 0.938), but tails of 32, 24, 16, 12
    periods give 1.2e-4, 6.4e-5, 4.0e-5, 2.7e-5: the limit drifts down, the trend is not steady. The rule called
    this ratcheting before the tails had to agree within STEADY_FRACTION of D_inf."""
    v = classify_increments(CONE_NEAR_LIMIT, 1e-3, floor=1e-9)
    assert v.regime == "undetermined" and "disagree" in v.reason, v.reason
    assert 10 < v.periods_to_decide < 200


@pytest.mark.parametrize("a, b, r1, r2", [(1e-3, 5e-4, 0.9, 0.97), (1e-3, 3e-4, 0.85, 0.96), (2e-3, 2e-4, 0.8, 0.975)])
def test_a_decay_that_slows_down_is_not_called_ratcheting(a, b, r1, r2):
    """Two decaying modes (the free cone near its limit: per-period ratios 0.94 rising to 0.958 over 40 periods)
    look like ``D_inf + C r^n`` with ``D_inf > 0`` on one tail, but the fitted limit falls tail after tail: not a
    steady trend, so 40 periods are undetermined, and enough periods shake down."""
    n = np.arange(400)
    inc = a * r1 ** n + b * r2 ** n
    v = classify_increments(inc[:40], 1e-3, floor=1e-9)
    assert v.regime == "undetermined" and "disagree" in v.reason and v.periods_to_decide > 0
    assert classify_increments(inc, 1e-3, floor=1e-9).regime == "shakedown"


def test_fit_trend_recovers_the_parameters():
    t = fit_trend(0.3 + 0.7 * 0.8 ** np.arange(15), floor=1e-12)
    assert (t.D_inf, t.ratio) == (pytest.approx(0.3, abs=1e-9), pytest.approx(0.8, abs=1e-8))
    assert t.aitken == pytest.approx(0.3, abs=1e-9) and t.periods_fitted == 12
    assert fit_trend([1.0, 0.5, 0.25]) is None
    assert math.isnan(fit_trend(np.full(8, 0.25), floor=1e-12).ratio)  # nothing changes: no ratio


@pytest.mark.parametrize("w", [0.3, 0.5])
def test_cylinder_at_one_percent_from_the_limit(w):
    """Real runs 1 % below and above the exact limit: ratcheting is told at 6 periods; shakedown is told at
    6 periods or, honestly undetermined there, after the periods the verdict said it would need."""
    limit = float(core.ft_limit(w))
    below = core.simulate_cycles(0.99 * limit, w, periods=6)
    if below.regime == "undetermined":
        assert below.periods_to_decide is not None and "more periods would likely decide" in below.regime_reason
        below = core.simulate_cycles(0.99 * limit, w, periods=6 + below.periods_to_decide)
    assert below.regime == "shakedown", below.regime_reason
    assert abs(below.D_inf) < 3 * below.D_inf_error + 1e-6 and 0 < below.decay_ratio < 1
    above = core.simulate_cycles(1.01 * limit, w, periods=6)
    assert above.regime == "ratcheting" and "tends to a constant" in above.regime_reason, above.regime_reason
    long = core.simulate_cycles(1.01 * limit, w, periods=40)  # the increment it settles to
    assert abs(above.D_inf - long.increment_per_period[-1]) <= 3 * above.D_inf_error + 1e-9
    assert above.D_inf_error < 0.1 * above.D_inf
    s = above.summary()
    assert (s["D_inf"], s["D_inf_error"], s["dx"]) == (above.D_inf, above.D_inf_error, pytest.approx(above.dx))
    assert math.isnan(s["decay_ratio"]) or s["decay_ratio"] == above.decay_ratio


def test_cylinder_at_a_tenth_of_a_percent_from_the_limit():
    """0.1 % from the limit the fit still decides, before the increments fall below the tolerance."""
    w = 0.5
    limit = float(core.ft_limit(w))
    below = core.simulate_cycles(0.999 * limit, w, periods=8)
    assert below.regime == "shakedown" and "decays geometrically" in below.regime_reason, below.regime_reason
    above = core.simulate_cycles(1.001 * limit, w, periods=8)
    assert above.regime == "undetermined" and above.periods_to_decide is not None, above.regime_reason
    above = core.simulate_cycles(1.001 * limit, w, periods=8 + 2 * above.periods_to_decide)
    assert above.regime == "ratcheting" and "tends to a constant" in above.regime_reason, above.regime_reason


def test_both_results_use_the_rule():
    for r in (core.simulate_cycles(0.4, 0.6, periods=5, dx=0.1),
              core.simulate_cycles(0.4, 0.6, periods=5, dx=0.25, body="sphere")):
        v = classify_increments(r.increment_per_period, r.shakedown_rtol, r.periodic_from, floor=10 * r.tol)
        assert (r.shakedown_period, r.regime) == (v.shakedown_period, v.regime)
        # the reason names both trends: the walk's (this rule's words) and the energy's
        assert "walk: " + v.reason.split(" mu ")[0] in r.regime_reason and "; energy: " in r.regime_reason
        assert (r.D_inf, r.D_inf_error) == (v.trend.D_inf, v.trend.D_inf_error)
        assert r.periods_to_decide == v.periods_to_decide
        s = r.summary()
        for name in ("D_inf", "D_inf_error", "decay_ratio", "dx"):
            assert name in s
    assert r.regime == "ratcheting" and np.all(r.increment_per_period > 0)


def test_tol_reaches_point_contacts():
    r = core.simulate_cycles(0.4, 0.3, periods=1, dx=0.25, body="sphere", tol=1e-6)
    assert r.tol == 1e-6
    assert core.simulate_cycles(0.4, 0.3, periods=1, dx=0.25, body="sphere").tol == core.solvers.solver3d.TOL_3D


def test_the_cli_prints_the_trend_and_the_grid(capsys):
    from core.command.cli import main

    assert main(["run", "--ft", "0.3", "--w", "0.3", "--periods", "6"]) == 0
    out = capsys.readouterr().out
    assert "D_inf (limit increment)" in out and "r (decay per period)" in out
    assert re.search(r"element width dx +0\.025 a \(the body's default\)", out), out
    assert main(["run", "--ft", "0.2075", "--w", "0.6", "--periods", "5", "--body", "sphere", "--dx", "0.25"]) == 0
    out = capsys.readouterr().out
    assert "mu Fn/(E* a)" in out and "element width dx" in out and "0.25 a\n" in out
    assert main(["run", "--ft", "0.3", "--w", "0.3", "--periods", "2"]) == 0
    assert "too few periods to fit the trend" in capsys.readouterr().out


# ---- Melan's limit of the run's own grid checks the verdicts read from the trend -----------------------------

def _cone_near_limit():
    """The measured full cone at w 0.5 (``tests/data/cone_near_limit_increments.csv``): increments 3 % below and
    above Melan's limit on the run's grid, the two loads, and the limit ``(lo, hi)``."""
    path = Path(__file__).parent / "data" / "cone_near_limit_increments.csv"
    head = path.read_text().splitlines()[:4]
    values = dict(re.findall(r"(\w+) = ([0-9.e+-]+)", " ".join(head)))
    data = np.loadtxt(path, delimiter=",", skiprows=5)
    return (data[:, 1], data[:, 2], float(values["ft_below"]), float(values["ft_above"]),
            (float(values["lo"]), float(values["hi"])))


def _fit_each_tail_once(monkeypatch):
    """Let :func:`classify_increments` fit each sequence once: the same increments classified with and without
    Melan's limit are fitted by the same pure function (:func:`fit_trend`, 98 % of a verdict's time), so the second
    verdict gets the first one's fit. Returns the fits made, by increments."""
    import core.records.verdict as verdict

    fits, fit = {}, verdict.fit_trend

    def once(increments, floor=0.0):
        key = (np.asarray(increments, dtype=float).tobytes(), floor)
        if key not in fits:
            fits[key] = fit(increments, floor)
        return fits[key]

    monkeypatch.setattr(verdict, "fit_trend", once)
    return fits


def test_the_slow_cone_below_its_limit_is_never_called_ratcheting(monkeypatch):
    """Below the limit the ratio of successive increments creeps up (0.9946 after 156 periods, 0.9964 after 330)
    each time the slip zones change: on tails of some lengths the trend alone reads ratcheting (after 185, 236,
    291 and 334 periods it did). With Melan's limit of the grid the verdict is undetermined there, and says the
    run will shake down; above the limit the same checks leave the ratcheting verdict. Each tail is fitted once
    for its two verdicts (:func:`_fit_each_tail_once`: 1600 fits took 39 s of a CI run)."""
    fits = _fit_each_tail_once(monkeypatch)
    below, above, ft_below, ft_above, limit = _cone_near_limit()
    alone = [classify_increments(below[:n], 1e-3, floor=1e-8).regime for n in range(4, below.size + 1)]
    assert alone.count("ratcheting") > 10  # what the guard is for
    for n in range(4, below.size + 1):
        v = classify_increments(below[:n], 1e-3, floor=1e-8, load=ft_below, limit=limit)
        assert v.regime != "ratcheting", n
    assert v.regime == "undetermined" and "3.00% below Melan's limit on this grid" in v.reason
    assert v.reason.endswith("it will shake down")
    checked = [classify_increments(above[:n], 1e-3, floor=1e-8, load=ft_above, limit=limit).regime
               for n in range(4, above.size + 1)]
    assert "shakedown" not in checked and checked[-1] == "ratcheting"
    assert checked == [classify_increments(above[:n], 1e-3, floor=1e-8).regime for n in range(4, above.size + 1)]
    assert len(fits) == below.size - 3 + above.size - 3  # every tail fitted, once


def test_a_decay_to_zero_above_the_limit_is_not_called_shakedown():
    """The mirror case: a clean geometric decay that the trend reads as shakedown, at a load above the limit."""
    inc = _sequence(0.0, 0.95, 40)
    assert classify_increments(inc, 1e-3, floor=1e-9).regime == "shakedown"
    v = classify_increments(inc, 1e-3, floor=1e-9, load=0.51, limit=(0.5, 0.5))
    assert v.regime == "undetermined" and "2.00% above Melan's limit" in v.reason and "keep walking" in v.reason
    # the increments themselves still decide: every one below the tolerance from some period on
    assert classify_increments(_sequence(0.0, 0.5, 40), 1e-3, floor=1e-9, load=0.51, limit=(0.5, 0.5)).regime \
        == "shakedown"


def test_the_limit_is_asked_for_only_when_a_trend_verdict_needs_it():
    calls = []

    def limit():
        calls.append(1)
        return (0.5, 0.5)
    classify_increments([1.0, 1e-4, 1e-5], 1e-3, load=0.4, limit=limit)  # decided by the increments
    classify_increments([1.0, 0.5, 0.2], 1e-3, periodic_from=2, load=0.4, limit=limit)  # a repeating state
    assert calls == []
    classify_increments(_sequence(0.02, 0.95, 40), 1e-3, floor=1e-9, load=0.6, limit=limit)
    assert calls == [1]
    for bad in (None, (math.nan, 1.0), (0.0, 0.0)):  # no limit, or none usable: the trend's verdict stands
        assert classify_increments(_sequence(0.02, 0.95, 40), 1e-3, floor=1e-9, load=0.4,
                                   limit=bad).regime == "ratcheting"


@pytest.mark.parametrize("body, dx, exact", [("cylinder", 1 / 40, 1e-12), (core.Punch(flat=0.5), 1 / 40, 5e-4),
                                             ("sphere", 0.1, 5e-3)])
def test_a_run_knows_melan_limit_of_its_grid(body, dx, exact):
    """``sum mu p_min dA`` of the run's own lowest pressure: the closed-form limit to the grid's accuracy (the
    cylinder's element means are exact for aligned shifts)."""
    r = core.simulate_cycles(0.3, 0.3, periods=4, dx=dx, body=body)
    lo, hi = r.melan_limit
    assert lo == hi and lo == pytest.approx(float(core.ft_limit(0.3, body=body)), rel=exact)


def test_a_cone_run_uses_the_grid_programme_and_says_where_the_load_is():
    body = core.Cone(inner=0.5)
    lim = body.grid_limit(0.3)
    r = core.simulate_cycles(0.5, 0.3, periods=6, body=body)
    assert r.melan_limit == (pytest.approx(lim["lo"], rel=1e-8), pytest.approx(lim["hi"], rel=1e-8))  # HiGHS
    assert r.regime == "undetermined" and "below Melan's limit on this grid" in r.regime_reason


def test_melan_limit_needs_a_constant_tangential_load_in_the_last_period():
    assert core.simulate_cycles(0.3, 0.3, periods=4, shape="sine").melan_limit is not None
    varying = core.simulate_cycles(0.3, 0.3, periods=4, history="tangential")
    assert np.ptp(varying.Q[varying.period == varying.period[-1]]) > 0 and varying.melan_limit is None
    # a normal force 1 +- 0.2 under a constant Ft: p_min is also the lowest over the load, so the limit is lower
    # than at constant load (0.6238, eq 35 at w 0.3) and is the sum of the run's own lowest pressure
    normal = core.simulate_cycles(0.3, 0.3, periods=4, history="normal")
    last = normal.period == normal.period[-1]
    assert np.ptp(normal.P[last]) == pytest.approx(0.4) and np.ptp(normal.Q[last]) == 0
    lo, hi = normal.melan_limit
    step = np.flatnonzero(last)[-1]
    expected = normal.lowest_pressure.sum() / normal.pressure[step].sum() * normal.P[step]
    assert lo == hi == pytest.approx(expected, rel=1e-12) and 0.55 < lo < float(core.ft_limit(0.3)) - 0.01
