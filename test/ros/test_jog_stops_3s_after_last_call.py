"""jog through ROS on the zu5 twin: every direction in every coordinate system moves the right
way; the jog stops 3.0 ± 0.1 s after the last call, is kept alive by calling again, and stops
at a joint limit."""
import time

import numpy as np
import pytest
from std_srvs.srv import Empty

from ros_harness import START, at_rest, go_home, position, wait_until
from jaka_msgs.srv import Move

pytestmark = pytest.mark.ros



@pytest.fixture(autouse=True)
def at_start(call):
    go_home(call)

def jog(call, coord, index, speed):
    return call("jog", Move, coord_mode=coord, index=index, mvvelo=speed)


def moving(recorder):
    msg = recorder.latest()
    return msg is not None and np.max(np.abs(msg.velocity)) > 1e-3


def test_jog_stops_3_s_after_the_last_call(call, joints):
    t_call = time.monotonic()
    assert jog(call, 0, 0, 0.2).ret == 1
    assert wait_until(lambda: moving(joints), 1.0)
    assert wait_until(lambda: not moving(joints), 5.0, 0.005)
    stopped_after = time.monotonic() - t_call
    # the stop begins at 3.0 s and the ramp down at 0.2 rad/s takes ~0.02 s
    assert 2.9 <= stopped_after <= 3.15, stopped_after


def test_calling_again_keeps_the_jog_alive(call, joints):
    t0 = time.monotonic()
    for _ in range(5):
        assert jog(call, 0, 1, 0.1).ret == 1
        time.sleep(1.0)
    assert moving(joints), "jog stopped although it was called every second"
    assert wait_until(lambda: not moving(joints), 4.0, 0.005)
    assert time.monotonic() - t0 >= 4.0 + 2.9


@pytest.mark.parametrize("coord", [0, 1, 2])
def test_every_direction_moves_the_right_way(call, joints, tcp, coord):
    from jaka_driver.transforms import rotvec_to_matrix
    for index in range(12):
        axis, sign = index // 2, (-1 if index % 2 else 1)
        q0 = position(joints)
        p0 = tcp.latest()
        speed = 0.2 if (coord == 0 or axis >= 3) else 50.0
        reply = jog(call, coord, index, speed)
        assert reply.ret == 1, reply.message
        time.sleep(0.4)
        q1 = position(joints)
        p1 = tcp.latest()
        assert call("stop_move", Empty) is not None
        assert wait_until(lambda: not moving(joints), 1.0)
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
            from jaka_driver.transforms import matrix_to_rotvec
            turn = matrix_to_rotvec(r1 @ r0.T) if coord == 1 else matrix_to_rotvec(r0.T @ r1)
            assert sign * turn[axis - 3] > 0.03, (coord, index, turn)
            assert np.linalg.norm(b - a) < 1e-3      # rotation about the TCP: it stays put
        call("joint_move", Move, pose=START, mvvelo=2.0, mvacc=8.0)


def test_jog_comes_to_rest_at_a_joint_limit(call, joints):
    # joint_3 upper limit is 3.05 rad; from 2.9 rad at 0.5 rad/s it arrives in 0.3 s
    start = list(START)
    start[2] = 2.9
    start[1] = 0.5
    assert call("joint_move", Move, pose=start, mvvelo=2.0, mvacc=8.0).ret == 1
    assert jog(call, 0, 4, 0.5).ret == 1
    time.sleep(1.0)
    q = position(joints)
    assert 3.0 <= q[2] <= 3.05 + 1e-3, q[2]
    assert not moving(joints)


def test_bad_jog_requests_are_refused(call):
    assert jog(call, 3, 0, 0.1).ret == -2
    assert jog(call, 0, 12, 0.1).ret == -2
    reply = jog(call, 0, 0, -0.1)
    assert reply.ret == -2 and "mvvelo" in reply.message


def test_mvacc_is_the_speed_when_mvvelo_is_zero_like_jakas_driver(call, joints):
    reply = call("jog", Move, coord_mode=0, index=10, mvvelo=0.0, mvacc=0.3)
    assert reply.ret == 1 and "mvacc" in reply.message
    call("stop_move", Empty)
