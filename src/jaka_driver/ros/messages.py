"""RobotState → the driver's ROS messages (docs/interface.md, "Topics").

Plain conversions, no publishing; numpy values are turned into Python floats and bools
because rospy's serialiser mishandles numpy 2 scalars.
"""
from __future__ import annotations

import rospy
from geometry_msgs.msg import TwistStamped
from sensor_msgs.msg import JointState

from jaka_msgs.msg import RobotMsg

from ..robot_state import RobotState
from ..transforms import matrix_to_rotvec


def user_frame_id(user_id: int) -> str:
    """TF frame of user frame ``user_id`` (0 is the base)."""
    return "base_link" if user_id == 0 else f"user_frame_{user_id}"


def tool_position(st: RobotState, stamp: rospy.Time) -> TwistStamped:
    """TCP pose: ``twist.linear`` position m, ``twist.angular`` rotation vector rad
    (docs/interface.md, "Topics"),
    of the active tool in the active user frame."""
    msg = TwistStamped()
    msg.header.stamp = stamp
    msg.header.frame_id = user_frame_id(st.user_id)
    x, y, z = (float(v) for v in st.tcp_pose[:3, 3])
    rx, ry, rz = (float(v) for v in matrix_to_rotvec(st.tcp_pose[:3, :3]))
    msg.twist.linear.x, msg.twist.linear.y, msg.twist.linear.z = x, y, z
    msg.twist.angular.x, msg.twist.angular.y, msg.twist.angular.z = rx, ry, rz
    return msg


def joint_state(st: RobotState, names, stamp: rospy.Time) -> JointState:
    """Joints: position rad, velocity rad/s, effort N·m."""
    msg = JointState()
    msg.header.stamp = stamp
    msg.name = list(names)
    msg.position = st.joint_position.tolist()
    msg.velocity = st.joint_velocity.tolist()
    msg.effort = st.joint_effort.tolist()
    return msg


def robot_msg(st: RobotState) -> RobotMsg:
    """``servo_state`` is servo *mode* (JAKA's documented meaning), not robot enable."""
    return RobotMsg(motion_state=int(st.motion_state), power_state=int(bool(st.powered)),
                    servo_state=int(bool(st.servo_mode)),
                    collision_state=int(bool(st.collision)))
