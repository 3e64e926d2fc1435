"""Point contacts under every loading history: one path from any body and any history to a result.

The sphere under an oscillating tangential force at a fixed centre is Mindlin and Deresiewicz's
problem: at nu = 0 the loading curve is Mindlin's U(Q) = (3/4)(1 - (1 - Q)^(2/3)) [mu Fn/(E* a)] and
the unloading branch from Q* follows Masing's rule U(Q) = U(Q*) - 2 U((Q* - Q)/2), a hysteresis loop
that a linear-elastic contact would not have.
"""

import numpy as np
import pytest

import core
from core.command.cli import main


def _mindlin(q):
    """Mindlin's tangential displacement of a sphere loaded from rest to ``q = Ft/(mu Fn)`` (nu = 0)."""
    return np.sign(q) * 0.75 * (1.0 - (1.0 - np.abs(q)) ** (2.0 / 3.0))


@pytest.fixture(scope="module")
def fretting():
    amplitude = 0.6
    r = core.simulate_cycles(0.0, 0.0, periods=2, dx=0.1, dW=0.05, body="sphere", history="tangential",
                             amplitude=amplitude, nu=0.0, normal="exact")
    return r, amplitude


def test_sphere_tangential_is_mindlin_deresiewicz(fretting):
    r, amplitude = fretting
    assert r.is_patch and r.params["history"] == "tangential" and r.params["amplitude"] == amplitude
    u = r.displacement[:, 0]
    np.testing.assert_array_equal(r.displacement[:, 1], 0.0, err_msg="no lateral displacement at nu = 0")
    up = (r.period == 0) & (np.arange(r.Q.size) <= int(np.argmax(r.Q)))  # first loading: Mindlin's curve
    np.testing.assert_allclose(u[up], _mindlin(r.Q[up]), atol=2e-3, err_msg="loading curve (Mindlin)")
    top = int(np.argmax(r.Q))
    down = np.arange(top, int(np.argmin(r.Q)) + 1)  # unloading from +Q* to -Q*: Masing's rule
    masing = u[top] - 2.0 * _mindlin((r.Q[top] - r.Q[down]) / 2.0)
    np.testing.assert_allclose(u[down], masing, atol=3e-3, err_msg="unloading branch (Masing)")
    at_zero = down[np.isclose(r.Q[down], 0.0)]
    assert at_zero.size == 1 and u[at_zero[0]] > 0.02, "a hysteresis loop: U > 0 where Q returns to 0"
    # the loop closes from the first period on (no ratcheting under a fixed centre); the last period's reloading
    # from -Q* is the unloading branch turned over
    ends = np.flatnonzero(np.diff(r.period))
    np.testing.assert_allclose(u[-1], u[ends[-1]], atol=1e-6)
    last = np.flatnonzero(r.period == r.period[-1])
    rise = last[last <= last[0] + int(np.argmax(r.Q[last]))]
    np.testing.assert_allclose(u[rise], -u[top] + 2.0 * _mindlin((r.Q[rise] + r.Q[top]) / 2.0), atol=3e-3,
                               err_msg="reloading branch (Masing)")
    assert abs(r.increment_per_period[-1]) < 1e-6  # no walk: the loop closes
    # the body does not walk but slips every period (issue 30): not a shakedown. Two periods are too few to fit
    # the energy's trend (undetermined); tests/test_regimes.py runs 4 and finds cyclic slip. The energy of the
    # closed loop is Mindlin-Deresiewicz's with Masing's rule, exact at nu = 0: +5.2 % at this coarse a/10
    assert r.regime == "undetermined" and "energy: 2 periods are too few" in r.regime_reason, r.regime_reason
    np.testing.assert_allclose(r.dissipation_per_period[-1], core.fretting_energy(amplitude, "sphere", nu=0.0),
                               rtol=0.06)


def test_sphere_normal_history_scales_the_bound():
    """Under an oscillating normal force each step's bound carries that step's load: sum(mu p) dA = P * total_load,
    and an amplitude of 0 is the rocking history to round-off."""
    r = core.simulate_cycles(0.3, 0.3, periods=2, dx=0.2, body="sphere", history="normal", amplitude=0.4)
    assert r.params["history"] == "normal" and np.ptp(r.P) > 0.7
    dA = r.dx ** 2
    carried = np.array([r.pressure_at(k).sum() * dA for k in range(r.xc.size)])
    np.testing.assert_allclose(carried, r.P * r.body.total_load, rtol=1e-6, err_msg="load of every step")
    flat = core.simulate_cycles(0.3, 0.3, periods=2, dx=0.2, body="sphere", history="normal", amplitude=0.0)
    rocking = core.simulate_cycles(0.3, 0.3, periods=2, dx=0.2, body="sphere")
    np.testing.assert_allclose(flat.increment_per_period, rocking.increment_per_period, rtol=0, atol=1e-12)


def test_point_contact_takes_arrays():
    """A mapping of per-step arrays runs on a point contact as on a line."""
    xc = np.r_[0.0, 0.2, 0.0, -0.2, 0.0, 0.2, 0.0, -0.2, 0.0]
    r = core.simulate_cycles(0.2, 0.0, dx=0.2, body="sphere", history={"xc": xc, "period": [-1, 0, 0, 0, 0, 1, 1, 1, 1]})
    np.testing.assert_array_equal(r.xc, xc)
    assert r.params["history"] == "arrays" and r.params["periods"] == 2


def test_point_contact_simulate_passes_the_history():
    c = core.Contact(Rx=0.01, Ry=0.01, Fn=100.0, mu=0.5, E2=2e11, nu2=0.3, Ft=20.0)
    r = c.simulate(periods=2, dx=0.2, history="tangential", amplitude=0.3)
    assert r.params["history"] == "tangential" and float(np.ptp(r.Q)) == pytest.approx(0.6)


def test_cli_runs_a_sphere_under_a_tangential_history(capsys):
    code = main(["run", "--ft", "0.3", "--w", "0", "--body", "sphere", "--history", "tangential", "--dx", "0.2",
                 "--periods", "2"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "oscillating tangential force at a fixed centre" in out.splitlines()[0]
    assert "3D half-space" in out.splitlines()[0]
