"""Tests of core.api.export: tables, CSV with a parameter header, JSON."""

import io
import json

import numpy as np
import pandas as pd
import pytest

import core
from core.api.export import TABLES, parameters, result_table, to_csv, to_json


@pytest.fixture(scope="module")
def run():
    contact = core.PAPER_SIMULATION.replace(ft=0.3, w=0.5)
    return core.simulate_contact(contact, periods=6), contact


@pytest.fixture(scope="module")
def plane_run():
    return core.simulate_cycles(0.6, 0.6, periods=3)


def test_steps_table_columns_and_values(run):
    result, contact = run
    df = result_table(result, "steps", contact)
    assert list(df.columns) == ["step", "period", "xc_a", "displacement_muP_Estar", "u_U_over_U0",
                                "dissipation", "xc_m", "displacement_m"]
    assert len(df) == result.xc.size
    np.testing.assert_allclose(df["u_U_over_U0"], result.displacement / result.u0, rtol=1e-15)
    np.testing.assert_allclose(df["displacement_m"], result.displacement * contact.displacement_unit, rtol=1e-15)


def test_periods_table_sums_to_the_displacement_after_loading(run):
    result, _ = run
    df = result_table(result, "periods")
    assert list(df["period"]) == list(range(result.periods))
    loaded = result.displacement[result.period == -1][-1]
    np.testing.assert_allclose(df["increment_muP_Estar"].sum(), result.displacement[-1] - loaded, atol=1e-12)


def test_final_table_zones_and_traction(run):
    result, contact = run
    df = result_table(result, "final", contact)
    assert len(df) == result.x.size
    assert set(df["zone_name"]) <= {"no contact", "stick", "slip", "zero traction"}
    np.testing.assert_allclose(df["traction_Pa"], result.traction[-1] * contact.traction_unit, rtol=1e-15)
    # the load balance survives the export
    np.testing.assert_allclose(df["traction_mu_p0"].sum() * result.dx, 0.3 * np.pi / 2, rtol=1e-8)


def test_plane_kernel_has_no_u_columns(plane_run):
    assert "u_U_over_U0" not in result_table(plane_run, "steps").columns
    assert "increment_U_over_U0" not in result_table(plane_run, "periods").columns


@pytest.mark.parametrize("table", TABLES)
def test_csv_round_trip_with_parameter_header(run, table):
    result, contact = run
    text = to_csv(result, table, contact)
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert any(line.startswith("# ft = 0.3") for line in header)
    assert any(line.startswith("# contact_mu = 0.58") for line in header)
    assert f"# regime = {result.regime}" in header
    assert "# contact_E1 = inf" in header
    df = pd.read_csv(io.StringIO(text), comment="#")
    expected = result_table(result, table, contact)
    assert list(df.columns) == list(expected.columns)
    num = expected.select_dtypes("number").columns
    np.testing.assert_allclose(df[num].to_numpy(float), expected[num].to_numpy(float), rtol=1e-9, atol=1e-300)


def test_json_holds_every_table_and_is_strict(run):
    result, contact = run
    data = json.loads(to_json(result, contact))
    assert set(data) == {"parameters", *TABLES}
    assert data["parameters"]["regime"] == result.regime
    assert data["parameters"]["a_m"] == pytest.approx(contact.a)
    assert len(data["steps"]["displacement_muP_Estar"]) == result.xc.size
    assert data["periods"]["increment_muP_Estar"] == pytest.approx(result.increment_per_period.tolist())


def test_parameters_without_contact(plane_run):
    p = parameters(plane_run)
    assert p["ft"] == 0.6 and p["regime"] == plane_run.regime
    assert not any(k.startswith("contact_") for k in p)


@pytest.mark.parametrize("kwargs, name", [
    (dict(result="nope"), "result"),
    (dict(table="nope"), "table"),
    (dict(contact="nope"), "contact"),
])
def test_bad_arguments_name_the_parameter(plane_run, kwargs, name):
    args = dict(result=plane_run, table="steps", contact=None) | kwargs
    with pytest.raises(ValueError, match=name):
        result_table(args["result"], args["table"], args["contact"])


def test_final_table_writes_each_bodys_own_closure_only():
    """Issue 28: the 'final' table wrote the cylinder's closure traction (eqs 22-30) for every line body. The
    cylinder's column is its closure (equal to core.shakedown_traction); the punch has none (NaN), nor has a
    history other than the paper's rocking."""
    cyl = core.simulate_cycles(0.2, 0.3, periods=2, dx=0.05)
    df = result_table(cyl, "final")
    np.testing.assert_allclose(df["closure_traction_mu_p0"], core.shakedown_traction(cyl.x, 0.2, 0.3), rtol=1e-15)
    assert np.isfinite(df["closure_traction_mu_p0"]).any()
    punch = core.simulate_cycles(0.2, 0.3, periods=2, dx=0.05, body="punch")
    assert result_table(punch, "final")["closure_traction_mu_p0"].isna().all()
    tangential = core.simulate_cycles(0.2, 0.3, periods=2, dx=0.05, history="tangential")
    assert result_table(tangential, "final")["closure_traction_mu_p0"].isna().all()
