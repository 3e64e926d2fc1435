"""The paper's parametric figures (Figs 10-16), live: the solver beside the paper's closed forms and regressions.

:func:`paper_figures_tab` builds a tab's content: every figure is drawn from
the data shipped in ``app/data/paper_figures.json`` (made by
``python -m core.maps.paper_figures --out app/data/paper_figures.json``, see
``app/data/README.md``), and a Recompute button under each one reruns its
solver part (:mod:`core.maps.paper_figures`) in a worker thread, with a progress
bar, and redraws it in the session when done. One recompute runs at a time on
the whole server, at the shipped settings, so the work a visitor can ask for
is bounded (a few seconds).

No physics here: the numbers come from :mod:`core.maps.paper_figures`. Every Bokeh,
Panel and HoloViews object is made inside :func:`paper_figures_tab`, per
session; only the read-only shipped data is shared.
"""

from __future__ import annotations

import copy
import functools
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import holoviews as hv
import numpy as np
import panel as pn

from core.maps import paper_figures as pf

from . import runs, slides

__all__ = ["DATA_PATH", "TITLES", "FIGURES", "shipped_data", "figure", "paper_figures_tab"]

import holoviews.plotting.bokeh  # noqa: E402,F401 - the bokeh backend

hv.Store.set_current_backend("bokeh")
# Plain canvas, as in the explorer's figures: WebGL without a GPU stalls the page (and warns in the console).
hv.plotting.bokeh.BokehRenderer.webgl = False

#: The shipped data (see app/data/README.md for the command that made it).
DATA_PATH = Path(__file__).resolve().parent / "data" / "paper_figures.json"
#: Okabe-Ito colours (distinguishable under the common colour-vision deficiencies), one per amplitude or case.
PALETTE = ("#000000", "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00")
#: Height of a figure, its legend included.
HEIGHT = 480
FONT = {"title": 15, "labels": 14, "xticks": 12, "yticks": 12, "legend": 12}
#: Wheel zoom stays in the toolbar (one click away) but is not active, so the wheel scrolls the page.
_TOOLS = dict(default_tools=["pan", "box_zoom", "wheel_zoom", "reset", "save"], active_tools=["pan"],
              backend_opts={"plot.toolbar.active_scroll": None})
#: Legends in two columns under the plot: three did not fit the width a 1024 px screen leaves (Fig 13's 855 px in 634);
#: legend_offset: HoloViews anchors a legend at the bottom of its panel, its margin (10 px) below the canvas, where
#: the border was cut off; 20 px up centres it in the panel.
_PLOT = dict(responsive=True, height=HEIGHT, show_grid=True, fontsize=FONT, toolbar="above",
             legend_position="bottom", legend_cols=2, legend_offset=(0, 20),
             legend_opts={"spacing": 6, "label_standoff": 6, "padding": 6}, **_TOOLS)

# One recompute at a time on the whole server (the solver uses the cores; sessions share them).
_POOL = ThreadPoolExecutor(max_workers=1, thread_name_prefix="paper-figures")
_BUSY = threading.Lock()


@functools.lru_cache(maxsize=1)
def shipped_data() -> dict:
    """The shipped figure data (read-only: copy before changing it)."""
    return pf.load(DATA_PATH)


def _a(values) -> np.ndarray:
    """JSON lists (None for NaN) as a float array."""
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def _w(w) -> str:
    return f"w = {w:g}"


def _solver(dims, x, y, label, color, marker="circle", size=8):
    """Solver values as markers; ``dims`` names the axes (so no two figures share a range by accident)."""
    return hv.Scatter((_a(x), _a(y)), *dims, label=label).opts(color=color, marker=marker, size=size)


def _paper(dims, x, y, label, color, dash="solid", width=2.5):
    """A line (the paper's formula, unless labelled otherwise)."""
    return hv.Curve((_a(x), _a(y)), *dims, label=label).opts(color=color, line_dash=dash, line_width=width)


def _axes(overlay: hv.Overlay, title: str, xlabel: str, ylabel: str, **opts) -> hv.Overlay:
    return overlay.opts(hv.opts.Overlay(title=title, xlabel=xlabel, ylabel=ylabel, **{**_PLOT, **opts}))


FT_LABEL = "ft = Ft/(μ Fn)  [-]"
#: Each figure's title (the SVG export finds the drawn figure by it).
TITLES = {
    "fig10": "Fig 10: stick half-width after shakedown",
    "fig11": "Fig 11: traction after shakedown, w = 0.26",
    "fig12": "Fig 12: traction after shakedown, ft = 0.08",
    "fig13": "Fig 13: shakedown displacement",
    "fig14": "Fig 14: shakedown limit",
    "fig15": "Fig 15: largest shakedown displacement",
    "fig16": "Fig 16: ratcheting increment per period",
}


# --------------------------------------------------------------------------
# the figures: data (one figure's dict, and the whole data for cross-references) -> overlay
# --------------------------------------------------------------------------
def _fig10(fig, data):
    d = ("ft", "c_sd")
    layers = []
    for color, c in zip(PALETTE, fig["curves"]):
        layers.append(_paper(d, c["ft"], c["eq30"], f"paper's closure eq 30, {_w(c['w'])}", color))
        layers.append(_solver(d, c["ft"], c["solver"], f"solver, {_w(c['w'])}", color))
    return _axes(hv.Overlay(layers), TITLES["fig10"], FT_LABEL, "c_sd / a  [-]",
                 xlim=(0, 1), ylim=(0, 1.05))


def _traction(fig, data, title, vary):
    d = ("x", "q")
    layers = []
    for color, c in zip(PALETTE[1:], fig["curves"]):
        case = f"{vary} = {c[vary]:g}"
        layers.append(_paper(d, c["x"], c["ansatz"], f"paper's ansatz, {case}", color, dash="dashed"))
        layers.append(_paper(d, c["x"], c["solver"], f"solver, {case}", color, width=2))
    return _axes(hv.Overlay(layers), title, "x / a  [-]", "q / (μ p0)  [-]")


def _fig13(fig, data):
    d = ("ft", "u")
    layers = []
    for color, c in zip(PALETTE, fig["curves"]):
        layers.append(_paper(d, c["ft"], c["eq34"], f"paper's regression eq 34, {_w(c['w'])}", color))
        if "eq13" in c:
            layers.append(_paper(d, c["ft"], c["eq13"], "paper's static eq 13 (w = 0)", color,
                                 dash="dotted"))
        layers.append(_solver(d, c["ft"], c["solver"], f"solver, {_w(c['w'])}", color))
    checks = [(t, u) for c in fig["curves"] for t, u in zip(c["check_ft"], c["check_transient"])]
    if checks:  # one layer for all amplitudes: each diamond sits on its amplitude's markers
        layers.append(_solver(d, *zip(*checks), "solver transients (all w)", "#555555", marker="diamond",
                              size=16).opts(fill_alpha=0.0, line_width=2))
    lim = data["figures"].get("fig15")
    if lim:
        layers.append(_paper(d, lim["ft_lim"], lim["solver"], "u_lim, solver (Fig 15)", "#999999",
                             dash="dashdot"))
    return _axes(hv.Overlay(layers), TITLES["fig13"], FT_LABEL, "u_sd = U_sd / U0  [-]",
                 xlim=(0, 1), ylim=(0, 1.05))


def _fig14(fig, data):
    p, line = fig["points"], fig["line"]
    d = ("ft_lim", "w_lim")
    layers = [
        _paper(d, line["ft"], line["w_eq35"], "exact limit eq 35", PALETTE[0]),
        _paper(d, line["ft"], line["w_eq36"], "paper's regression eq 36", PALETTE[2], dash="dashed"),
        _paper(d, line["ft"], line["w_sphere"], "sphere, ellipsoid: exact (1 − w)²(2 + w)/2", PALETTE[3],
               dash="dotdash"),
        _solver(d, p["ft"], p["w_shakedown"], "solver: last shakedown", PALETTE[1], marker="triangle", size=11),
        _solver(d, p["ft"], p["w_ratcheting"], "solver: first ratcheting", PALETTE[4], marker="inverted_triangle",
                size=11),
    ]
    return _axes(hv.Overlay(layers), TITLES["fig14"], "ft_lim = Ft/(μ Fn) at the limit  [-]",
                 "w_lim = W/a  [-]", xlim=(0, 1), ylim=(0, 1))


def _fig15(fig, data):
    d = ("ft_lim", "u_lim")
    layers = [_paper(d, fig["ft_lim"], fig["eq34_at_limit"], "paper's eq 34 at (ft_lim, w); eq 37 unreadable",
                     PALETTE[2], dash="dashed"),
              _paper(d, fig["ft_lim"], fig["solver"], "", PALETTE[1], width=1.5),
              _solver(d, fig["ft_lim"], fig["solver"], "solver: u_sd as ft → ft_lim", PALETTE[1])]
    return _axes(hv.Overlay(layers), TITLES["fig15"], "ft_lim = Ft/(μ Fn) at the limit  [-]",
                 "u_lim = U_lim / U0  [-]", xlim=(0, 1), ylim=(0, 1.05), legend_cols=1)


def _fig16(fig, data):
    d = ("ft", "du")
    layers = []
    for color, c in zip(PALETTE[1:], fig["curves"]):
        layers.append(_paper(d, c["ft"], c["eq38"], f"paper's regression eq 38, {_w(c['w'])}", color, dash="dashed"))
        layers.append(_solver(d, c["ft"], c["solver"], f"solver, {_w(c['w'])}", color))
    return _axes(hv.Overlay(layers), TITLES["fig16"], FT_LABEL,
                 "Δu per period = ΔU / U0  [-]", xlim=(0, 1))


def _d(x) -> str:
    return "n/a" if x is None else f"{x:.3g}"


#: key -> (draw(figure data, all data), caption(figure data)): one line saying what you see.
FIGURES = {
    "fig10": (_fig10, lambda f: (
        f"Stick half-width after shakedown against the load: solver markers (direct shaken-down state, strip "
        f"model of eq 17, dx = a/{1 / f['settings']['dx']:.0f}) on the paper's closure eq 30; w = 0 is Cattaneo. "
        f"Largest difference {_d(f['max_difference'])} a.")),
    "fig11": (functools.partial(_traction, title=TITLES["fig11"], vary="ft"), lambda f: (
        f"Traction after shakedown at w = 0.26 for three loads: solver (solid) against the paper's ansatz "
        f"(dashed, eqs 22-26 with c_sd of eq 30); outside the stick zone both sit at μ p_min. Largest difference "
        f"{_d(f['max_difference'])} μ p0.")),
    "fig12": (functools.partial(_traction, title=TITLES["fig12"], vary="w"), lambda f: (
        f"Traction after shakedown at ft = 0.08 for three amplitudes: the stick zone shrinks and the released "
        f"edge grows with w. Solver solid, ansatz dashed; largest difference {_d(f['max_difference'])} μ p0.")),
    "fig13": (_fig13, lambda f: (
        f"Shakedown displacement u_sd = U_sd/U0 against the load: solver markers (direct state; diamonds: "
        f"transients of {f['settings']['periods']} periods) on the paper's regression eq 34 (lines); dash-dot: "
        f"u_lim. Largest difference {_d(f['max_difference'])}; transient vs direct "
        f"{_d(f['max_transient_difference'])}.")),
    "fig14": (_fig14, lambda f: (
        f"Shakedown limit: the solver's bracket (last shakedown ▲, first ratcheting ▼, transients of "
        f"{f['settings']['periods']} periods, to ±{f['settings']['tol']:g} in w) around the exact eq 35; "
        f"eq 35 inside {f['eq35_in_bracket'][0]} of {f['eq35_in_bracket'][1]} brackets; the paper's regression "
        f"eq 36 is off by up to {_d(f['max_regression_difference'])}. Dash-dot: the sphere's exact limit (any ellipsoid's), "
        f"below the cylinder's at every amplitude: the sphere bears the lower tangential force (the paper states the "
        f"opposite).")),
    "fig15": (_fig15, lambda f: (
        f"u_lim, the largest shakedown displacement, is here u_sd in the limit ft → ft_lim(w): the whole "
        f"contact carries μ p_min (strip model). The paper's eq 37 is unreadable; eq 34 at the limit is shown. "
        f"Largest difference {_d(f['max_difference'])}.")),
    "fig16": (_fig16, lambda f: (
        f"Ratcheting increment of u = U/U0 per period against the load: solver markers (last of "
        f"{f['settings']['periods']} periods) and the paper's regression eq 38 (dashed), which is off by up to "
        f"{_d(f['max_difference'])} ({100 * f['max_relative_difference']:.0f} % relative).")),
}
#: Figures whose drawing also reads another figure's data.
_DEPENDENTS = {"fig15": ("fig13",)}


def figure(name: str, data: dict | None = None) -> hv.Overlay:
    """Figure ``name`` (a key of :data:`FIGURES`) as a HoloViews overlay, from ``data`` (default: the shipped)."""
    data = shipped_data() if data is None else data
    return FIGURES[name][0](data["figures"][name], data)


def caption(name: str, data: dict | None = None) -> str:
    """The one-line caption of figure ``name``."""
    data = shipped_data() if data is None else data
    return FIGURES[name][1](data["figures"][name])


class _Block:
    """One figure in one session: its pane, caption, Recompute button, progress bar and status."""

    def __init__(self, name: str, data: dict):
        self.name = name
        # linked_axes=False: each figure keeps its own ranges (Panel links panes' axes of equal names)
        self.pane = pn.pane.HoloViews(None, sizing_mode="stretch_width", min_height=HEIGHT, linked_axes=False)
        self.caption = pn.pane.Markdown(caption(name, data), sizing_mode="stretch_width",
                                        css_classes=["paper-figure-caption"])
        self.button = pn.widgets.Button(label=f"Recompute Fig {pf.FIGURES[name][0]} with the solver",
                                        color="primary", width=300,
                                        description="Rerun the solver part of this figure at the shipped settings")
        self.bar = pn.indicators.Progress(value=0, max=100, visible=False, width=200)
        self.status = pn.pane.Str("shipped data", css_classes=["paper-figure-status"])

    def draw(self, data: dict):
        """Draw the figure and its caption from ``data``."""
        self.pane.object = figure(self.name, data)
        self.caption.object = caption(self.name, data)

    def view(self):
        return pn.Column(self.caption, self.pane, pn.Row(self.button, self.bar, self.status, margin=(8, 0, 0, 0)),
                         sizing_mode="stretch_width", css_classes=["paper-figure"], name=self.name)


def paper_figures_tab() -> pn.viewable.Viewable:
    """The content of the "Paper's figures" tab: Figs 10-16 from the solver beside the paper's formulas.

    Every model is made here, per session. A Recompute button reruns one
    figure's solver part in a worker thread (one at a time on the server) and
    redraws it in this session when done; the progress bar and the status line
    say how far it got.

    Returns
    -------
    panel.viewable.Viewable
    """
    data = copy.deepcopy(shipped_data())  # this session's copy: recomputes replace parts of it
    meta = data["meta"]
    blocks = {name: _Block(name, data) for name in FIGURES}
    doc = pn.state.curdoc
    cancel = threading.Event()

    loop = runs.session_loop()

    def in_session(fn):  # from the recompute's threads: through the session's event loop
        if doc is not None and doc.session_context is not None:
            runs.call_in_session(doc, loop, fn)
        else:
            fn()

    def recompute(name: str):
        block = blocks[name]
        if not _BUSY.acquire(blocking=False):
            block.status.object = "another recompute is running on this server: try again in a few seconds"
            return
        block.button.disabled = True
        block.bar.param.update(value=0, visible=True)
        block.status.object = "recomputing with the solver…"
        t0 = time.perf_counter()

        def progress(_name, done, total):
            value = int(100 * done / max(total, 1))
            in_session(lambda: setattr(block.bar, "value", value))

        def work():
            try:
                return pf.compute([name], progress=progress, cancel=cancel)["figures"][name]
            finally:
                _BUSY.release()

        def finished(future):
            def apply():
                block.button.disabled = False
                block.bar.visible = False
                try:
                    fig = future.result()
                except Exception as e:  # noqa: BLE001 - shown to the user; the shipped figure stays
                    block.status.object = f"recompute failed: {type(e).__name__}: {e}"[:300]
                    return
                data["figures"][name] = fig
                for other in (name, *_DEPENDENTS.get(name, ())):
                    blocks[other].draw(data)
                block.status.object = (f"recomputed now in {time.perf_counter() - t0:.1f} s "
                                       f"(largest difference {_d(fig['max_difference'])})")
            in_session(apply)

        _POOL.submit(work).add_done_callback(finished)

    for name, block in blocks.items():
        block.button.on_click(lambda event, n=name: recompute(n))
    served = doc is not None and doc.session_context is not None
    if served:
        pn.state.on_session_destroyed(lambda ctx: cancel.set())
    # draw after the page has loaded, one figure per callback, so the tab shows at once and fills in
    for block in blocks.values():
        if served:
            pn.state.onload(functools.partial(block.draw, data))
        else:
            block.draw(data)

    intro = pn.pane.Markdown(
        "The paper's parametric figures, recomputed with this project's solver in the paper's own numerical "
        "model (eq 17: the truncated-3D strip of length L, L/a = 292.6, ν = 0.5) and drawn beside the paper's closed "
        "forms and regressions. Markers and solid lines marked *solver* come from the solver; lines marked "
        "*paper's* are the paper's formulas. Lengths in a, tractions in μ p0, displacements in U0. "
        f"The shipped data was made by `{meta['command']}` ({meta.get('total_seconds', '?')} s, "
        f"{meta['created_utc']}).", sizing_mode="stretch_width")
    # for slides: each figure as SVG, in a file named after it (the toolbar's save button gives a PNG)
    svg = slides.save_svg({TITLES[name]: slides.stem(f"paper {TITLES[name].split(':')[0]}") for name in blocks})
    return pn.Column(intro, svg, *(b.view() for b in blocks.values()), sizing_mode="stretch_width",
                     name="Paper's figures")
