"""The explorer's layout: the main area (verdict, cards, player, figures), the sidebar of inputs, the tabs and
the served page's template.

:class:`LayoutMixin` puts together what the other modules build: the badge and cards of :mod:`app.cards`,
the player of :mod:`app.player`, the figures of :mod:`app.figures`, the compare controls of
:mod:`app.compare`, the SVG chooser of :mod:`app.slides`, the map controls of :mod:`app.mapview` and the
downloads of :mod:`app.downloads`.
"""

from __future__ import annotations

import html
import re
from pathlib import Path
from typing import ClassVar

import panel as pn
from panel.io.state import set_curdoc

from . import panes, plots, point_view, slides
from .compare import Pins
from .figures import ORDER
from .limits import SOLVE_BUDGET_S
from .paper_figures import paper_figures_tab
from .state import MAX_POINT_RESOLUTION
from .styles import A11Y_JS, CSS, KATEX_CSS, PAGE_CSS, PRESENT_JS, MathFonts
from .widgets import filled_when

__all__ = ["LayoutMixin", "REFINE_COST", "refine_fits"]

#: How many times longer a point contact's run takes on a grid twice as fine: measured 3.8 (sphere) and 4.1
#: (ellipsoid) from a/10 to a/20 (twice the steps, four times the elements; benchmarks/app.py prints the
#: per-body times), taken as 5 for a margin.
REFINE_COST = 5.0


def refine_fits(runtime: float, budget: float | None = None) -> bool:
    """Whether the run on a grid twice as fine as that of a run of ``runtime`` [s] is expected to end within
    ``budget`` [s] (default: the server's, ``SHAKEDOWN_SOLVE_BUDGET_S``; :data:`REFINE_COST`)."""
    return REFINE_COST * runtime <= (SOLVE_BUDGET_S if budget is None else budget)

_ABOUT = Path(__file__).with_name("about.md")
#: How long a lazy tab's spinner is shown before its content is built [ms]: the tab's first message (the
#: spinner) is sent before the build holds the event loop.
_BUILD_DELAY_MS = 50
#: When the model applies (one sentence, under the inputs).
_APPLIES = ("*When the model applies:* a long cylinder (L ≫ a) rocking without macroscopic sliding "
            "(Ft < μ Fn) on an elastic half-space, slowly (no inertia), with one constant friction coefficient, "
            "elastic bodies whose normal and tangential problems are uncoupled (Dundurs β ≈ 0).")


def _building(title: str) -> pn.viewable.Viewable:
    """What a lazy tab shows while it is built: a spinner and a line saying what comes."""
    return pn.Row(pn.indicators.LoadingSpinner(value=True, size=36, margin=(10, 10)),
                  pn.pane.HTML(f"<div style='font-size: 17px; padding-top: 14px'>Building “{html.escape(title)}”…</div>"),
                  css_classes=["tab-building"], sizing_mode="stretch_width")


class LayoutMixin:
    """The explorer's page (methods of :class:`app.explorer.Explorer`)."""

    # ------------------------------------------------------------------ layout
    def __panel__(self):
        return self.template()

    def main_area(self) -> pn.viewable.Viewable:
        """The badge, the key numbers, the tabs with the player and the figures, without the sidebar (for notebooks).

        The first screen (1280x720 or 1024x768) shows the verdict, a strip of the key numbers (every number one
        click away, in a folded card built when first opened), the cycle player and, under it, the three figures
        it drives that tell the story (:data:`app.figures.KEY_FIGURES`: by body and loading; under an oscillating
        load the fretting loop is beside the displacement)."""
        live = dict(ft=self.param.ft_live, w=self.param.w_live)
        badge = panes.HTML(pn.bind(self._badge, **live, result=self.param.result, error=self.param.error,
                                   pending=self.param.pending, coupled=self.param.coupled_limit),
                           css_classes=["regime"], margin=(4, 10), sizing_mode="stretch_width", stylesheets=[CSS])
        numbers = dict(**live, mu=self.mu_slider.param.value, contact=self.param.contact, result=self.param.result,
                       pending=self.param.pending, units=self.state.param.units, cycles=self.engineer.param.cycles,
                       grid_error=self.param.grid_error)
        strip = panes.HTML(pn.bind(self._strip, **numbers), css_classes=["summary-strip"], margin=(2, 4),
                           sizing_mode="stretch_width", stylesheets=[CSS])
        # the strip is the header of the folded card of every number: one click opens it
        details = pn.Card(header=strip, collapsed=True, sizing_mode="stretch_width", margin=(2, 10),
                          css_classes=["all-numbers"], header_background="#f3f6fa",
                          title="Every number: click the strip")
        # the cards are built and kept up to date only once opened (most visitors read the strip)
        filled_when(details, details.param.collapsed.rx.not_(), lambda: [panes.HTML(
            pn.bind(self._cards, **numbers), css_classes=["summary-cards"], margin=(0, 4),
            sizing_mode="stretch_width", stylesheets=[CSS])])
        self._warnings_pane = self._alerts(live)
        top = pn.FlexBox(
            pn.Column(badge, self.status, self._grid_action(), sizing_mode="stretch_width",
                      styles={"flex": "0 1 350px", "min-width": "250px"}, margin=0),
            pn.Column(details, *self._input_alerts, sizing_mode="stretch_width",
                      styles={"flex": "1 1 280px", "min-width": "250px"}, margin=0),
            flex_wrap="wrap", sizing_mode="stretch_width", css_classes=["first-row"])
        tabs = pn.Tabs(("Explorer", self.explorer_tab()), *self._lazy_tabs(), sizing_mode="stretch_width",
                       dynamic=False)  # the lazy tabs hold a spinner until built: a click shows it at once
        tabs.param.watch(lambda e: self._fill_tab(tabs, e.new), "active")
        return pn.Column(top, tabs, sizing_mode="stretch_width")

    def _alerts(self, live) -> pn.viewable.Viewable:
        """The invalid-input and URL alerts (:attr:`_input_alerts`, at the top) and the model's warnings (returned:
        under the first-screen figures, so that they do not push the figures down)."""
        model_warnings = pn.bind(self._warnings, **live, contact=self.param.contact, result=self.param.result)
        warnings = panes.Alert(pn.bind(lambda m: "\n".join(f"- {html.escape(x)}" for x in m), model_warnings),
                               visible=pn.bind(bool, model_warnings), alert_type="warning",
                               sizing_mode="stretch_width", css_classes=["model-warnings"])
        errors = panes.Alert(pn.bind(lambda e: f"**Invalid input:** {html.escape(e)}", self.param.error),
                             alert_type="danger", visible=self.param.error.rx.bool(),
                             sizing_mode="stretch_width", css_classes=["input-error"])
        notices = panes.Alert(pn.bind(lambda n: "**Some URL parameters were not applied:**\n\n"
                                      + "\n".join(f"- {html.escape(m)}" for m in n), self.param.notices),
                              alert_type="warning", visible=self.param.notices.rx.bool(),
                              sizing_mode="stretch_width", css_classes=["url-notice"])
        self._input_alerts = [errors, notices]
        return warnings

    def _grid_action(self) -> pn.viewable.Viewable:
        """The point contacts' 'Refine grid' button under the verdict (the strip's 'grid error' is the run's
        estimated discretisation error): one click doubles the elements per a and re-runs. It is offered only
        when the finer run is expected to end within the server's time budget (:func:`refine_fits`); should it
        still run out of time, the explorer goes back to the grid it came from and says so (:meth:`refine_grid`)."""
        button = pn.widgets.Button(label="Refine grid", width=210, height=28, css_classes=["refine-grid"],
                                   margin=(0, 10, 2, 10), stylesheets=[":host button {font-size: 13px; padding: 0;}"],
                                   visible=self.state.param.body.rx().rx.pipe(lambda b: self.state.refinable))

        def label(*_):
            resolution = self.state.point_resolution
            finer = min(2 * resolution, MAX_POINT_RESOLUTION)
            result = self.result
            runtime = result.runtime if (result is not None and result.is_patch
                                         and abs(1 / result.dx - resolution) < 1e-9) else None
            if finer <= resolution:
                button.param.update(label=f"Finest grid (a/{resolution})", disabled=True, description=None)
            elif runtime is not None and not refine_fits(runtime):
                button.param.update(
                    label=f"Finest grid in time (a/{resolution})", disabled=True,
                    description=f"a/{finer} would take about {REFINE_COST * runtime:.0f} s, past this server's "
                                f"{SOLVE_BUDGET_S:.0f} s for one run (SHAKEDOWN_SOLVE_BUDGET_S)")
            else:
                button.param.update(label=f"Refine grid: a/{resolution} → a/{finer}", disabled=False,
                                    description=None)

        label()
        self.state.param.watch(label, "point_resolution")
        self.param.watch(label, "result")
        button.on_click(lambda e: self.refine_grid())
        return button

    def refine_grid(self) -> None:
        """Re-run the point contact on a grid twice as fine (up to the finest the app accepts). If that run is
        stopped by the time budget, the explorer goes back to this grid (its run is cached) with a notice."""
        old = self.state.point_resolution
        self._refined_from = old
        self.state.point_resolution = min(2 * old, MAX_POINT_RESOLUTION)

    #: The tabs built only when first shown (most visitors never open them): title, builder.
    _LAZY_TABS: ClassVar[dict] = {"Paper's figures": lambda self: paper_figures_tab(),
                                  "About the model": lambda self: self.about()}

    def _lazy_tabs(self) -> list:
        """The lazy tabs' holders: each shows a spinner and 'Building ...' until its content is built."""
        self._unbuilt = dict(self._LAZY_TABS)
        return [(title, pn.Column(_building(title), name=title, sizing_mode="stretch_width"))
                for title in self._LAZY_TABS]

    def _fill_tab(self, tabs: pn.Tabs, index: int) -> None:
        """Build tab ``index`` when first shown (its spinner, sent with the page, shows meanwhile: the Paper's
        figures take seconds to build, and a blank tab looked broken). In a served session the build waits for
        the next turns of the event loop, so that the messages of the tab switch are handled first."""
        holder = tabs[index]
        build = self._unbuilt.pop(holder.name, None)
        if build is None:
            return
        doc = self._doc

        def fill():
            holder.objects = [build(self)]

        if doc is None or doc.session_context is None:
            fill()
            return

        def later():
            with set_curdoc(doc):
                fill()

        doc.add_timeout_callback(later, _BUILD_DELAY_MS)

    #: Every figure's place, in the page's order (:data:`app.figures.ORDER`).
    _GRID = ORDER

    def explorer_tab(self) -> pn.Column:
        """The player, under it the first-screen figures it drives, then the compare and SVG controls and the other
        figures, each with a one-line caption; the figures wrap to fewer columns when narrow. A figure, its
        caption and its controls are built when the browser first scrolls near their place."""
        self.figures(when_shown=True)
        # one place a figure, in the first screen's grid or the one below as the body and the loading have it
        self._key_grid = pn.FlexBox(*self._slots(True), flex_wrap="wrap", sizing_mode="stretch_width",
                                    css_classes=["key-figures"])
        self._grid = pn.FlexBox(*self._slots(False), flex_wrap="wrap", sizing_mode="stretch_width")
        self.pins = Pins(self)
        svg = slides.save_svg(slides.figure_titles(), run=dict(ft=self.ft_slider, w=self.w_slider),
                              offered=self._svg_titles(self.state.body))
        self.svg_select = svg.figure_menu
        self.state.param.watch(lambda e: self.svg_select.param.update(
            options=self._svg_titles(e.new), value=self._svg_titles(e.new)[0]), "body")
        warnings = getattr(self, "_warnings_pane", None)
        return pn.Column(self.player_controls(), self._key_grid, self.key_captions(),
                         *([warnings] if warnings is not None else []),
                         self.pins, svg, self._grid, sizing_mode="stretch_width", name="Explorer")

    def _svg_titles(self, body: str) -> list[str]:
        """The titles of the figures ``body`` shows, as the SVG menu offers them (in the grid's order)."""
        return [plots.FIGURES[name]["opts"]["title"] for name in self._figures_of(body)]

    def sidebar(self) -> list:
        """The input widgets."""
        physical = self.state.param.units.rx() == "physical"
        solver_card = pn.Card(title="Solver", collapsed=True, sizing_mode="stretch_width")
        # folded like the solver's options: the first screen is the contact; its dozen inputs are built on opening
        geometry_card = pn.Card(title="Geometry and materials", collapsed=True, sizing_mode="stretch_width")
        return [
            self.preset, self.preset_note, *point_view.body_inputs(self.state),
            pn.pane.Markdown("### Loads"), self.ft_slider, self.w_slider, self.mu_slider,
            pn.pane.Markdown("### Units"), self.units_toggle,
            # the loads in physical units are shown with the physical units, the geometry's and the solver's
            # options when their card is opened: all are sent to the browser only then (most visitors never
            # open them)
            filled_when(pn.Column(sizing_mode="stretch_width", margin=0, visible=physical), physical,
                         lambda: [self.engineer]),
            filled_when(geometry_card, geometry_card.param.collapsed.rx.not_(),
                        lambda: [*self.geometry_inputs, self.materials_select, self.rigid_box, *self.cylinder_inputs]),
            filled_when(solver_card, solver_card.param.collapsed.rx.not_(), lambda: self.solver_inputs),
            pn.pane.Markdown("### Download the run"), self.csv_table, self.csv_download, self.json_download,
            pn.pane.Markdown(_APPLIES, styles={"font-size": "14px"}, css_classes=["model-applies"]),
        ]

    @staticmethod
    def about() -> pn.Column:
        """The 'About the model' tab: Markdown with KaTeX equations."""
        parts = re.split(r"^\$\$(.+?)\$\$$", _ABOUT.read_text(encoding="utf-8"), flags=re.M | re.S)
        objs = []
        for i, part in enumerate(parts):
            if i % 2:
                objs.append(pn.pane.LaTeX(f"$${part.strip()}$$", renderer="katex", styles={"font-size": "20px"},
                                          margin=(0, 30), stylesheets=KATEX_CSS, sizing_mode="stretch_width"))
            elif part.strip():
                objs.append(pn.pane.Markdown(part, styles={"font-size": "17px"}, sizing_mode="stretch_width"))
        return pn.Column(*objs, name="About the model", max_width=1100, sizing_mode="stretch_width")

    def template(self) -> pn.template.BaseTemplate:
        """The served page: sidebar, header with the presentation-mode switch, the main area."""
        present = pn.widgets.Toggle(label="Presentation mode", width=170, css_classes=["presentation-toggle"],
                                    color="light", margin=(8, 10))
        present.jscallback(value=PRESENT_JS)
        template = pn.template.BootstrapTemplate(
            title="Shakedown Explorer: rocking contacts with Coulomb friction",
            # the sidebar is one root, not one per input: the template renders each root in a `config.set`
            # block that reads and restores every Panel setting (15% of a page's build with 20 roots)
            sidebar=[pn.Column(*self.sidebar(), sizing_mode="stretch_width", margin=0)], main=[self.main_area()],
            header=[present], sidebar_width=340,
            header_background="#1f5f99",
            # Panel's busy indicator follows the whole process (any session's callback) and is updated in every
            # session on every event: with 10 sessions sliding it took a third of the server's CPU. The run's
            # own spinner (beside the verdict) says when this session's solve is running.
            busy_indicator=None,
        )
        template.config.raw_css.append(PAGE_CSS)
        doc = self._doc
        if doc is not None:
            from bokeh.models import CustomJS

            doc.js_on_event("document_ready", CustomJS(code=A11Y_JS % MathFonts.url))
        return template
