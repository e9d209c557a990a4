"""JAKA's official ROS 1 node, as its code calls JAKA's SDK (test/jaka_sdk_model.py: the SDK's
requests and its strict reading of replies, from the measured evidence), runs its whole session
against the emulator in its default profile (the controller JAKA's SDK is written for; found
powered off, so the node's own power-on runs): start-up
(login, status over port 10004, power, enable, the servo filter), its state loop polling
get_program_state and the status about 8 times a second the whole time, and one call of every
service. Nothing would abort the SDK (a number for programState killed the real node 5.5 s
after its start), every service answers success — except servo disable, whose -61 is the SDK's
own bug — and each reaches the arm."""
from __future__ import annotations

import json
import math
import time

import numpy as np
import pytest

from jaka_ros_node_model import JakaRosNode
from jaka_sdk_model import RC_OK, RC_TIMEOUT, JakaSdk

from jaka_driver.emulator import Emulator


@pytest.fixture(scope="module")
def emu():
    with Emulator("zu5", command_port=0, status_port=0, start="off") as emulator:
        yield emulator


@pytest.fixture(scope="module")
def node(emu):
    sdk = JakaSdk("127.0.0.1", emu.command_port, emu.data_port)
    ros = JakaRosNode(sdk, power_wait=0.2, enable_wait=0.2)   # the node sleeps 8 s and 4 s
    assert not emu.backend.state().powered
    ros.identity = ros.start_up()
    ros.start_polling()
    yield ros
    ros.stop_polling()
    sdk.close()
    # the state loop ran the whole module without anything that would abort the SDK
    assert not ros.failures, ros.failures
    assert ros.polls > 10


def test_start_up_logs_in_powers_on_enables_and_sets_the_servo_filter(emu, node):
    assert set(node.identity) == {"version", "controller_id", "controller_guarantee",
                                  "robot_id", "robot_name", "scb_version", "servo_version"}
    assert node.identity["version"] == emu.profile.version == "1.7.2_16_X64"
    assert "emulator" in node.identity["robot_name"]
    assert emu.backend.state().powered and emu.backend.state().enabled
    assert emu.controller.servo_filter == (5, {"mmf_max_buf": 15, "mmf_kp": 0.03})
    motion, status = node.robot_state()
    assert motion == 0, "idle: errcode 0, in position, program idle, not dragging"
    assert status.powered_on == 1 and status.enabled and status.errcode == 0


def test_joint_move_fk_ik_and_linear_move(emu, node):
    _, status = node.sdk.get_robot_status()
    start = np.array(status.joint_position)
    target = start + np.array([0.2, -0.1, 0.15, 0.1, 0.0, 0.2])
    assert node.joint_move(target, 1.0, 3.0) == RC_OK
    assert np.max(np.abs(emu.backend.state().joint_position - target)) < 1e-3
    rc, pose = node.get_fk(target)
    assert rc == RC_OK
    rc, q = node.get_ik(target, pose)
    assert rc == RC_OK and np.allclose(q, target, atol=1e-5)
    up = list(pose)
    up[2] += 30.0                                             # mm
    assert node.linear_move(up, 50.0, 200.0) == RC_OK
    _, status = node.sdk.get_robot_status()
    assert np.allclose(status.cartesiantran_position[:3], up[:3], atol=0.5)
    assert node.joint_move(start, 1.0, 3.0) == RC_OK


def test_jog_and_stop_move(emu, node):
    before = emu.backend.state().joint_position.copy()
    assert node.jog(1, 0, 0.2) == RC_OK                      # joint 1, negative, 0.2 rad/s
    time.sleep(0.5)
    assert emu.backend.state().joint_position[0] < before[0] - 0.03
    assert node.stop_move() == RC_OK
    time.sleep(0.4)
    assert not emu.controller.moving and not emu.backend.twin.motion_active


def test_servo_mode_servo_j_servo_p_and_the_sdks_own_disable_timeout(emu, node):
    assert node.servo_move_enable(True) == RC_OK and emu.backend.state().servo_mode
    q0 = emu.backend.state().joint_position.copy()
    for _ in range(50):
        assert node.servo_j([0.001, 0, 0, 0, 0, 0.001]) == RC_OK
        time.sleep(0.008)
    assert node.servo_p([0.5, 0, 0, 0, 0, 0]) == RC_OK
    time.sleep(0.3)
    moved = emu.backend.state().joint_position - q0
    assert abs(moved[0] - 0.05) < 5e-3 and abs(moved[5] - 0.05) < 5e-3
    # the SDK waits for in_servomove true also when it disables: -61, and servo mode is left
    assert node.servo_move_enable(False) == RC_TIMEOUT
    assert not emu.backend.state().servo_mode


def test_frames_payload_collision_and_drag(emu, node):
    assert node.set_toolframe(1, [0.0, 0.0, 100.0, 0.0, 0.0, math.pi / 2]) == RC_OK
    rc, tool = node.sdk.get_tool_data(1)
    assert rc == RC_OK and np.allclose(tool, [0, 0, 100, 0, 0, math.pi / 2], atol=1e-6)
    assert node.set_userframe(1, [300.0, -200.0, 50.0, 0.0, 0.0, 0.3]) == RC_OK
    rc, user = node.sdk.get_user_frame_data(1)
    assert rc == RC_OK and np.allclose(user, [300, -200, 50, 0, 0, 0.3], atol=1e-6)
    assert node.set_payload(1, 1.0, 0.0, 0.0, 50.0) == RC_OK
    assert emu.controller.payload_mass == 1.0 and emu.backend.state().tool_id == 1
    assert node.set_payload(0, 0.0, 0.0, 0.0, 0.0) == RC_OK and emu.backend.state().tool_id == 0
    assert node.set_collisionlevel(50) == RC_OK and emu.backend.twin.collision_level == 2
    assert node.drag_move(True) == RC_OK and emu.backend.state().drag_mode
    motion, status = node.robot_state()
    assert status.drag_status and motion == 3
    assert node.drag_move(False) == RC_OK and not emu.backend.state().drag_mode


def test_set_io_and_get_io(emu, node):
    assert node.set_io("digital", 0, 2, 1.0) == RC_OK
    assert node.get_io("digital", 1, 0, 2) == (RC_OK, 1.0)
    assert node.set_io("analog", 0, 6, 2.5) == RC_OK
    assert node.get_io("analog", 1, 0, 6) == (RC_OK, 2.5)
    assert node.set_io("digital", 1, 0, 1.0) == RC_OK      # tool output 0
    assert node.get_io("digital", 0, 0, 0) == (RC_OK, 0.0)
    _, status = node.sdk.get_robot_status()
    # element 0 is the count; the SDK's index i is element i + 1
    assert status.dout[0] == 144 and status.dout[3] == 1 and status.aout[7] == 2.5
    assert status.tio_dout[0] == 8 and status.tio_dout[1] == 1
    for signal, io_type, index in (("digital", 0, 2), ("analog", 0, 6), ("digital", 1, 0)):
        assert node.set_io(signal, io_type, index, 0.0) == RC_OK


def test_every_command_the_node_sent_is_one_the_emulator_knows(emu, node):
    sent = {json.loads(text)["cmdName"] for text in node.sdk.sent}
    assert sent <= set(emu.handlers.command_names), sent - set(emu.handlers.command_names)
