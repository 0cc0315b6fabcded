"""The domain vocabulary of the core: phases and their per-sample labels, signals and topics, recordings.

Plain Python + numpy, no ROS and no storage import (mypy strict): the monitor, the twin, the
diagnosis, the replay and the node all name phases, signals and recordings through this package.

* :mod:`.phases`: :class:`~.phases.Phase`, the four phases of a brake application (000 Fig. 2,
  interface.md section 4) and ``idle`` between applications, with their interface names.
* :mod:`.segmentation`: :class:`~.segmentation.Labels`, the phase and application of every sample that
  both segmentation modes give (the monitor's causal state machine,
  :mod:`ebm_wear_monitor.monitor.segmentation`, and the diagnosis' offline labelling,
  :mod:`ebm_wear_monitor.diagnosis.phases`), and the run arithmetic they share.
* :mod:`.signals`: the signal and topic contract (interface.md sections 1-2, 4): signal names,
  topics under a unit's namespace, the message type.
* :mod:`.recording`: :class:`~.recording.Recording`, one unit's recorded signals (per signal int64 ns
  header stamps and float64 values; float-seconds views for the diagnosis).

What is not here: the Float64Stamped codec (:mod:`ebm_wear_monitor.monitor.wire`), the actuator
model of 004 eq. 1-9 that the twin and the diagnosis share (:mod:`ebm_wear_monitor.twin.dynamics`),
and the decision rules of the two segmentation modes (they stay with their users:
:mod:`.segmentation` says why they differ).
"""
