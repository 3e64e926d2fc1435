"""The loading path of a history: how the loads are first applied, before the periods the verdict reads.

With an uncoupled contact (Dundurs ``beta = 0``) Melan's theorem decides shakedown whatever the path, and the
steady dissipation does not depend on the initial state (Barber, Davies & Hills 2011); with coupling neither is
promised (Klarbring, Ciavarella & Barber 2007), so the path becomes a parameter worth varying. A
:class:`LoadingPath` says in what order the normal and tangential loads are raised, in how many steps, where the
centre is when they are, which way the rocking starts, and which earlier periods at other loads come first.
Every step of the path belongs to the loading block (period ``-1``): the increments, energies and the verdict of
a run are those of the history's own periods, after the path.

This module imports neither numpy nor numba (the command line parses ``--path`` with it); the schedules are
built by :mod:`core.loading.histories`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Integral, Real

__all__ = ["LoadingPath", "ORDERS", "DEFAULT_PATH", "as_path"]

#: The orders in which the normal load ``P`` and the tangential load ``Q`` are raised.
ORDERS = ("P-then-Q", "together")
_MAX_STEPS = 10_000
_MAX_PRELOADS = 20


def _real(name, value, lo, hi, lo_closed=True, hi_closed=True) -> float:
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(float(value)):
        raise ValueError(f"{name} must be a finite number, got {value!r:.60}")
    v = float(value)
    if (v < lo or (v == lo and not lo_closed)) or (v > hi or (v == hi and not hi_closed)):
        span = f"{'[' if lo_closed else '('}{lo:g}, {hi:g}{']' if hi_closed else ')'}"
        raise ValueError(f"{name} must be in {span}, got {v:g}")
    return v


def _int(name, value, lo, hi) -> int:
    if isinstance(value, bool) or not isinstance(value, Integral) or not lo <= int(value) <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value!r:.60}")
    return int(value)


@dataclass(frozen=True)
class LoadingPath:
    """How a history's loads are first applied (all of it in the loading block, period ``-1``).

    The default is the path every run had before paths existed, and gives bitwise the same schedule: the normal
    load ``P`` applied at once with the first step of ``Q``, ``Q`` raised in the history's ``load_steps`` steps
    at ``xc = 0``, then the periods ``0 -> +W -> -W -> 0``.

    Parameters
    ----------
    order : {"P-then-Q", "together"}
        ``"P-then-Q"``: ``P`` raised to its value in ``ramp_steps`` steps with ``Q = 0`` (0: applied at once with
        the first step of ``Q``), then ``Q`` raised in the history's ``load_steps`` steps at constant ``P``.
        ``"together"``: ``P`` and ``Q`` raised in proportion (``Q/P`` constant) in ``ramp_steps`` steps (0: the
        history's ``load_steps``).
    ramp_steps : int
        Steps of the normal ramp, in [0, 10000] (see ``order``).
    first_direction : {1, -1}
        The first way the oscillation goes in every period: ``+1`` the centre ``0 -> +W -> -W -> 0`` (a tangential
        history: the force first up), ``-1`` the mirror image ``0 -> -W -> +W -> 0`` (the force first down).
    start_at : float
        Where the centre is while the loads are raised, as a fraction of ``W``, in [-1, 1] (``1``: at ``+W``);
        the centre then moves to 0 in steps no larger than ``dW`` under the full loads. 0 for a tangential
        history (its centre is fixed).
    preload : tuple of (ft, amplitude, periods)
        Earlier periods of the same history at other loads, run in turn after the ramp (each ``periods`` in
        [1, 10000], at most 20 of them): ``ft`` in (-1, 1) and ``amplitude`` the history's own (``W/a`` in
        [0, 1) for rocking and normal; the force's amplitude [mu P] for tangential). ``Q`` moves between the
        levels in ``load_steps`` steps at ``xc = 0``.

    Raises
    ------
    ValueError
        Naming the field and its range.

    Examples
    --------
    >>> from core.loading.paths import LoadingPath
    >>> p = LoadingPath(order="together", ramp_steps=10, first_direction=-1, preload=[(0.5, 0.3, 5)])
    >>> str(p)
    'order=together,ramp=10,first=-1,preload=0.5:0.3:5'
    >>> LoadingPath.parse(str(p)) == p, LoadingPath().is_default
    (True, True)
    """

    order: str = "P-then-Q"
    ramp_steps: int = 0
    first_direction: int = 1
    start_at: float = 0.0
    preload: tuple = ()

    def __post_init__(self):
        if self.order not in ORDERS:
            raise ValueError(f"order must be one of {ORDERS}, got {self.order!r:.60}")
        object.__setattr__(self, "ramp_steps", _int("ramp_steps", self.ramp_steps, 0, _MAX_STEPS))
        if isinstance(self.first_direction, bool) or self.first_direction not in (1, -1):
            raise ValueError(f"first_direction must be +1 or -1, got {self.first_direction!r:.60}")
        object.__setattr__(self, "first_direction", int(self.first_direction))
        object.__setattr__(self, "start_at", _real("start_at", self.start_at, -1.0, 1.0) + 0.0)
        try:
            entries = list(self.preload)
        except TypeError as e:
            raise ValueError(f"preload must be a sequence of (ft, amplitude, periods), got {self.preload!r:.60}") from e
        if len(entries) > _MAX_PRELOADS:
            raise ValueError(f"preload must have at most {_MAX_PRELOADS} entries, got {len(entries)}")
        checked = []
        for i, entry in enumerate(entries):
            if isinstance(entry, (str, bytes)) or not hasattr(entry, "__len__") or len(entry) != 3:
                raise ValueError(f"preload[{i}] must be (ft, amplitude, periods), got {entry!r:.60}")
            ft, amplitude, periods = entry
            checked.append((_real(f"preload[{i}].ft", ft, -1.0, 1.0, False, False),
                            _real(f"preload[{i}].amplitude", amplitude, 0.0, 1.0, True, False),
                            _int(f"preload[{i}].periods", periods, 1, _MAX_STEPS)))
        object.__setattr__(self, "preload", tuple(checked))

    @property
    def is_default(self) -> bool:
        """Whether this is the default path (the schedule is then exactly the history's without a path)."""
        return self == DEFAULT_PATH

    def __str__(self) -> str:
        """The command line's text of the path (``shakedown run --path``); the fields left at their default
        are left out ("default" for the default path)."""
        parts = []
        if self.order != "P-then-Q":
            parts.append(f"order={self.order}")
        if self.ramp_steps:
            parts.append(f"ramp={self.ramp_steps}")
        if self.first_direction != 1:
            parts.append("first=-1")
        if self.start_at:
            parts.append(f"start={self.start_at:g}")
        if self.preload:
            parts.append("preload=" + "+".join(f"{f:g}:{a:g}:{n}" for f, a, n in self.preload))
        return ",".join(parts) or "default"

    @classmethod
    def parse(cls, text: str) -> LoadingPath:
        """A path from its text: comma-separated ``key=value`` fields, any of

        ``order=P-then-Q|together``, ``ramp=N``, ``first=+1|-1``, ``start=X`` (a fraction of ``W`` in [-1, 1], or
        ``+W``, ``-W``), ``preload=FT:AMPLITUDE:PERIODS[+FT:AMPLITUDE:PERIODS...]``; ``default`` (or nothing) is
        the default path. Example: ``order=together,ramp=10,first=-1,start=+W,preload=0.5:0.3:5+0.2:0.6:3``.

        Raises
        ------
        ValueError
            Naming the field that is unknown or out of range.
        """
        if not isinstance(text, str) or len(text) > 1000:
            raise ValueError(f"path must be a text of at most 1000 characters, got {text!r:.60}")
        fields = {}
        keys = {"order": "order", "ramp": "ramp_steps", "first": "first_direction", "start": "start_at",
                "preload": "preload"}
        for part in filter(None, (p.strip() for p in text.split(","))):
            if part == "default":
                continue
            key, sep, value = part.partition("=")
            key, value = key.strip(), value.strip()
            if not sep or key not in keys:
                raise ValueError(f"path: each field must be KEY=VALUE with KEY one of {', '.join(keys)}, "
                                 f"got {part!r:.60}")
            name = keys[key]
            if name in fields:
                raise ValueError(f"path: {key} given twice")
            try:
                if name == "order":
                    fields[name] = value
                elif name == "ramp_steps":
                    fields[name] = int(value)
                elif name == "first_direction":
                    fields[name] = {"+": 1, "-": -1, "+1": 1, "1": 1, "-1": -1}[value]
                elif name == "start_at":
                    fields[name] = {"+W": 1.0, "W": 1.0, "-W": -1.0}.get(value.upper()) or float(value)
                else:
                    fields[name] = [(float(f), float(a), int(n)) for f, a, n in
                                    (entry.split(":") for entry in value.split("+") if entry.strip())]
            except (ValueError, KeyError) as e:
                raise ValueError(f"path: {key}={value!r:.60} is not valid (order=P-then-Q|together, ramp=N, "
                                 "first=+1|-1, start=X|+W|-W, preload=FT:AMPLITUDE:PERIODS[+...])") from e
        return cls(**fields)


#: The default path (today's: ``P`` at once, ``Q`` raised at ``xc = 0``, the centre first towards ``+W``).
DEFAULT_PATH = LoadingPath()


def as_path(path) -> LoadingPath:
    """``path`` as a :class:`LoadingPath`: None (the default), a :class:`LoadingPath`, its text
    (:meth:`LoadingPath.parse`) or a mapping of its fields.

    Raises
    ------
    ValueError
        If ``path`` is none of these, or a field is out of range.
    """
    if path is None:
        return DEFAULT_PATH
    if isinstance(path, LoadingPath):
        return path
    if isinstance(path, str):
        return LoadingPath.parse(path)
    if isinstance(path, dict):
        unknown = sorted(set(map(str, path)) - {"order", "ramp_steps", "first_direction", "start_at", "preload"})
        if unknown:
            raise ValueError(f"path has unknown fields {unknown!r:.80}: order, ramp_steps, first_direction, "
                             "start_at, preload")
        return LoadingPath(**path)
    raise ValueError(f"path must be None, a core.LoadingPath, its text or a dict of its fields, got {path!r:.60}")
