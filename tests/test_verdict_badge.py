"""The app's badge shows an undetermined verdict as its own state, with the reason (issue 13, item 4)."""

import core
from app.explorer import Explorer


def test_the_badge_shows_undetermined_with_its_reason():
    result = core.simulate_cycles(0.1, 0.2, periods=1)
    html = Explorer._badge(Explorer, 0.1, 0.2, result, "")
    assert 'data-regime="undetermined"' in html and "UNDETERMINED" in html
    assert "too few" in html
    shaken = core.simulate_cycles(0.1, 0.2, periods=10)
    assert 'data-regime="shakedown"' in Explorer._badge(Explorer, 0.1, 0.2, shaken, "")
