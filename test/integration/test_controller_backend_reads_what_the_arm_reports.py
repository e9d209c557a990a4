"""The controller backend against the scripted fake controller (test/support/fake_controller.py,
which answers from the fixtures in test/data/, not the emulator): frames defined on the teach pendant
are read back by id (at connection, and when the pendant activates another one); the arm's
kinematic parameters (get_dh_param) and identity strings are read at connection, compared with
the model's own chain and shown in describe(), with a warning when they are another arm's;
moveL carries the driver's orientation limits and is timed by the twin's law; joint velocity
and effort come from the packet's instVel and monitor_data; the torque sensor's error counts;
a reply that cannot be parsed closes the command connection, the link reconnects and the drop
is counted."""
from __future__ import annotations

import json
import logging
import math

import numpy as np
import pytest

from support.fake_controller import backend, fake  # noqa: F401 - fixtures
from support.fake_controller import (FakeController, load_status_packet, load_transcript,
                                     start_backend)
from support.move_helpers import run_move
from support.ros_harness import wait_until

from jaka_driver.common.results import Code
from jaka_driver.common.transforms import pose_mm_rpy_to_matrix, pose_to_matrix
from jaka_driver.kinematics.controller_dh import CALIBRATION_TOLERANCE
from jaka_driver.motion.linear_path import line_duration

PACKET = json.loads(load_status_packet())


def transcript_reply(name):
    for request, reply, _ in load_transcript():
        if json.loads(request)["cmdName"] == name and '"errorCode": "0"' in reply:
            return json.loads(reply)
    raise KeyError(name)


def wire_pose(row):
    """A frame table row (mm, RPY deg) as a 4x4 in metres."""
    return pose_mm_rpy_to_matrix([*row[:3], *np.radians(row[3:])])


# ---- frames by id ------------------------------------------------------------------------------

def test_frames_defined_on_the_pendant_are_read_back_by_id(fake, backend):
    tools = transcript_reply("get_tool_offsets")["tool_offsets"]
    users = transcript_reply("get_user_offsets")["user_offsets"]
    assert fake.received("get_tool_offsets") and fake.received("get_user_offsets")
    assert backend.describe()["tool offsets read from the controller"]

    # the fixture's tables hold tool 1 and user frame 1: known since the connection
    fake.on_pendant("tool", 1)
    fake.on_pendant("user", 1)
    assert wait_until(lambda: backend.state().tool_id == 1 and backend.state().user_id == 1, 1)
    tool, user = backend.frames()
    np.testing.assert_allclose(tool, wire_pose(tools[1]), atol=1e-12)
    np.testing.assert_allclose(user, wire_pose(users[1]), atol=1e-12)
    assert tool[2, 3] == pytest.approx(0.1)   # 100 mm along the flange's z

    # an operator stores tool 4 and activates it: the backend reads the table again
    reads = len(fake.received("get_tool_offsets"))
    fake.on_pendant("tool", 4, [10, -20, 30, 0, 0, 45])
    assert wait_until(lambda: len(fake.received("get_tool_offsets")) > reads, 2.0)
    expected = wire_pose([10, -20, 30, 0, 0, 45])
    assert wait_until(lambda: np.allclose(backend.frames()[0], expected, atol=1e-12), 2.0)


def test_an_id_the_tables_do_not_hold_reads_as_identity_with_one_warning(fake, backend, caplog):
    with caplog.at_level(logging.WARNING, logger="jaka_driver.controller.frames_by_id"):
        fake.on_pendant("user", 12)   # beyond the 11 rows (ids 0-10) a controller stores
        assert wait_until(lambda: backend.state().user_id == 12, 1.0)
        np.testing.assert_allclose(backend.frames()[1], np.eye(4))
        backend.frames()
    warnings = [r for r in caplog.records if "user frame 12" in r.getMessage()]
    assert len(warnings) == 1 and "ids 0-10" in warnings[0].getMessage()


def test_a_table_of_another_shape_leaves_the_frames_unknown_not_wrong(caplog):
    with FakeController() as fake:
        fake.replies["get_tool_offsets"]["tool_offsets"] = [0, 0, 100, 0, 0, 90]   # flat
        fake.offsets["tool"] = [0, 0, 100, 0, 0, 90]
        with caplog.at_level(logging.WARNING):
            backend = start_backend(fake)
        try:
            assert not backend.describe()["tool offsets read from the controller"]
            assert backend.describe()["user frame offsets read from the controller"]
            assert any("tool offsets could not be read" in r.getMessage()
                       for r in caplog.records)
        finally:
            backend.shutdown()


# ---- identity and kinematic parameters -----------------------------------------------------------

def test_the_arms_kinematic_parameters_and_identity_are_read_at_connection(fake, backend):
    info = backend.describe()
    version = transcript_reply("get_version")
    assert info["controller version"] == version["version"]
    assert info["robot id"] == version["robot_id"] and info["robot name"] == version["robot_name"]
    assert info["controller id"] == version["controller_id"]
    assert info["servo version"] == version["servo_version"]
    assert fake.received("get_dh_param")
    assert info["controller dh_param"].startswith("alpha deg [0.000, 90.000")
    # the fixture is a Zu 5's: within a calibration of model zu5
    assert info["arm matches the model"] is True
    assert info["dh difference to the model (mm)"] < CALIBRATION_TOLERANCE * 1000


def test_another_arms_parameters_are_named_and_refuse_motion(caplog):
    with FakeController() as fake, caplog.at_level(logging.INFO,
                                                    logger="jaka_driver.controller"):
        backend = start_backend(fake, model="zu12")
        try:
            info = backend.describe()
            assert info["arm matches the model"] is False
            assert info["dh difference to the model (mm)"] > 100
            assert "motion refused" in info["kinematics"]
            refused = backend.start_joint_move(np.zeros(6), 1.0, 1.0)
            assert refused.code == Code.WRONG_MODE and "model:=zu5" in refused.message
            assert not fake.received("joint_move")
        finally:
            backend.shutdown()
    messages = [r.getMessage() for r in caplog.records]
    # one line says what is wrong and what to do: the recorded arm is a (calibrated) Zu 5
    errors = [r.getMessage() for r in caplog.records if r.levelno == logging.ERROR]
    assert any("model:=zu12 does not match the arm" in m and "a zu5's" in m
               and "restart with model:=zu5" in m and "kinematics:=model" in m for m in errors), errors
    # logged beside each other: the controller's parameters and the model's
    assert any("of the controller (get_dh_param)" in m and "d mm [120.150" in m
               for m in messages)
    assert any("of model zu12" in m for m in messages)


# ---- moveL ---------------------------------------------------------------------------------------

def test_move_l_carries_the_drivers_orientation_limits_and_the_twins_time_law(fake, backend):
    here = backend.state().tcp_pose
    target = here @ pose_to_matrix([0.03, 0.0, 0.02, 0.0, 0.0, 0.4])
    speed, accel = 0.05, 0.2                     # m/s, m/s²
    started = backend.start_linear_move(target, speed, accel)
    assert started.ok, started.message
    sent = fake.received("moveL")[-1]
    # the twin's limits for this speed: speed / 0.1 m (a point 0.1 m from the axis), capped
    assert sent["ori_vel"] == pytest.approx(math.degrees(min(speed / 0.1, math.pi)))
    assert sent["ori_acc"] == pytest.approx(math.degrees(min(accel / 0.1, 2 * math.pi)))
    assert (sent["speed"], sent["accel"]) == pytest.approx((50.0, 200.0))
    assert started.value[1] == pytest.approx(line_duration(here, target, speed, accel))
    assert run_move(started).ok


def test_a_fast_move_l_turns_at_the_drivers_cap_not_the_controllers_default(fake, backend):
    target = backend.state().tcp_pose @ pose_to_matrix([0.0, 0.0, 0.0, 0.0, 0.0, 1.0])
    assert run_move(backend.start_linear_move(target, 1.0, 5.0)).ok
    sent = fake.received("moveL")[-1]
    assert sent["ori_vel"] == pytest.approx(180.0) and sent["ori_acc"] == pytest.approx(360.0)
    assert sent["ori_vel"] < math.degrees(3.14) + 1 and sent["ori_acc"] < math.degrees(12.56)


# ---- the packet: velocity, effort, errors --------------------------------------------------------

def test_velocity_and_effort_come_from_the_packet(fake, backend):
    torques = [row[9] for row in PACKET["monitor_data"][5]]
    st = backend.state()
    np.testing.assert_allclose(st.joint_effort, torques)
    np.testing.assert_allclose(st.joint_velocity, np.zeros(6))
    with fake.lock:
        fake.packet["instVel"] = [10.0, -5.0, 0.0, 0.0, 0.0, 90.0]   # deg/s
    assert wait_until(lambda: backend.state().joint_velocity[0] > 0, 1.0)
    np.testing.assert_allclose(backend.state().joint_velocity,
                               np.radians([10.0, -5.0, 0.0, 0.0, 0.0, 90.0]))


def test_a_torque_sensor_error_is_the_arms_error_when_the_controller_reports_none(fake, backend):
    with fake.lock:
        fake.packet["torqsensor"][1][1] = 4
    assert wait_until(lambda: backend.state().error_code == 4, 1.0)
    st = backend.state()
    assert st.in_error and "torque sensor error 4" in st.error_message


def test_an_unreadable_packet_position_keeps_the_last_joints_not_zeros(fake, backend):
    before = backend.state().joint_position
    assert np.all(np.abs(before[:5]) > 0.1)
    with fake.lock:
        fake.joints = [None] * 6   # what no controller sends
    assert wait_until(lambda: "joint_actual_position" in
                      backend.describe().get("malformed status fields", ()), 1.0)
    np.testing.assert_allclose(backend.state().joint_position, before)
    assert backend.describe()[f"status port {fake.status_port} fields dropped"] > 0


# ---- malformed replies ---------------------------------------------------------------------------

def test_a_malformed_reply_closes_the_command_connection_and_the_link_comes_back(fake, backend):
    fake.raw_replies["get_digital_input"] = (b'{"errorCode": "0", "errorMsg": "", "cmdName": '
                                             b'"get_digital_input", "value": ' + b"[" * 100_000)
    result = backend.get_io("digital", 0, 0, 0)
    assert result.code == Code.COMMUNICATION_ERROR and "malformed" in result.message
    assert wait_until(lambda: backend.link.reconnects == 1 and backend.link.connected, 5.0)
    assert backend.describe()["command replies dropped"] == 1
    assert backend.get_io("digital", 0, 0, 0).ok
