"""The ``shakedown`` command line: outputs, resume, and bad input (exit 2, a message, no traceback)."""

import io
import json
import re
import shutil
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings, strategies as st

import core
from core.command.cli import main, parse_range
from core.maps.tables import normalise_table

FAST = ["--periods", "4", "--workers", "1", "--no-progress"]


def _run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _command():
    exe = shutil.which("shakedown")
    return [exe] if exe else [sys.executable, "-m", "core.command.cli"]


# --------------------------------------------------------------------------
# run
# --------------------------------------------------------------------------
def test_run_prints_a_summary_and_writes_csv_and_json(capsys, tmp_path):
    code, out, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.5", "--periods", "6",
                          "--out", str(tmp_path / "r.json"))
    assert code == 0, err
    assert "regime" in out and "shakedown" in out and "mu P/E*" in out
    doc = json.loads((tmp_path / "r.json").read_text())
    assert doc["summary"]["regime"] == "shakedown" and len(doc["increment_per_period"]) == 6
    code, _, err = _run(capsys, "run", "--ft", "0.6", "--w", "0.5", "--periods", "6", "--out", str(tmp_path / "r.csv"))
    assert code == 0, err
    row = pd.read_csv(tmp_path / "r.csv").iloc[0]
    assert row["regime"] == "ratcheting" and row["ft"] == 0.6 and row["increment_last_period"] > 0


def test_run_with_a_physical_contact(capsys):
    code, out, err = _run(capsys, "run", "--R1", "0.04", "--L", "0.08", "--Fn", "32.2", "--mu", "0.79",
                          "--E2", "3.6e6", "--nu2", "0.5", "--Ft", "5", "--W", "3e-4", "--periods", "4")
    assert code == 0, err
    assert "strip kernel" in out and "a = 2.0" in out and "in metres" in out


# --------------------------------------------------------------------------
# sweep: formats and resume
# --------------------------------------------------------------------------
def test_sweep_resumes_and_skips_rows_already_done(capsys, tmp_path):
    out = tmp_path / "map.csv"
    code, _, err = _run(capsys, "sweep", "--ft", "0.1:0.5:2", "--w", "0.2:0.6:2", "--out", str(out), *FAST)
    assert code == 0, err
    first = normalise_table(pd.read_csv(out))
    assert len(first) == 4 and "0 already" in err
    # a bigger grid sharing two w values: only the new rows run, the old ones are kept as they were
    code, _, err = _run(capsys, "sweep", "--ft", "0.1:0.5:2", "--w", "0.2:0.6:3", "--out", str(out), *FAST)
    assert code == 0, err
    assert "6 runs in the grid, 4 already" in err and "2 to run" in err
    second = normalise_table(pd.read_csv(out))
    assert len(second) == 6
    assert list(zip(second["ft"], second["w"])) == [(f, w) for f in (0.1, 0.5) for w in (0.2, 0.4, 0.6)]
    kept = second.merge(first, on=["ft", "w"], suffixes=("", "_first"))
    np.testing.assert_array_equal(kept["runtime"], kept["runtime_first"])  # not recomputed
    code, _, err = _run(capsys, "sweep", "--ft", "0.1:0.5:2", "--w", "0.2:0.6:3", "--out", str(out), *FAST)
    assert code == 0 and "nothing new" in err
    # the same grid through the API gives the same table
    api = core.sweep([0.1, 0.5], [0.2, 0.4, 0.6], scheduler="serial", periods=4)
    pd.testing.assert_frame_equal(second.drop(columns="runtime"), api.drop(columns="runtime"))


def test_an_interrupted_sweep_resumes_from_its_journal(capsys, tmp_path, monkeypatch):
    sweep_module = sys.modules["core.maps.sweeps"]
    real, calls = sweep_module.run_chunk, []

    def interrupted(points):
        calls.append(points)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(points)

    monkeypatch.setattr(sweep_module, "run_chunk", interrupted)
    out = tmp_path / "map.parquet"
    code, _, err = _run(capsys, "sweep", "--ft", "0.1,0.3,0.5", "--w", "0.2,0.6", "--out", str(out), *FAST)
    journal = tmp_path / "map.parquet.partial.csv"
    assert code == 130 and "rerun the same command" in err
    assert not out.exists() and len(pd.read_csv(journal)) == 2
    with journal.open("a") as f:  # a line cut short when the process was killed
        f.write("0.5,0.6,4,0.02")
    monkeypatch.setattr(sweep_module, "run_chunk", real)
    code, _, err = _run(capsys, "sweep", "--ft", "0.1,0.3,0.5", "--w", "0.2,0.6", "--out", str(out), *FAST)
    assert code == 0 and "2 already" in err and "4 to run" in err
    assert not journal.exists()
    table = pd.read_parquet(out)
    assert len(table) == 6 and table["error"].isna().all()


def test_sweep_to_gzip_and_overwrite(capsys, tmp_path):
    out = tmp_path / "map.csv.gz"
    args = ["sweep", "--ft", "0.2", "--w", "0.1,0.9", "--out", str(out), *FAST]
    assert _run(capsys, *args)[0] == 0
    assert _run(capsys, *args, "--overwrite")[0] == 0
    table = normalise_table(pd.read_csv(out))
    assert list(table["regime"]) == ["shakedown", "ratcheting"]


def test_failed_runs_are_rows_and_exit_status_1(capsys, tmp_path):
    out = tmp_path / "m.csv"
    # a 1 us budget stops the longer run (the shorter one ends before the first check)
    code, _, err = _run(capsys, "sweep", "--ft", "0.3", "--w", "0.05,0.8", "--out", str(out), "--time-budget", "1e-6",
                        *FAST)
    assert code == 1 and "1 of 2 runs failed" in err
    table = normalise_table(pd.read_csv(out))
    assert list(table["regime"]) == ["shakedown", "error"] and "SolveCancelled" in table["error"][1]
    code, _, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.8", "--time-budget", "1e-6")
    assert code == 1 and "SolveCancelled" in err and "Traceback" not in err


# --------------------------------------------------------------------------
# limit
# --------------------------------------------------------------------------
def test_limit_prints_and_writes_the_curve(capsys, tmp_path):
    code, out, err = _run(capsys, "limit", "--ft", "0.3,0.6", "--tol", "0.005", "--out", str(tmp_path / "l.json"),
                          "--workers", "1", "--no-progress")
    assert code == 0, err
    assert "w_limit_eq35" in out and "eq35_inside" in out and "start_lo" in out
    rows = json.loads((tmp_path / "l.json").read_text())
    assert [r["ft"] for r in rows] == [0.3, 0.6]
    assert all(r["converged"] and abs(r["difference"]) <= 0.005 + 1e-3 for r in rows)
    # the search starts from the whole range, not from eq 35, and says whether eq 35 is in its final bracket
    assert all((r["start_lo"], r["start_hi"]) == (0.0, 0.999) for r in rows)
    assert all(r["eq35_inside"] == (r["w_shakedown"] <= r["w_limit_eq35"] <= r["w_ratcheting"]) for r in rows)
    assert all(r["w_ratcheting"] - r["w_shakedown"] <= 2 * 0.005 for r in rows)


# --------------------------------------------------------------------------
# bad input: exit 2, a message naming the problem, no traceback
# --------------------------------------------------------------------------
LONG = "9" * 5000


@pytest.mark.parametrize("argv, message", [
    (["run", "--ft", "nan", "--w", "0.3"], "ft must be a number"),
    (["run", "--ft", "inf", "--w", "0.3"], "ft must be a finite number in"),
    (["run", "--ft", "-0.1", "--w", "0.3"], "ft must be in"),
    (["run", "--ft", "1", "--w", "0.3"], "ft must be in [0, 1)"),
    (["run", "--ft", "0.3", "--w", "1.0"], "w must be in [0, 1)"),
    (["run", "--ft", "abc", "--w", "0.3"], "ft must be a number"),
    (["run", "--ft", "0.3", "--ft", "0.2", "--w", "0.3"], "given more than once"),
    (["run", "--ft", "0.3"], "give --ft and --w"),
    (["run", "--ft", "0.3", "--w", "0.3", "--periods", "1e9"], "periods must be a whole number"),
    (["run", "--ft", "0.3", "--w", "0.3", "--periods", "100000"], "periods must be an integer"),
    (["run", "--ft", "0.3", "--w", "0.9", "--periods", "5000"], "cells"),
    (["run", "--ft", "0.3", "--w", "0.3", "--dx", "1e-5"], "--dx must be in [0.000122085, 0.5]"),
    (["run", "--ft", "0.3", "--w", "0.3", "--dx", "1.2e-4"], "--dx must be in [0.000122085, 0.5]"),
    (["run", "--ft", "0.3", "--w", "0.9", "--dx", "6e-4"], "elements"),
    (["run", "--ft", "0.3", "--w", "0.3", "--kernel", "strip"], "--L-over-a is required with --kernel strip"),
    (["run", "--ft", "0.3", "--w", "0.3", "--body", "banana"], "--body must be one of cylinder"),
    (["sweep", "--ft", "0.3", "--w", "0.3", "--out", "m.csv", "--body", "banana"], "--body must be one of"),
    (["run", "--ft", "0.3", "--w", "0.3", "--history", "banana"], "--history must be one of"),
    (["run", "--ft", "0.3", "--w", "0.3", "--kernel", "x" * 300], "too long"),
    (["run", "--ft", "0.3", "--w", "0.3", "--kernel", LONG], "too long"),
    (["run", "--R1", "0.04", "--ft", "0.3", "--w", "0.3"], "needs --L --Fn --mu --E2"),
    (["run", "--R1", "-1", "--L", "0.08", "--Fn", "32", "--mu", "0.8", "--E2", "3e6", "--ft", "0.1", "--w", "0.1"],
     "R1 must be in"),
    (["run", "--R1", "0.04", "--L", "0.08", "--Fn", "32", "--mu", "0.8", "--E2", "0", "--ft", "0.1", "--w", "0.1"],
     "E2 must be in"),
    (["run", "--R1", "0.04", "--L", "0.08", "--Fn", "32", "--mu", "0.8", "--E2", "3e6", "--nu2", "0.6", "--ft", "0.1",
      "--w", "0.1"], "nu2 must be in"),
    (["run", "--R1", "0.04", "--L", "0.08", "--Fn", "32", "--mu", "0.8", "--E2", "3e6", "--Ft", "100", "--w", "0.1"],
     "Ft must be in"),
    (["run", "--R1", "0.04", "--L", "0.08", "--Fn", "32", "--mu", "0.8", "--E2", "3e6", "--Ft", "1", "--ft", "0.1",
      "--w", "0.1"], "exactly one of --Ft and --ft"),
    (["run", "--ft", "0.3", "--w", "0.3", "--out", "x.txt"], "--out must end in"),
    (["sweep", "--ft", "0:0.9:1000", "--w", "0:0.9:1000", "--out", "m.csv"], "1000000 runs"),
    (["sweep", "--ft", "0:0.9:10", "--w", "0:0.9:10", "--out", "m.csv", "--max-runs", "50"], "100 runs"),
    (["sweep", "--ft", "0:1:10", "--w", "0.1", "--out", "m.csv"], "ft must be in"),
    (["sweep", "--ft", "0.1:0.2:1", "--w", "0.1", "--out", "m.csv"], "N in START:STOP:N"),
    (["sweep", "--ft", "0.1,0.1", "--w", "0.1", "--out", "m.csv"], "distinct"),
    (["sweep", "--ft", "0.1", "--w", "0.1", "--out", "/no/such/dir/m.csv"], "does not exist"),
    (["sweep", "--ft", "0.1", "--w", "0.1"], "required: --out"),
    (["sweep", "--ft", "0.1", "--w", "0.1", "--out", "m.csv", "--workers", "0"], "workers must be"),
    (["sweep", "--ft", "0.1", "--w", "0.1", "--out", "m.csv", "--scheduler", "bogus"], "tcp://host:8786"),
    (["sweep", "--ft", "0.1", "--w", "0.1", "--out", "m.csv", "--scheduler", "tcp://a:1", "--scheduler", "tcp://b:2"],
     "given more than once"),
    (["limit", "--ft", "0:0.5:3"], "ft must be in (0, 1)"),
    (["limit", "--ft", "0.5", "--tol", "1"], "tol must be in"),
    (["bogus"], "invalid choice"),
    ([LONG], "too long"),
    ([], ""),
])
def test_bad_input_exits_2_with_a_message(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(capsys, *argv)
    assert code == 2
    assert message in err and "Traceback" not in err + out
    assert len(err) < 5000
    if message:  # one error line with the same prefix for every command, after argparse's usage line if any
        assert [line for line in err.splitlines() if not line.startswith(("usage:", " "))][0].startswith(
            "shakedown: error: "), err
    assert not list(tmp_path.iterdir())  # nothing written


def test_sweep_refuses_to_mix_another_grid_or_options_into_its_file(capsys, tmp_path):
    out = tmp_path / "map.csv"
    assert _run(capsys, "sweep", "--ft", "0.1,0.5", "--w", "0.2", "--out", str(out), *FAST)[0] == 0
    before = out.read_bytes()
    for other in (["--ft", "0.1,0.5", "--w", "0.2", "--periods", "5"],    # other options
                  ["--ft", "0.1,0.4", "--w", "0.2", "--periods", "4"],    # another grid
                  ["--ft", "0.1,0.5", "--w", "0.2", "--periods", "4", "--shape", "sine"]):
        code, _, err = _run(capsys, "sweep", *other, "--out", str(out), "--workers", "1", "--no-progress")
        assert code == 2 and "not runs of this sweep" in err and "overwrite" in err, err
        assert out.read_bytes() == before
    code, _, err = _run(capsys, "sweep", "--ft", "0.1,0.4", "--w", "0.2", "--out", str(out), "--overwrite", *FAST)
    assert code == 0, err
    assert list(normalise_table(pd.read_csv(out))["ft"]) == [0.1, 0.4]


def test_small_tables_go_to_stdout_without_float_noise(capsys):
    code, out, err = _run(capsys, "sweep", "--ft", "0.1:0.5:5", "--w", "0.3", "--out", "-", *FAST)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].startswith("ft,w,periods,dx,kernel,shape,regime,regime_reason,")
    assert [line.split(",")[0] for line in lines[1:]] == ["0.1", "0.2", "0.3", "0.4", "0.5"]
    assert not re.search(r"0000000\d|9999999\d", out), out  # no round-off noise in any number
    code, out, err = _run(capsys, "limit", "--ft", "0.5", "--tol", "0.01", "--periods", "6", "--out", "-",
                          "--workers", "1", "--no-progress")
    assert code == 0, err
    table = pd.read_csv(io.StringIO(out))
    assert list(table["ft"]) == [0.5] and bool(table["eq35_inside"][0])


def test_body_and_history_pass_through(capsys):
    code, out, err = _run(capsys, "run", "--ft", "0.1", "--w", "0.2", "--periods", "1", "--body", "cylinder",
                          "--history", "rocking")
    assert code == 0, err
    # one period cannot tell the regime of this clear shakedown case: it says so
    assert "undetermined" in out and "too few" in out



@pytest.mark.parametrize("name, says", [("normal", "oscillating normal force"),
                                        ("tangential", "oscillating tangential force at a fixed centre")])
def test_history_names_reach_the_solver(capsys, name, says):
    code, out, err = _run(capsys, "run", "--ft", "0.2", "--w", "0.3", "--periods", "2", "--dx", "0.05",
                          "--history", name)
    assert code == 0, err
    assert says in out.splitlines()[0]


def test_help_and_version_import_nothing_heavy():
    code = ("import sys, contextlib, io\n"
            "from core.command.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    for argv in (['--help'], ['sweep', '--help'], ['--version']):\n"
            "        assert main(argv) == 0, argv\n"
            "print(sorted(m for m in ('numpy', 'pandas', 'scipy', 'numba') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"
    done = subprocess.run([*_command(), "--version"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.startswith("shakedown ") and done.stdout.split()[1][0].isdigit()


def test_the_cli_copies_of_library_constants_agree():
    import core.command.cli as cli
    from core.loading import schedule
    from core.elastic import kernels
    from core.api import solver
    from core.maps import grid

    assert cli._KERNELS == tuple(kernels.KERNELS) and cli._SHAPES == schedule.SHAPES
    assert cli._DEFAULT_DX == solver.DEFAULT_DX and cli._MAX_ELEMENTS == solver.MAX_FFT_ELEMENTS
    from core.geometry import resolution
    assert (cli._DEFAULT_DX, cli._DEFAULT_DX_POINT) == (resolution.default_dx("cylinder"), resolution.default_dx("sphere"))
    assert (cli._MAX_RUNS, cli._MAX_CELLS) == (grid.MAX_RUNS, grid.MAX_CELLS)
    from core.march import engine
    assert set(cli._SOLVERS) == {"auto", *engine.STEP_SOLVERS}
    fft = solver.MAX_FFT_ELEMENTS
    solver.make_grid(1.0, cli._DX_MIN, fft)  # the finest dx --dx accepts works at w = 0
    with pytest.raises(ValueError, match="elements"):
        solver.make_grid(1.0, cli._DX_MIN * 0.999, fft)


def test_solver_flag_reaches_the_engine_or_is_refused_for_the_grid(capsys, tmp_path):
    """--solver picks the per-step solver (the same increments from dense and fft); one of the other grid shape is
    refused with the valid choices and the body's name."""
    incs = {}
    for name in ("dense", "fft"):
        out = tmp_path / f"{name}.json"
        code, _, err = _run(capsys, "run", "--ft", "0.6", "--w", "0.5", "--periods", "4", "--solver", name,
                            "--out", str(out))
        assert code == 0, err
        incs[name] = json.loads(out.read_text())
        assert incs[name]["summary"]["solver"] == name
    assert np.allclose(incs["dense"]["increment_per_period"], incs["fft"]["increment_per_period"], rtol=1e-6)
    code, _, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.3", "--body", "sphere", "--solver", "dense")
    assert code == 2 and "--solver must be one of ('auto', 'pcg3d') for the sphere (a patch of elements)" in err
    code, _, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.3", "--body", "punch", "--solver", "pcg3d")
    assert code == 2 and "for the punch (a line of elements)" in err and "'pcg3d' solves the other grid" in err
    code, out, err = _run(capsys, "sweep", "--ft", "0.3", "--w", "0.3", "--solver", "fft", *FAST, "--out", "-")
    assert code == 0 and ",fft," in out.splitlines()[1]


def test_run_prints_melan_limit_of_its_grid(capsys):
    """The limit the verdict is checked against: the cylinder's grid gives eq 35 (aligned element means), the cone
    its programme's bracket, a history with a varying tangential load none."""
    code, out, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.5", "--periods", "4")
    assert code == 0, err
    assert f"Melan's limit on this grid  {float(core.ft_limit(0.5)):.6g} = ft_lim" in out
    code, out, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.5", "--periods", "4", "--body", "cone")
    lim = core.Cone().grid_limit(0.5)
    assert code == 0 and f"between {lim['lo']:.6g} and {lim['hi']:.6g} = ft_lim" in out, out
    code, out, err = _run(capsys, "run", "--ft", "0.2", "--w", "0.3", "--periods", "2", "--history", "tangential")
    assert code == 0 and "Melan's limit on this grid" in out and "the tangential load varies" in out


def test_run_finer_than_the_dense_solver_takes(capsys):
    """--dx below the dense solver's cap runs on the matrix-free solver (the CLI stopped at 4000 elements)."""
    code, out, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.05", "--dx", "0.00045", "--periods", "1")
    assert code == 0, err
    assert "dx = 0.00045 a" in out


def test_sweep_cap_from_the_environment(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("SHAKEDOWN_MAX_RUNS", "3")
    code, _, err = _run(capsys, "sweep", "--ft", "0.1,0.2", "--w", "0.1,0.2", "--out", str(tmp_path / "m.csv"))
    assert code == 2 and "SHAKEDOWN_MAX_RUNS" in err


def test_cli_as_a_subprocess():
    done = subprocess.run([*_command(), "--help"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and all(c in done.stdout for c in ("run", "sweep", "limit"))
    done = subprocess.run([*_command(), "sweep", "--help"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0
    for text in ("START:STOP:N", "[a]", "--scheduler", "SHAKEDOWN_MAX_RUNS", "mu P/E*"):
        assert text in " ".join(done.stdout.split()), text
    done = subprocess.run([*_command(), "run", "--ft", "nan", "--w", "0.3"], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and "ft must be a number" in done.stderr and "Traceback" not in done.stderr


# --------------------------------------------------------------------------
# the range parser, fuzzed
# --------------------------------------------------------------------------
@settings(max_examples=300, deadline=None)
@given(st.one_of(
    st.text(max_size=60),
    st.text(alphabet="0123456789.:,-+e naif", max_size=30),
    st.builds(lambda a, b, n: f"{a}:{b}:{n}", st.floats(allow_nan=True), st.floats(allow_nan=True),
              st.integers(-5, 20_000)),
))
def test_parse_range_returns_valid_values_or_raises_value_error(text):
    try:
        values = parse_range(text, "ft", 0.0, 1.0, hi_closed=False)
    except ValueError as e:
        assert "ft" in str(e)
        return
    assert values.ndim == 1 and 1 <= values.size <= 10_000
    assert np.isfinite(values).all() and (values >= 0).all() and (values < 1).all()
    assert np.unique(values).size == values.size


@settings(deadline=None)  # up to 500 values each rounded to 12 digits: slow on a loaded machine
@given(st.floats(0, 0.99), st.floats(0, 0.99), st.integers(2, 500))
def test_parse_range_start_stop_n_is_linspace(start, stop, n):
    text = f"{start!r}:{stop!r}:{n}"
    if start == stop:
        with pytest.raises(ValueError):
            parse_range(text, "w", 0.0, 1.0, hi_closed=False)
        return
    try:
        values = parse_range(text, "w", 0.0, 1.0, hi_closed=False)
    except ValueError as e:  # values so close that linspace repeats one
        assert "distinct" in str(e)
        return
    # linspace, rounded to 12 significant digits inside (0.3, not 0.30000000000000004); the ends as written
    np.testing.assert_allclose(values, np.linspace(start, stop, n), rtol=5e-12, atol=1e-300)
    assert values[0] == start and values[-1] == stop


def test_run_a_sphere(capsys):
    """The command line runs the point contacts too (issue 13, item 5), in their own units and limit."""
    code, out, err = _run(capsys, "run", "--ft", "0.3", "--w", "0.3", "--body", "sphere", "--dx", "0.25",
                          "--periods", "3")
    assert code == 0, err
    assert "sphere, 3D half-space" in out and "mu Fn/(E* a)" in out and "eq 30" not in out
    assert "0.5635 = ft_lim" in out  # the sphere's exact limit (1 - w)^2 (2 + w) / 2 at w = 0.3
