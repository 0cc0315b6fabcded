"""The phases of a brake application (000 Fig. 2, Sec. 4.1): one enumeration for the whole project.

A brake application (duty cycle) runs through four phases, named as in interface.md section 4:

* ``clearance_elimination``: the screw turns in the apply direction, no clamp force yet
  (004 eq. 5 with x <= x_ag);
* ``force_generation``: the pads touch, the force rises to its maximum while the screw slows down;
* ``force_maintenance``: the screw is at rest and the force is held (the stick branch of 004 eq. 9;
  no sliding, hence no wear: 000 Sec. 2);
* ``force_release``: the screw turns back and the force falls to zero.

``idle`` is the time between applications (at rest with the pads open, or any motion outside an
application). The integer codes are the enumeration values: per-sample phase arrays (the twin's
truth, the monitor's kept samples, the diagnosis' labels) hold them as int8, and arrays indexed by
phase have ``len(Phase)`` entries in this order.
"""

from __future__ import annotations

from enum import IntEnum


class Phase(IntEnum):
    """Phase code of a sample: the four phases of a brake application, then ``idle``."""

    CLEARANCE_ELIMINATION = 0
    FORCE_GENERATION = 1
    FORCE_MAINTENANCE = 2
    FORCE_RELEASE = 3
    IDLE = 4

    @property
    def label(self) -> str:
        """The phase's name in interface.md section 4 (``"force_generation"``; ``"idle"``)."""
        return self.name.lower()


#: the four phases of a brake application, in code order
APPLICATION_PHASES: tuple[Phase, ...] = tuple(p for p in Phase if p is not Phase.IDLE)
#: their names (interface.md section 4: the phase strings of the JSON outputs and the messages)
PHASES: tuple[str, ...] = tuple(p.label for p in APPLICATION_PHASES)
#: every phase name in code order, ``idle`` last (the twin's truth: ``phase_names``)
PHASE_NAMES: tuple[str, ...] = tuple(p.label for p in Phase)

