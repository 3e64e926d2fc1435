"""Take a screenshot of the served explorer for the README: docs/screenshot.png.

Usage: python scripts/screenshot.py [--query "?ft=0.3&w=0.5"] [--pin 0.26 --pin 0.77] [--tab "Paper's figures"]
                                   [--width 1920 --height 1080] [--out docs/screenshot.png]
       python scripts/screenshot.py --first-screens   # docs/screenshot.png and docs/screenshot_{body}_{size}.png
       python scripts/screenshot.py --fretting-screens benchmarks/results/screens_s3   # issue 30's loop and map

``--first-screens`` takes the first screen of the cylinder and of the sphere at 1280x720 and 1024x768
(``docs/screenshot_cylinder_1280x720.png`` ...; ``docs/screenshot.png`` is the cylinder at 1280x720) and
prints where the verdict and each key figure start (y, CSS pixels).

Serves ``app/main.py`` on a free loopback port, opens it in headless Chromium at a projector's
1280x720 CSS pixels, waits until the solver's verdict and the figures are drawn, pins the runs at the
``--pin`` amplitudes w (then returns to the query's w), opens ``--tab``, scrolls the main area to ``--scroll``
pixels, and saves a PNG (palette-quantised to stay small).
"""

from __future__ import annotations

import argparse
import io
import sys
from urllib.parse import parse_qs
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from app.serving import ROOT, VERDICT_SELECTOR, chromium, served_app, wait_until  # noqa: E402
from app.slides import FIGURE_VIEWS_JS  # noqa: E402

#: A verdict of any regime (cyclic slip included: the tangential loading's).
BADGE = VERDICT_SELECTOR
#: The page's top (y) of the figure titled ``title`` once drawn (null before).
_TOP = "(title) => {" + FIGURE_VIEWS_JS + """
  const v = figure_views().find((v) => v.model.title && v.model.title.text === title);
  return v ? v.el.getBoundingClientRect().y : null; }"""
#: Reads (and with SET replaced by assignments, sets) the w slider in the browser.
_SLIDER = """(v) => { for (const m of Bokeh.documents[0].all_models)
    if (m.title === 'w = W/a' && 'value_throttled' in m) { SET return m.value; } }"""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--query", default="?ft=0.3&w=0.5", help="URL query of the view to capture")
    ap.add_argument("--out", default=str(ROOT / "docs" / "screenshot.png"), help="output PNG")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=720)
    ap.add_argument("--scroll", type=int, default=0, help="scroll the main area by this many CSS pixels")
    ap.add_argument("--full-page", action="store_true", help="capture the whole page, not the viewport")
    ap.add_argument("--tab", default="Explorer", help="the tab to show, e.g. \"Paper's figures\"")
    ap.add_argument("--pin", type=float, action="append", default=[], help="pin the run at this w first (repeatable)")
    ap.add_argument("--first-screens", action="store_true",
                    help="the first screens of the cylinder and the sphere at 1280x720 and 1024x768 (docs/)")
    ap.add_argument("--bodies", nargs="*", default=None, help="--fretting-screens of these bodies only (default all)")
    ap.add_argument("--verdict-wait", type=float, default=180.0,
                    help="--fretting-screens: seconds to wait for a run's verdict before the screenshot is taken anyway")
    ap.add_argument("--fretting-screens", metavar="DIR",
                    help="the first screens of every body under the tangential and the normal loading at 1280x720 "
                         "(the fretting loop beside the displacement) and the regime map of each loading, into DIR")
    args = ap.parse_args(argv)
    if args.first_screens:
        return first_screens()
    if args.fretting_screens:
        return fretting_screens(Path(args.fretting_screens), args.bodies, args.verdict_wait)
    with served_app() as url, chromium() as browser:
        page = browser.new_page(viewport={"width": args.width, "height": args.height})
        page.goto(url + args.query, timeout=180_000)
        page.locator(BADGE).first.wait_for(timeout=60_000)
        query = parse_qs(args.query.lstrip("?"))
        _wait_key_figures(page, query.get("body", ["cylinder"])[0], query.get("loading", ["rocking"])[0])
        if args.pin:
            w0 = page.evaluate(_SLIDER.replace("SET", ""), None)
            for k, w in enumerate([*args.pin, w0]):
                page.evaluate(_SLIDER.replace("SET", "m.value = v; m.value_throttled = v;"), w)
                page.locator(".regime-note", has_text=f"w = {w:.2f}").first.wait_for(timeout=60_000)
                page.locator(BADGE).first.wait_for(timeout=60_000)  # the new run's verdict (not 'solving')
                if k < len(args.pin):
                    page.get_by_text("Pin this run", exact=True).first.click()
                    page.locator(f"[data-pin='{k + 1}']").first.wait_for(timeout=20_000)
        if args.tab != "Explorer":
            page.get_by_text(args.tab, exact=True).first.click()
            page.wait_for_timeout(3000)  # the tab is built when first shown, its figures drawn after it loads
        page.evaluate("(y) => { const m = document.getElementById('main'); if (m) m.scrollTop = y; }", args.scroll)
        page.wait_for_timeout(1500)  # let the last figures paint (one-off script, not a test)
        png = page.screenshot(full_page=args.full_page)
    _save(png, Path(args.out))
    return 0


def _titles(body: str, loading: str = "rocking") -> list[str]:
    from app.figures import key_figures
    from app.plots import FIGURES

    return [FIGURES[name]["opts"]["title"] for name in key_figures(body, loading)]


def _wait_key_figures(page, body: str, loading: str = "rocking") -> list[float]:
    """Wait until the first-screen figures of ``body`` under ``loading`` are drawn; their tops (y) in the page."""
    titles = _titles(body, loading)
    return wait_until(lambda: (lambda ys: ys if all(y is not None for y in ys) else None)(
        [page.evaluate(_TOP, t) for t in titles]), 60, message="the first-screen figures")


def _save(png: bytes, out: Path) -> None:
    out.parent.mkdir(parents=True, exist_ok=True)
    try:
        from PIL import Image

        img = Image.open(io.BytesIO(png)).convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT)
        img.save(out, optimize=True)
    except ImportError:
        out.write_bytes(png)
    print(f"wrote {out} ({out.stat().st_size / 1024:.0f} KB)")


def first_screens() -> int:
    """The first screens of the cylinder and the sphere at 1280x720 and 1024x768, with the figures' tops."""
    with served_app(env={"SHAKEDOWN_SOLVE_BUDGET_S": "180"}) as url, chromium() as browser:
        for body in ("cylinder", "sphere"):
            for width, height in ((1280, 720), (1024, 768)):
                page = browser.new_page(viewport={"width": width, "height": height})
                page.goto(url + f"?body={body}&ft=0.3&w=0.5", timeout=180_000)
                page.locator(BADGE).first.wait_for(timeout=180_000)
                tops = _wait_key_figures(page, body)
                page.wait_for_timeout(1500)  # let the figures paint (one-off script, not a test)
                tops = [page.evaluate(_TOP, t) for t in _titles(body)]
                badge = page.locator("[data-regime]").first.bounding_box()["y"]
                print(f"{body} {width}x{height}: badge y = {badge:.0f}, "
                      + ", ".join(f"{t!r} y = {y:.0f}" for t, y in zip(_titles(body), tops)))
                png = page.screenshot()
                _save(png, ROOT / "docs" / f"screenshot_{body}_{width}x{height}.png")
                if body == "cylinder" and width == 1280:
                    _save(png, ROOT / "docs" / "screenshot.png")
                page.close()
    return 0


#: The loadings of :func:`fretting_screens` (URL queries besides the body).
_FRETTING = {"tangential": "loading=tangential&amplitude=0.5&ft=0.3&w=0.5",
             "normal": "loading=normal&amplitude=0.3&phase=90&ft=0.3&w=0.5", "rocking": "ft=0.3&w=0.5"}


def fretting_screens(out: Path, bodies=None, verdict_wait: float = 180.0) -> int:
    """Issue 30's screens at 1280x720: every body's first screen under the tangential and the normal loading (the
    fretting loop beside the displacement, the badge), and the regime map of each loading (the cylinder's). A run
    that has no verdict after ``verdict_wait`` seconds is shot as it is (the badge says SOLVING), and said so."""
    from app.bodies import BODIES

    with served_app(env={"SHAKEDOWN_SOLVE_BUDGET_S": "300"}) as url, chromium() as browser:
        for body in BODIES if bodies is None else bodies:
            for loading in ("tangential", "normal"):
                page = browser.new_page(viewport={"width": 1280, "height": 720})
                page.goto(url + f"?body={body}&{_FRETTING[loading]}&periods=4", timeout=180_000)
                page.locator("[data-regime]").first.wait_for(timeout=180_000)
                _wait_key_figures(page, body, loading)
                try:
                    page.locator(BADGE).first.wait_for(timeout=verdict_wait * 1000)
                except Exception:  # noqa: BLE001 - Playwright's TimeoutError: shot without a verdict
                    print(f"{body} {loading}: no verdict after {verdict_wait:.0f} s")
                page.wait_for_timeout(1500)  # let the figures paint (one-off script, not a test)
                regime = page.locator("[data-regime]").first.get_attribute("data-regime")
                print(f"{body} {loading}: {regime}")
                _save(page.screenshot(), out / f"{body}_{loading}_1280x720.png")
                page.close()
        for loading in ("rocking", "normal", "tangential"):
            page = browser.new_page(viewport={"width": 1280, "height": 720})
            page.goto(url + f"?{_FRETTING[loading]}&periods=4", timeout=180_000)
            page.locator(BADGE).first.wait_for(timeout=300_000)
            page.locator(".place-map").first.scroll_into_view_if_needed(timeout=60_000)
            wait_until(lambda: page.evaluate(_TOP, "Regime map: (ft, w) or (ft, A)"), 120, message="the map")
            page.wait_for_timeout(1500)
            _save(page.screenshot(), out / f"map_{loading}_1280x720.png")
            page.close()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
