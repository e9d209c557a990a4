"""The speed ratio on ROS: ``~set_speed_ratio`` (``jaka_driver_msgs/SetSpeedRatio``: ratio in
(0, 1] → ret, message) and ``~speed_ratio`` (``std_msgs/Float64``, latched), the ratio the robot
runs at — published when set and whenever the robot reports another (a pendant's rapid rate),
looked at once a second. ``robot_states`` keeps JAKA's RobotMsg fields (and md5), so the ratio
has a topic of its own.
"""
from __future__ import annotations

import threading

import rospy
from std_msgs.msg import Float64

from jaka_driver_msgs.srv import SetSpeedRatio, SetSpeedRatioResponse

from ..driver import RobotDriver
from ..host import realtime


class SpeedRatio:
    def __init__(self, driver: RobotDriver):
        self._driver = driver
        self._pub = rospy.Publisher("~speed_ratio", Float64, queue_size=1, latch=True)
        self._published = None
        self._lock = threading.Lock()
        self._service = rospy.Service("~set_speed_ratio", SetSpeedRatio, self._set)
        self.refresh()
        threading.Thread(target=self._run, name="speed-ratio", daemon=True).start()

    def _set(self, req) -> SetSpeedRatioResponse:
        result = self._driver.set_speed_ratio(req.ratio)
        if not result.ok:
            rospy.logwarn("set_speed_ratio refused (%d): %s", result.code, result.message)
        self.refresh()
        return SetSpeedRatioResponse(ret=int(result.code), message=result.message)

    def refresh(self) -> None:
        """Publish the ratio if it changed (after a set, a twin's reset)."""
        with self._lock:
            ratio = self._driver.speed_ratio()
            if ratio != self._published:
                self._pub.publish(Float64(ratio))
                self._published = ratio

    @realtime.runs_periodically
    def _run(self) -> None:
        while not rospy.is_shutdown():
            try:
                self.refresh()
            except Exception as exc:  # noqa: BLE001
                rospy.logerr_throttle(10.0, f"speed ratio publishing failed: {exc!r}")
            rospy.rostime.wallsleep(1.0)
