"""Sweep tables: their columns and dtypes, one row per run, files that a sweep resumes, the shipped map.

A sweep table has one row per run of :func:`core.simulate_cycles`: the inputs
(:data:`INPUT_COLUMNS` and any further option), then :data:`RESULT_COLUMNS`.
:func:`normalise_table` gives any such table (fresh, or read back from CSV or
Parquet) the same dtypes, so tables from every execution path compare equal.

:class:`TableFile` is a table on disk that a sweep fills and resumes: finished
rows go to a journal (``OUT.partial.csv``) as they come in, the complete table
replaces ``OUT`` atomically at the end, and a rerun skips the rows already in
``OUT`` or the journal. It refuses to mix grids: a file holding rows that are
not part of the new sweep (other values, other options) is not appended to.
"""

from __future__ import annotations

import math
import os
import time
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["INPUT_COLUMNS", "RESULT_COLUMNS", "REGIMES", "DEFAULT_MAP", "normalise_table", "tidy", "input_columns",
           "run_point", "run_chunk", "failed_row", "TableFile", "CSV_FLOAT_FORMAT", "read_table", "write_table", "atomic_write",
           "load_default_map"]

#: Inputs that every sweep table has as columns (further options add theirs).
INPUT_COLUMNS = ("ft", "w", "periods", "dx", "kernel", "shape")
#: Result columns of a sweep table, in order.
RESULT_COLUMNS = ("regime", "regime_reason", "increment", "D_inf", "D_inf_error", "decay_ratio", "periods_to_decide",
                  "energy", "E_inf", "E_inf_error", "stick_halfwidth", "shakedown_period", "runtime", "max_kkt_residual", "max_iterations", "elements",
                  "steps", "periodic_from", "error")
#: Values of the ``regime`` column.
REGIMES = ("shakedown", "cyclic slip", "ratcheting", "undetermined", "error")
#: How CSV files write floats: 15 significant digits, so that round-off noise of the last digits
#: (``0.5750000000000001``, ``0.30000000000000004``) does not reach the file.
CSV_FLOAT_FORMAT = "%.15g"
#: File name of the shipped map under ``core/data`` (see :func:`load_default_map`).
DEFAULT_MAP = "default_map.csv.gz"
_INT_COLUMNS = ("periods", "load_steps", "shakedown_period", "max_iterations", "elements", "steps",
                "periodic_from", "periods_to_decide")
_STR_COLUMNS = ("kernel", "shape", "body", "history", "regime", "regime_reason", "error")
_BOOL_COLUMNS = ("detect_periodic",)


# --------------------------------------------------------------------------
# columns and dtypes
# --------------------------------------------------------------------------
def normalise_table(df: pd.DataFrame) -> pd.DataFrame:
    """Give a sweep table its canonical dtypes: nullable ints, str for text, float64 otherwise.

    Used on fresh tables and on tables read back from CSV or Parquet, so that
    they compare equal with :func:`pandas.testing.assert_frame_equal`.
    Columns that are neither known integers, text nor flags become float64
    when all their values are numbers, and text otherwise (an option such as
    a body name).
    """
    df = df.copy()
    for col in df.columns:
        if col in _INT_COLUMNS:
            df[col] = pd.to_numeric(df[col]).astype("Int64")
        elif col in _STR_COLUMNS:
            df[col] = df[col].astype("str")
        elif col in _BOOL_COLUMNS:
            df[col] = df[col].astype(bool)
        else:
            numbers = pd.to_numeric(df[col], errors="coerce")
            text = df[col].notna() & numbers.isna()
            df[col] = df[col].astype("str") if text.any() else numbers.astype("float64")
    return df.reset_index(drop=True)


def tidy(rows: list[dict], columns) -> pd.DataFrame:
    """A table with fixed columns and dtypes from a list of row dicts."""
    return normalise_table(pd.DataFrame(rows, columns=list(columns)))


def input_columns(points: list[dict]) -> list[str]:
    """The input columns of a table of these points: :data:`INPUT_COLUMNS`, then every further option."""
    names = list(INPUT_COLUMNS)
    for p in points:
        names += [k for k in p if k not in names]
    return names


# --------------------------------------------------------------------------
# one run, one chunk (these run in the workers)
# --------------------------------------------------------------------------
def failed_row(message: str, runtime: float = float("nan")) -> dict:
    """The result columns of a run that failed with ``message``."""
    return {"regime": "error", "regime_reason": None, "increment": float("nan"), "D_inf": float("nan"),
            "D_inf_error": float("nan"), "decay_ratio": float("nan"), "periods_to_decide": None,
            "energy": float("nan"), "E_inf": float("nan"), "E_inf_error": float("nan"), "stick_halfwidth": float("nan"),
            "shakedown_period": None, "runtime": runtime, "max_kkt_residual": float("nan"),
            "max_iterations": None, "elements": None, "steps": None, "periodic_from": None,
            "error": message[:500]}


def run_point(point: dict) -> dict:
    """Run one point; return its result columns. Never raises: a failure becomes an error row."""
    from ..api.solver import simulate_cycles

    t0 = time.perf_counter()
    try:
        r = simulate_cycles(**point)
        s = r.summary()
    except Exception as e:  # noqa: BLE001 - a failing point must not stop the sweep
        return failed_row(f"{type(e).__name__}: {e}", time.perf_counter() - t0)
    return {"regime": s["regime"], "regime_reason": r.regime_reason, "increment": s["increment_last_period"],
            "D_inf": s["D_inf"], "D_inf_error": s["D_inf_error"], "decay_ratio": s["decay_ratio"],
            "periods_to_decide": s["periods_to_decide"], "energy": s["energy_last_period"], "E_inf": s["E_inf"],
            "E_inf_error": s["E_inf_error"], "stick_halfwidth": s["stick_halfwidth"], "shakedown_period": s["shakedown_period"],
            "runtime": s["runtime_s"], "max_kkt_residual": s["max_kkt_residual"],
            "max_iterations": s["max_iterations"], "elements": s["elements"], "steps": s["steps"],
            "periodic_from": s["periodic_from"], "error": None}


def run_chunk(points: list[dict]) -> list[dict]:
    """Run a chunk of points in order (the unit of work sent to a worker)."""
    return [run_point(p) for p in points]


# --------------------------------------------------------------------------
# files
# --------------------------------------------------------------------------
def atomic_write(path: Path, write) -> None:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it over ``path``."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _is_parquet(path: Path) -> bool:
    return Path(path).name.lower().endswith(".parquet")


def read_table(path) -> pd.DataFrame:
    """A sweep table from ``.csv``, ``.csv.gz`` or ``.parquet``, with its canonical dtypes."""
    path = Path(path)
    if _is_parquet(path):
        try:
            return normalise_table(pd.read_parquet(path))
        except ImportError as e:
            raise ValueError(f"Parquet needs pyarrow (pip install pyarrow): {e}") from e
    return normalise_table(pd.read_csv(path))


def write_table(table: pd.DataFrame, path) -> None:
    """Write a table atomically as ``.csv``, ``.csv.gz``, ``.json`` or ``.parquet`` (by the suffix).

    CSV floats have 15 significant digits (:data:`CSV_FLOAT_FORMAT`), so values
    given as decimals come back as written (``0.3``, not ``0.30000000000000004``).
    """
    path = Path(path)
    name = path.name.lower()
    if _is_parquet(path):
        atomic_write(path, lambda tmp: table.to_parquet(tmp, index=False))
    elif name.endswith(".json"):
        atomic_write(path, lambda tmp: table.to_json(tmp, orient="records", indent=2))
    else:
        compression = "gzip" if name.endswith(".gz") else None
        atomic_write(path, lambda tmp: table.to_csv(tmp, index=False, compression=compression,
                                                    float_format=CSV_FLOAT_FORMAT))


def _key_value(v):
    if v is None or v is pd.NA or (isinstance(v, float) and math.isnan(v)):
        return None
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return float(f"{float(v):.12g}")
    return str(v)


def _keys(rows, columns) -> list[tuple]:
    return [tuple(_key_value(row.get(c)) for c in columns) for row in rows]


class TableFile:
    """A sweep table on disk that a sweep fills in and resumes.

    Parameters
    ----------
    path : str or Path
        ``.csv``, ``.csv.gz`` or ``.parquet``.
    points : list of dict
        The runs of the sweep (as made by :func:`core.sweep_grid`).
    overwrite : bool
        Start afresh: ignore, and replace, rows already in ``path``.

    Raises
    ------
    ValueError
        If ``path`` (or its journal) cannot be read as a sweep table, or holds
        rows that are not runs of ``points`` (another grid, other options):
        the file is never mixed with another sweep.

    Attributes
    ----------
    existing : pandas.DataFrame or None
        Rows already on disk (failed runs included).
    todo : list of dict
        The points still to run: every point without a successful row.
    """

    def __init__(self, path, points: list[dict], *, overwrite: bool = False):
        self.path = Path(path)
        self.journal = self.path.with_name(self.path.name + ".partial.csv")
        self.points = points
        self.key_columns = input_columns(points)
        self.existing = None
        if overwrite:
            self.journal.unlink(missing_ok=True)
        else:
            self.existing = self._read_existing()
        if self.existing is not None and self.journal.exists():
            # fold the journal of an interrupted run into the file, so that this run's journal starts empty
            self.existing = self.merge(None)
            write_table(self.existing, self.path)
            self.journal.unlink()
        if self.existing is None:
            self.todo = list(points)
        else:
            ok = self.existing[self.existing["regime"] != "error"]
            done = set(_keys(ok.to_dict("records"), self.key_columns))
            self.todo = [p for p, k in zip(points, _keys(points, self.key_columns)) if k not in done]

    def _read_existing(self) -> pd.DataFrame | None:
        parts = []
        for path in (self.path, self.journal):
            if path.exists() and path.stat().st_size > 0:
                try:
                    parts.append(read_table(path))
                except (OSError, ValueError, pd.errors.ParserError) as e:
                    raise ValueError(f"cannot resume from {path} ({e}); overwrite it or write elsewhere") from e
        if not parts:
            return None
        table = pd.concat(parts, ignore_index=True) if len(parts) > 1 else parts[0]
        if "regime" not in table.columns or "ft" not in table.columns:
            raise ValueError(f"{self.path} is not a sweep table (no ft/regime columns); overwrite it or write "
                             "elsewhere")
        # a line cut short by a kill has no valid regime: drop it, its run is done again
        table = table[table["regime"].isin(REGIMES)]
        self._check_same_sweep(table)
        return table

    def _check_same_sweep(self, table: pd.DataFrame) -> None:
        """Refuse a file whose rows are not runs of this sweep (other grid values or other options)."""
        inputs = [c for c in table.columns if c not in RESULT_COLUMNS]
        if set(inputs) != set(self.key_columns):
            raise ValueError(f"{self.path.name} was written with other options (input columns "
                             f"{', '.join(sorted(inputs))}; this sweep has {', '.join(sorted(self.key_columns))}): "
                             "overwrite it or write elsewhere")
        grid = set(_keys(self.points, self.key_columns))
        records = table.to_dict("records")
        foreign = [r for r, k in zip(records, _keys(records, self.key_columns)) if k not in grid]
        if foreign:
            example = ", ".join(f"{c} = {_key_value(foreign[0][c])}" for c in self.key_columns)
            raise ValueError(f"{self.path.name} holds {len(foreign)} of {len(table)} rows that are not runs of this "
                             f"sweep (e.g. {example}): it was made with another grid or other options; "
                             "overwrite it or write elsewhere")

    def append(self, rows: pd.DataFrame) -> None:
        """Append finished rows to the journal (the hook for :func:`core.run_points`' ``on_rows``)."""
        header = not self.journal.exists() or self.journal.stat().st_size == 0
        rows.to_csv(self.journal, mode="a", header=header, index=False, float_format=CSV_FLOAT_FORMAT)

    def merge(self, new: pd.DataFrame | None) -> pd.DataFrame:
        """Existing and new rows, one per run (new wins), in grid order."""
        tables = [t for t in (self.existing, new) if t is not None and len(t)]
        if not tables:
            return new if new is not None else self.existing
        merged = normalise_table(pd.concat(tables, ignore_index=True) if len(tables) > 1 else tables[0])
        keys = _keys(merged.to_dict("records"), self.key_columns)
        merged = merged.assign(_key=keys).drop_duplicates("_key", keep="last")
        order = {k: i for i, k in enumerate(_keys(self.points, self.key_columns))}
        merged = merged.assign(_rank=merged["_key"].map(order)).sort_values("_rank", kind="stable")
        return normalise_table(merged.drop(columns=["_key", "_rank"]))

    def finish(self, new: pd.DataFrame) -> pd.DataFrame:
        """Write the complete table over ``path``, remove the journal; return the table."""
        table = self.merge(new)
        write_table(table, self.path)
        self.journal.unlink(missing_ok=True)
        return table


# --------------------------------------------------------------------------
# the shipped map
# --------------------------------------------------------------------------
def load_default_map() -> pd.DataFrame:
    """The numerical (ft, w) map shipped with the package, as a sweep table.

    A 40 x 40 grid over ``ft, w`` in [0.02, 0.95] at the solver's default
    resolution (plane-strain kernel, triangle rocking, ``dx = dW = 1/40``, 10
    periods), made with the command recorded in ``core/data/README.md``.

    Returns
    -------
    pandas.DataFrame
        The columns of :func:`core.sweep`; ``attrs["source"]`` names the file.

    Examples
    --------
    >>> import core
    >>> m = core.load_default_map()
    >>> len(m), sorted(m["regime"].unique())
    (1600, ['ratcheting', 'shakedown'])
    """
    path = resources.files("core") / "data" / DEFAULT_MAP
    with resources.as_file(path) as p:
        table = pd.read_csv(p)
    # the shipped map predates the energy columns (energy, E_inf, E_inf_error): they read NaN, not measured
    table = normalise_table(table.reindex(columns=list(INPUT_COLUMNS) + list(RESULT_COLUMNS)))
    table.attrs["source"] = f"core/data/{DEFAULT_MAP}"
    return table
