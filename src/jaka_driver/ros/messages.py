"""RobotState → the driver's ROS messages (docs/interface.md, "Topics").

Plain conversions, no publishing. :class:`StateMessages` owns one message of each kind and
refills it for every sample: the state publisher publishes synchronously (the message is
serialised before ``publish`` returns), so nothing keeps a reference to the previous fill,
and the per-message Python work is the field values alone — no message constructors, no
header objects, no name list per sample. numpy values are turned into Python floats and
bools because rospy's serialiser mishandles numpy 2 scalars.
"""
from __future__ import annotations

import rospy
from geometry_msgs.msg import PoseStamped, TwistStamped
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState

from jaka_msgs.msg import RobotMsg

from ..backend.robot_state import RobotState
from ..common.transforms import matrix_to_quat, matrix_to_rotvec
from ..conventions import DOCUMENT, Conventions


def user_frame_id(user_id: int) -> str:
    """TF frame of user frame ``user_id`` (0 is the base)."""
    return "base_link" if user_id == 0 else f"user_frame_{user_id}"


def tool_position(st: RobotState, stamp: rospy.Time, msg: TwistStamped) -> None:
    """Fill ``msg`` with the TCP pose: ``twist.linear`` position m, ``twist.angular`` rotation
    vector rad (docs/interface.md, "Topics"), of the active tool in the active user frame."""
    msg.header.stamp = stamp
    msg.header.frame_id = user_frame_id(st.user_id)
    linear, angular = msg.twist.linear, msg.twist.angular
    linear.x, linear.y, linear.z = st.tcp_pose[:3, 3].tolist()
    angular.x, angular.y, angular.z = matrix_to_rotvec(st.tcp_pose[:3, :3]).tolist()


def tool_pose(st: RobotState, stamp: rospy.Time, msg: PoseStamped) -> None:
    """Fill ``msg`` with the TCP pose as JAKA's driver code publishes it (``jaka_code``
    conventions): position **mm**, orientation the quaternion of the pose; frame_id as
    :func:`tool_position` (``base_link`` in user frame 0, as JAKA's code always says)."""
    msg.header.stamp = stamp
    msg.header.frame_id = user_frame_id(st.user_id)
    position, orientation = msg.pose.position, msg.pose.orientation
    position.x, position.y, position.z = (st.tcp_pose[:3, 3] * 1000.0).tolist()
    orientation.x, orientation.y, orientation.z, orientation.w = \
        matrix_to_quat(st.tcp_pose[:3, :3]).tolist()


def joint_state(st: RobotState, stamp: rospy.Time, msg: JointState) -> None:
    """Fill ``msg`` (its names kept) with the joints: position rad, velocity rad/s,
    effort N·m."""
    msg.header.stamp = stamp
    msg.position = st.joint_position.tolist()
    msg.velocity = st.joint_velocity.tolist()
    msg.effort = st.joint_effort.tolist()


def robot_msg(st: RobotState, msg: RobotMsg, servo_state_is_enabled: bool = False) -> None:
    """Fill ``msg``; ``servo_state`` is servo *mode* (JAKA's documented meaning), or robot
    enable when ``servo_state_is_enabled`` (JAKA's driver code: ``jaka_code`` conventions)."""
    msg.motion_state = int(st.motion_state)
    msg.power_state = int(bool(st.powered))
    msg.servo_state = int(bool(st.enabled if servo_state_is_enabled else st.servo_mode))
    msg.collision_state = int(bool(st.collision))


class StateMessages:
    """One ``tool_position``, ``joint_position``/``joint_states``, ``robot_states`` and ``/clock``
    message, refilled by :meth:`fill` for each sample (see the module). ``conventions`` chooses
    tool_position's type (``tool``: TwistStamped, or PoseStamped for ``jaka_code``) and what
    servo_state means."""

    def __init__(self, names, conventions: Conventions = DOCUMENT):
        self._pose = conventions.tool_position_pose
        self._enabled = conventions.servo_state_is_enabled
        self.tool = PoseStamped() if self._pose else TwistStamped()
        self.joints = JointState()
        self.joints.name = list(names)
        self.robot = RobotMsg()
        self.clock = Clock()         # published when the twin owns time

    def fill(self, st: RobotState) -> None:
        stamp = rospy.Time.from_sec(st.stamp)
        (tool_pose if self._pose else tool_position)(st, stamp, self.tool)
        joint_state(st, stamp, self.joints)
        robot_msg(st, self.robot, self._enabled)
        self.clock.clock = stamp
