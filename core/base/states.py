"""Element states, zones and residual names: one code each, shared by every solver, the result, the export and the app.

:class:`State` is what a per-step solver records for every element at every
step (``CycleResult.state``); :class:`Zone` classifies the final traction of a
run, or the closed-form shaken-down state of the paper's ansatz (eqs 22-26 of
Wetter 2015): the two differ because "at the bound" is a zone, while slipping
forward or backward is a state.
"""

from __future__ import annotations

from enum import IntEnum

__all__ = ["State", "Zone", "STATE_NAMES", "ZONE_NAMES", "RESIDUAL_NAMES"]


class State(IntEnum):
    """State of an element at the end of a step (the codes stored in ``CycleResult.state``, int8).

    The same codes on a line and on a patch of elements: on a patch the slip
    increment is a vector, "forward" when its x component (the rocking
    direction) is >= 0, and the traction is on the Coulomb disk along it.
    """

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

#: Names of the KKT residuals every per-step solver reports, for a line and for a patch alike (the
#: ``residuals`` of a step and of a :class:`core.records.result.CycleResult`): ``stick_slip``, the slip on the
#: stick set [displacement unit]; ``bound``, ``|q|`` above ``mu p`` [mu p0]; ``slip_direction``, slip
#: against (or, on a patch, across) the traction; ``out_of_contact``, traction where ``p = 0`` [mu p0];
#: ``load_balance``, the sum of the tractions against the load (``sum q`` on a line, ``sum q dA`` on a patch).
RESIDUAL_NAMES = ("stick_slip", "bound", "slip_direction", "out_of_contact", "load_balance")
