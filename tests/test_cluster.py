"""Sweeps on a Dask cluster the way the README starts one: `dask scheduler` and `dask worker` processes on loopback.

The tables from the CLI (``--scheduler``) and from the API (an address, a
``Client``, a ``LocalCluster``) must equal the local one in every column but
``runtime``.
"""

import os
import shutil
import signal
import socket
import subprocess
import sys
import time

import distributed
import pandas as pd
import pytest

import core
from core.maps.tables import read_table

FT, W = [0.1, 0.6], [0.2, 0.7]
OPTIONS = dict(periods=6)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _dask_command(*args):
    exe = shutil.which("dask")
    return [exe, *args] if exe else [sys.executable, "-m", "distributed.cli.dask_" + args[0], *args[1:]]


def _shakedown_command():
    exe = shutil.which("shakedown")
    return [exe] if exe else [sys.executable, "-m", "core.command.cli"]


@pytest.fixture(scope="module")
def cluster_address(tmp_path_factory):
    """A scheduler and a worker (2 processes, 1 thread each) as subprocesses, as the README starts them."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = tmp_path_factory.mktemp("dask")
    procs = []
    try:
        with open(logs / "scheduler.log", "w") as log:
            procs.append(subprocess.Popen(_dask_command("scheduler", "--host", "127.0.0.1", "--port", str(port),
                                                        "--dashboard-address", ":0"),
                                          stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
        with open(logs / "worker.log", "w") as log:
            procs.append(subprocess.Popen(_dask_command("worker", address, "--nworkers", "2", "--nthreads", "1",
                                                        "--no-dashboard", "--host", "127.0.0.1"),
                                          stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
        deadline = time.monotonic() + 120
        while True:
            try:
                with distributed.Client(address, timeout="5s", set_as_default=False) as client:
                    client.wait_for_workers(2, timeout=max(1.0, deadline - time.monotonic()))
                    break
            except (OSError, TimeoutError):
                if time.monotonic() > deadline or any(p.poll() is not None for p in procs):
                    raise RuntimeError("the Dask cluster did not start: "
                                       + (logs / "scheduler.log").read_text()[-2000:]
                                       + (logs / "worker.log").read_text()[-2000:])
                time.sleep(0.5)
        yield address
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGTERM)
        for p in reversed(procs):
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()


@pytest.fixture(scope="module")
def local_table():
    return core.sweep(FT, W, workers=1, **OPTIONS)


def _same(table, local):
    pd.testing.assert_frame_equal(table.drop(columns="runtime"), local.drop(columns="runtime"))


def test_cli_sweep_on_the_cluster_equals_the_local_one(cluster_address, local_table, tmp_path):
    out = tmp_path / "map.csv"
    done = subprocess.run([*_shakedown_command(), "sweep", "--ft", "0.1,0.6", "--w", "0.2,0.7", "--periods", "6",
                           "--out", str(out), "--scheduler", cluster_address, "--no-progress"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    _same(read_table(out), local_table)


def test_api_on_the_cluster_by_address_and_client_equals_the_local_one(cluster_address, local_table):
    by_address = core.sweep(FT, W, scheduler=cluster_address, **OPTIONS)
    assert by_address.attrs["backend"].startswith(f"dask({cluster_address}") and by_address.attrs["workers"] == 2
    _same(by_address, local_table)
    # a Client that is not the default one (the case that failed with "No clients found")
    with distributed.Client(cluster_address, set_as_default=False) as client:
        _same(core.sweep(FT, W, scheduler=client, **OPTIONS), local_table)
        curve = core.numerical_limit_curve([0.5], tol=0.01, scheduler=client, periods=6)
    assert curve["converged"].all() and curve["eq35_inside"].all(), curve


def test_api_on_a_local_cluster_equals_the_local_one(local_table):
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        _same(core.sweep(FT, W, scheduler=cluster, **OPTIONS), local_table)
