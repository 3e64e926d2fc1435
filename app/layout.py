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

from . import panes, plots, point_view, slides
from .compare import Pins
from .paper_figures import paper_figures_tab
from .styles import A11Y_JS, CSS, KATEX_CSS, PAGE_CSS, MathFonts
from .widgets import filled_when

__all__ = ["LayoutMixin"]

_ABOUT = Path(__file__).with_name("about.md")
#: When the model applies (one sentence, under the inputs).
_APPLIES = ("*When the model applies:* a long cylinder (L ≫ a) rocking without macroscopic sliding "
            "(Ft < μ Fn) on an elastic half-space, slowly (no inertia), with one constant friction coefficient, "
            "elastic bodies whose normal and tangential problems are uncoupled (Dundurs β ≈ 0).")


class LayoutMixin:
    """The explorer's page (methods of :class:`app.explorer.Explorer`)."""

    # ------------------------------------------------------------------ layout
    def __panel__(self):
        return self.template()

    def main_area(self) -> pn.viewable.Viewable:
        """The badge, cards, player and figures, without the sidebar (for notebooks)."""
        live = dict(ft=self.param.ft_live, w=self.param.w_live)
        badge = panes.HTML(pn.bind(self._badge, **live, result=self.param.result, error=self.param.error,
                                     pending=self.param.pending),
                             css_classes=["regime"], margin=(6, 10), sizing_mode="stretch_width", stylesheets=[CSS])
        cards = panes.HTML(pn.bind(self._cards, **live, mu=self.mu_slider.param.value,
                                     contact=self.param.contact, result=self.param.result,
                                     pending=self.param.pending, units=self.state.param.units,
                                     cycles=self.engineer.param.cycles),
                             css_classes=["summary-cards"], margin=(0, 10), sizing_mode="stretch_width",
                             stylesheets=[CSS])
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
        top = pn.FlexBox(
            pn.Column(badge, pn.Row(self.spinner, self.status), sizing_mode="stretch_width",
                      styles={"flex": "0 1 300px", "min-width": "260px"}),
            pn.Column(cards, errors, notices, warnings, sizing_mode="stretch_width",
                      styles={"flex": "1 1 500px", "min-width": "260px"}),
            flex_wrap="wrap", sizing_mode="stretch_width")
        tabs = pn.Tabs(("Explorer", self.explorer_tab()), *self._lazy_tabs(), sizing_mode="stretch_width",
                       dynamic=True)  # a tab's models are sent only when shown
        tabs.param.watch(lambda e: self._fill_tab(tabs, e.new), "active")
        return pn.Column(top, tabs, sizing_mode="stretch_width")

    #: The tabs built only when first shown (most visitors never open them): title, builder.
    _LAZY_TABS: ClassVar[dict] = {"Paper's figures": lambda self: paper_figures_tab(),
                                  "About the model": lambda self: self.about()}

    def _lazy_tabs(self) -> list:
        self._unbuilt = dict(self._LAZY_TABS)
        return [(title, pn.Column(name=title, sizing_mode="stretch_width")) for title in self._LAZY_TABS]

    def _fill_tab(self, tabs: pn.Tabs, index: int) -> None:
        holder = tabs[index]
        build = self._unbuilt.pop(holder.name, None)
        if build is not None:
            holder.objects = [build(self)]

    _GRID = ("sketch", "pressure", "traction", "states", "displacement", "point_pressure", "point_traction",
             "point_zones", "point_cut", "point_displacement", "map", "increments", "point_increments")

    def explorer_tab(self) -> pn.Column:
        """The player and the figures, each with a one-line caption; the figures wrap to one column when narrow.
        A figure, its caption and its controls are built when the browser first scrolls near their place."""
        self.figures(when_shown=True)
        self._grid = pn.FlexBox(*(self._slots() if self._when_shown else [self._cell(name) for name in self._GRID]),
                                flex_wrap="wrap", sizing_mode="stretch_width")
        self.pins = Pins(self)
        svg = slides.save_svg(slides.figure_titles(), run=dict(ft=self.ft_slider, w=self.w_slider),
                              offered=self._svg_titles(self.state.body))
        self.svg_select = svg.figure_menu
        self.state.param.watch(lambda e: self.svg_select.param.update(
            options=self._svg_titles(e.new), value=self._svg_titles(e.new)[0]), "body")
        return pn.Column(self.player_controls(), self.pins, svg, self._grid, sizing_mode="stretch_width", name="Explorer")

    def _svg_titles(self, body: str) -> list[str]:
        """The titles of the figures ``body`` shows, as the SVG menu offers them (in the grid's order)."""
        return [plots.FIGURES[name]["opts"]["title"] for name in self._figures_of(body)]

    def sidebar(self) -> list:
        """The input widgets."""
        physical = self.state.param.units.rx() == "physical"
        solver_card = pn.Card(title="Solver", collapsed=True, sizing_mode="stretch_width")
        return [
            self.preset, self.preset_note, *point_view.body_inputs(self.state),
            pn.pane.Markdown("### Loads"), self.ft_slider, self.w_slider, self.mu_slider,
            pn.pane.Markdown("### Units"), self.units_toggle,
            # the loads in physical units are shown with the physical units, the solver's options when their
            # card is opened: both are sent to the browser only then (most visitors never open them)
            filled_when(pn.Column(sizing_mode="stretch_width", margin=0, visible=physical), physical,
                         lambda: [self.engineer]),
            pn.Card(*self.geometry_inputs, self.rigid_box, *self.cylinder_inputs,
                    title="Geometry and materials", collapsed=False, sizing_mode="stretch_width"),
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
                                    button_type="light", margin=(8, 10))
        present.jscallback(value="""
            const on = cb_obj.active;
            document.documentElement.classList.toggle('presenting', on);
            window.dispatchEvent(new Event('resize'));
        """)
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
