"""The explorer's style sheets and page scripts (strings only: no Panel model is made here).

:data:`CSS` styles the badge (its regimes in :data:`BADGE_COLORS`), the cards and the captions inside their shadow roots; :data:`PAGE_CSS` is
document-level (presentation mode, narrow screens); :data:`A11Y_JS` labels the widgets for screen readers and
loads the math fonts; :class:`MathFonts` serves those fonts.
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

from panel.models.katex import KaTeX as KaTeXModel

__all__ = ["BADGE_COLORS", "CSS", "PAGE_CSS", "PRESENT_JS", "KATEX_CSS", "A11Y_JS", "MathFonts"]

_ASSETS = Path(__file__).with_name("assets")
#: Background and text colour of the verdict badge per regime (:data:`CSS`). Okabe and Ito's blue and orange and a
#: dark vermillion, far apart in lightness (relative luminance 0.15, 0.42, 0.06; pale grey 0.72 with a dashed
#: border for a run the periods cannot tell yet): they read in greyscale and for colour-blind viewers, and the badge
#: also says the regime in words. Every text contrast is at least 5:1.
BADGE_COLORS = {"shakedown": ("#0072B2", "white"), "cyclic slip": ("#E69F00", "black"),
                "ratcheting": ("#7F2704", "white"), "undetermined": ("#dddddd", "black")}
CSS = """
.regime-badge {display: inline-block; padding: 5px 16px; border-radius: 10px; color: white;
               font-size: calc(23px * var(--shakedown-text-scale, 1)); font-weight: 700; letter-spacing: 0.04em;}
.regime-shakedown {background: #0072B2;} .regime-cyclicslip {background: #E69F00; color: black;}
.regime-ratcheting {background: #7F2704;}
.regime-none, .regime-undetermined {background: #dddddd; color: black; border: 2px dashed #555; padding: 3px 14px;}
.solve-spinner {display: inline-block; width: 0.8em; height: 0.8em; margin-right: 0.4em; vertical-align: -0.05em;
                border: 3px solid #555; border-right-color: transparent; border-radius: 50%; opacity: 0;
                animation: solve-spin 0.9s linear infinite, solve-appear 0s linear forwards;}
@keyframes solve-spin {to {transform: rotate(360deg);}}
@keyframes solve-appear {to {opacity: 1;}}
.regime-note {font-size: calc(13px * var(--shakedown-text-scale, 1)); color: #333; margin-top: 4px; line-height: 1.3;}
.strip {display: flex; flex-wrap: wrap; gap: 2px 18px; font-size: calc(15px * var(--shakedown-text-scale, 1)); line-height: 1.35;}
.strip .item {white-space: nowrap;} .strip .more {color: #1f5f99; cursor: pointer; white-space: nowrap;} .strip .k {color: #444;} .strip .v {font-weight: 600;}
.regime-note details.why {display: inline;} .regime-note details.why[open] {display: block;}
.regime-note summary {display: inline; cursor: pointer; color: #1f5f99; text-decoration: underline;}
.strip .pending {color: #6b6b6b; font-style: italic; font-weight: 400;}
.cards {display: grid; grid-template-columns: repeat(auto-fill, minmax(235px, 1fr)); gap: 0 22px;
        font-size: 15px;}
.cards div {display: flex; justify-content: space-between; gap: 10px; border-bottom: 1px solid #eee;
            padding: 2px 0;}
.cards .k {color: #444;} .cards .v {font-weight: 600; text-align: right;}
.cards .pending {color: #6b6b6b; font-style: italic; font-weight: 400;}
.readout {font-size: calc(14px * var(--shakedown-text-scale, 1)); color: #222;}
.caption {font-size: calc(14px * var(--shakedown-text-scale, 1)); color: #333; margin: 0 10px 14px 10px;}
.caption ul {margin: 2px 0 0 0; padding-left: 20px;}
"""
#: The presentation-mode switch (a ``jscallback`` on the header's toggle): the class ``presenting`` on the document
#: enlarges the badge, the key numbers and the captions (a CSS variable: it reaches into the shadow roots) and
#: the sidebar is folded with the template's own menu button, so that one click on it brings the loads back.
#: No CSS zoom: Bokeh measured the zoomed page wrongly and cropped the figures.
PRESENT_JS = """
const on = cb_obj.active;
document.documentElement.classList.toggle('presenting', on);
const sidebar = document.getElementById('sidebar');
const menu = document.getElementById('sidebar-toggle');
if (sidebar && menu && sidebar.classList.contains('show') === on) menu.click();
setTimeout(() => window.dispatchEvent(new Event('resize')), 400);
"""
#: Document-level CSS (outside every shadow root). The math fonts are declared here because Chromium
#: ignores @font-face inside a shadow root, where Panel renders the equations; presentation mode
#: (sidebar folded, larger type) is a class on the document.
PAGE_CSS = """
html.presenting {--shakedown-text-scale: 1.2;}
@media (max-width: 1100px) {  /* the full-size title pushed the busy indicator off a 1024 px screen */
  #header .title {font-size: 1.3em;}
  /* a narrower sidebar: the three first-screen figures fit in one row beside it, above the fold */
  html:root {--sidebar-width: 260px;}
}
@media (max-width: 700px) {
  #header .title {font-size: 1.05em; white-space: normal; line-height: 1.3em;}
  #header-items {display: none;}
  #content {flex-wrap: nowrap; flex-direction: column; overflow-y: auto !important;}
  #sidebar {max-width: 100% !important; width: 100% !important; height: auto; border-right: 0;}
  #main {flex: 1 0 auto; overflow: visible; padding: 6px;}
}
"""



#: KaTeX's layout rules, inside each equation's shadow root (Panel puts them only in the document's head, where
#: they do not reach the equations); the fonts they name are declared at document level (:class:`MathFonts`).
KATEX_CSS = [css for css in getattr(KaTeXModel, "__css__", []) if "katex" in css]


class MathFonts:
    """The KaTeX fonts shipped in ``app/assets/katex`` (MIT licence), served by Panel's component-resource
    route (``/components/app.styles/MathFonts/__css__/<file>``: only the files listed here are served)."""

    __css__: ClassVar[list[str]] = sorted(str(p.relative_to(_ASSETS.parent)) for p in (_ASSETS / "katex").iterdir()
                                          if p.suffix in (".css", ".woff2"))
    #: The stylesheet, relative to the page.
    url = "components/app.styles/MathFonts/__css__/assets/katex/fonts.css"



#: Declares the math fonts last in the document, and labels every slider handle and unnamed button with an accessible name (Bokeh gives the handles none), in
#: every shadow root, now and when tabs and cards render later.
A11Y_JS = """
function label(root) {
  for (const el of root.querySelectorAll('*')) {
    if (el.shadowRoot) label(el.shadowRoot);
  }
  const title = root.querySelector('.bk-slider-title');
  for (const h of root.querySelectorAll('.noUi-handle')) {
    if (!h.getAttribute('aria-label') && title) h.setAttribute('aria-label', title.textContent.split(':')[0].trim());
  }
  for (const i of root.querySelectorAll('input')) {  // a checkbox's text is a sibling, not its <label>
    if (i.getAttribute('aria-label') || (i.labels && i.labels.length)) continue;
    const text = (i.nextElementSibling || i.parentNode.querySelector('span, label') || {}).textContent;
    if (text && text.trim()) i.setAttribute('aria-label', text.trim());
  }
  for (const b of root.querySelectorAll('button')) {
    if (b.getAttribute('aria-label') || b.textContent.trim()) continue;
    const spin = b.classList.contains('bk-spin-btn-up') ? 'Increase' : b.classList.contains('bk-spin-btn-down')
      ? 'Decrease' : null;
    const name = b.title || spin;
    if (name) b.setAttribute('aria-label', name);
  }
}
label(document);
// a phone: the figures' legends in one column (two do not fit in 390 px), and no toolbar (it does not fit);
// also for the figures drawn later (each is drawn when the page is scrolled to it)
function phone() {
  if (window.innerWidth > 700) return;
  for (const d of Bokeh.documents) for (const m of d.all_models) {
    if ('ncols' in m && 'items' in m && m.ncols !== 1) m.ncols = 1;
    if ('toolbar_location' in m && 'renderers' in m && m.toolbar_location !== null) m.toolbar_location = null;
  }
}
phone();
if (!window._shakedownPhone) {
  window._shakedownPhone = true;
  for (const d of Bokeh.documents) d.on_change(() => setTimeout(phone, 0));
}
// the math fonts: Panel's KaTeX stylesheet in the document's head names font files that Panel does not ship
// (404s, then the system font); it is replaced by one that names the fonts shipped in app/assets/katex
for (const l of document.querySelectorAll('link[href*="katex.min.css"]')) l.remove();
if (!document.getElementById('shakedown-math-fonts')) {
  const link = document.createElement('link');
  link.id = 'shakedown-math-fonts'; link.rel = 'stylesheet'; link.href = '%s';
  document.head.appendChild(link);
}
// a phone starts with the inputs folded away (the menu button opens them above the results)
const sidebar = document.getElementById('sidebar');
if (sidebar && window.innerWidth <= 700 && !window._shakedownA11y) sidebar.classList.remove('show');
if (!window._shakedownA11y) { window._shakedownA11y = setInterval(() => label(document), 1000); }
"""

