"""Export a run (a :class:`~core.records.result.CycleResult`, on a line of elements: the cylinder, the punch; or on
a patch: a sphere, an ellipsoid, a height map) as tidy tables, CSV or JSON, with its parameters.

Three tables describe a run:

* ``"steps"``: one row per step (period, contact centre, rigid-body
  displacement, ``U/U0`` for the strip kernel, dissipation);
* ``"periods"``: one row per rocking period (its displacement increment and the
  energy dissipated by friction in it, ``CycleResult.dissipation_per_period``:
  ``_mu2P2_Estar`` in mu^2 P^2/E* per unit length, a point contact's
  ``_mu2Fn2_Estar_a`` in mu^2 Fn^2/(E* a); with a contact also in J/m or J);
* ``"final"``: one row per element (final traction, lowest pressure of the last
  period, zone, and the body's closed-form shaken-down traction beside the
  numerical one: the cylinder's closure, eqs 22-30, under the paper's rocking;
  NaN for a body without one, such as the punch, or another history); for a point contact, one row per element of the line
  ``y = 0`` (both traction components and the state).

Periods are numbered from ``first_period`` (0 by default; the loading is
``first_period - 1``): the explorer numbers them from 1, as its cycle player.
Point contacts are in their own units: lengths in ``a``, tractions in
``mu p0``, displacements in ``mu Fn/(E* a)`` (suffix ``_muFn_Estar_a``).

Columns carry their unit in their name (``_a``: in the half-width a,
``_muP_Estar``: in mu P/E*, ``_mu_p0``: in mu p0, ``_m``/``_Pa``: SI). Physical
columns are added when a :class:`~core.api.contact.Contact` is given. The CSV form
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
from ..records.result import CycleResult
from ..base.states import STATE_NAMES, ZONE_NAMES

__all__ = ["TABLES", "ZONE_NAMES", "POINT_STATE_NAMES", "parameters", "result_table", "to_csv", "to_json"]

#: Names of the tables of a run.
TABLES = ("steps", "periods", "final")
#: Names of a point contact's element states (``CycleResult.state`` on a patch's cut), by code.
POINT_STATE_NAMES = ("released", "stick", "slip +x", "slip -x")


def _check(result, contact, first_period=0):
    if not isinstance(result, CycleResult):
        raise ValueError(f"result must be a core.CycleResult, got {type(result).__name__}")
    if contact is not None and not isinstance(contact, Contact):
        raise ValueError(f"contact must be a core.Contact or None, got {type(contact).__name__}")
    if contact is not None and contact.is_point != result.is_patch:
        raise ValueError(f"contact must be a {'point' if result.is_patch else 'line'} core.Contact or None for "
                         f"a {'point' if result.is_patch else 'line'}-contact run, got a "
                         f"{'point' if contact.is_point else 'line'} contact")
    if isinstance(first_period, bool) or not isinstance(first_period, (int, np.integer)) or not 0 <= first_period <= 1:
        raise ValueError(f"first_period must be 0 or 1, got {first_period!r}")


def _contact_summary(contact) -> dict:
    """The inputs and derived quantities of a contact (SI units)."""
    return dict(contact.summary())


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
        The contact in physical units (of the run's kind); adds its inputs and derived quantities
        (prefixed ``contact_``, SI units) and the unit conversions.

    Returns
    -------
    dict
        ``result.summary()`` plus, with a contact, ``contact_*`` and the units
        ``a_m``, ``mu_p0_Pa``, ``muP_Estar_m`` (a point contact: ``muFn_Estar_a_m``).

    Raises
    ------
    ValueError
        If ``result`` or ``contact`` has the wrong type.
    """
    _check(result, contact)
    out = dict(result.summary())
    if contact is not None:
        out.update({f"contact_{k}": v for k, v in _contact_summary(contact).items()})
        unit = "muFn_Estar_a_m" if result.is_patch else "muP_Estar_m"
        energy = "mu2Fn2_Estar_a_J" if result.is_patch else "mu2P2_Estar_J_per_m"
        out.update({"a_m": contact.a, "mu_p0_Pa": contact.traction_unit, unit: contact.displacement_unit,
                    energy: contact.energy_unit})
    return {k: (v.item() if isinstance(v, np.generic) else v) for k, v in out.items()}


def result_table(result, table: str = "steps", contact=None, first_period: int = 0) -> pd.DataFrame:
    """One table of a run (see the module docstring for the columns).

    Parameters
    ----------
    result : CycleResult
        The run.
    table : {"steps", "periods", "final"}
        Which table.
    contact : Contact, optional
        The run's contact (of the same kind): adds columns in SI units.
    first_period : {0, 1}
        The number of the first rocking period (the loading is ``first_period - 1``).

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    ValueError
        If ``table`` is not one of :data:`TABLES`, ``first_period`` is not 0 or 1, or an
        argument has the wrong type.

    Examples
    --------
    >>> import core
    >>> from core.api.export import result_table
    >>> r = core.simulate_cycles(0.2, 0.3, periods=2)
    >>> list(result_table(r, "periods").columns)
    ['period', 'increment_muP_Estar', 'energy_mu2P2_Estar']
    >>> list(result_table(r, "periods", first_period=1)["period"])
    [1, 2]
    """
    _check(result, contact, first_period)
    if table not in TABLES:
        raise ValueError(f"table must be one of {TABLES}, got {table!r}")
    if result.is_patch:
        return _point_table(result, table, contact, first_period)
    u_unit = None if contact is None else contact.displacement_unit
    if table == "steps":
        df = pd.DataFrame({
            "step": np.arange(result.xc.size),
            "period": result.period + first_period,
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
        energy = result.dissipation_per_period
        df = pd.DataFrame({"period": np.arange(inc.size) + first_period, "increment_muP_Estar": inc})
        if result.u0 is not None:
            df["increment_U_over_U0"] = inc / result.u0
        df["energy_mu2P2_Estar"] = energy
        if contact is not None:
            df["increment_m"] = inc * u_unit
            df["energy_J_per_m"] = energy * contact.energy_unit
        return df
    zones = result.final_zones
    ft, w = float(result.params.get("ft", math.nan)), float(result.params.get("w", math.nan))
    # the body's own closed form of the shaken-down traction (the cylinder's eqs 22-30), under the paper's rocking
    # at constant loads only; NaN for a body without one (the punch) or another history
    own = getattr(result.body, "shakedown_traction", None)
    rocking = result.params.get("history", "rocking") == "rocking"
    closure = (own(result.x, ft, w) if own is not None and rocking and math.isfinite(ft) and math.isfinite(w)
               else np.full(result.x.size, math.nan))
    df = pd.DataFrame({
        "x_a": result.x,
        "traction_mu_p0": result.traction[-1],
        "lowest_pressure_p0": result.lowest_pressure,
        "zone": zones,
        "zone_name": np.asarray(ZONE_NAMES)[zones],
        "state": np.asarray(STATE_NAMES)[result.state[-1]],
        "closure_traction_mu_p0": closure,  # the body's closed-form shakedown traction; NaN past ft_lim or without one
    })
    if contact is not None:
        df["x_m"] = result.x * contact.a
        df["traction_Pa"] = result.traction[-1] * contact.traction_unit
    return df


def _point_table(result: CycleResult, table: str, contact, first_period: int) -> pd.DataFrame:
    """:func:`result_table` of a point-contact run."""
    u_unit = None if contact is None else contact.displacement_unit
    if table == "steps":
        along = result.displacement @ np.array([math.cos(result.angle), math.sin(result.angle)])
        df = pd.DataFrame({
            "step": np.arange(result.xc.size),
            "period": result.period + first_period,
            "xc_a": result.xc,
            "ux_muFn_Estar_a": result.displacement[:, 0],
            "uy_muFn_Estar_a": result.displacement[:, 1],
            "u_along_Ft_muFn_Estar_a": along,
            "dissipation": result.dissipation,
        })
        if contact is not None:
            df["xc_m"] = result.xc * contact.a
            df["u_along_Ft_m"] = along * u_unit
        return df
    if table == "periods":
        inc = result.increment_per_period
        energy = result.dissipation_per_period
        df = pd.DataFrame({"period": np.arange(inc.size) + first_period, "increment_muFn_Estar_a": inc,
                           "energy_mu2Fn2_Estar_a": energy})
        if contact is not None:
            df["increment_m"] = inc * u_unit
            df["energy_J"] = energy * contact.energy_unit
        return df
    q, state = result.traction_cut[-1], result.state_cut[-1].astype(int)
    df = pd.DataFrame({
        "x_a": result.x,
        "qx_mu_p0": q[0],
        "qy_mu_p0": q[1],
        "lowest_pressure_p0": result.lowest_pressure[result.cut_row],
        "state_code": state,
        "state": np.asarray(POINT_STATE_NAMES)[state],
    })
    if contact is not None:
        df["x_m"] = result.x * contact.a
        df["qx_Pa"] = q[0] * contact.traction_unit
        df["qy_Pa"] = q[1] * contact.traction_unit
    return df


def to_csv(result, table: str = "steps", contact=None, first_period: int = 0) -> str:
    """One table of a run as CSV text, preceded by ``# name = value`` lines of all its parameters.

    Parameters
    ----------
    result, table, contact, first_period :
        See :func:`result_table`.

    Returns
    -------
    str
        CSV; read it back with ``pandas.read_csv(io.StringIO(text), comment="#")``.
    """
    df = result_table(result, table, contact, first_period)
    header = "".join(f"# {k} = {v}\n" for k, v in parameters(result, contact).items())
    buf = io.StringIO()
    buf.write(f"# shakedown explorer run, table: {table}\n")
    if first_period:
        buf.write(f"# periods numbered from {first_period}: the loading is period {first_period - 1}\n")
    buf.write(header)
    df.to_csv(buf, index=False, float_format="%.10g")
    return buf.getvalue()


def to_json(result, contact=None, first_period: int = 0) -> str:
    """The whole run as JSON: ``{"parameters": {...}, "steps": {...}, "periods": {...}, "final": {...}}``.

    Each table is stored column-wise (``{column: [values]}``); non-finite
    numbers become ``null``.

    Parameters
    ----------
    result, contact, first_period :
        See :func:`result_table`.

    Returns
    -------
    str
    """
    out = {"parameters": {k: _plain(v) for k, v in parameters(result, contact).items()}}
    for table in TABLES:
        df = result_table(result, table, contact, first_period)
        out[table] = {c: [_plain(v) for v in df[c].tolist()] for c in df.columns}
    return json.dumps(out, allow_nan=False)
