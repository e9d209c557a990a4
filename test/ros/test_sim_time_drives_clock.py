"""sim_time through ROS on the zu5 twin at real_time_factor 0: /use_sim_time is set and /clock
ticks every 8 ms cycle with the samples stamped on it; a joint_move takes its planned time and
a servo stream is followed, both measured in sim time; its threads keep the default
scheduling policy."""
import os
import time

import numpy as np
import pytest
from rosgraph_msgs.msg import Clock

from support.ros_harness import (START, Recorder, go_home, pause_twin, sample_at, sim_sleep,
                                 start_sim_time_driver, stamp, step_twin, wait_until)
from support.scheduling import thread_policies
from jaka_msgs.srv import Move, ServoMove, ServoMoveEnable

from jaka_driver.common.models import load_model
from jaka_driver.motion.profiles import SyncJointProfile

pytestmark = pytest.mark.ros


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):
    return start_sim_time_driver(request)


@pytest.fixture(scope="module")
def clock(sim_driver, rospy_node):
    recorder = Recorder("/clock", Clock)
    yield recorder
    recorder.close()


def test_clock_ticks_every_cycle_and_the_samples_are_stamped_on_it(sim_driver, clock, joints,
                                                                    rospy_node):
    assert rospy_node.get_param("/use_sim_time") is True
    assert wait_until(lambda: len(clock.samples) > 300, 20.0)
    ticks = np.array([m.clock.to_sec() for _, m in clock.samples])
    assert np.allclose(np.diff(ticks), 0.008, atol=1e-6), np.diff(ticks)[:10]
    # the joint samples up to the last tick have come (the twin runs as fast as it can and this
    # process, on a busy machine, receives them later than the ticks)
    assert wait_until(lambda: stamp(joints.latest()) >= ticks[-1] - 1e-6, 30.0)
    stamps = {round(stamp(m) / 0.008) for _, m in joints.samples}
    # every tick since the joint recorder subscribed has its sample
    ticked = {round(t / 0.008) for t in ticks if min(stamps) <= round(t / 0.008) <= max(stamps)}
    assert len(ticked) > 100 and ticked <= stamps


def test_joint_move_takes_its_planned_time_in_sim_time(call, joints):
    go_home(call)
    target = [0.5, 1.2, -1.0, 1.9, 1.2, 0.8]
    planned = SyncJointProfile(np.array(START), np.array(target), np.full(6, 1.0),
                               np.full(6, 3.0)).duration
    wall = time.monotonic()
    t0 = stamp(sim_sleep(joints, 0.1))
    assert call("joint_move", Move, pose=target, mvvelo=1.0, mvacc=3.0).ret == 1

    def at_target():
        return next((stamp(m) for _, m in list(joints.samples) if stamp(m) >= t0
                     and np.max(np.abs(np.array(m.position) - target)) <= 1e-3), None)
    # the arrival's sample, waited for: the move has ended on the twin when its call returns,
    # but at factor 0 the samples received here can be up to MAX_LAG cycles (0.128 s) older
    arrived = wait_until(at_target, 30.0, 0.005)
    assert arrived is not None, "no sample at the target within 30 s of wall time"
    moving = [stamp(m) for _, m in list(joints.samples)
              if stamp(m) >= t0 and np.max(np.abs(m.velocity)) > 1e-3]
    # from the first cycle of motion to within 1e-3 rad: the profile's time, to a few cycles
    assert planned - 0.05 <= arrived - moving[0] <= planned + 0.05, (arrived - moving[0],
                                                                      planned)
    print(f"{planned:.3f} s of sim time in {time.monotonic() - wall:.3f} s of wall time")


def test_a_servo_stream_paced_by_the_samples_is_followed(call, joints):
    go_home(call)
    assert call("servo_move_enable", ServoMoveEnable, enable=True).ret == 1
    q = np.array(START)
    last = stamp(joints.latest())
    for _ in range(125):                        # 1 s of sim time, one target per cycle
        q = q + np.array([0.004, -0.002, 0.003, 0.0, 0.0, 0.005])
        assert call("servo_j", ServoMove, pose=q.tolist(), speed=[]).ret == 1
        last = stamp(sample_at(joints, last + 0.008))
    # 0.1 s of sim time after the last target came in: the latest sample this process has
    # received can be some cycles older than the twin (it runs up to MAX_LAG cycles ahead of
    # its publisher), so the twin is paused and stepped 13 cycles, and the sample read is the
    # one at the sim time that step answers
    pause_twin(call)
    try:
        reached = sample_at(joints, step_twin(call, 13))
    finally:
        pause_twin(call, False)
    assert np.max(np.abs(np.array(reached.position) - q)) < 1e-3
    assert call("servo_move_enable", ServoMoveEnable, enable=False).ret == 1


def test_a_twin_in_sim_time_keeps_the_default_scheduling_policy(sim_driver):
    """At real_time_factor 0 its cycles run back to back: at real-time priority they would
    hold cores from every other program (jaka_driver.host.realtime)."""
    assert set(thread_policies(sim_driver.proc.pid).values()) == {(os.SCHED_OTHER, 0)}
    assert "scheduling: no real-time priority in sim time" in sim_driver.log_path.read_text()
