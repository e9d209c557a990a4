"""The joint position stream on topics: each message one servo_j target, under servo_j's rules
and on its path in the driver (:meth:`RobotDriver.servo_j_target`: servo mode on, joint limits,
the step check against the last target, the servo stream's watchdog), on either backend.

- ``~joint_command`` (``trajectory_msgs/JointTrajectory``): exactly one point, its
  ``positions`` (rad) named by ``joint_names`` — all six of the model's, in any order (they are
  reordered), as moveit_servo publishes to a controller (read from its bytes:
  :mod:`.trajectory_wire`);
- ``~joint_position_command`` (``std_msgs/Float64MultiArray``): ``data`` the six positions
  (rad) in the model's joint order, as a ros_control position group takes them.

Absolute positions always, whatever ``~servo_increment`` says of the servo_j service. Refusals
and the stream's end go to ``~command_status`` (:mod:`.command_status`).
"""
from __future__ import annotations

import rospy
from std_msgs.msg import Float64MultiArray

from ..common.results import Result
from ..driver import RobotDriver
from .command_status import CommandStatus, StreamEnd
from .trajectory_wire import TrajectoryReader, TrajectoryTarget

TRAJECTORY_TOPIC = "~joint_command"
ARRAY_TOPIC = "~joint_position_command"


class JointCommandInput:
    """Subscribes both topics; each message → :meth:`RobotDriver.servo_j_target`."""

    def __init__(self, driver: RobotDriver, status: CommandStatus, servo_timeout: float):
        self._driver = driver
        self._status = status
        self._trajectory = TrajectoryReader(driver.model.joint_names)
        ends = "the stream stopped: the arm holds its last target"
        self._resolved = {topic: rospy.resolve_name(topic)
                          for topic in (TRAJECTORY_TOPIC, ARRAY_TOPIC)}
        self._ends = {topic: StreamEnd(status, name, servo_timeout, ends)
                      for topic, name in self._resolved.items()}
        # tcp_nodelay: a stream of small messages is sent at once, not batched by Nagle
        self._subs = [
            rospy.Subscriber(TRAJECTORY_TOPIC, TrajectoryTarget, self._on_trajectory,
                             queue_size=8, tcp_nodelay=True),
            rospy.Subscriber(ARRAY_TOPIC, Float64MultiArray, self._on_array, queue_size=8,
                             tcp_nodelay=True)]

    def _on_trajectory(self, msg: TrajectoryTarget) -> None:
        self._target(TRAJECTORY_TOPIC, self._trajectory.positions(msg))

    def _on_array(self, msg: Float64MultiArray) -> None:
        self._target(ARRAY_TOPIC, list(msg.data))

    def _target(self, topic: str, positions) -> None:
        name = self._resolved[topic]
        result = positions if isinstance(positions, Result) else \
            self._driver.servo_j_target(positions)
        if result.ok:
            self._status.accepted(name)
            self._ends[topic].fed()
        else:
            self._status.refused(name, result)
