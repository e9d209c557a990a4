"""A speed ratio of 0.5 doubles a joint_move's duration within 2 % on the twin and on the
controller backend through the emulator (whose get_rapid_rate then reads 0.5): the law is time
× 1/r (speeds × r, accelerations × r²) everywhere; a ratio outside (0, 1] is refused and changes
nothing; a servo stream is not scaled.

Durations are what the code decides: on the twin, its simulated time; through the emulator, the
duration the emulator's twin planned for each move it played and the one the driver planned for
it — not the wall-clock span of the driver's call, which adds the time to notice the end (up to a
30 ms status period and a busy machine's scheduling) to a move whether it is doubled or not."""
import time

import numpy as np
import pytest

from support.emulated_arm import CATCH_UP, driver_on_emulator, planned_moves
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
    with driver_on_emulator() as (emu, driver), planned_moves(emu.backend) as played, \
            planned_moves(driver.backend) as expected:
        full, half = doubled(driver, time.monotonic)          # wall-clock spans of the calls
        played_full, _, played_half = played                 # the controller's plans (s)
        assert abs(played_half / played_full - 2.0) <= 0.04, played
        # the driver's own plan follows the same law: the move was not cut as overrun, and the
        # driver expects of the controller what it then plays (within 1 %: the driver plans
        # from the joints of the latest status packet, the twin from its setpoint)
        np.testing.assert_allclose(expected, played, rtol=0.01)
        # each call waited for the whole move the controller played (the twin, paced to the
        # wall clock, can end at most CATCH_UP early after a stall)
        assert full >= played_full - CATCH_UP and half >= played_half - CATCH_UP, \
            (full, half, played)
        assert driver.backend.send.read(commands.get_rapid_rate(), commands.reply_value) == 0.5
        assert driver.speed_ratio() == 0.5
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
