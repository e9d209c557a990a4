"""jog through ROS on the zu5 twin: every direction in every coordinate system moves the right
way; the jog stops 3.0 ± 0.1 s after the last call, is kept alive by calling again, and stops
at a joint limit. Timing is what these tests check, so the twin owns time (sim_time) and stands
still unless the test steps it: each test resets the arm to rest where it starts, jogs, and
steps the sim time it reads. A busy machine cannot change what they see, and no sample piles
up while a test waits (running free at real_time_factor 0, the twin ran ahead of the test's
subscriber by as much as its socket buffers held, seconds to minutes of sim time, and a jog
showed up that late: "the arm did not start moving" after 30 s of wall time)."""

import numpy as np
import pytest
from std_srvs.srv import Empty

from support.ros_harness import (START, pause_twin, reset_twin, sample_at,
                                 start_sim_time_driver, stamp, step_twin, step_twin_to,
                                 wait_until)
from jaka_msgs.srv import Move

pytestmark = pytest.mark.ros


@pytest.fixture(scope="module")
def sim_driver(request, rospy_node):
    return start_sim_time_driver(request)


@pytest.fixture(scope="module", autouse=True)
def paused(sim_driver, call):
    """The module's twin stands still between the steps its tests make."""
    pause_twin(call)
    yield
    pause_twin(call, False)


def jog(call, coord, index, speed):
    return call("jog", Move, coord_mode=coord, index=index, mvvelo=speed)


def is_moving(m) -> bool:
    return np.max(np.abs(m.velocity)) > 1e-3


def first_moving(recorder, after: float, until: float):
    """The first sample stamped in (``after``, ``until``] (sim s) in which the arm moves; the
    twin has been stepped to ``until``."""
    sample_at(recorder, until)                  # every sample up to it has been received
    with recorder._lock:
        msg = next((m for _, m in recorder.samples
                    if after < stamp(m) <= until + 1e-6 and is_moving(m)), None)
    assert msg is not None, f"the arm did not start moving in ({after:.3f}, {until:.3f}] s"
    return msg


def moving_span(recorder, t0: float, t1: float):
    """(first, last) stamp in [t0, t1] at which the arm moved (sim time, s); the twin has been
    stepped to ``t1``."""
    sample_at(recorder, t1)
    with recorder._lock:
        moved = [stamp(m) for _, m in recorder.samples if t0 <= stamp(m) <= t1 and is_moving(m)]
    assert moved, "the arm did not move"
    return moved[0], moved[-1]


def test_jog_stops_3_s_after_the_last_call(call, joints):
    t0 = reset_twin(call, START)
    assert jog(call, 0, 0, 0.2).ret == 1
    first = stamp(first_moving(joints, t0, step_twin(call, 5)))
    end = step_twin_to(call, first + 4.0)
    first, last = moving_span(joints, t0, end)
    # the stop begins 3.0 s after the call; the ramp down at 0.2 rad/s takes ~0.02 s
    assert 2.9 <= last - first <= 3.15, (first, last)


def test_calling_again_keeps_the_jog_alive(call, joints):
    t0 = reset_twin(call, START)
    # Calls 0.504 s of the twin's time apart, exactly: 63 cycles stepped between two calls.
    for _ in range(9):
        assert jog(call, 0, 1, 0.1).ret == 1
        stepped = step_twin(call, 63)
    last_call = sample_at(joints, stepped)
    assert is_moving(last_call), "jog stopped although it was called every 0.5 s"
    # the last call came ≥ 4 s after the motion began; its 3 s run out after 6.9 s
    first = stamp(first_moving(joints, t0, stepped))
    end = step_twin_to(call, first + 8.5)
    first, last = moving_span(joints, t0, end)
    assert last - first >= 4.0 + 2.9, (first, last)


@pytest.mark.parametrize("coord", [0, 1, 2])
def test_every_direction_moves_the_right_way(call, joints, tcp, coord):
    from jaka_driver.common.transforms import rotvec_to_matrix
    for index in range(12):
        axis, sign = index // 2, (-1 if index % 2 else 1)
        # the arm at rest at START, joints and TCP of one sample; 0.4 s of sim time after the
        # jog's first moving sample, where it has got to
        t0 = reset_twin(call, START)
        q0, p0 = np.array(sample_at(joints, t0).position), sample_at(tcp, t0)
        speed = 0.2 if (coord == 0 or axis >= 3) else 50.0
        reply = jog(call, coord, index, speed)
        assert reply.ret == 1, reply.message
        t1 = stamp(first_moving(joints, t0, step_twin(call, 5))) + 0.4
        q1 = np.array(sample_at(joints, step_twin_to(call, t1)).position)
        p1 = sample_at(tcp, t1)
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
    t0 = reset_twin(call, start)
    assert jog(call, 0, 4, 0.5).ret == 1
    t1 = stamp(first_moving(joints, t0, step_twin(call, 5))) + 1.0
    msg = sample_at(joints, step_twin_to(call, t1))
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
