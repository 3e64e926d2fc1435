"""The CLI's body flags (--body punch --flat, --body ellipsoid --ratio --angle, --normal), run by the command's
own function (the installed ``shakedown`` and ``python -m core.command.cli`` as processes: tests/test_cli.py)."""

import contextlib
import io
import json
import re
import types

import pytest

from core.command.cli import main


def _cli(*args):
    """``shakedown ARGS`` in this process (a subprocess cost 3-10 s each, mostly imports): status and output."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return types.SimpleNamespace(returncode=code, stdout=out.getvalue(), stderr=err.getvalue())


def test_run_punch(tmp_path):
    out = tmp_path / "run.json"
    p = _cli("run", "--ft", "0.45", "--w", "0.3", "--body", "punch", "--flat", "0.8", "--periods", "20",
             "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert "Punch(flat=0.8)" in p.stdout and re.search(r"exact limit at this w +0.4917", p.stdout)
    assert "eq 30" not in p.stdout
    doc = json.loads(out.read_text())
    assert doc["summary"]["regime"] == "shakedown"


def test_run_punch_numerical_normal():
    p = _cli("run", "--ft", "0.2", "--w", "0.3", "--body", "punch", "--normal", "numerical", "--periods", "5")
    assert p.returncode == 0, p.stderr
    assert "Punch(flat=0.5)" in p.stdout and "shakedown" in p.stdout


def test_sweep_punch():
    p = _cli("sweep", "--ft", "0.2,0.7", "--w", "0.3", "--body", "punch", "--flat", "0.5", "--periods", "10",
             "--out", "-", "--no-progress")
    assert p.returncode == 0, p.stderr
    rows = p.stdout.strip().splitlines()
    assert len(rows) == 3 and "Punch(flat=0.5),shakedown" in rows[1] and "Punch(flat=0.5),ratcheting" in rows[2]


@pytest.mark.parametrize("args, message", [
    (("--flat", "0.8"), "--flat is for --body punch"),
    (("--body", "punch", "--flat", "1.0"), "flat"),
    (("--body", "punch", "--ratio", "2"), "--ratio is for --body ellipsoid"),
    (("--body", "sphere", "--normal", "closed"), "normal"),
    (("--body", "punch", "--normal", "closed"), "normal"),
])
def test_bad_body_flags(args, message):
    p = _cli("run", "--ft", "0.2", "--w", "0.3", "--periods", "2", *args)
    assert p.returncode != 0 and message in p.stderr


def test_ellipsoid_ratio_angle_parse():
    """--ratio and --angle [degrees] reach the point-contact run (a coarse grid: dx = 0.25)."""
    p = _cli("run", "--ft", "0.2", "--w", "0.3", "--body", "ellipsoid", "--ratio", "2", "--angle", "30",
             "--periods", "2", "--dx", "0.25")
    assert p.returncode == 0, p.stderr
    assert "ellipsoid, 3D half-space" in p.stdout and re.search(r"exact limit at this w +0.5635", p.stdout)


def test_help_lists_the_registry():
    from core.command.cli import _BODY_FLAGS, _BODY_NAMES
    from core.geometry.registry import REGISTRY
    assert set(_BODY_NAMES) == set(REGISTRY)
    for flag, bodies in _BODY_FLAGS.items():
        assert all(b in REGISTRY for b in bodies)
        if flag != "angle":  # angle is a run option of the point contacts, not a body parameter
            assert all(flag in {p.name for p in REGISTRY[b].parameters} for b in bodies)
    p = _cli("run", "--help")
    assert p.returncode == 0 and "cylinder, punch, sphere, ellipsoid" in " ".join(p.stdout.split())
