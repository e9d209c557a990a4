"""jog through ROS on the zu5 twin: every direction in every coordinate system moves the right
way; the jog stops 3.0 ± 0.1 s after the last call, is kept alive by calling again, and stops
at a joint limit. Timing is what these tests check, so the twin owns time (sim_time, as fast
as it can step): a busy machine cannot change what they see."""

import numpy as np
import pytest
from std_srvs.srv import Empty

from support.ros_harness import (START, go_home, position, sample_at,
                                 start_sim_time_driver, stamp, wait_until)
from jaka_msgs.srv import Move
from jaka_driver_msgs.srv import PauseTwin, StepTwin

pytestmark = pytest.mark.ros


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):
    return start_sim_time_driver(request)


@pytest.fixture(autouse=True)
def at_start(call):
    go_home(call)

def jog(call, coord, index, speed):
    return call("jog", Move, coord_mode=coord, index=index, mvvelo=speed)


REST_S = 0.1       # sim s of samples at rest that make "at rest"


def moving(recorder):
    msg = recorder.latest()
    return msg is not None and np.max(np.abs(msg.velocity)) > 1e-3


def rest_at(recorder, q, timeout: float = 30.0):
    """The latest sample, once it and every sample of the ``REST_S`` before it show the arm at
    rest at ``q`` (rad), *after* every moving sample received so far. The test's subscriber
    may lag the twin (on a busy machine by more than a second of sim time at real_time_factor
    0), so "the latest sample at rest at START" alone could be one from before the last jog;
    this one cannot. And one sample alone is not rest: a move that ends settles, its speed
    dipping under 1e-3 rad/s for a cycle and rising over it again (2e-3 rad/s), and that rise
    would pass for the next jog's start."""
    q = np.asarray(q)

    def still(m) -> bool:
        return (np.max(np.abs(m.velocity)) < 1e-3
                and np.max(np.abs(np.array(m.position) - q)) < 2e-3)

    def found():
        with recorder._lock:
            samples = [m for _, m in recorder.samples]
        if not samples:
            return None
        last_motion = max((stamp(m) for m in samples if np.max(np.abs(m.velocity)) > 1e-3),
                          default=-np.inf)
        m = samples[-1]
        window = [x for x in samples if stamp(x) >= stamp(m) - REST_S]
        return m if (stamp(m) - REST_S > last_motion and len(window) >= REST_S / 0.008
                     and all(still(x) for x in window)) else None

    msg = wait_until(found, timeout)
    if not msg:
        with recorder._lock:
            samples = [m for _, m in recorder.samples]
        m = samples[-1]
        moving_stamps = [stamp(x) for x in samples if np.max(np.abs(x.velocity)) > 1e-3]
        raise AssertionError(f"the arm did not come to rest at {q}: latest {stamp(m):.3f} s, "
                             f"|v| {np.max(np.abs(m.velocity)):.2e}, |q - target| "
                             f"{np.max(np.abs(np.array(m.position) - q)):.2e}, last motion "
                             f"{moving_stamps[-1] if moving_stamps else None}")
    return msg


def first_moving(recorder, after: float, timeout: float = 30.0):
    """The first sample stamped after ``after`` (sim s) in which the arm moves, waiting for it."""
    def find():
        with recorder._lock:
            return next((m for _, m in recorder.samples
                         if stamp(m) > after and np.max(np.abs(m.velocity)) > 1e-3), None)

    msg = wait_until(find, timeout, 0.005)
    assert msg is not None, "the arm did not start moving"
    return msg


def moving_span(recorder, t0: float, t1: float):
    """(first, last) stamp in [t0, t1] at which the arm moved (sim time, s)."""
    moved = [stamp(m) for _, m in recorder.samples
             if t0 <= stamp(m) <= t1 and np.max(np.abs(m.velocity)) > 1e-3]
    assert moved, "the arm did not move"
    return moved[0], moved[-1]


def test_jog_stops_3_s_after_the_last_call(call, joints):
    t0 = stamp(rest_at(joints, START))
    assert jog(call, 0, 0, 0.2).ret == 1
    end = stamp(sample_at(joints, stamp(first_moving(joints, t0)) + 4.0))
    first, last = moving_span(joints, t0, end)
    # the stop begins 3.0 s after the call; the ramp down at 0.2 rad/s takes ~0.02 s
    assert 2.9 <= last - first <= 3.15, (first, last)


def test_calling_again_keeps_the_jog_alive(call, joints):
    t0 = stamp(rest_at(joints, START))
    # Calls 0.504 s of the twin's time apart, exactly: the twin paused, stepped 63 cycles
    # between two calls. (Paced by the test's subscriber instead, the calls drifted apart by however
    # far a busy machine let the subscriber fall behind the twin, past the 3 s watchdog.)
    assert call("sim/pause", PauseTwin, pause=True).ret == 1
    try:
        for _ in range(9):
            assert jog(call, 0, 1, 0.1).ret == 1
            stepped = call("sim/step", StepTwin, cycles=63)
            assert stepped.ret == 1, stepped.message
    finally:
        assert call("sim/pause", PauseTwin, pause=False).ret == 1
    last_call = sample_at(joints, stepped.sim_time)
    assert np.max(np.abs(last_call.velocity)) > 1e-3, \
        "jog stopped although it was called every 0.5 s"
    # the last call came ≥ 4 s after the motion began; its 3 s run out after 6.9 s
    end = stamp(sample_at(joints, stamp(first_moving(joints, t0)) + 8.5))
    first, last = moving_span(joints, t0, end)
    assert last - first >= 4.0 + 2.9, (first, last)


@pytest.mark.parametrize("coord", [0, 1, 2])
def test_every_direction_moves_the_right_way(call, joints, tcp, coord):
    from jaka_driver.common.transforms import rotvec_to_matrix
    for index in range(12):
        axis, sign = index // 2, (-1 if index % 2 else 1)
        # where the arm rests before the jog, joints and TCP of one sample; 0.4 s of sim
        # time after the jog's first moving sample, where it has got to
        rest = rest_at(joints, START)
        q0, p0 = np.array(rest.position), sample_at(tcp, stamp(rest))
        speed = 0.2 if (coord == 0 or axis >= 3) else 50.0
        reply = jog(call, coord, index, speed)
        assert reply.ret == 1, reply.message
        t1 = stamp(first_moving(joints, stamp(rest))) + 0.4
        q1 = np.array(sample_at(joints, t1).position)
        p1 = sample_at(tcp, t1)
        go_home(call)                                   # stops the jog, back to START
        if coord == 0:
            dq = q1 - q0
            assert sign * dq[axis] > 0.03, (index, dq)
            assert np.max(np.abs(np.delete(dq, axis))) < 1e-3
            continue
        a = np.array([p0.twist.linear.x, p0.twist.linear.y, p0.twist.linear.z])
        b = np.array([p1.twist.linear.x, p1.twist.linear.y, p1.twist.linear.z])
        r0 = rotvec_to_matrix([p0.twist.angular.x, p0.twist.angular.y, p0.twist.angular.z])
        r1 = rotvec_to_matrix([p1.twist.angular.x, p1.twist.angular.y, p1.twist.angular.z])
        frame = np.eye(3) if coord == 1 else r0
        if axis < 3:
            moved = frame.T @ (b - a)                  # in the jog frame, m
            assert sign * moved[axis] > 0.01, (coord, index, moved)
            assert np.max(np.abs(np.delete(moved, axis))) < 1e-3
        else:
            from jaka_driver.common.transforms import matrix_to_rotvec
            turn = matrix_to_rotvec(r1 @ r0.T) if coord == 1 else matrix_to_rotvec(r0.T @ r1)
            assert sign * turn[axis - 3] > 0.03, (coord, index, turn)
            assert np.linalg.norm(b - a) < 1e-3      # rotation about the TCP: it stays put


def test_jog_comes_to_rest_at_a_joint_limit(call, joints):
    # joint_3 upper limit is 3.05 rad; from 2.9 rad at 0.5 rad/s it arrives in 0.3 s
    start = list(START)
    start[2] = 2.9
    start[1] = 0.5
    assert call("joint_move", Move, pose=start, mvvelo=2.0, mvacc=8.0).ret == 1
    t0 = stamp(rest_at(joints, start))
    assert jog(call, 0, 4, 0.5).ret == 1
    msg = sample_at(joints, stamp(first_moving(joints, t0)) + 1.0)
    q = np.array(msg.position)
    assert 3.0 <= q[2] <= 3.05 + 1e-3, q[2]
    assert np.max(np.abs(msg.velocity)) < 1e-3, "still moving 1 s after the jog began"


def test_bad_jog_requests_are_refused(call):
    assert jog(call, 3, 0, 0.1).ret == -2
    assert jog(call, 0, 12, 0.1).ret == -2
    reply = jog(call, 0, 0, -0.1)
    assert reply.ret == -2 and "mvvelo" in reply.message


def test_mvacc_is_the_speed_when_mvvelo_is_zero_like_jakas_driver(call, joints):
    reply = call("jog", Move, coord_mode=0, index=10, mvvelo=0.0, mvacc=0.3)
    assert reply.ret == 1 and "mvacc" in reply.message
    call("stop_move", Empty)
