"""The explorer's style sheets and page scripts (strings only: no Panel model is made here).

:data:`CSS` styles the badge (its regimes in :data:`BADGE_COLORS`), the cards and the captions inside their shadow roots; :data:`PAGE_CSS` is
document-level (presentation mode, narrow screens); :data:`A11Y_JS` labels the widgets for screen readers and
loads the math fonts; :class:`MathFonts` serves those fonts.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import ClassVar

from panel.models.katex import KaTeX as KaTeXModel

__all__ = ["BADGE_COLORS", "CVD_MATRICES", "relative_luminance", "contrast_ratio", "lightness", "colour_difference",
           "colour_report", "CSS", "PAGE_CSS", "PRESENT_JS", "KATEX_CSS", "A11Y_JS", "MathFonts"]

_ASSETS = Path(__file__).with_name("assets")
#: Background and text colour of the verdict badge per regime (:data:`CSS`). Okabe and Ito's blue and orange and a
#: dark vermillion-brown, far apart in lightness (CIE L* 46, 71 and 22; the pale grey of a run the periods cannot
#: tell yet, L* 94, has a dashed border too): any two differ by at least 23 in L*, so they read in greyscale, and
#: by at least 40 in colour (CIE76 ΔE) for protan, deutan and tritan viewers (:func:`colour_report`). The badge
#: also says the regime in words. Every text contrast is at least 5:1.
BADGE_COLORS = {"shakedown": ("#0072B2", "white"), "cyclic slip": ("#E69F00", "black"),
                "ratcheting": ("#631E03", "white"), "undetermined": ("#eeeeee", "black")}
#: Machado, Oliveira and Fernandes' (2009) matrices of full-severity colour-vision deficiency, on linear RGB.
CVD_MATRICES = {
    "protan": ((0.152286, 1.052583, -0.204868), (0.114503, 0.786281, 0.099216), (-0.003882, -0.048116, 1.051998)),
    "deutan": ((0.367322, 0.860646, -0.227968), (0.280085, 0.672501, 0.047413), (-0.011820, 0.042940, 0.968881)),
    "tritan": ((1.255528, -0.076749, -0.178779), (-0.078411, 0.930809, 0.147602), (0.004733, 0.691367, 0.303900)),
}
_HEX = re.compile(r"#[0-9a-fA-F]{6}")
_SRGB_TO_XYZ = ((0.4124, 0.3576, 0.1805), (0.2126, 0.7152, 0.0722), (0.0193, 0.1192, 0.9505))
_WHITE = (0.95047, 1.0, 1.08883)  # D65


def _linear(colour: str) -> tuple[float, float, float]:
    """Linear RGB of a colour ``#rrggbb``, ``white`` or ``black`` (sRGB's transfer curve undone)."""
    colour = {"white": "#ffffff", "black": "#000000"}.get(colour, colour)
    if not isinstance(colour, str) or not _HEX.fullmatch(colour):
        raise ValueError(f"colour must be '#rrggbb', 'white' or 'black', got {colour!r:.40}")
    c = [int(colour[i:i + 2], 16) / 255 for i in (1, 3, 5)]
    return tuple(v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4 for v in c)


def _lab(rgb) -> tuple[float, float, float]:
    """CIE L*a*b* (D65) of linear RGB ``rgb``."""
    def f(t):
        return t ** (1 / 3) if t > 216 / 24389 else (24389 / 27 * t + 16) / 116
    x, y, z = (f(sum(m * c for m, c in zip(row, rgb)) / w) for row, w in zip(_SRGB_TO_XYZ, _WHITE))
    return 116 * y - 16, 500 * (x - y), 200 * (y - z)


def relative_luminance(colour: str) -> float:
    """WCAG 2's relative luminance of ``colour`` (``#rrggbb``, ``white`` or ``black``), in [0, 1].

    Examples
    --------
    >>> round(relative_luminance("#0072B2"), 3)
    0.152
    """
    r, g, b = _linear(colour)
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def contrast_ratio(a: str, b: str) -> float:
    """WCAG 2's contrast ratio of two colours, ``(L1 + 0.05) / (L2 + 0.05)``, in [1, 21].

    Examples
    --------
    >>> round(contrast_ratio("white", "black"), 1)
    21.0
    """
    la, lb = relative_luminance(a), relative_luminance(b)
    return (max(la, lb) + 0.05) / (min(la, lb) + 0.05)


def lightness(colour: str) -> float:
    """CIE L* of ``colour`` in [0, 100]: its grey in a greyscale print (L* differences above about 20 read apart)."""
    return _lab(_linear(colour))[0]


def colour_difference(a: str, b: str, vision: str = "normal") -> float:
    """CIE76 colour difference ΔE of two colours as a viewer with ``vision`` sees them.

    Parameters
    ----------
    a, b : str
        Colours ``#rrggbb`` (or ``white``, ``black``).
    vision : {"normal", "protan", "deutan", "tritan"}
        Normal vision, or a full-severity colour-vision deficiency (:data:`CVD_MATRICES`).

    Returns
    -------
    float
        ΔE (about 2.3: just noticeable; above 40: different colours).

    Raises
    ------
    ValueError
        If ``vision`` is not one of the four, or a colour is not ``#rrggbb``.
    """
    if vision != "normal" and vision not in CVD_MATRICES:
        raise ValueError(f"vision must be 'normal' or one of {sorted(CVD_MATRICES)}, got {vision!r:.40}")

    def seen(colour):
        rgb = _linear(colour)
        if vision == "normal":
            return _lab(rgb)
        return _lab([min(1.0, max(0.0, sum(m * c for m, c in zip(row, rgb)))) for row in CVD_MATRICES[vision]])

    return math.dist(seen(a), seen(b))


def colour_report(colours: dict | None = None) -> dict:
    """How far apart the badge's backgrounds are (default :data:`BADGE_COLORS`), pair by pair: their contrast
    ratio, their L* difference (greyscale) and their ΔE for each vision of :func:`colour_difference`; and each
    badge's text contrast.

    Returns
    -------
    dict
        ``{"pairs": {(a, b): {"contrast": ..., "dL": ..., "normal": ..., "protan": ..., ...}},
        "text": {regime: contrast}}``.
    """
    colours = BADGE_COLORS if colours is None else colours
    names = list(colours)
    pairs = {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            ca, cb = colours[a][0], colours[b][0]
            pairs[(a, b)] = {"contrast": contrast_ratio(ca, cb), "dL": abs(lightness(ca) - lightness(cb)),
                             **{v: colour_difference(ca, cb, v) for v in ("normal", *CVD_MATRICES)}}
    return {"pairs": pairs, "text": {k: contrast_ratio(bg, fg) for k, (bg, fg) in colours.items()}}


def _badge_css() -> str:
    """The badge's background and text colour of each regime, from :data:`BADGE_COLORS` (the one place they are
    written)."""
    return " ".join(f".regime-{re.sub(r'[^a-z]', '', regime)} {{background: {bg}; color: {fg};}}"
                    for regime, (bg, fg) in BADGE_COLORS.items())


CSS = """
.regime-badge {display: inline-block; padding: 5px 16px; border-radius: 10px; color: white;
               font-size: calc(23px * var(--shakedown-text-scale, 1)); font-weight: 700; letter-spacing: 0.04em;}
.regime-none {background: #eeeeee; color: black;}
.regime-none, .regime-undetermined {border: 2px dashed #555; padding: 3px 14px;}
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
""" + _badge_css()
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

