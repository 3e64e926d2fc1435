"""The figures' reference curves describe the run they are drawn beside.

The closed forms (Hertz's pressure and its lowest over the rocking, the paper's closure of eqs 22-30, u_sd of
eq 34) are the constant-load rocking's of an uncoupled contact. Beside a run under the oscillating normal force,
a coupled run (beta != 0) or the tangential loading, the figures draw the run's own pressure and lowest pressure
and leave out the closure and u_sd, which would otherwise sit beside the run as if they were its prediction.
"""

import numpy as np
import pytest

import core
from app import plots

U = plots.make_units("normalised", None, "plane")


def _layer(name, inputs, label):
    labels = [getattr(s, "label", None) for s in plots.specs(name, U)]
    return plots.layers(name, inputs)[labels.index(label)]


def _stairs_values(layer):
    """The per-element values of a stairs layer (every second point)."""
    return np.asarray(layer[1])[::2]


@pytest.fixture(scope="module")
def runs():
    return {
        # (the strip kernel: u_sd of eq 34 is drawn beside a run with a displacement scale U0; the coupled solver
        # is plane strain's, and draws no u_sd anyway)
        "rocking": core.simulate_cycles(0.3, 0.4, periods=2, dx=0.05, kernel="strip", L_over_a=20.0),
        "normal": core.simulate_cycles(0.3, 0.4, periods=2, dx=0.05, kernel="strip", L_over_a=20.0, history="normal",
                                       amplitude=0.4),
        "coupled": core.simulate_cycles(0.3, 0.4, periods=2, dx=0.05, beta=0.25, mu=0.3),
        "tangential": core.simulate_cycles(0.3, 0.4, periods=2, dx=0.05, kernel="strip", L_over_a=20.0, history="tangential",
                                           amplitude=0.3),
    }


def test_the_rocking_keeps_its_closed_forms(runs):
    r = runs["rocking"]
    i = plots.Inputs(0.3, 0.4, U, r)
    low = _layer("pressure", i, "μ p_min (cycle)")
    np.testing.assert_allclose(low[1], U.mu * core.lowest_pressure(np.asarray(low[0]), 0.4), atol=1e-12)
    assert len(_layer("traction", i, "closure (paper)")[0]) > 0
    assert len(plots.displacement_curves(r, U)[1]) == 1, "u_sd of eq 34"


@pytest.mark.parametrize("kind", ["normal", "coupled"])
def test_an_oscillating_force_or_coupling_draws_the_runs_own_pressures(runs, kind):
    r = runs[kind]
    i = plots.Inputs(0.3, 0.4, U, r, frame=7)
    low = _layer("pressure", i, "μ p_min (cycle)")
    np.testing.assert_allclose(_stairs_values(low), U.mu * r.lowest_pressure, rtol=0, atol=1e-15)
    step = _layer("pressure", i, "this step")
    np.testing.assert_allclose(_stairs_values(step), r.pressure[7], rtol=0, atol=1e-15)
    bound = _layer("traction", i, "±μ p_min")
    np.testing.assert_allclose(_stairs_values(bound), r.lowest_pressure, rtol=0, atol=1e-15)
    assert len(_layer("traction", i, "closure (paper)")[0]) == 0, "no closure of the constant-load rocking"
    assert plots.displacement_curves(r, U)[1] == [], "no u_sd of eq 34"


def test_the_drawn_lowest_pressure_is_the_runs_not_the_constant_loads(runs):
    """Under the oscillating force (A = 0.4) the lowest pressure falls below the constant load's closed form:
    drawing the closed form would show a bound the run's tractions exceed."""
    r = runs["normal"]
    closed = core.lowest_pressure(r.x, 0.4)
    assert np.max(closed - r.lowest_pressure) > 0.1


def test_the_tangential_loading_has_no_closure_and_its_bound_at_the_fixed_centre(runs):
    r = runs["tangential"]
    i = plots.Inputs(0.3, 0.4, U, r)
    assert len(_layer("traction", i, "closure (paper)")[0]) == 0
    bound = _layer("traction", i, "±μ p_min")
    np.testing.assert_allclose(bound[1], U.q * core.lowest_pressure(np.asarray(bound[0]), 0.0), atol=1e-12)
    assert plots.displacement_curves(r, U)[1] == []


@pytest.mark.parametrize("kind", ["rocking", "normal", "coupled", "tangential"])
def test_the_traction_title_names_only_what_every_run_draws(runs, kind):
    """The closure is drawn beside the constant-load rocking only; the title is the same for every run (it names
    the figure for the slides and screenshots), so it must not promise the closure."""
    title = plots.FIGURES["traction"]["opts"]["title"]
    assert "traction" in title.lower() and "bound" in title.lower(), title
    closure = _layer("traction", plots.Inputs(0.3, 0.4, U, runs[kind]), "closure (paper)")
    assert len(closure[0]) > 0 or "closure" not in title.lower(), (kind, title)
