"""linear_move through ROS on the zu5 twin: the measured TCP stays on the straight line,
ends on the target, honours coord_mode, and an unreachable path is refused before moving."""
import time

import numpy as np
import pytest

from support.ros_harness import START, at_rest, go_home, position, wait_until
from jaka_msgs.srv import GetFK, Move

pytestmark = pytest.mark.ros



@pytest.fixture(autouse=True)
def at_start(call):
    go_home(call)

def current_pose_mm(call, joints):
    fk = call("get_fk", GetFK, joint=position(joints).tolist())
    return np.array(fk.cartesian_pose)


def linear(call, pose, v=100.0, a=500.0, coord_mode=0, **kw):
    return call("linear_move", Move, pose=list(pose), mvvelo=v, mvacc=a,
                coord_mode=coord_mode, **kw)


def positions_mm(samples):
    return np.array([[m.twist.linear.x, m.twist.linear.y, m.twist.linear.z]
                     for _, m in samples]) * 1000


def distance_from_segment(points, a, b):
    ab = b - a
    s = np.clip((points - a) @ ab / (ab @ ab), 0, 1)
    return np.linalg.norm(points - (a + s[:, None] * ab), axis=1)


def test_tcp_deviates_less_than_half_a_millimetre_at_100_mm_s(call, joints, tcp):
    start = current_pose_mm(call, joints)
    target = start + np.array([150.0, -120.0, 80.0, 0, 0, 0])
    t0 = time.time()
    reply = linear(call, target, v=100.0, a=500.0)
    assert reply.ret == 1, reply.message
    time.sleep(0.05)
    path = positions_mm(tcp.since(t0))
    deviation = distance_from_segment(path, start[:3], target[:3])
    assert len(path) > 100
    assert deviation.max() <= 0.5, f"max deviation {deviation.max():.3f} mm"
    final = current_pose_mm(call, joints)
    assert np.linalg.norm(final[:3] - target[:3]) <= 0.1
    # compare rotations, not vectors: at 180° a rotation vector and its negative are equal
    from jaka_driver.common.transforms import rotation_angle_between, rotvec_to_matrix
    assert rotation_angle_between(rotvec_to_matrix(final[3:]), rotvec_to_matrix(target[3:])) <= 1e-3


def test_speed_is_what_was_asked(call, joints, tcp):
    start = current_pose_mm(call, joints)
    target = start + np.array([0.0, 0.0, 200.0, 0, 0, 0])
    t0 = time.time()
    assert linear(call, target, v=100.0, a=1000.0).ret == 1
    samples = tcp.since(t0)
    p = positions_mm(samples)
    t = np.array([m.header.stamp.to_sec() for _, m in samples])
    dt = np.diff(t)
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1)[dt > 0] / dt[dt > 0]
    assert 95.0 <= np.percentile(speed, 90) <= 105.0


def test_coord_mode_2_moves_relative_to_the_tool(call, joints):
    start = current_pose_mm(call, joints)
    reply = linear(call, [0, 0, 50.0, 0, 0, 0], coord_mode=2)
    assert reply.ret == 1, reply.message
    end = current_pose_mm(call, joints)
    from jaka_driver.common.transforms import rotvec_to_matrix
    tool_z = rotvec_to_matrix(start[3:])[:, 2]
    assert np.allclose(end[:3] - start[:3], 50.0 * tool_z, atol=0.1)


def test_coord_mode_1_is_the_base_frame_even_with_a_user_frame(call, joints):
    from jaka_msgs.srv import SetUserFrame
    assert call("set_userframe", SetUserFrame, pose=[100, 0, 0, 0, 0, 0], user_num=1).ret == 1
    try:
        base_pose = current_pose_mm(call, joints) + np.array([100.0, 0, 0, 0, 0, 0])  # user→base
        target_base = base_pose + np.array([0, 50.0, 0, 0, 0, 0])
        assert linear(call, target_base, coord_mode=1).ret == 1
        assert np.allclose(current_pose_mm(call, joints)[:3] + [100.0, 0, 0], target_base[:3],
                           atol=0.1)
    finally:
        assert call("set_userframe", SetUserFrame, pose=[0] * 6, user_num=0).ret == 1


def test_unreachable_target_is_refused_with_minus_4_and_no_motion(call, joints):
    before = at_rest(joints)
    reply = linear(call, [3000.0, 0, 500.0, np.pi, 0, 0])
    assert reply.ret == -4, reply.message
    time.sleep(0.1)
    assert np.max(np.abs(position(joints) - before)) < 1e-4
