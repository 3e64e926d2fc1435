"""The documentation: the site builds with no warning, the gallery draws every figure, the API page lists every
public name of core (docs/conf.py, docs/_ext), and the command-line reference is the parser's."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

#: The gallery's scripts: one per paper figure 6-16, Table 1, and the bodies and histories beyond the paper.
PAPER_FIGURES = [f"fig{n:02d}" for n in range(6, 17)]


def _examples() -> list[Path]:
    return sorted((ROOT / "examples").glob("plot_*.py"))


def test_gallery_has_every_paper_figure_and_table1():
    names = [p.stem for p in _examples()]
    for fig in PAPER_FIGURES:
        assert any(n.startswith(f"plot_{fig}_") for n in names), f"no gallery script for the paper's {fig}"
    assert "plot_table1" in names and "plot_sphere" in names and "plot_ellipsoid" in names


def test_gallery_has_every_body():
    """Every body of the library, by name (the line bodies, the point contacts, the cone, the sampled surfaces)."""
    import core

    names = [p.stem for p in _examples()]
    for body in (*core.BODIES, *core.POINT_BODIES):
        if body != "cylinder":  # the paper's figures
            assert f"plot_{body}" in names, f"no gallery script for the body {body!r}"
    assert "plot_cone" in names and "plot_heightmap" in names


def test_every_gallery_script_says_what_it_shows_and_how_it_compares():
    for path in _examples():
        text = path.read_text()
        doc = text.split('"""')[1]
        title, underline = doc.strip().splitlines()[:2]
        assert set(underline) == {"="} and len(underline) >= len(title), path.name
        assert "How it compares" in doc, f"{path.name}: the docstring must say how it compares with the paper"
        assert not re.search(r"^\s*(from app\b|import app\b)", text, flags=re.M), f"{path.name}: the gallery uses core only"


def test_api_page_lists_every_public_name(tmp_path):
    import core
    from api_page import write_api_page

    page = tmp_path / "api.md"
    names = write_api_page(page, core)
    text = page.read_text()
    assert sorted(names) == sorted(core.__all__)
    listed = re.findall(r"^   (\w+)$", text, flags=re.M) + re.findall(r"^\.\. py:data:: (\w+)$", text, flags=re.M)
    assert sorted(listed) == sorted(core.__all__)


def test_core_all_is_every_public_name():
    import core

    assert len(core.__all__) == len(set(core.__all__)) > 50
    for name in core.__all__:
        assert not name.startswith("_")
        getattr(core, name)
    for name in ("simulate_cycles", "ft_limit", "w_limit", "sweep", "shakedown_state", "Contact", "approximations"):
        assert name in core.__all__


def test_cli_reference_parser_keeps_every_option():
    from cli_parser import parser

    from core.command.cli import build_parser

    def flags(p):
        out = {tuple(a.option_strings) for a in p._actions}
        for a in p._actions:
            if hasattr(a, "choices") and isinstance(a.choices, dict):
                for name, sub in a.choices.items():
                    out |= {(name, *f) for f in flags(sub)}
        return out

    assert flags(parser()) == flags(build_parser())
    helps = [a.help or "" for a in parser()._subparsers._group_actions[0].choices["run"]._actions]
    assert not any(re.search(r"(?<!\\)\|", h) for h in helps), "an unescaped | would be an RST substitution"


@pytest.mark.slow
def test_docs_build_with_no_warning(tmp_path):
    out = tmp_path / "html"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
           "SHAKEDOWN_DOCS_RERUN_EXAMPLES": "1", "MPLBACKEND": "Agg"}
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-E", "-q", "-b", "html",
                           str(DOCS), str(out)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=570)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-5000:]

    import core

    api = (out / "api.html").read_text()
    missing = [n for n in core.__all__ if f"core.{n}" not in api]
    assert not missing, f"not on the API page: {missing}"
    for path in _examples():
        page = out / "auto_examples" / f"{path.stem}.html"
        assert page.exists(), page
        assert (out / "_images" / f"sphx_glr_{path.stem}_001.png").exists(), f"{path.stem} drew no figure"
    cli = (out / "cli-reference.html").read_text()
    for flag in ("--ft", "--time-budget", "--scheduler", "--tol"):
        assert flag in cli
    notebook = (out / "guide" / "notebook.html").read_text()
    assert "data-root-id" in notebook, "the executed notebook shows no Panel output"
    assert "Traceback" not in notebook
    assert "shakedown shakedown 0.50" in notebook, "the notebook's explorer and API runs agree (ft_lim(0.4) = 0.5046)"


def test_readme_is_short_and_its_links_resolve():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(readme.splitlines()) < 150
    assert "bash scripts/test.sh" in readme and "panel serve app/main.py" in readme
    # exactly two set-up commands, each a shell block of its own: run the app, run the tests (the Python
    # examples are fenced blocks, run by test_python_blocks_of_the_pages_run)
    fenced, shell = False, []
    for line in readme.splitlines():
        fenced ^= line.startswith("```")
        if not fenced and line.startswith("    ") and line.strip():
            shell.append(line.strip())
    assert len(shell) == 2 and shell[0].startswith("pip install -e . && panel serve app/main.py"), shell
    assert shell[1] == "bash scripts/test.sh", shell
    links = re.findall(r"\]\(([^)#]+)\)", readme)
    assert links and not [link for link in links if not (ROOT / link).exists()]


@pytest.mark.slow
@pytest.mark.parametrize("page", ["README.md", "docs/getting-started.md", "docs/guide/histories.md"])
def test_python_blocks_of_the_pages_run(page):
    """The Python blocks of the README and the guide pages run, in order, as a reader pastes them (the notebook's
    ``pn.extension`` block and the maps snippet, a file for spawned workers, are run elsewhere)."""
    text = (ROOT / page).read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "pn.extension" not in b]
    assert blocks
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, page, "exec"), namespace)  # noqa: S102 - the project's own documentation
