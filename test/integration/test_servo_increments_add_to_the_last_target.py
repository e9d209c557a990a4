"""``servo_increment``: RobotDriver reads servo_j / servo_p as increments of the last target it
commanded, as JAKA's driver code sends them (its servoj_demo: {0.001, 0, 0, 0, 0, 0.001}, again
and again), on the real zu5 twin without ROS: N increments of d move the target by exactly N·d
however fast they come; a servo_p increment after servo_j starts from the TCP of the last joint
target; a refused increment leaves the next one relative to where the arm stands."""
from __future__ import annotations

import time

import numpy as np
import pytest

from jaka_driver.common import load_model
from jaka_driver.driver import RobotDriver
from jaka_driver.kinematics import Kinematics
from jaka_driver.sim import SimBackend

STEP = [0.001, 0, 0, 0, 0, 0.001]     # rad: JAKA's servoj_demo


@pytest.fixture(scope="module")
def driver():
    d = RobotDriver(SimBackend(load_model("zu5")), servo_increment=True)
    d.start()
    yield d
    d.shutdown()


def goal(driver) -> np.ndarray:
    return driver.backend.twin.servo_goal()


def test_increments_add_up_to_their_sum(driver):
    assert driver.servo_move_enable(True).ok
    q0 = driver.state().joint_position.copy()
    for _ in range(50):
        reply = driver.servo_j(STEP)
        assert reply.ok, reply.message
        time.sleep(0.002)                 # faster than the arm follows: the target adds up
    np.testing.assert_allclose(goal(driver), q0 + 50 * np.array(STEP), atol=1e-12)


def test_a_servo_p_increment_starts_from_the_last_joint_target(driver):
    kin = Kinematics(driver.model)
    before = kin.tcp_pose(goal(driver))
    reply = driver.servo_p([0.0, 0.0, 2.0, 0.0, 0.0, 0.0])      # mm
    assert reply.ok, reply.message
    after = kin.tcp_pose(goal(driver))
    np.testing.assert_allclose(after[:3, 3] - before[:3, 3], [0, 0, 0.002], atol=1e-6)
    np.testing.assert_allclose(after[:3, :3], before[:3, :3], atol=1e-6)


def test_a_refused_increment_leaves_the_next_relative_to_the_arm(driver):
    refused = driver.servo_j([1.0, 0, 0, 0, 0, 0])               # 1 rad in one cycle
    assert refused.code == -2 and "joint_1" in refused.message
    time.sleep(0.1)                                              # the arm reaches its target
    here = driver.state().joint_position.copy()
    assert driver.servo_j(STEP).ok
    np.testing.assert_allclose(goal(driver), here + STEP, atol=2e-5)
    assert driver.servo_move_enable(False).ok
