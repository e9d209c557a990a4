"""Every convention where JAKA's document and JAKA's driver code differ, in both modes
(``document`` and ``jaka_code``), on RobotDriver over the real twin: one row per convention,
the expected numbers from the two written conventions (rotation vector / RPY as
R = Rz·Ry·Rx, mm vs m, mvvelo vs mvacc, servo mode vs enabled), computed here with their own
small formulas, not with the driver's transforms.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.conventions import DOCUMENT, JAKA_CODE, conventions_named
from jaka_driver.conventions.cartesian import reading_note
from jaka_driver.driver import RobotDriver
from jaka_driver.ros import messages
from jaka_driver.sim import SimBackend

from support.ros_harness import wait_until

Q_START = [-1.2, 1.57, -1.57, 1.57, 1.57, 0.0]   # rad
#: the issue's example: what a program written for JAKA's node sends (RPY, rad)
ANGLES = [math.pi, 0.0, -math.pi / 2]
POSITION_MM = [150.0, -460.0, 350.0]
RAD_S_SLOW, RAD_S_FAST = 0.1, 0.4


def rot_rpy(rx, ry, rz):
    """R = Rz(rz)·Ry(ry)·Rx(rx): JAKA's SDK's RPY."""
    cx, sx, cy, sy, cz, sz = (math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry),
                              math.cos(rz), math.sin(rz))
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def rot_vec(v):
    """Rodrigues: angle |v| about v/|v|."""
    v = np.asarray(v, float)
    angle = np.linalg.norm(v)
    if angle < 1e-12:
        return np.eye(3)
    k = v / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


READ = {"document": rot_vec, "jaka_code": lambda a: rot_rpy(*a)}


@pytest.fixture(scope="module", params=["document", "jaka_code"])
def driver(request):
    d = RobotDriver(SimBackend(load_model("zu5")), conventions=conventions_named(request.param))
    d.start()
    try:
        yield d
    finally:
        d.shutdown()


@pytest.fixture
def at_start(driver):
    driver.servo_move_enable(False)
    driver.stop_move()
    # a previous test's stop may still be decelerating the arm (-10 until it rests)
    assert wait_until(lambda: driver.joint_move(Q_START, 1.5, 4.0).ok, 5.0, 0.1)
    return driver


def test_the_switch_names_both_modes_and_servo_increment_is_the_finer_control():
    assert conventions_named("jaka_code") is JAKA_CODE and conventions_named("document") is DOCUMENT
    with pytest.raises(ValueError, match="document, jaka_code"):
        conventions_named("jaka")
    finer = DOCUMENT.with_servo_increment(True)
    assert finer.servo_increment and finer.name == "document + servo_increment"
    assert finer.cartesian_rotation == DOCUMENT.cartesian_rotation
    assert DOCUMENT.with_servo_increment(False) is DOCUMENT
    assert JAKA_CODE.with_servo_increment(False) is JAKA_CODE    # increments implied


def test_linear_move_reads_the_orientation_as_its_mode_says(at_start):
    d = at_start
    mode = d.conventions.name
    result = d.linear_move([*POSITION_MM, *ANGLES], 100.0, 100.0)
    assert result.ok, result.message
    tcp = d.state().tcp_pose
    assert tcp[:3, 3] * 1000 == pytest.approx(POSITION_MM, abs=1.0)
    assert tcp[:3, :3] == pytest.approx(READ[mode](ANGLES), abs=2e-3)
    # a document-mode answer says which reading it used, far apart as these two are
    note = "read as a rotation vector" in result.message and "conventions:=jaka_code" in \
        result.message
    assert note == (mode == "document"), result.message


def test_angles_that_read_alike_both_ways_carry_no_note(at_start):
    d = at_start
    # tool straight down: rotation vector (π, 0, 0) and RPY (π, 0, 0) are the same rotation
    result = d.linear_move([*POSITION_MM, math.pi, 0.0, 0.0], 100.0, 100.0)
    assert result.ok and "read as" not in result.message, result.message
    assert d.state().tcp_pose[:3, :3] == pytest.approx(rot_rpy(math.pi, 0, 0), abs=2e-3)
    assert reading_note(DOCUMENT, "pose", [0, 0, 0, 0.05, -0.03, 0.04]) is None


def test_linear_move_coord_mode_is_not_read_in_jaka_code(at_start):
    d = at_start
    here = d.state().tcp_pose.copy()
    pose = d.get_fk(d.state().joint_position).value
    # coord_mode 2 = relative in the tool frame (document); JAKA's code: the absolute target
    result = d.linear_move([0.0, 0.0, 20.0, 0.0, 0.0, 0.0] if d.conventions is DOCUMENT
                           else [pose[0], pose[1], pose[2] - 20, *pose[3:]], 100.0, 100.0,
                           coord_mode=2)
    assert result.ok, result.message
    moved = (d.state().tcp_pose[:3, 3] - here[:3, 3]) * 1000
    expected = here[:3, 2] * 20 if d.conventions is DOCUMENT else [0, 0, -20]
    assert moved == pytest.approx(expected, abs=1.0)
    assert ("coord_mode 2" in result.message) == (d.conventions is JAKA_CODE)


def test_get_fk_answers_in_the_modes_orientation(driver):
    d = driver
    fk = d.get_fk(Q_START)
    assert fk.ok
    T = d.backend.forward_kinematics(np.array(Q_START)).value
    assert np.array(fk.value[:3]) == pytest.approx(T[:3, 3] * 1000, abs=1e-6)
    assert READ[d.conventions.name](fk.value[3:]) == pytest.approx(T[:3, :3], abs=1e-9)


def test_get_ik_reads_the_modes_orientation(driver):
    d = driver
    ik = d.get_ik(Q_START, [*POSITION_MM, *ANGLES])
    assert ik.ok, ik.message
    T = d.backend.forward_kinematics(np.array(ik.value)).value
    assert T[:3, 3] * 1000 == pytest.approx(POSITION_MM, abs=0.1)
    assert T[:3, :3] == pytest.approx(READ[d.conventions.name](ANGLES), abs=1e-6)


def test_jog_speed_comes_from_the_modes_field(at_start):
    d = at_start
    result = d.jog(0, 0, RAD_S_FAST, RAD_S_SLOW)        # J1+, mvvelo fast, mvacc slow
    try:
        assert result.ok, result.message
        expected = RAD_S_FAST if d.conventions is DOCUMENT else RAD_S_SLOW
        assert wait_until(lambda: abs(d.state().joint_velocity[0] - expected) < 0.01, 3.0), \
            d.state().joint_velocity
    finally:
        d.stop_move()
    assert wait_until(lambda: np.abs(d.state().joint_velocity).max() < 1e-3, 3.0)
    zero = d.jog(0, 0, RAD_S_FAST, 0.0)    # mvacc 0: document jogs at mvvelo, jaka_code refuses
    d.stop_move()
    if d.conventions is DOCUMENT:
        assert zero.ok, zero.message
    else:
        assert zero.code == -2 and "mvacc" in zero.message and "jaka_code" in zero.message


def test_servo_j_takes_the_modes_reading(at_start):
    d = at_start
    assert d.servo_move_enable(True).ok
    try:
        start = d.state().joint_position.copy()
        step = np.array([0.001, 0, 0, 0, 0, 0.001])
        for _ in range(50):
            pose = step if d.conventions is JAKA_CODE else start + step
            result = d.servo_j(pose.tolist())
            assert result.ok, result.message
            time.sleep(0.008)
        expected = start + (50 * step if d.conventions is JAKA_CODE else step)
        assert wait_until(lambda: np.allclose(d.state().joint_position, expected, atol=2e-3),
                          3.0), d.state().joint_position - start
    finally:
        d.servo_move_enable(False)


def test_servo_state_and_tool_position_are_the_modes(driver):
    d = driver
    assert wait_until(lambda: d.state().enabled and not d.state().servo_mode, 3.0)
    msgs = messages.StateMessages(d.model.joint_names, d.conventions)
    st = d.state()
    msgs.fill(st)
    if d.conventions is JAKA_CODE:
        assert msgs.robot.servo_state == 1       # enabled, servo mode off
        assert type(msgs.tool).__name__ == "PoseStamped"
        p, q = msgs.tool.pose.position, msgs.tool.pose.orientation
        assert [p.x, p.y, p.z] == pytest.approx(st.tcp_pose[:3, 3] * 1000, abs=1e-9)
        x, y, z, w = q.x, q.y, q.z, q.w
        R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        assert R == pytest.approx(st.tcp_pose[:3, :3], abs=1e-9)
    else:
        assert msgs.robot.servo_state == 0       # servo mode off
        assert type(msgs.tool).__name__ == "TwistStamped"
        lin, ang = msgs.tool.twist.linear, msgs.tool.twist.angular
        assert [lin.x, lin.y, lin.z] == pytest.approx(st.tcp_pose[:3, 3], abs=1e-12)
        assert rot_vec([ang.x, ang.y, ang.z]) == pytest.approx(st.tcp_pose[:3, :3], abs=1e-9)
    assert msgs.tool.header.frame_id == "base_link"
