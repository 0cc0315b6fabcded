"""The domain vocabulary of the core: phases, signals and topics, recordings, phase runs.

Plain Python + numpy, no ROS and no storage import (mypy strict): the monitor, the twin, the
diagnosis, the replay and the node all name phases, signals and recordings through this package.

* :mod:`.phases`: :class:`~.phases.Phase`, the four phases of a brake application (000 Fig. 2,
  interface.md section 4) and ``idle`` between applications, with their interface names.
"""
