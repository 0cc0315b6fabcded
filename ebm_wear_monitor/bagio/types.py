"""The ``ebm_wear_msgs`` message types, registered with rosbags from the ``.msg`` files.

One source of truth (issue 2 item 3): the very ``.msg`` files that rosidl builds
for rclpy (``msg_defs/msg/``) are parsed here at run time and registered in a
rosbags typestore, so bag reading/writing and the live node can never drift.
The files are looked up in the source tree first (editable install, the normal
case in this repository) and then where rosidl installs them,
``<sys.prefix>/share/ebm_wear_msgs/msg/``. The text is never copied.
"""

from __future__ import annotations

import sys
from functools import cache
from pathlib import Path

from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from ebm_wear_monitor.domain.signals import FLOAT64_STAMPED

#: ROS 2 interface package of the project's messages (``msg_defs/``)
MSG_PACKAGE = FLOAT64_STAMPED.split("/", 1)[0]
#: the ROS 2 distribution whose std_msgs/builtin_interfaces definitions the typestore starts from
ROS_STORE = Stores.ROS2_KILTED


def msg_dir() -> Path:
    """Directory holding ``ebm_wear_msgs``'s ``.msg`` files (source tree first, then install prefix)."""
    candidates = (
        Path(__file__).resolve().parents[2] / "msg_defs" / "msg",
        Path(sys.prefix) / "share" / MSG_PACKAGE / "msg",
    )
    for directory in candidates:
        if any(directory.glob("*.msg")):
            return directory
    raise FileNotFoundError(
        f"no {MSG_PACKAGE} .msg files found in {' or '.join(str(c) for c in candidates)}")


@cache
def typestore() -> Typestore:
    """A rosbags typestore of ROS 2 Kilted plus every ``ebm_wear_msgs/msg/*`` type (one per process)."""
    store = get_typestore(ROS_STORE)
    types: dict = {}
    for path in sorted(msg_dir().glob("*.msg")):
        types.update(get_types_from_msg(path.read_text(encoding="utf-8"), f"{MSG_PACKAGE}/msg/{path.stem}"))
    store.register(types)
    return store
