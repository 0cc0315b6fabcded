"""The ROS-free wear monitor core: used unchanged by the live node and by replay / fleet.

Public API::

    core = MonitorCore(unit, config=None, state=None)     # state from load_state(path)
    core.add("angle" | "velocity" | "axial_force", stamps, values)   # int64 ns or float s; any chunk
    cycles = core.process(final=False)                    # list[CycleSummary], completed applications
    feeder = Feeder(core); events = feeder.feed(batch)    # wire.Batch in, [Application(cycle, snapshot)]
                                                          # out: how the node and the replay drive it
    snap = core.snapshot()                                # MonitorSnapshot; snap.to_json_dict() is the
                                                          # replay JSON entry of interface.md section 4
    save_state(path, core.state); state, problems = load_state(path)
    labels = label_samples(t, angle, velocity, force, config=cfg, thresholds=cfg.resolve(unit))
                                                          # every sample of a recording labelled with the
                                                          # phase and application MonitorCore gives it

See :mod:`.core` for the data flow and :mod:`.config` for every threshold.
"""

from ebm_wear_monitor.monitor.alignment import FAULT_KINDS
from ebm_wear_monitor.monitor.config import MonitorConfig, Thresholds, parameter_specs
from ebm_wear_monitor.monitor.core import Application, MonitorCore
from ebm_wear_monitor.monitor.feeder import Feeder
from ebm_wear_monitor.monitor.persistence import load_state, save_state
from ebm_wear_monitor.monitor.segmentation import SampleLabels, label_samples
from ebm_wear_monitor.monitor.state import MonitorState, StateError
from ebm_wear_monitor.monitor.wire import Batch, stamp_ns
from ebm_wear_monitor.schema.monitor import (
    STATUS_DUE,
    STATUS_INSUFFICIENT,
    STATUS_OK,
    STATUS_WARN,
    STATUSES,
    CycleSummary,
    MonitorSnapshot,
)

__all__ = [
    "FAULT_KINDS",
    "STATUSES",
    "STATUS_DUE",
    "STATUS_INSUFFICIENT",
    "STATUS_OK",
    "STATUS_WARN",
    "Application",
    "Batch",
    "CycleSummary",
    "Feeder",
    "MonitorConfig",
    "MonitorCore",
    "MonitorSnapshot",
    "MonitorState",
    "SampleLabels",
    "StateError",
    "Thresholds",
    "label_samples",
    "load_state",
    "parameter_specs",
    "save_state",
    "stamp_ns",
]
