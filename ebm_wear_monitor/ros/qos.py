"""QoS profiles of the wear monitor's topics."""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy


def input_qos(reliable: bool, depth: int) -> QoSProfile:
    """Input topics: the sensor-data profile (best effort, volatile, keep last ``depth``) or reliable.

    Reliable keeps every sample (``depth`` unused): a writer waits for slow readers, and a reader's
    history never overwrites a sample not yet taken. With keep-last, a node starved of CPU for longer
    than ``depth`` samples of a topic loses the oldest silently, although every one was delivered.
    """
    return QoSProfile(
        depth=depth,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        history=HistoryPolicy.KEEP_ALL if reliable else HistoryPolicy.KEEP_LAST,
        durability=DurabilityPolicy.VOLATILE)


def event_qos(depth: int = 100) -> QoSProfile:
    """``wear`` and ``duty_cycle``: reliable, one message per brake application, none may be lost."""
    return QoSProfile(depth=depth, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)


def latched_qos() -> QoSProfile:
    """``remaining_life``: reliable, transient-local (latched): a late subscriber gets the last value."""
    return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)
