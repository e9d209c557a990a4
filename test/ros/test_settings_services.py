"""Frames, payload, drag, collision level (set and read back), the installation angle, the
latched on_limit, IO, clear_err and FK/IK through ROS on the zu5
twin: each does what docs/interface.md says, and each bad request is refused naming the field."""
import time

import numpy as np
import pytest
import rosservice
from geometry_msgs.msg import TwistStamped
from std_msgs.msg import Bool
from std_srvs.srv import Empty, SetBool

from support.ros_harness import START, Recorder, at_rest, position, wait_until
from jaka_driver_msgs.srv import GetCollisionLevel, GetInstallationAngle, SetInstallationAngle
from jaka_msgs.msg import RobotMsg
from jaka_msgs.srv import (ClearErr, ClearError, GetFK, GetIK, GetIO, Move, SetCollision,
                           SetIO, SetPayload, SetTcpFrame, SetUserFrame)

pytestmark = pytest.mark.ros


CONTRACT_SERVICES = {
    "linear_move", "joint_move", "jog", "servo_move_enable", "servo_p", "servo_j", "stop_move",
    "set_toolframe", "set_userframe", "set_payload", "drag_mode", "drag_move",
    "set_collisionlevel", "set_io", "get_io", "clear_err", "clear_error", "get_fk", "get_ik",
    "power", "enable", "get_collision_level", "set_installation_angle",
    "get_installation_angle"}


def fk(call, q):
    return np.array(call("get_fk", GetFK, joint=list(q)).cartesian_pose)


def test_the_node_serves_every_contract_service(sim_driver):
    served = {name.rsplit("/", 1)[1] for name in rosservice.get_service_list()
              if name.startswith("/jaka_driver/")}
    assert CONTRACT_SERVICES <= served, CONTRACT_SERVICES - served


def test_tool_frame_moves_the_reported_tcp_along_the_flange_axes(call):
    flange = fk(call, START)
    assert call("set_toolframe", SetTcpFrame, pose=[0, 0, 100.0, 0, 0, 0], tool_num=1).ret == 1
    try:
        tool = fk(call, START)
        from jaka_driver.common.transforms import rotvec_to_matrix
        z = rotvec_to_matrix(flange[3:])[:, 2]
        assert np.allclose(tool[:3] - flange[:3], 100.0 * z, atol=1e-3)
    finally:
        assert call("set_toolframe", SetTcpFrame, pose=[0] * 6, tool_num=0).ret == 1
    assert np.allclose(fk(call, START), flange, atol=1e-4)


def test_user_frame_expresses_poses_relative_to_it(call, sim_driver, rospy_node):
    base = fk(call, START)
    assert call("set_userframe", SetUserFrame, pose=[100, 200, 0, 0, 0, np.pi / 2],
                user_num=2).ret == 1
    tcp = Recorder(sim_driver.name("tool_position"), TwistStamped)
    try:
        in_user = fk(call, START)
        # user x axis = base y, origin (100, 200): base (x, y) → user (y - 200, -(x - 100))
        assert np.allclose(in_user[:2], [base[1] - 200, -(base[0] - 100)], atol=1e-3)
        msg = wait_until(lambda: (m := tcp.latest()) is not None
                         and m.header.frame_id == "user_frame_2" and m, 2.0)
        assert msg, "tool_position not in user_frame_2"
    finally:
        tcp.close()
        call("set_userframe", SetUserFrame, pose=[0] * 6, user_num=0)


@pytest.mark.parametrize("service, srv, fields, words", [
    ("set_toolframe", SetTcpFrame, dict(pose=[0] * 6, tool_num=12), "tool_num is 12, expected 0–11"),
    ("set_userframe", SetUserFrame, dict(pose=[0] * 6, user_num=11), "user_num is 11, expected 0–10"),
    ("set_toolframe", SetTcpFrame, dict(pose=[0] * 5, tool_num=1), "pose has 5 values"),
    ("set_payload", SetPayload, dict(tool_num=0, mass=8.0), "mass is 8 kg, expected 0–7.5 kg"),
    ("set_payload", SetPayload, dict(tool_num=0, mass=-1.0), "mass is -1 kg"),
    ("set_collisionlevel", SetCollision, dict(is_enable=True, value=5), "value is 5, expected 10–100"),
    ("set_io", SetIO, dict(signal="foo", type=0, index=0, value=1), "signal is 'foo'"),
    ("set_io", SetIO, dict(signal="digital", type=3, index=0, value=1), "type is 3, expected 0–2"),
    ("set_io", SetIO, dict(signal="digital", type=0, index=99, value=1), "index is 99"),
])
def test_bad_settings_are_refused_with_the_field_named(call, service, srv, fields, words):
    reply = call(service, srv, **fields)
    assert reply.ret == -2, reply.message
    assert words in reply.message, reply.message


def test_payload_is_carried_by_the_twin(call, joints):
    assert call("joint_move", Move, pose=[0, 0.3, 0.0, 0, 0, 0], mvvelo=2.0, mvacc=8.0).ret == 1
    time.sleep(0.2)
    effort_before = np.array(joints.latest().effort)
    assert call("set_payload", SetPayload, tool_num=0, mass=5.0, xc=0, yc=0, zc=50).ret == 1
    time.sleep(0.3)
    effort_after = np.array(joints.latest().effort)
    # 5 kg held out ~0.9 m from joint 2: ≈ 44 N·m more on the shoulder.
    assert abs(effort_after[1] - effort_before[1]) > 20.0, (effort_before, effort_after)
    assert np.max(np.abs(position(joints) - [0, 0.3, 0.0, 0, 0, 0])) < 2e-3
    assert call("set_payload", SetPayload, tool_num=0, mass=0.0).ret == 1
    assert call("joint_move", Move, pose=START, mvvelo=2.0, mvacc=8.0).ret == 1


def test_drag_mode_releases_the_servos_and_refuses_motion(call, joints):
    assert call("drag_mode", SetBool, data=True).success
    try:
        reply = call("joint_move", Move, pose=START, mvvelo=1.0, mvacc=1.0)
        assert reply.ret == -9 and "drag" in reply.message
        time.sleep(0.5)
        # gravity compensated: the released arm does not sag
        assert np.max(np.abs(position(joints) - START)) < 0.01
    finally:
        assert call("drag_move", SetBool, data=False).success


def test_io_outputs_read_back_and_digital_is_0_or_1(call):
    assert call("set_io", SetIO, signal="DIGITAL", type=0, index=3, value=5.0).ret == 1
    assert call("get_io", GetIO, signal="digital", path=1, type=0, index=3).value == 1.0
    assert call("set_io", SetIO, signal="analog", type=2, index=1, value=2.5).ret == 1
    assert call("get_io", GetIO, signal="analog", path=1, type=2, index=1).value == 2.5
    bad = call("get_io", GetIO, signal="digital", path=2, type=0, index=0)
    assert bad.value == -999999 and bad.message.startswith("error:")


def test_collision_level_can_be_turned_off(call):
    reply = call("set_collisionlevel", SetCollision, is_enable=False, value=0)
    assert reply.ret == 1 and "off" in reply.message
    assert call("get_collision_level", GetCollisionLevel).level == 0
    reply = call("set_collisionlevel", SetCollision, is_enable=True, value=60)
    assert reply.ret == 1 and "level 3" in reply.message
    got = call("get_collision_level", GetCollisionLevel)
    assert (got.level, got.ret) == (3, 1)


def test_installation_angle_turns_gravity_and_reads_back_in_rad(call, sim_driver, rospy_node):
    try:
        reply = call("set_installation_angle", SetInstallationAngle, tilt_x=np.pi / 2, rot_z=0.5)
        assert reply.ret == 1 and "keep the launch's mounting" in reply.message
        got = call("get_installation_angle", GetInstallationAngle)
        assert got.ret == 1 and np.allclose(got.rpy, [np.pi / 2, 0.0, 0.5])
        # Rz(0.5)·Rx(π/2) = (cos 0.25 + k sin 0.25)(cos π/4 + i sin π/4), as (x, y, z, w)
        c, s, h = np.cos(0.25), np.sin(0.25), np.sqrt(0.5)
        assert np.allclose(got.quaternion, [c * h, s * h, s * h, c * h], atol=1e-9)
        bad = call("set_installation_angle", SetInstallationAngle, tilt_x=3.5, rot_z=0.0)
        assert bad.ret == -2 and "tilt_x is 3.5 rad" in bad.message and "180" in bad.message
        assert np.allclose(call("get_installation_angle", GetInstallationAngle).rpy,
                           [np.pi / 2, 0.0, 0.5])          # the refusal changed nothing
    finally:
        assert call("set_installation_angle", SetInstallationAngle, tilt_x=0, rot_z=0).ret == 1


def test_on_limit_is_latched_and_false_at_home(sim_driver, rospy_node):
    latched = Recorder(sim_driver.name("on_limit"), Bool)
    message = wait_until(latched.latest, 3.0)
    assert message is not None and message.data is False


def test_ik_inverts_fk_near_the_reference(call):
    q = [0.3, 1.4, -1.3, 1.7, 1.5, 0.2]
    pose = fk(call, q)
    reply = call("get_ik", GetIK, ref_joint=[0.25, 1.35, -1.25, 1.65, 1.45, 0.25],
                 cartesian_pose=list(pose))
    assert np.allclose(reply.joint, q, atol=1e-4), reply.message
    bad = call("get_ik", GetIK, ref_joint=q, cartesian_pose=[5000, 0, 0, 0, 0, 0])
    assert list(bad.joint) == [9999] * 6 and bad.message.startswith("error:")


def test_clear_err_is_served_under_both_names(call):
    assert call("clear_err", ClearErr).ret == 1
    assert call("clear_error", ClearError, enable=True).ret == 1


def test_robot_states_report_powered_idle_arm(sim_driver, rospy_node):
    states = Recorder(sim_driver.name("robot_states"), RobotMsg)
    try:
        msg = wait_until(states.latest, 2.0)
        assert (msg.motion_state, msg.power_state, msg.servo_state, msg.collision_state) == \
            (0, 1, 0, 0)
    finally:
        states.close()
