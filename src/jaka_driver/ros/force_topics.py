"""The force/torque sensor's topics (docs/interface.md, "Force"):

- ``~wrench`` (geometry_msgs/WrenchStamped): every sample's ``actual`` reading — zeroed, the
  tool's weight still in it — in the sensor frame (``header.frame_id`` ``flange``), stamped
  with the sample's time, from the state publisher's thread right after the state topics;
- ``~wrench_compensated``: the same sample's ``real`` reading, the tool's weight taken out
  too: what the world does to the tool;
- ``~force_control_state`` (jaka_driver_msgs/ForceControlState, latched): the settings and
  what force control does, published at start, after every force service and whenever it
  changes otherwise (a stop ends force control, a twin reset, an identification ends: looked
  at 10 times a second).

Without a sensor, or while it is off, the wrench topics are silent. Request units in the
state message: rebound N/mm (x y z) and N·m/rad, payload centroid mm.
"""
from __future__ import annotations

import threading
import time
import warnings

import rospy
from geometry_msgs.msg import Wrench, WrenchStamped

from jaka_driver_msgs.msg import AdmittanceAxis, ForceControlState, ToolDriveAxis

from ..backend.force import SENSOR_FRAME, ForceSettings
from ..backend.robot_state import RobotState
from ..driver import RobotDriver
from ..host import realtime

STATE_CHECK_PERIOD = 0.1        # s (wall) between looks for a change of the force state


def wrench_values(msg: Wrench) -> list:
    """A geometry_msgs/Wrench as ``[Fx, Fy, Fz, Mx, My, Mz]``."""
    return [msg.force.x, msg.force.y, msg.force.z, msg.torque.x, msg.torque.y, msg.torque.z]


def fill_wrench(msg: Wrench, values) -> None:
    """``values`` (Fx Fy Fz N, Mx My Mz N·m) into ``msg``."""
    v = [float(x) for x in values]
    msg.force.x, msg.force.y, msg.force.z = v[:3]
    msg.torque.x, msg.torque.y, msg.torque.z = v[3:]


def state_message(s: ForceSettings) -> ForceControlState:
    """``s`` (the facet's units) as the message (request units)."""
    msg = ForceControlState(
        mounted=s.mounted, sensor_on=s.sensor_on, mode=s.mode, sensor_frame=SENSOR_FRAME,
        range=[float(v) for v in s.range], filter_hz=float(s.filter_hz),
        soft_limit=[float(v) for v in s.soft_limit], payload_mass=float(s.tool_payload.mass),
        payload_centroid=[float(v) * 1000.0 for v in s.tool_payload.centroid],
        sensor_compensation=bool(s.compensation), compliance_type=int(s.compliance_type),
        velocity_level=int(s.velocity.level),
        velocity_rates=[float(v) for v in s.velocity.rates], frame=int(s.frame),
        tool_drive_frame=int(s.tool_drive_frame),
        condition=[float(v) for v in s.condition])
    msg.admittance = [AdmittanceAxis(opt=int(a.enabled), ft_user=float(a.ft_user),
                                     ft_rebound=float(a.rebound),
                                     ft_constant=float(a.constant),
                                     normal_track=int(a.normal_track))
                      for a in s.admittance]
    msg.tool_drive = [ToolDriveAxis(opt=int(a.enabled), rigidity=float(a.rigidity),
                                    rebound=float(a.rebound))
                      for a in s.tool_drive]
    return msg


class ForceTopics:
    """The wrench topics (:meth:`publish_sample`, called by the state publisher for every
    sample) and the latched state (:meth:`refresh`)."""

    def __init__(self, driver: RobotDriver):
        self._driver = driver
        # synchronous, as the state topics (node.py says why): no sample dropped from a queue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self._wrench = rospy.Publisher("~wrench", WrenchStamped, queue_size=None)
            self._compensated = rospy.Publisher("~wrench_compensated", WrenchStamped,
                                                queue_size=None)
        self._state = rospy.Publisher("~force_control_state", ForceControlState, queue_size=1,
                                      latch=True)
        self._actual, self._real = WrenchStamped(), WrenchStamped()
        for msg in (self._actual, self._real):
            msg.header.frame_id = SENSOR_FRAME
        self._lock = threading.Lock()
        self._last: str | None = None
        self.refresh()
        if driver.force.settings().value.mounted:    # without a sensor nothing ever changes
            threading.Thread(target=self._watch, name="force-state", daemon=True).start()

    def publish_sample(self, st: RobotState) -> None:
        reading = st.force
        if reading is None:
            return
        stamp = rospy.Time.from_sec(st.stamp)
        for msg, values, pub in ((self._actual, reading.actual, self._wrench),
                                 (self._real, reading.real, self._compensated)):
            msg.header.stamp = stamp
            fill_wrench(msg.wrench, values)
            pub.publish(msg)

    def refresh(self) -> None:
        """Publish the state if it differs from the last one published."""
        result = self._driver.force.settings()
        if not result.ok:
            return
        msg = state_message(result.value)
        key = str([getattr(msg, slot) for slot in msg.__slots__ if slot != "header"])
        with self._lock:
            if key == self._last:
                return
            self._last = key
            msg.header.stamp = rospy.Time.from_sec(self._driver.state().stamp)
            self._state.publish(msg)

    @realtime.runs_periodically
    def _watch(self) -> None:
        while not rospy.is_shutdown():
            time.sleep(STATE_CHECK_PERIOD)      # wall time: a look, not a timeout
            try:
                self.refresh()
            except Exception as exc:  # noqa: BLE001 — the watcher must outlive a bad moment
                rospy.logwarn_throttle(10.0, f"force_control_state: {exc!r}")
