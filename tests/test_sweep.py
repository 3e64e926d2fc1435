"""The sweep API: grids, regimes against eq 35, identical tables on every backend, the numerical limit."""

import importlib
import io
import threading

import numpy as np
import pandas as pd
import pytest

import core
from core.maps.sweeps import ProgressBar, normalise_table, sweep_grid

# a small grid with a failing axis value: the strip runs stop on a tiny time budget except the shortest
FT = [0.1, 0.5]
W = [0.05, 0.8]
OPTIONS = dict(periods=6, time_budget=[None, 1e-6])


def _without_runtime(table):
    return table.drop(columns="runtime")


@pytest.fixture(scope="module")
def serial_table():
    return core.sweep(FT, W, scheduler="serial", **OPTIONS)


@pytest.fixture(scope="module")
def dask_client():
    import distributed
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        yield client


# --------------------------------------------------------------------------
# the grid
# --------------------------------------------------------------------------
def test_grid_is_the_product_in_order():
    points = sweep_grid([0.1, 0.2], [0.3, 0.4], periods=[4, 8], shape="sine")
    got = [(p["ft"], p["w"], p["periods"], p["shape"]) for p in points]
    want = [(f, w, n, "sine") for f in (0.1, 0.2) for w in (0.3, 0.4) for n in (4, 8)]
    assert got == want
    assert all(p["dx"] == core.api.solver.DEFAULT_DX and p["kernel"] == "plane" for p in points)


@pytest.mark.parametrize("kwargs, match", [
    (dict(ft=[0.1, float("nan")], w=0.2), "ft must be a number"),
    (dict(ft=0.1, w=[0.2, float("inf")]), "w must be a finite number in"),
    (dict(ft=1.0, w=0.2), "ft must be in"),
    (dict(ft=0.1, w=1.0), "w must be in"),
    (dict(ft=0.1, w=-0.1), "w must be in"),
    (dict(ft=[], w=0.2), "at least one value"),
    (dict(ft="0.1", w=0.2), "ft must be a number"),
    (dict(ft=0.1, w=0.2, bogus=1), "unknown solver option"),
    (dict(ft=0.1, w=0.2, periods=[]), "at least one value"),
    (dict(ft=0.1, w=0.2, dx=-1.0), "dx must be"),
    (dict(ft=0.1, w=0.2, kernel="strip"), "L_over_a is required"),
    (dict(ft=0.1, w=0.2, shape="square"), "shape must be"),
    (dict(ft=0.1, w=0.2, tol=1.0), "tol must be"),
    (dict(ft=np.linspace(0, 0.9, 200), w=np.linspace(0, 0.9, 200)), "40000 runs"),
    (dict(ft=0.1, w=0.9, periods=10_000), "cells"),
])
def test_bad_grids_are_refused_before_any_work(kwargs, match):
    with pytest.raises(ValueError, match=match):
        sweep_grid(**kwargs)


def test_caps_are_configurable(monkeypatch):
    with pytest.raises(ValueError, match="4 runs"):
        sweep_grid([0.1, 0.2], [0.1, 0.2], max_runs=3)
    monkeypatch.setenv("SHAKEDOWN_MAX_RUNS", "3")
    with pytest.raises(ValueError, match="SHAKEDOWN_MAX_RUNS"):
        sweep_grid([0.1, 0.2], [0.1, 0.2])
    monkeypatch.setenv("SHAKEDOWN_MAX_RUNS", "lots")
    with pytest.raises(ValueError, match="positive integer"):
        sweep_grid(0.1, 0.1)
    monkeypatch.setenv("SHAKEDOWN_MAX_RUNS", "10")
    monkeypatch.setenv("SHAKEDOWN_MAX_CELLS", "1000")
    with pytest.raises(ValueError, match="cells"):
        sweep_grid(0.1, 0.5)


# --------------------------------------------------------------------------
# the table
# --------------------------------------------------------------------------
def test_regimes_agree_with_eq35_away_from_the_limit():
    ft = np.array([0.1, 0.4, 0.7])
    w = np.array([0.1, 0.5, 0.9])
    table = core.sweep(ft, w, scheduler="serial")
    assert list(table.columns[:6]) == ["ft", "w", "periods", "dx", "kernel", "shape"]
    assert len(table) == 9 and table["error"].isna().all()
    margin = table["ft"] - core.ft_limit(table["w"].to_numpy())
    far = np.abs(margin) > 0.05
    assert far.sum() >= 6
    expected = np.where(margin < 0, "shakedown", "ratcheting")
    assert (table["regime"][far] == expected[far]).all(), table[["ft", "w", "regime"]]
    shaken = table["regime"] == "shakedown"
    assert (table.loc[shaken, "stick_halfwidth"] > 0).all()
    assert (table.loc[~shaken, "increment"] > 1e-3).all()
    assert table["max_kkt_residual"].max() < 1e-8
    assert table.attrs["backend"] == "serial"


def test_a_failing_run_is_a_row_not_a_crash(serial_table):
    t = serial_table
    assert len(t) == 8
    failed = t["regime"] == "error"
    # every run with a 1 us budget fails except the shortest (it ends before the first budget check)
    assert list(failed) == [False, False, False, True] * 2
    assert t.loc[failed, "error"].str.startswith("SolveCancelled").all()
    assert t.loc[failed, "increment"].isna().all()
    assert t.loc[~failed, "error"].isna().all()


def test_local_processes_give_the_serial_table(serial_table):
    table = core.sweep(FT, W, workers=2, **OPTIONS)
    assert table.attrs["backend"] == "processes(2)" and len(table.attrs["warmup_s"]) == 2
    pd.testing.assert_frame_equal(_without_runtime(table), _without_runtime(serial_table))


def test_dask_gives_the_serial_table(serial_table, dask_client):
    by_client = core.sweep(FT, W, scheduler=dask_client, **OPTIONS)
    by_address = core.sweep(FT, W, scheduler=dask_client.scheduler.address, **OPTIONS)
    for table in (by_client, by_address):
        assert table.attrs["backend"].startswith("dask(")
        pd.testing.assert_frame_equal(_without_runtime(table), _without_runtime(serial_table))


@pytest.mark.parametrize("scheduler, match", [
    (123, "scheduler must be"), ("tcp://", "tcp://host:8786"), ("bogus", "tcp://host:8786"),
    ("tcp://host:port", "tcp://host:8786"), ("x" * 400, "at most 300 characters"),
])
def test_bad_schedulers_are_refused(scheduler, match):
    with pytest.raises(ValueError, match=match):
        core.sweep(0.1, 0.1, scheduler=scheduler, periods=2)


def test_a_map_like_callable_is_used_as_scipy_does(serial_table):
    calls = []

    def mapper(fn, iterable):
        calls.append(1)
        return map(fn, iterable)

    table = core.sweep(FT, W, workers=mapper, **OPTIONS)
    assert calls == [1]  # one call over every task
    pd.testing.assert_frame_equal(_without_runtime(table), _without_runtime(serial_table))


def test_workers_follow_the_size_of_the_job():
    from core.maps.grid import run_cells
    from core.maps.tasks import auto_workers

    def cells(n):
        grid = np.linspace(0.02, 0.95, n)
        return sum(run_cells(p) for p in sweep_grid(grid, grid))

    # a 5 x 5 map is a fraction of a second of solving: no pool to wait for; a 40 x 40 one uses both cores
    assert auto_workers(cells(5), 25, cores=2) == 1
    assert auto_workers(cells(40), 1600, cores=2) == 2
    assert auto_workers(None, 10, cores=2) == 1 and auto_workers(None, 1000, cores=2) == 2
    table = core.sweep([0.1, 0.5], [0.2, 0.6], periods=4)
    assert table.attrs["backend"] == "serial" and table.attrs["workers"] == 1
    with pytest.raises(ValueError, match="workers must be"):
        core.sweep(0.1, 0.1, workers=0, periods=2)
    with pytest.raises(ValueError, match="not both"):
        core.sweep(0.1, 0.1, workers=1, max_workers=1, periods=2)


def test_a_caller_executor_is_used_and_left_running(serial_table):
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(2) as pool:
        table = core.sweep(FT, W, scheduler=pool, **OPTIONS)
        assert pool.submit(lambda: 1).result() == 1
    pd.testing.assert_frame_equal(_without_runtime(table), _without_runtime(serial_table))


def test_tables_survive_csv_and_parquet(serial_table, tmp_path):
    serial_table.to_csv(tmp_path / "t.csv", index=False)
    back = normalise_table(pd.read_csv(tmp_path / "t.csv"))
    pd.testing.assert_frame_equal(back, serial_table, check_exact=True)
    serial_table.to_parquet(tmp_path / "t.parquet", index=False)
    pd.testing.assert_frame_equal(normalise_table(pd.read_parquet(tmp_path / "t.parquet")), serial_table)


def test_progress_on_rows_and_cancel():
    seen, chunks, stop = [], [], threading.Event()

    def progress(done, total):
        seen.append((done, total))
        if done >= 2:
            stop.set()

    points = sweep_grid([0.1, 0.2], [0.1, 0.2], periods=2)
    # RuntimeError: under pytest's importlib mode core.sweep may be loaded twice, with two SweepCancelled classes
    with pytest.raises(RuntimeError, match="cancelled") as info:
        core.run_points(points, "serial", progress=progress, on_rows=chunks.append, cancel=stop, chunksize=1)
    assert type(info.value).__name__ == "SweepCancelled"
    assert seen[0] == (0, 4) and seen[-1] == (2, 4)
    assert len(info.value.table) == 2 and [len(c) for c in chunks] == [1, 1]
    with pytest.raises(RuntimeError, match="timed out"):
        core.sweep([0.1, 0.2], 0.1, scheduler="serial", timeout=1e-9, periods=2)
    with pytest.raises(ValueError, match="cancel must be"):
        core.sweep(0.1, 0.1, scheduler="serial", cancel=1)


def test_progress_bar_draws_lines():
    log = io.StringIO()
    bar = ProgressBar(log, label="runs")
    for done in range(11):
        bar(done, 10)
    lines = log.getvalue().splitlines()
    assert len(lines) == 11 and lines[-1].startswith("[" + "#" * 30 + "] 10/10 runs 100%")


# --------------------------------------------------------------------------
# the verdict
# --------------------------------------------------------------------------
def test_a_run_too_short_to_tell_is_undetermined_not_misnamed():
    one = core.simulate_cycles(0.1, 0.2, periods=1)  # a clear shakedown case, far below eq 35
    assert one.regime == "undetermined" and "1 period" in one.regime_reason
    two = core.simulate_cycles(0.1, 0.2, periods=2)
    assert two.regime == "undetermined" and "too few" in two.regime_reason and two.periods_to_decide == 2
    ten = core.simulate_cycles(0.1, 0.2, periods=10)
    assert ten.regime == "shakedown" and "fell to" in ten.regime_reason
    settled = core.simulate_cycles(0.6, 0.5, periods=5, detect_periodic=False)  # far above eq 35: a constant
    assert settled.regime == "ratcheting" and "tends to a constant" in settled.regime_reason
    assert settled.D_inf == pytest.approx(settled.increment_per_period[-1], abs=10 * settled.D_inf_error)
    repeated = core.simulate_cycles(0.6, 0.5, periods=10)
    assert repeated.regime == "ratcheting" and "repeats" in repeated.regime_reason
    table = core.sweep(0.1, 0.2, workers=1, periods=[1, 10])
    assert list(table["regime"]) == ["undetermined", "shakedown"]
    assert list(table["regime_reason"]) == [one.regime_reason, ten.regime_reason]
    assert one.summary()["regime_reason"] == one.regime_reason


# --------------------------------------------------------------------------
# the numerical limit
# --------------------------------------------------------------------------
def test_the_limit_search_starts_from_the_whole_range_not_eq35():
    res = core.numerical_limit(0.5, tol=0.01, periods=6)
    assert (res.start_lo, res.start_hi) == (0.0, 0.999)
    runs = res.runs
    assert list(runs["w"][:2]) == [0.0, 0.999]
    # each run is placed by bisection of the bracket so far: a dyadic point of [0, 0.999]
    k = runs["w"] / 0.999 * 2 ** 10
    np.testing.assert_array_equal(k, np.round(k))
    assert res.converged and res.w_ratcheting - res.w_shakedown <= 2 * 0.01
    assert res.eq35_inside == (res.w_shakedown <= res.w_limit_eq35 <= res.w_ratcheting)
    assert res.eq35_inside  # measured: eq 35 lies in the final bracket
    # an undetermined run is repeated with twice the periods at the same w
    undetermined = runs.index[runs["regime"] == "undetermined"]
    for i in undetermined:
        assert runs["w"][i + 1] == runs["w"][i] and runs["periods"][i + 1] == 2 * runs["periods"][i]
    assert res.periods == runs["periods"].max()



TOL = 2e-3


def test_numerical_w_limit_is_eq35_within_tolerance():
    ft = 0.5
    w = core.numerical_w_limit(ft, tol=TOL)
    # measured: the numerical limit lies 0 to 2e-4 above eq 35 at the default resolution
    assert abs(w - float(core.w_limit(ft))) <= TOL + 1e-3


def test_limit_curve_brackets_eq35_on_dask(dask_client):
    curve = core.numerical_limit_curve([0.2, 0.5, 0.8], tol=TOL, scheduler=dask_client)
    assert curve["converged"].all(), curve["message"]
    np.testing.assert_allclose(curve["w_limit"], core.w_limit(curve["ft"].to_numpy()), atol=TOL + 1e-3,
                               err_msg="numerical shakedown limit against eq 35")
    assert (curve["w_ratcheting"] - curve["w_shakedown"] <= 2 * TOL + 1e-12).all()
    # the same search in this process gives the same numbers
    single = core.numerical_limit(0.5, tol=TOL)
    assert single.w_limit == curve["w_limit"][1]
    runs = single.runs
    assert (runs.loc[runs["w"] <= single.w_shakedown, "regime"] == "shakedown").all()
    assert (runs.loc[runs["w"] >= single.w_ratcheting, "regime"] == "ratcheting").all()
    assert single.difference == pytest.approx(single.w_limit - single.w_limit_eq35)


@pytest.mark.parametrize("kwargs, match", [
    (dict(ft=0.0), "ft must be in"), (dict(ft=1.0), "ft must be in"), (dict(ft=float("nan")), "ft must be"),
    (dict(ft=0.5, tol=0.0), "tol must be"), (dict(ft=0.5, periods=[5, 6]), "single value"),
])
def test_limit_refuses_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        core.numerical_limit(**kwargs)


# --------------------------------------------------------------------------
# the shipped map
# --------------------------------------------------------------------------
def test_default_map_loads_and_matches_eq35():
    m = core.load_default_map()
    assert len(m) == 1600 and m["error"].isna().all()
    grid = np.linspace(0.02, 0.95, 40)
    np.testing.assert_allclose(np.unique(m["ft"]), grid, atol=1e-12)  # the CLI rounds to 12 digits
    np.testing.assert_allclose(np.unique(m["w"]), grid, atol=1e-12)
    assert set(m["kernel"]) == {"plane"} and set(m["periods"]) == {10}
    margin = m["ft"] - core.ft_limit(m["w"].to_numpy())
    far = np.abs(margin) > 0.01
    expected = np.where(margin < 0, "shakedown", "ratcheting")
    assert (m["regime"][far] == expected[far]).all()
    # undetermined only near the limit, where 10 periods are too few to tell
    assert (np.abs(margin[m["regime"] == "undetermined"]) < 0.05).all()
    module = importlib.import_module("core.maps.tables")
    assert list(m.columns) == list(module.INPUT_COLUMNS) + list(module.RESULT_COLUMNS)


def test_the_readme_maps_snippet_runs_as_a_file():
    """The maps snippet of the user guide (docs/guide/cli.md, once in the README). Saved as a file, the snippet's work runs only under its __main__ guard (spawned workers re-import it)."""
    import ast
    import pathlib
    import re

    page = (pathlib.Path(__file__).parents[1] / "docs" / "guide" / "cli.md").read_text(encoding="utf-8")
    section = page[page.index("# Maps of the (ft, w) plane"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    tree = ast.parse(code)
    *imports, guard = tree.body
    assert all(isinstance(node, (ast.Import, ast.ImportFrom)) for node in imports)
    assert isinstance(guard, ast.If) and ast.unparse(guard.test) == "__name__ == '__main__'"
    called = {ast.unparse(n.func) for n in ast.walk(guard) if isinstance(n, ast.Call)}
    assert {"core.sweep", "core.numerical_limit_curve", "core.load_default_map"} <= called
    compile(code, "maps.py", "exec")


def test_the_body_is_an_axis_of_a_sweep():
    """core.sweep(ft, w, body="sphere") maps the point contact (issue 13, item 5): below the sphere's exact
    limit (ft_lim(0.3) = 0.5635) it shakes down, above it it ratchets."""
    import core

    table = core.sweep([0.3, 0.6], [0.3], body="sphere", dx=0.25, periods=8, workers=1)
    assert list(table["body"]) == ["sphere", "sphere"] and table["error"].isna().all()
    assert list(table["regime"]) == ["shakedown", "ratcheting"]
