"""Export a :class:`~core.result.CycleResult` as tidy tables, CSV or JSON, with its parameters.

Three tables describe a run:

* ``"steps"``: one row per step (period, contact centre, rigid-body
  displacement, ``U/U0`` for the strip kernel, dissipation);
* ``"periods"``: one row per rocking period (its displacement increment);
* ``"final"``: one row per element (final traction, lowest pressure of the last
  period, zone).

Columns carry their unit in their name (``_a``: in the half-width a,
``_muP_Estar``: in mu P/E*, ``_mu_p0``: in mu p0, ``_m``/``_Pa``: SI). Physical
columns are added when a :class:`~core.contact.Contact` is given. The CSV form
starts with ``# name = value`` lines holding every parameter of the run (read it
back with ``pandas.read_csv(..., comment="#")``).
"""

from __future__ import annotations

import io
import json
import math

import numpy as np
import pandas as pd

from .contact import Contact
from .result import CycleResult
from .states import STATE_NAMES, ZONE_NAMES

__all__ = ["TABLES", "ZONE_NAMES", "parameters", "result_table", "to_csv", "to_json"]

#: Names of the tables of a run.
TABLES = ("steps", "periods", "final")


def _check(result, contact):
    if not isinstance(result, CycleResult):
        raise ValueError(f"result must be a core.CycleResult, got {type(result).__name__}")
    if contact is not None and not isinstance(contact, Contact):
        raise ValueError(f"contact must be a core.Contact or None, got {type(contact).__name__}")


def _plain(v):
    """A JSON-safe scalar: numpy scalars to Python, non-finite floats to None."""
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def parameters(result: CycleResult, contact: Contact | None = None) -> dict:
    """Every input and scalar figure of a run, as a flat dict.

    Parameters
    ----------
    result : CycleResult
        The run.
    contact : Contact, optional
        The contact in physical units; adds its inputs and derived quantities
        (prefixed ``contact_``, SI units) and the unit conversions.

    Returns
    -------
    dict
        ``result.summary()`` plus, with a contact, ``contact_*`` and the units
        ``a_m``, ``mu_p0_Pa``, ``muP_Estar_m``.

    Raises
    ------
    ValueError
        If ``result`` or ``contact`` has the wrong type.
    """
    _check(result, contact)
    out = dict(result.summary())
    if contact is not None:
        out.update({f"contact_{k}": v for k, v in contact.summary().items()})
        out.update(a_m=contact.a, mu_p0_Pa=contact.traction_unit, muP_Estar_m=contact.displacement_unit)
    return {k: (v.item() if isinstance(v, np.generic) else v) for k, v in out.items()}


def result_table(result: CycleResult, table: str = "steps", contact: Contact | None = None) -> pd.DataFrame:
    """One table of a run (see the module docstring for the columns).

    Parameters
    ----------
    result : CycleResult
        The run.
    table : {"steps", "periods", "final"}
        Which table.
    contact : Contact, optional
        Adds columns in SI units.

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    ValueError
        If ``table`` is not one of :data:`TABLES`, or an argument has the wrong type.

    Examples
    --------
    >>> import core
    >>> from core.export import result_table
    >>> r = core.simulate_cycles(0.2, 0.3, periods=2)
    >>> list(result_table(r, "periods").columns)
    ['period', 'increment_muP_Estar']
    """
    _check(result, contact)
    if table not in TABLES:
        raise ValueError(f"table must be one of {TABLES}, got {table!r}")
    u_unit = None if contact is None else contact.displacement_unit
    if table == "steps":
        df = pd.DataFrame({
            "step": np.arange(result.xc.size),
            "period": result.period,
            "xc_a": result.xc,
            "displacement_muP_Estar": result.displacement,
            "dissipation": result.dissipation,
        })
        if result.u is not None:
            df.insert(4, "u_U_over_U0", result.u)
        if contact is not None:
            df["xc_m"] = result.xc * contact.a
            df["displacement_m"] = result.displacement * u_unit
        return df
    if table == "periods":
        inc = result.increment_per_period
        df = pd.DataFrame({"period": np.arange(inc.size), "increment_muP_Estar": inc})
        if result.u0 is not None:
            df["increment_U_over_U0"] = inc / result.u0
        if contact is not None:
            df["increment_m"] = inc * u_unit
        return df
    zones = result.final_zones
    df = pd.DataFrame({
        "x_a": result.x,
        "traction_mu_p0": result.traction[-1],
        "lowest_pressure_p0": result.lowest_pressure,
        "zone": zones,
        "zone_name": np.asarray(ZONE_NAMES)[zones],
        "state": np.asarray(STATE_NAMES)[result.state[-1]],
    })
    if contact is not None:
        df["x_m"] = result.x * contact.a
        df["traction_Pa"] = result.traction[-1] * contact.traction_unit
    return df


def to_csv(result: CycleResult, table: str = "steps", contact: Contact | None = None) -> str:
    """One table of a run as CSV text, preceded by ``# name = value`` lines of all its parameters.

    Parameters
    ----------
    result, table, contact :
        See :func:`result_table`.

    Returns
    -------
    str
        CSV; read it back with ``pandas.read_csv(io.StringIO(text), comment="#")``.
    """
    df = result_table(result, table, contact)
    header = "".join(f"# {k} = {v}\n" for k, v in parameters(result, contact).items())
    buf = io.StringIO()
    buf.write(f"# shakedown explorer run, table: {table}\n")
    buf.write(header)
    df.to_csv(buf, index=False, float_format="%.10g")
    return buf.getvalue()


def to_json(result: CycleResult, contact: Contact | None = None) -> str:
    """The whole run as JSON: ``{"parameters": {...}, "steps": {...}, "periods": {...}, "final": {...}}``.

    Each table is stored column-wise (``{column: [values]}``); non-finite
    numbers become ``null``.

    Parameters
    ----------
    result, contact :
        See :func:`result_table`.

    Returns
    -------
    str
    """
    out = {"parameters": {k: _plain(v) for k, v in parameters(result, contact).items()}}
    for table in TABLES:
        df = result_table(result, table, contact)
        out[table] = {c: [_plain(v) for v in df[c].tolist()] for c in df.columns}
    return json.dumps(out, allow_nan=False)
