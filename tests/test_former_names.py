"""The modules' former flat names (``core.engine``, ``core.solver3d``, ... before core's layer packages, issue 28)
still import the same module, with a DeprecationWarning that names the new place (core/__init__.py's import hook).
Each check runs in a fresh interpreter: a former name warns on its first import only."""

import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
# move_core: former names (the script that made the layer packages leaves this file's former names as they are)


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", code], capture_output=True,
                          text=True, timeout=120, cwd=ROOT)


def test_every_module_has_its_former_name():
    import core

    names = core.former_names()
    files = sorted(p for p in (ROOT / "core").glob("*/*.py") if p.name != "__init__.py")
    assert len(names) == len(files) > 40
    assert names["core.engine"] == "core.march.engine" and names["core.registry"] == "core.geometry.registry"
    assert all(new == f"core.{p.parent.name}.{p.stem}" for p in files for new in [names[f"core.{p.stem}"]])


@pytest.mark.parametrize("statement", ["import core.engine as former",
                                       "from core import engine as former",
                                       "import core; former = core.engine"])
def test_a_former_name_warns_and_is_the_same_module(statement):
    code = (f"import warnings\nwith warnings.catch_warnings(record=True) as caught:\n"
            f"    warnings.simplefilter('always')\n    {statement}\n"
            "import core.march.engine as now\n"
            "assert former is now, (former, now)\n"
            "assert [str(w.message) for w in caught] == ['core.engine is now core.march.engine (core\\'s layer "
            "packages, issue 28): import it from there'], [str(w.message) for w in caught]\n"
            "assert caught[0].filename == '<string>' and caught[0].category is DeprecationWarning\n"
            "print(now.run is former.run)")
    done = _run(code)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip() == "True"


def test_a_patch_through_the_former_name_reaches_the_module():
    """A mock target written with the former name patches the module the code uses."""
    code = ("import warnings; warnings.simplefilter('ignore')\n"
            "from unittest import mock\n"
            "import core.geometry.resolution as now\n"
            "with mock.patch('core.resolution.default_dx', lambda *a, **k: 0.5):\n"
            "    print(now.default_dx())\n")
    done = _run(code)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip() == "0.5"


def test_the_new_names_do_not_warn_and_unknown_names_still_fail():
    code = ("import core, core.march.engine, core.command.cli\n"
            "from core.geometry import registry\n"
            "assert core.loading.histories.__name__ == 'core.loading.histories'\n"
            "for name in ('core.no_such_module', 'core.march.no_such_module'):\n"
            "    try:\n"
            "        __import__(name)\n"
            "    except ModuleNotFoundError:\n"
            "        pass\n"
            "    else:\n"
            "        raise AssertionError(name)\n"
            "try:\n"
            "    core.no_such_name\n"
            "except AttributeError:\n"
            "    print('ok')\n")
    done = _run(code)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip() == "ok"


def test_python_dash_m_with_a_former_name_runs_the_module():
    """``python -m core.cli`` (the command line's former module) runs ``core.command.cli`` as ``__main__``, with
    the warning naming the new module (it failed in runpy's get_code before)."""
    import os

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p))
    done = subprocess.run([sys.executable, "-W", "always::DeprecationWarning", "-m", "core.cli", "--version"],
                          capture_output=True, text=True, env=env, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("shakedown ")
    assert "core.cli is now core.command.cli" in done.stderr and "python -m core.command.cli" in done.stderr
