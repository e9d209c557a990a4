"""The Cartesian velocity input: ``~twist_command`` (``geometry_msgs/TwistStamped``), a velocity
jog (:meth:`RobotDriver.velocity_jog`) on either backend, as joystick and space-mouse teleop
publish it.

``header.frame_id`` chooses the frame of the twist: the base (``""``, ``base_link``,
``base``, or the node's ``<tf_prefix>base_link``) or the active tool (``tool``, ``tool_<n>``,
``flange`` counts as the tool too). ``twist.linear`` m/s, ``twist.angular`` rad/s, at most
jog's limits (the model's TCP speed, the tool rotation cap). The arm ramps to rest
``~twist_timeout`` s (default 0.1) after the last message. Refusals, slowdowns (a joint limit,
a singularity) and stops go to ``~command_status``.
"""
from __future__ import annotations

import rospy
from geometry_msgs.msg import TwistStamped

from ..common.results import Code, Result
from ..driver import RobotDriver
from .command_status import CommandStatus, StreamEnd

TOPIC = "~twist_command"
BASE_FRAMES = ("", "base", "base_link", "world")


def twist_frame(frame_id: str) -> "bool | Result":
    """True for the tool frame, False for the base, or the refusal naming the frame."""
    name = frame_id.rsplit("/", 1)[-1]
    if name in BASE_FRAMES:
        return False
    if name in ("tool", "flange") or name.startswith("tool_"):
        return True
    return Result.failure(Code.INVALID_PARAMETER, f"header.frame_id is {frame_id!r}, expected "
                          "the base ('', base_link) or the tool (tool, tool_<n>)")


class TwistInput:
    """Subscribes ``~twist_command``; each message → :meth:`RobotDriver.velocity_jog`."""

    def __init__(self, driver: RobotDriver, status: CommandStatus):
        self._driver = driver
        self._status = status
        self._name = rospy.resolve_name(TOPIC)
        self._end = StreamEnd(status, self._name, driver.twist_timeout,
                              f"no twist for {driver.twist_timeout:g} s: the arm ramps to rest")
        self._slowed = False
        self._sub = rospy.Subscriber(TOPIC, TwistStamped, self._on_twist, queue_size=8,
                                     tcp_nodelay=True)

    def _on_twist(self, msg: TwistStamped) -> None:
        in_tool = twist_frame(msg.header.frame_id)
        if isinstance(in_tool, Result):
            self._status.refused(self._name, in_tool)
            return
        t = msg.twist
        result = self._driver.velocity_jog((t.linear.x, t.linear.y, t.linear.z),
                                           (t.angular.x, t.angular.y, t.angular.z), in_tool)
        if not result.ok:
            self._status.refused(self._name, result)
            return
        self._status.accepted(self._name)
        self._end.fed()
        slowed = result.value is not None       # why the jog slowed (motion.velocity_jog)
        if slowed and not self._slowed:       # once per slowdown, not once per message
            self._status.count(self._name, "slowdowns")
            self._status.publish(self._name, 1, result.message, result.code)
        self._slowed = slowed
