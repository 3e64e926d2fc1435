"""What :mod:`app.live` changes in Bokeh to send a page for less CPU leaves what is sent as it was."""

from __future__ import annotations

import re

from bokeh.core.json_encoder import serialize_json
from bokeh.document import Document
from bokeh.models import ColumnDataSource, Selection
from panel.io.state import set_curdoc

from app import plots
from app.explorer import Explorer
from app.live import LiveFigure, faster_bokeh


def _page_json(doc) -> str:
    """The document as the server sends it, without the buffers' ids (new at each encoding)."""
    return re.sub(r'"data":\{"id":"p\d+"\}', '"data":"buffer"', serialize_json(doc.to_json()))


def test_a_page_encodes_to_the_same_json_with_bokehs_own_methods():
    """The served page (every figure drawn, the cards opened) encodes to the same JSON with app.live's
    HasProps.query_properties_with_values and themed_values as with Bokeh's own."""
    doc = Document()
    with set_curdoc(doc):
        ex = Explorer()
        with doc.models.freeze():
            ex.template().server_doc(doc)
        for sentinel in list(ex.sentinels.values()):
            sentinel.shown = True
        for card in (m for m in doc.models if type(m).__name__ == "Card"):
            card.collapsed = False
        before = faster_bokeh(True)
        try:
            ours = _page_json(doc)
            faster_bokeh(False)
            bokehs = _page_json(doc)
        finally:
            faster_bokeh(before)
    assert len(ex._live) >= 7 and '"name":"Slider"' in ours
    assert ours == bokehs


def test_a_figures_sources_share_one_empty_selection():
    """No figure has a selection tool: one Selection for all the layers of a figure, its own (not another
    figure's, nor the template's), empty."""
    inputs = Explorer()._inputs()
    figures = [LiveFigure(plots.specs(n, inputs.units), plots.layers(n, inputs), plots.group(n))
               for n in ("traction", "traction", "pressure")]
    selections = []
    for fig in figures:
        models = fig.figure.references()
        assert sum(isinstance(m, ColumnDataSource) for m in models) == len(fig.sources()) > 4
        (selection,) = [m for m in models if isinstance(m, Selection)]
        assert all(s.selected is selection for s in fig.sources()) and selection.indices == []
        selections.append(selection)
    assert len({id(s) for s in selections}) == 3


def test_importing_the_app_leaves_bokeh_as_it_is_and_the_served_app_installs_the_faster_methods():
    """A notebook that imports app (the Explorer) keeps Bokeh's own methods for its other plots; the served
    entry point (app/main.py) installs app.live's."""
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    check = ("import app, app.explorer, app.notebook, app.live as live; from bokeh.core.has_props import HasProps; "
             "print(HasProps.themed_values is live._themed_values); import runpy; "
             "runpy.run_path('app/main.py', run_name='shakedown_main'); print(HasProps.themed_values is live._themed_values)")
    out = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True, cwd=root, timeout=300,
                         env={**__import__("os").environ, "PYTHONPATH": str(root)})
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split()[-2:] == ["False", "True"], out.stdout


def test_copying_a_figure_leaves_bokehs_validation_on_for_other_threads():
    """A figure's copy skips validating the template's values itself, never through Bokeh's process-wide switch:
    a session built in another thread meanwhile would skip it too, and with it the conversions it drives (a
    HoloViews figure then kept its title as a str and failed: seen in CI as the served app's first page)."""
    import bokeh.core.property.bases as bases

    from app import live

    explorer = Explorer()
    explorer.figures()
    render = explorer._live["pressure"]._render
    seen = []
    decode = live._Copier._decode_object_ref

    def watched(self, obj):
        seen.append(bases.validation_on())
        return decode(self, obj)

    live._Copier._decode_object_ref = watched
    try:
        figure, models = render.copy()
    finally:
        live._Copier._decode_object_ref = decode
    assert seen and all(seen), f"validation was off during {seen.count(False)} of {len(seen)} model decodes"
    assert type(figure.title).__name__ == "Title" and figure.title.text == render.copy()[0].title.text
    assert len(models) == len(render.model_ids)
