"""A body defined in this file alone (no closed form) runs through the API: docs/dev/adding-a-body.md's example."""

import math

import numpy as np
import pytest

import core
from core.geometry.bodies import Body


class Crowned(Body):
    """A roller crowned by a quartic term: ``h = (2/pi) (x^2 + c x^4)`` [P/E*] (c = 0: the cylinder)."""

    name = "crowned"

    def __init__(self, c=0.5):
        if not (0.0 <= c <= 10.0):
            raise ValueError(f"c must be in [0, 10], got {c!r}")
        self.c = float(c)

    @property
    def parameters(self):
        return {"c": self.c}

    def profile(self, x):
        x = np.asarray(x, dtype=float)
        return (2.0 / math.pi) * (x**2 + self.c * x**4)


def test_the_body_needs_only_its_profile():
    b = Crowned(0.5)
    assert not b.closed_form and b.normal_mode("auto") == "numerical"
    with pytest.raises(ValueError, match="normal='exact'"):
        b.normal_mode("exact")
    edges, sol = b.solve_normal(0.01)
    # the stiffer profile carries the same load over a narrower contact, with a higher peak
    assert 1.5 < sol.area < 2.0 and sol.pressure.max() > 1.0
    assert sol.pressure.sum() * 0.01 == pytest.approx(np.pi / 2, rel=1e-12)


def test_c_zero_is_the_cylinder():
    b = Crowned(0.0)
    for w in (0.1, 0.5):
        assert float(core.ft_limit(w, body=b)) == pytest.approx(float(core.ft_limit(w)), abs=2e-5)
    r = core.simulate_cycles(0.5, 0.3, periods=8, body=b)
    ref = core.simulate_cycles(0.5, 0.3, periods=8)
    assert np.allclose(r.increment_per_period, ref.increment_per_period, rtol=1e-3, atol=1e-6)


def test_runs_limit_and_sweep():
    b = Crowned(0.5)
    lim = float(core.ft_limit(0.3, body=b))
    assert 0 < lim < 1
    assert float(core.w_limit(lim, body=b)) == pytest.approx(0.3, abs=1e-5)
    below = core.simulate_cycles(0.9 * lim, 0.3, periods=30, body=b)
    above = core.simulate_cycles(1.1 * lim, 0.3, periods=30, body=b)
    assert below.regime == "shakedown" and above.regime == "ratcheting"
    assert above.body_name == "crowned" and above.body == b and above.params["c"] == 0.5
    assert above.params["normal"] == "numerical"
    assert above.pressure.shape == above.traction.shape
    t = core.sweep([0.9 * lim, 1.1 * lim], [0.3], body=b, periods=30)
    assert list(t["regime"]) == ["shakedown", "ratcheting"]


def test_exact_is_refused():
    with pytest.raises(ValueError, match="normal='exact'"):
        core.simulate_cycles(0.2, 0.3, periods=2, body=Crowned(), normal="exact")


def test_one_registry_line_makes_its_cli_flag(monkeypatch, capsys):
    """Registered, the body is a --body of the command line with its parameter's flag (built from the registry:
    core/command/cli.py names no body), refused with another body."""
    from core.geometry import bodies, registry
    from core.command.cli import build_parser, main
    monkeypatch.setattr(registry, "REGISTRY", dict(registry.REGISTRY))
    monkeypatch.setattr(bodies, "BODIES", dict(bodies.BODIES))
    registry.register(registry.BodyEntry("crowned", Crowned, "line", "a roller crowned by a quartic term",
                                         (registry.Parameter("c", 0.5, 0.0, 10.0, "the quartic coefficient"),)))
    run_help = build_parser()._subparsers._group_actions[0].choices["run"].format_help()
    assert "crowned" in run_help and "--c C" in run_help and "--body crowned: the quartic coefficient" in run_help
    assert main(["run", "--body", "crowned", "--c", "0.25", "--ft", "0.3", "--w", "0.3", "--periods", "2",
                 "--dx", "0.1"]) == 0
    assert "Crowned(c=0.25)" in capsys.readouterr().out  # the body it ran, with the flag's value
    assert main(["run", "--body", "punch", "--c", "0.25", "--ft", "0.3", "--w", "0.3"]) == 2
    assert "--c is for --body crowned, not 'punch'" in capsys.readouterr().err
