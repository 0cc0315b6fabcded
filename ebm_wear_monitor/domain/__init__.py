"""The domain vocabulary of the core: phases and their per-sample labels, signals and topics, recordings.

Plain Python + numpy (and scipy's moving average in the offline segmentation), no ROS and no storage
import (mypy strict): the monitor, the twin, the diagnosis, the replay and the node all name phases,
signals and recordings through this package, and segment recordings with its segmenter.

* :mod:`.phases`: :class:`~.phases.Phase`, the four phases of a brake application (000 Fig. 2,
  interface.md section 4) and ``idle`` between applications, with their interface names.
* :mod:`.segmentation`: the segmenter, one component in two modes over one vocabulary:
  :class:`~.segmentation.Labels` (the phase and application of every sample) and the rules both modes
  apply (the phase of a sample from its direction of motion and contact, the cycle index, the run
  arithmetic); the causal mode :mod:`.segmentation.causal` (the monitor's streaming state machine,
  used through :mod:`ebm_wear_monitor.monitor.segmentation`) and the offline mode
  :mod:`.segmentation.offline` (the diagnosis' labelling of a whole recording, used through
  :mod:`ebm_wear_monitor.diagnosis.phases`).
* :mod:`.signals`: the signal and topic contract (interface.md sections 1-2, 4): signal names,
  topics under a unit's namespace, the message type.
* :mod:`.recording`: :class:`~.recording.Recording`, one unit's recorded signals (per signal int64 ns
  header stamps and float64 values; float-seconds views for the diagnosis).

What is not here: the Float64Stamped codec (:mod:`ebm_wear_monitor.monitor.wire`), the actuator
model of 004 eq. 1-9 that the twin and the diagnosis share (:mod:`ebm_wear_monitor.twin.dynamics`),
and the inputs each segmentation mode is fed (the monitor's aligned batches and unit thresholds, the
diagnosis' angle speed and noise levels).
"""
