"""Element states and zones: one code each, shared by the solvers, the result, the export and the app.

:class:`State` is what a per-step solver records for every element at every
step (``CycleResult.state``); :class:`Zone` classifies the final traction of a
run, or the closed-form shaken-down state of the paper's ansatz (eqs 22-26 of
Wetter 2015): the two differ because "at the bound" is a zone, while slipping
forward or backward is a state.
"""

from __future__ import annotations

from enum import IntEnum

__all__ = ["State", "Zone", "STATE_NAMES", "ZONE_NAMES"]


class State(IntEnum):
    """State of an element at the end of a step (the codes stored in ``CycleResult.state``, int8)."""

    RELEASED = 0        #: out of contact (traction 0)
    STICK = 1           #: no slip increment (including at the bound with zero slip)
    SLIP_FORWARD = 2    #: slip increment in +x, traction at +mu p
    SLIP_BACKWARD = 3   #: slip increment in -x, traction at -mu p

    @property
    def label(self) -> str:
        """Human-readable name (``"slip forward"``)."""
        return STATE_NAMES[self]


class Zone(IntEnum):
    """Zone of an element in a final or shaken-down traction (``CycleResult.final_zones``, ``shakedown_zones``)."""

    NONE = 0            #: never in contact
    STICK = 1           #: traction strictly below mu p_min
    SLIP = 2            #: traction at mu p_min (the slip zone of eq 22)
    RELEASED = 3        #: zero traction: contact lost once a period

    @property
    def label(self) -> str:
        """Human-readable name (``"zero traction"``)."""
        return ZONE_NAMES[self]


#: Names of the states, indexed by code.
STATE_NAMES = ("released", "stick", "slip forward", "slip backward")
#: Names of the zones, indexed by code.
ZONE_NAMES = ("no contact", "stick", "slip", "zero traction")
