"""A speed ratio of 0.5 doubles a joint_move's duration within 2 % on the twin and on the
controller backend through the emulator (whose get_rapid_rate then reads 0.5): the law is time
× 1/r (speeds × r, accelerations × r²) everywhere; a ratio outside (0, 1] is refused and changes
nothing; a servo stream is not scaled."""
import time

import numpy as np
import pytest

from support.emulated_arm import driver_on_emulator
from jaka_driver.common.models import load_model
from jaka_driver.driver import RobotDriver
from jaka_driver.protocol import commands
from jaka_driver.sim import SimBackend

MODEL = load_model("zu5")
HOME = MODEL.home
TARGET = [0.5, 1.2, -1.0, 1.9, 1.2, 0.8]


def timed_move(driver, target, clock):
    t0 = clock()
    result = driver.joint_move(target, 1.0, 3.0)
    assert result.ok, result.message
    return clock() - t0


def doubled(driver, clock):
    """(duration at ratio 1, duration at ratio 0.5) of the same move out and back."""
    full = timed_move(driver, TARGET, clock)
    timed_move(driver, list(HOME), clock)
    assert driver.set_speed_ratio(0.5).ok
    half = timed_move(driver, TARGET, clock)
    return full, half


def test_a_ratio_of_half_doubles_a_joint_move_on_the_twin():
    driver = RobotDriver(SimBackend(MODEL, sim_time=True, real_time_factor=0))
    driver.start()
    try:
        clock = driver.clock
        with clock.hold():
            full, half = doubled(driver, clock.now)
        assert abs(half / full - 2.0) <= 0.04, (full, half)       # within 2 %
        assert driver.speed_ratio() == 0.5
    finally:
        driver.shutdown()


def test_a_ratio_of_half_doubles_a_joint_move_through_the_emulator():
    with driver_on_emulator() as (emu, driver):
        full, half = doubled(driver, time.monotonic)
        assert abs(half / full - 2.0) <= 0.04, (full, half)
        assert driver.backend.send.read(commands.get_rapid_rate(), commands.reply_value) == 0.5
        assert driver.speed_ratio() == 0.5
        # the driver's own plan follows the same law: the move was not cut as overrun
        assert driver.set_speed_ratio(1.0).ok
        assert emu.controller.rapid_rate == 1.0


@pytest.mark.parametrize("ratio", [0.0, -0.1, 1.5, float("nan")])
def test_a_ratio_outside_0_1_is_refused_and_changes_nothing(ratio):
    driver = RobotDriver(SimBackend(MODEL))
    driver.start()
    try:
        result = driver.set_speed_ratio(ratio)
        assert result.code == -2 and "ratio" in result.message, result
        assert driver.speed_ratio() == 1.0
    finally:
        driver.shutdown()


def test_servo_targets_are_not_scaled():
    driver = RobotDriver(SimBackend(MODEL, sim_time=True, real_time_factor=0))
    driver.start()
    try:
        clock = driver.clock
        with clock.hold():
            assert driver.set_speed_ratio(0.25).ok
            assert driver.servo_move_enable(True).ok
            q = driver.state().joint_position + [0, 0, 0, 0, 0, 0.01]
            assert driver.servo_j(q).ok
            clock.sleep(3 * 0.008)
            assert abs(driver.state().joint_position[5] - q[5]) < 2e-3
    finally:
        driver.shutdown()


def test_a_ratio_of_half_doubles_a_trajectory_and_its_monitor_sees_the_trajectory_s_time():
    from jaka_driver.motion.profiles import SyncJointProfile
    from jaka_driver.motion.trajectory import JointTrajectory
    driver = RobotDriver(SimBackend(MODEL, sim_time=True, real_time_factor=0))
    driver.start()
    try:
        clock = driver.clock
        profile = SyncJointProfile(HOME, np.array(TARGET), np.full(6, 1.0), np.full(6, 3.0))
        trajectory = JointTrajectory.from_profile(profile, 0.008)
        seen = []

        def monitor(t, st):
            seen.append(t)
            return None

        with clock.hold():
            assert driver.set_speed_ratio(0.5).ok
            t0 = clock.now()
            result = driver.follow_trajectory(trajectory, monitor)
            took = clock.now() - t0
        assert result.ok, result.message
        assert abs(took / trajectory.duration - 2.0) <= 0.04, (took, trajectory.duration)
        assert max(seen) <= trajectory.duration + 0.1, max(seen)     # the trajectory's time
        assert np.max(np.abs(driver.state().joint_position - TARGET)) <= 1e-3
    finally:
        driver.shutdown()
