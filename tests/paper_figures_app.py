"""Only the "Paper's figures" tab, for the browser test: ``panel serve tests/paper_figures_app.py``."""

import sys
from pathlib import Path

import panel as pn

if pn.state.served:  # not when pytest's doctest collection imports this file
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    from app.paper_figures import paper_figures_tab

    pn.extension(sizing_mode="stretch_width")
    paper_figures_tab().servable(title="Paper's figures")
