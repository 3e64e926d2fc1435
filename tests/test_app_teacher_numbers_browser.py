"""Real-browser tests of issue 31's numbers, state and behaviour (items 3, 4, 6, 9, 10, 17): what a teacher sees
in the served explorer at a projector's 1280x720 and 1024x768 (headless Chromium, fixtures of tests/conftest.py).

- item 3: the traction figure's shading agrees with its curve and with the strip's c_sd, read from the page's
  Bokeh models (the zone rectangles by their legend label, the numerical curve);
- item 4: ``?ft=0.206&w=0.678`` reads ft = 0.206 on the slider and in the verdict's note (ft_lim = 0.2084);
- item 6: a noisy link opens rounded, and a slider moved to a noisy value leaves a clean address;
- item 9: the cone's inputs and the body selector's tooltip speak a user's words, inside the window;
- item 10: a typed L below the contact width is named in mm under INVALID INPUT, and no run stays on show;
- item 17: closing a tab while the player plays or a solve runs leaves no traceback in the server's log.
"""

from __future__ import annotations

import re
import time

import pytest

import core
from app.serving import FIND_MODEL_JS, served_app, wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(900)]

VERDICT = "[data-regime='shakedown'], [data-regime='ratcheting'], [data-regime='undetermined']"
SIZES = [(1280, 720), (1024, 768)]

#: The zone rectangles (by legend label) and the numerical traction of the figure titled ``title``.
_SHADING = "(title) => {" + FIND_MODEL_JS + """
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  const out = {zones: {}, curve: null};
  const legend = fig.center.find((c) => c.items !== undefined);
  for (const item of legend ? legend.items : []) {
    const label = item.label && (item.label.value ?? item.label);
    for (const r of item.renderers) {
      const d = r.data_source.data;
      if (typeof label === 'string' && label.startsWith('zone: ')) {
        const left = d.left ?? d.x0, right = d.right ?? d.x1;
        out.zones[label.slice(6)] = Array.from(left ?? []).map((l, i) => [l, right[i]]);
      } else if (label === 'numerical' || label === 'q_x numerical') {
        out.curve = [Array.from(d.x ?? []), Array.from(d.y ?? [])];
      }
    }
  }
  return out;
}"""
#: The value of the widget titled ``title`` (null if it is not in the page).
_VALUE = "(title) => {" + FIND_MODEL_JS + """
  const m = find((m) => m.title === title && 'value' in m);
  return m === null ? null : m.value;
}"""
#: Set the widget titled ``title`` (a slider: also its release; a number box: its value).
_SET = """([title, v]) => {""" + FIND_MODEL_JS + """
  const m = find((m) => m.title === title && 'value' in m);
  if (m === null) return false;
  m.value = v;
  if ('value_throttled' in m) m.value_throttled = v;
  return true;
}"""


def _open(browser, url, size=(1280, 720)):
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    page.problems = []
    page.on("console", lambda m: page.problems.append(f"console: {m.text}") if m.type == "error" else None)
    page.on("pageerror", lambda e: page.problems.append(f"page error: {e}"))
    page.goto(url, timeout=180_000)
    page.locator(VERDICT).first.wait_for(timeout=180_000)
    return page


# ---------------------------------------------------------------- item 17: no traceback when a tab closes
def test_closing_a_tab_mid_update_leaves_no_traceback_in_the_server_log(browser, tmp_path):
    log = tmp_path / "server.log"
    with served_app(log_path=log) as url:
        for _ in range(2):  # the player playing at its fastest when the tab closes
            page = _open(browser, url + "?periods=4")
            page.locator(".player-speed select").first.select_option(index=2)
            page.locator(".play-period button").first.click()
            page.wait_for_timeout(700)
            page.close()
        for ft in (0.41, 0.43):  # a solve running (a point contact's: seconds) when the tab closes
            page = _open(browser, url + "?body=sphere&periods=6")
            assert page.evaluate(_SET, ["ft = Ft/(μ Fn)", ft])
            page.wait_for_timeout(400)
            page.close()
        time.sleep(8)  # the solves end and their updates find the sessions gone
        page = _open(browser, url)  # the server still serves
        page.close()
    text = log.read_text()
    assert "Task exception was never retrieved" not in text, text[-3000:]
    assert "WebSocketClosedError" not in text and "Traceback" not in text, text[-3000:]
