"""``jaka_code`` conventions on the controller backend, against the emulator (the twin behind
JAKA's protocol): the calls a program written for JAKA's driver makes reach the poses JAKA's
driver reaches — linear_move with an RPY target, servoj_demo's 200 joint increments (sent as
relative servo_j, as JAKA's SDK sends them), servo_p increments in mm, and a jog at the speed in
mvacc. Expected numbers from JAKA's driver code's conventions, with the test's own formulas.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pytest

from support.emulated_arm import driver_on_emulator
from support.ros_harness import wait_until

from jaka_driver.conventions import JAKA_CODE

START = [-1.2, 1.57, -1.57, 1.57, 1.57, 0.0]                # rad
TARGET_MM = [150.0, -460.0, 350.0]
TARGET_RPY = [math.pi, 0.0, -math.pi / 2]                 # rad
SERVOJ_DEMO_STEP = np.array([0.001, 0, 0, 0, 0, 0.001], dtype=np.float32).tolist()


def rot_rpy(rx, ry, rz):
    """R = Rz(rz)·Ry(ry)·Rx(rx)."""
    cx, sx, cy, sy, cz, sz = (math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry),
                              math.cos(rz), math.sin(rz))
    return (np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
            @ np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
            @ np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]]))


@pytest.fixture(scope="module")
def arm():
    with driver_on_emulator(conventions=JAKA_CODE) as (emu, driver):
        assert wait_until(lambda: driver.state().connected and driver.state().enabled, 10.0)
        yield emu, driver


@pytest.fixture
def at_start(arm):
    emu, d = arm
    d.servo_move_enable(False)
    # a previous test's stop may still be decelerating the arm (-10 until it rests)
    assert wait_until(lambda: d.joint_move(START, 1.5, 4.0).ok, 5.0, 0.1)
    return emu, d


def test_linear_move_reaches_the_rpy_target(at_start):
    emu, d = at_start
    result = d.linear_move([*TARGET_MM, *TARGET_RPY], 100.0, 100.0)
    assert result.ok, result.message
    tcp = emu.backend.state().tcp_pose        # the arm behind the controller
    assert tcp[:3, 3] * 1000 == pytest.approx(TARGET_MM, abs=1.0)
    assert tcp[:3, :3] == pytest.approx(rot_rpy(*TARGET_RPY), abs=2e-3)


def test_servoj_demos_increments_move_joints_1_and_6_by_0_2_rad(at_start):
    emu, d = at_start
    assert d.servo_move_enable(True).ok
    try:
        start = emu.backend.state().joint_position.copy()
        for _ in range(200):
            result = d.servo_j(SERVOJ_DEMO_STEP)
            assert result.ok, result.message
            time.sleep(0.008)
        expected = start + 200 * np.array(SERVOJ_DEMO_STEP)
        assert wait_until(lambda: np.allclose(emu.backend.state().joint_position, expected,
                                              atol=2e-3), 3.0), \
            emu.backend.state().joint_position - start
    finally:
        d.servo_move_enable(False)


def test_servo_p_increments_are_mm(at_start):
    emu, d = at_start
    assert d.servo_move_enable(True).ok
    try:
        start = emu.backend.state().tcp_pose.copy()
        for _ in range(20):
            result = d.servo_p([1.0, 0.0, 0.0, 0.0, 0.0, 0.0])     # +1 mm along x
            assert result.ok, result.message
            time.sleep(0.008)
        assert wait_until(lambda: np.allclose(
            (emu.backend.state().tcp_pose[:3, 3] - start[:3, 3]) * 1000, [20, 0, 0], atol=0.5),
            3.0), (emu.backend.state().tcp_pose[:3, 3] - start[:3, 3]) * 1000
        assert emu.backend.state().tcp_pose[:3, :3] == pytest.approx(start[:3, :3], abs=2e-3)
    finally:
        d.servo_move_enable(False)


def test_jog_runs_at_the_speed_in_mvacc(at_start):
    emu, d = at_start
    result = d.jog(0, 0, 0.4, 0.1)                # J1+: mvvelo 0.4 is not read, mvacc 0.1 is
    try:
        assert result.ok, result.message
        assert wait_until(lambda: abs(emu.backend.state().joint_velocity[0] - 0.1) < 0.01,
                          3.0), emu.backend.state().joint_velocity
    finally:
        d.stop_move()
