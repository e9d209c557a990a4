"""A twist of 0.05 m/s held for 1 s moves the TCP 5 cm (within 1 mm) along it and the arm is at
rest within 0.2 s of the last twist, on the twin (in its simulated time) and on the controller
backend through the emulator (0.4 mm per 8 ms target the backend streams, counted); a twist
towards a joint limit or a singularity slows the arm to rest without a jump (no joint step above
its speed limit), and a reverse twist drives it back out."""
import time

import numpy as np
import pytest

from support.emulated_arm import driver_on_emulator
from jaka_driver.common.constants import SERVO_CYCLE as CYCLE
from jaka_driver.common.models import load_model
from jaka_driver.driver import RobotDriver
from jaka_driver.sim import SimBackend
from support.ros_harness import wait_until

MODEL = load_model("zu5")
WATCHDOG = 0.5       # s: the twist watchdog of the run through the emulator


def stream_twist(driver, linear, seconds, sleep, angular=(0, 0, 0), in_tool=False):
    """Send the twist every cycle for ``seconds``; (tcp at the start, tcp at the end, the
    time of the last twist)."""
    p0 = driver.state().tcp_pose[:3, 3].copy()
    n = round(seconds / CYCLE)
    for _ in range(n):
        result = driver.velocity_jog(linear, angular, in_tool)
        assert result.ok, result.message
        sleep(CYCLE)
    return p0, driver.state().tcp_pose[:3, 3].copy()


def test_a_twist_moves_the_tcp_5_cm_in_1_s_and_stops_within_0_2_s_on_the_twin():
    driver = RobotDriver(SimBackend(MODEL, sim_time=True, real_time_factor=0))
    driver.start()
    try:
        clock = driver.clock
        with clock.hold():
            p0, p1 = stream_twist(driver, (0.05, 0, 0), 1.0, clock.sleep)
            last = clock.now()
            stopped_at = None
            while clock.now() - last < 0.5:
                clock.sleep(CYCLE)
                if stopped_at is None and np.max(np.abs(driver.state().joint_velocity)) < 1e-4:
                    stopped_at = clock.now() - last
        moved = (p1 - p0) * 1000.0
        assert abs(moved[0] - 50.0) <= 1.0, moved
        assert np.max(np.abs(moved[1:])) <= 0.1, moved
        assert stopped_at is not None and stopped_at <= 0.2, stopped_at
        assert not driver.moving
    finally:
        driver.shutdown()


def test_a_twist_moves_the_controller_through_the_emulator():
    """The backend's stream integrates the twist one 8 ms cycle per servo_j: each target is
    0.4 mm further along y (0.05 m/s; the ramp at 8 m/s² takes less than a cycle), so the arm
    moves 0.4 mm per target the emulator received — counted, not timed, as the stream's
    cycles are late on a busy machine. After the last twist the stream runs on for the
    driver's watchdog and its ramp down, then stops and leaves servo mode. The watchdog is 0.5 s
    here (0.1 s by default, timed in the twin's own time above): this loop's twists, 20 ms
    apart, can come 0.1 s late on a busy machine, and a jog the watchdog ended refuses the
    next twist until it has left servo mode."""
    with driver_on_emulator(twist_timeout=WATCHDOG) as (emu, driver):
        backend = driver.backend
        p0 = emu.backend.state().tcp_pose[:3, 3].copy()
        t0 = time.monotonic()
        while time.monotonic() - t0 < 1.0:
            result = driver.velocity_jog((0, 0.05, 0), (0, 0, 0), False)
            assert result.ok, result.message
            time.sleep(0.02)
        sent_by_the_last_twist = emu.handlers.counts["servo_j"]
        assert wait_until(lambda: not backend.motion.moving, 2.0)
        assert wait_until(lambda: not driver.state().servo_mode, 2.0)  # it left servo mode
        sent = emu.handlers.counts["servo_j"]
        assert wait_until(lambda: np.max(np.abs(emu.backend.state().joint_velocity)) < 1e-3, 2.0)
        moved = (emu.backend.state().tcp_pose[:3, 3] - p0) * 1000.0
        # never more than 0.4 mm per servo_j received; on a quiet machine exactly that (184 for
        # 185, the first from where the arm stood), and 10 % of the requests may have moved it
        # nothing on a loaded one (62.0 mm for 173 received, seen with two other workers)
        assert 0.9 * 0.4 * sent - 1.0 <= moved[1] <= 0.4 * sent + 1.0, (moved, sent)
        assert np.max(np.abs(moved[[0, 2]])) <= 0.5, moved
        assert sent >= 0.2 * 1.0 / CYCLE, sent      # it streamed, ≥ 20 % of 1 s of cycles
        assert sent - sent_by_the_last_twist <= WATCHDOG / CYCLE + 3, (sent, sent_by_the_last_twist)


@pytest.mark.parametrize("start, linear, angular, in_tool", [
    # towards the wrist singularity: J5 from 0.3 rad towards 0 (a rotation about tool y)
    ([0.0, 1.57, -1.57, 1.57, 0.3, 0.0], (0, 0, 0), (0, -0.5, 0), True),
    ([0.0, 1.57, -1.57, 1.57, 0.3, 0.0], (0, 0, 0), (0, 0.5, 0), True),
    # up against J6's limit
    ([0.0, 1.57, -1.57, 1.57, 1.57, 6.2], (0, 0, 0), (0, 0, 1.0), True),
    ([0.0, 1.57, -1.57, 1.57, 1.57, 6.2], (0, 0, 0), (0, 0, -1.0), True),
])
def test_a_twist_into_a_limit_or_singularity_slows_to_rest_without_a_jump(start, linear,
                                                                          angular, in_tool):
    driver = RobotDriver(SimBackend(MODEL, q0=np.array(start), sim_time=True,
                                    real_time_factor=0))
    driver.start()
    try:
        clock = driver.clock
        qs = []
        with clock.hold():
            for _ in range(round(3.0 / CYCLE)):
                answer = driver.velocity_jog(linear, angular, in_tool)
                clock.sleep(CYCLE)
                qs.append(driver.backend.twin.commanded_joints())
        qs = np.array(qs)
        steps = np.abs(np.diff(qs, axis=0)) / CYCLE
        assert np.all(steps <= MODEL.max_velocity + 1e-9), steps.max()
        q = qs[-1]
        assert np.all(q >= MODEL.lower) and np.all(q <= MODEL.upper), q
        # towards the limit or the singularity it has slowed to under a tenth of the commanded
        # speed (creeping to rest short of it); away from them it moves freely
        towards = angular[1] > 0 if start[5] == 0.0 else angular[2] > 0
        tcp_rate = np.max(steps[-1])
        if towards:
            assert tcp_rate < 0.1 * np.linalg.norm(angular), steps[-1]
            # and the answer says why (what ~command_status publishes as a slowdown)
            assert answer.ok and answer.value is not None, answer
            assert "slowed" in answer.message, answer
        else:
            assert np.max(steps[-20:]) > 0.3, steps[-20:]
        assert abs(q[4]) >= 0.03, q                      # never at J5 = 0
        assert q[5] <= MODEL.upper[5] - 5e-4, q
    finally:
        driver.shutdown()
