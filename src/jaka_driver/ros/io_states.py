"""``~io_states`` (``jaka_driver_msgs/IOStates``): every IO point the arm has — cabinet, tool,
extension, relays, fieldbus slaves; inputs and outputs, digital and analog — as they came in
one sample (``RobotState.io``: the twin's IO board, a controller's status packet arrays),
stamped with that sample's time.

Published from the state publisher's thread (:mod:`.state_publisher`), which hands it every
sample it publishes: a sample whose IO differs from the last message's is published at once
(so an output ``set_io`` changed shows in the sample it first appears in), and an unchanged one
again :data:`REPEAT` s after the last — of sample time, or of the driver's clock when samples
stop coming (a controller's link down: the latest is published again, as on the state topics;
in a twin's paused simulated time nothing is) — so the topic runs at 10 Hz or more. Latched: a
late subscriber gets the latest at once.
"""
from __future__ import annotations

import rospy

from jaka_driver_msgs.msg import IOGroup, IOStates

from ..backend.robot_state import IoValues, RobotState

#: s of sample time after which an unchanged state is published again (10 Hz)
REPEAT = 0.1
#: IO type → the group's name
GROUP_NAMES = {0: "cabinet", 1: "tool", 2: "extension", 3: "relay", 4: "modbus_slave",
               5: "profinet_slave", 6: "ethernet_ip_slave"}


def io_message(io: IoValues, stamp: float) -> IOStates:
    """The message of one sample's IO: one group per type that has points, in type order."""
    msg = IOStates()
    msg.header.stamp = rospy.Time.from_sec(stamp)
    for io_type in sorted({key[1] for key in io}):
        def values(signal: str, path: int):
            return io.get((signal, io_type, path), ())
        msg.groups.append(IOGroup(
            type=io_type, name=GROUP_NAMES.get(io_type, f"type_{io_type}"),
            digital_in=[bool(v) for v in values("digital", 0)],
            digital_out=[bool(v) for v in values("digital", 1)],
            analog_in=list(values("analog", 0)), analog_out=list(values("analog", 1))))
    return msg


class IoStatesTopic:
    """``~io_states``: :meth:`offer` each sample; it publishes on change and every
    :data:`REPEAT` s (sample time, or ``clock``'s when samples stop)."""

    def __init__(self, clock):
        self._clock = clock
        self._pub = rospy.Publisher("~io_states", IOStates, queue_size=10, latch=True)
        self._last_io: IoValues | None = None
        self._last_stamp = self._last_now = float("-inf")

    def offer(self, st: RobotState) -> None:
        io, now = st.io, self._clock.now()
        changed = io is not self._last_io and io != self._last_io
        due = REPEAT - 1e-9
        if changed or st.stamp - self._last_stamp >= due or now - self._last_now >= due:
            self._pub.publish(io_message(io, st.stamp))
            self._last_io, self._last_stamp, self._last_now = io, st.stamp, now
