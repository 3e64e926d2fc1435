"""The command line with coupling (issue 32): --beta, --materials and --mu on run, sweep and limit; a coupled run
prints eq 35 and Melan's limit as the uncoupled reference; bad input exits 2 naming the flag."""

import io

import pandas as pd
import pytest

from core.command.cli import main
from core.theory.materials import PAIRS

COARSE = ["--periods", "3", "--dx", "0.1"]


def _run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_run_coupled_by_beta_and_by_materials(capsys):
    code, out, err = _run(capsys, "run", "--ft", "0.5", "--w", "0.3", "--beta", "0.25", "--mu", "0.3", *COARSE)
    assert code == 0, err
    assert "coupled: Dundurs beta = 0.25, mu = 0.3" in out and "(uncoupled reference)" in out
    code, out, err = _run(capsys, "run", "--ft", "0.5", "--w", "0.3", "--materials", "steel/PMMA", "--mu", "0.3",
                          *COARSE)
    assert code == 0, err
    assert f"beta = {PAIRS['steel/PMMA'].beta:.4g}" in out
    # a physical contact from the pair: coupled on the plane kernel, with its own mu
    code, out, err = _run(capsys, "run", "--R1", "0.02", "--L", "0.1", "--Fn", "1000", "--mu", "0.3", "--materials",
                          "steel/aluminium", "--ft", "0.5", "--w", "0.3", *COARSE)
    assert code == 0, err
    assert "plane kernel" in out and "coupled: Dundurs beta = 0.1167" in out


def test_sweep_and_limit_take_beta(capsys):
    code, out, err = _run(capsys, "sweep", "--ft", "0.5", "--w", "0.2,0.5", "--beta", "-0.2", "--mu", "0.4",
                          "--out", "-", "--workers", "1", "--no-progress", *COARSE)
    assert code == 0, err
    table = pd.read_csv(io.StringIO(out))
    assert list(table["beta"]) == [-0.2, -0.2] and list(table["mu"]) == [0.4, 0.4]
    assert (table["regime"] != "error").all()
    code, out, err = _run(capsys, "limit", "--ft", "0.5", "--beta", "0.25", "--mu", "0.3", "--tol", "0.05",
                          "--out", "-", "--workers", "1", "--no-progress", *COARSE)
    assert code == 0, err
    row = pd.read_csv(io.StringIO(out)).iloc[0]
    assert row["converged"] and "uncoupled reference" in row["message"]


@pytest.mark.parametrize("argv, message", [
    (["run", "--ft", "0.3", "--w", "0.3", "--beta", "0.5", "--mu", "0.3"], "--beta must be in"),
    (["run", "--ft", "0.3", "--w", "0.3", "--beta", "0.1"], "--mu is required"),
    (["run", "--ft", "0.3", "--w", "0.3", "--beta", "0.1", "--materials", "steel/PMMA", "--mu", "0.3"],
     "--beta or --materials"),
    (["run", "--ft", "0.3", "--w", "0.3", "--materials", "steel/cheese", "--mu", "0.3"], "--materials must be"),
    (["run", "--ft", "0.3", "--w", "0.3", "--beta", "0.1", "--mu", "0.3", "--body", "sphere"], "line contacts only"),
    (["sweep", "--ft", "0.3", "--w", "0.3", "--beta", "0.1", "--mu", "0", "--out", "m.csv"], "--mu must be in"),
])
def test_bad_coupled_input_exits_2_naming_the_flag(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(capsys, *argv)
    assert code == 2, (out, err)
    assert message in err and "Traceback" not in err + out
