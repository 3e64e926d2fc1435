"""Sphinx configuration of the Shakedown Explorer documentation.

Build it from the repository root (no network needed)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

The API reference (``api.md``) is written here from ``core.__all__`` at every
build, so a new public name of :mod:`core` is documented without editing a page.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))  # core and app from this checkout, installed or not
sys.path.insert(0, str(DOCS / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")

import core  # noqa: E402

from api_page import write_api_page  # noqa: E402

project = "Shakedown Explorer"
author = "the Shakedown Explorer contributors"
copyright = "2026, " + author
try:
    from importlib.metadata import version as _version

    release = _version("shakedown-explorer")
except Exception:  # not installed: the source tree's pyproject is the truth
    import tomllib

    release = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
version = release

extensions = [
    "myst_nb",  # MyST markdown and notebooks (executed during the build)
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
    "sphinxarg.ext",  # the command-line reference from core.command.cli.build_parser
]

# -- sources -------------------------------------------------------------------
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = [
    "_build", "Thumbs.db", ".DS_Store", "**.ipynb_checkpoints", "jupyter_execute",
    # sphinx-gallery's downloads: the pages are its .rst files
    "auto_examples/*.ipynb", "auto_examples/*.py", "auto_examples/*.zip", "auto_examples/*.json",
    "auto_examples/*.md5", "auto_examples/*.pickle",
]
templates_path = ["_templates"]
root_doc = "index"
smartquotes = False  # keep "--flag" and quotes as typed (the command-line reference shows options)
nitpicky = False

# -- MyST and notebooks ----------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = "force"  # the notebook runs at every build: it proves the explorer and the API work
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True
# Panel's outputs carry, beside the text/html and application/javascript that the page shows, its own
# mime types (application/vnd.holoviews_load.v0+json, ..._exec...) for a live kernel: myst-nb skips those
# with a warning of this one kind, which would fail the -W build
suppress_warnings = ["mystnb.unknown_mime_type"]

# -- API reference ---------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": False}
autodoc_typehints = "none"  # numpydoc's Parameters sections give the types
numpydoc_show_class_members = False  # the class pages list no members twice (autosummary gives the names)
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set = set()  # docstrings are checked by the doctests, not by a style list
intersphinx_mapping: dict = {}  # no network during the build

write_api_page(DOCS / "api.md", core)

# -- the gallery -----------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": str(DOCS / "auto_examples"),
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "plot_gallery": "True",
    # run every example even when its output is cached in docs/auto_examples (tests/test_docs.py sets it)
    "run_stale_examples": os.environ.get("SHAKEDOWN_DOCS_RERUN_EXAMPLES") == "1",
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
    "show_memory": False,
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
}

# -- HTML ------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = "Shakedown Explorer"
html_static_path: list = []
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
    "icon_links": [],
}
html_sidebars = {"index": [], "getting-started": []}
html_show_sourcelink = False
