"""``~conventions:=jaka_code`` on the real node: the mode is logged at start and shown in
/diagnostics, tool_position is a PoseStamped in mm, robot_states.servo_state means "enabled",
and the services read RPY (linear_move) and answer RPY (get_fk); a wrong value stops the node
naming both modes."""
from __future__ import annotations

import math

import numpy as np
import pytest

from support.ros_harness import DriverProcess, start_driver, wait_until

pytestmark = pytest.mark.ros

RPY_TARGET = [150.0, -460.0, 350.0, math.pi, 0.0, -math.pi / 2]   # mm + RPY rad
START = [-1.2, 1.57, -1.57, 1.57, 1.57, 0.0]


@pytest.fixture(scope="module")
def jaka_code_driver(request, rospy_node):
    return start_driver(request, backend="sim", model="zu5", conventions="jaka_code")


def test_the_mode_is_logged_and_in_diagnostics(jaka_code_driver):
    import rospy
    from diagnostic_msgs.msg import DiagnosticArray
    assert "conventions jaka_code: linear_move/get_ik/get_fk orientation RPY" in \
        jaka_code_driver.log_path.read_text(errors="replace")
    msg = rospy.wait_for_message("/diagnostics", DiagnosticArray, 5.0)
    values = {kv.key: kv.value for status in msg.status for kv in status.values}
    assert values["conventions"] == "jaka_code" and values["servo increments"] == "True"


def test_tool_position_is_a_pose_stamped_in_mm_and_servo_state_means_enabled(jaka_code_driver,
                                                                             rospy_node):
    import rospy
    from geometry_msgs.msg import PoseStamped
    from jaka_msgs.msg import RobotMsg
    from jaka_msgs.srv import GetFK
    from sensor_msgs.msg import JointState
    types = dict(rospy.get_published_topics())
    assert types[jaka_code_driver.name("tool_position")] == "geometry_msgs/PoseStamped"
    joints = rospy.wait_for_message(jaka_code_driver.name("joint_position"), JointState, 5.0)
    pose = rospy.wait_for_message(jaka_code_driver.name("tool_position"), PoseStamped, 5.0)
    fk = rospy.ServiceProxy(jaka_code_driver.name("get_fk"), GetFK)(joint=joints.position)
    p = pose.pose.position
    assert [p.x, p.y, p.z] == pytest.approx(list(fk.cartesian_pose[:3]), abs=1.0)   # mm
    state = rospy.wait_for_message(jaka_code_driver.name("robot_states"), RobotMsg, 5.0)
    assert state.servo_state == 1        # enabled, not in servo mode


def test_linear_move_reads_rpy_and_get_fk_answers_rpy(jaka_code_driver, rospy_node):
    import rospy
    from jaka_msgs.srv import GetFK, Move
    from sensor_msgs.msg import JointState
    move = rospy.ServiceProxy(jaka_code_driver.name("joint_move"), Move)
    assert move(pose=START, mvvelo=1.5, mvacc=4.0).ret == 1
    line = rospy.ServiceProxy(jaka_code_driver.name("linear_move"), Move)
    reply = line(pose=RPY_TARGET, mvvelo=100.0, mvacc=100.0)
    assert reply.ret == 1, reply.message
    joints = rospy.wait_for_message(jaka_code_driver.name("joint_position"), JointState, 5.0)
    fk = rospy.ServiceProxy(jaka_code_driver.name("get_fk"), GetFK)(joint=joints.position)
    answer = np.array(fk.cartesian_pose)
    assert answer[:3] == pytest.approx(RPY_TARGET[:3], abs=1.0)
    # RPY (π, 0, -π/2) has the spelling (-π, 0, -π/2) too: compare angles modulo 2π
    turn = (answer[3:] - RPY_TARGET[3:] + math.pi) % (2 * math.pi) - math.pi
    assert turn == pytest.approx([0, 0, 0], abs=2e-3)


def test_an_unknown_mode_stops_the_node_naming_both(rospy_node):
    proc = DriverProcess(log_name="conventions_unknown", backend="sim", conventions="jaka")
    try:
        assert wait_until(lambda: not proc.alive(), 60.0)
    finally:
        proc.stop()
        import rospy
        rospy.delete_param("/jaka_driver/conventions")   # rosrun's _conventions:= stays
    assert proc.proc.returncode == 2
    assert "unknown conventions 'jaka'; expected one of document, jaka_code" in \
        proc.log_path.read_text(errors="replace")
