"""circular_move on the twin through RobotDriver, in simulated time: every measured sample of
the TCP lies within 0.1 mm of the circle through the three points (turns included), the move
ends on its end pose, collinear points are refused before anything moves, each attitude rule
turns the tool as it says, and a move paused by its hold comes to rest on its path, stays
there, and resumes to its end."""
import math
import threading

import numpy as np
import pytest

from support.twin_samples import collected_twin

from jaka_driver.common.models import load_model
from jaka_driver.common.results import Code
from jaka_driver.common.transforms import (matrix_to_pose_mm, pose_mm_to_matrix,
                                           rotation_angle_between)
from jaka_driver.motion.circular_path import arc_through, stop_pose
from jaka_driver.programs.executor import MoveHold

MODEL = load_model("zu5")
RADIUS = 80.0                                    # mm


@pytest.fixture(scope="module")
def twin():
    yield from collected_twin(MODEL)


@pytest.fixture
def arc(twin):
    """(start, mid, end) poses mm + rotation vector of a half circle of 80 mm in the
    horizontal plane, from home, the tool's attitude unchanged."""
    assert twin.twin.reset().ok
    start = matrix_to_pose_mm(twin.state().tcp_pose)
    center = start[:3] + [RADIUS, 0.0, 0.0]
    mid = np.concatenate([center + [0.0, RADIUS, 0.0], start[3:]])
    end = np.concatenate([center + [RADIUS, 0.0, 0.0], start[3:]])
    return start, mid, end


def measured(twin, since):
    """Every TCP pose (4x4, m) sampled after ``since`` up to now."""
    return np.array([st.tcp_pose for st in twin.samples.since(since, twin.state().stamp)])


def test_every_sample_of_an_arc_with_a_turn_lies_within_0_1_mm_of_the_circle(twin, arc):
    start, mid, end = arc
    t0 = twin.state().stamp
    result = twin.circular_move(mid, end, 200.0, 1000.0, turns=1)
    assert result.ok, result.message
    tcp = measured(twin, t0)
    circle = arc_through(start[:3] / 1000, mid[:3] / 1000, end[:3] / 1000)
    deviation = circle.distance_from(tcp[:, :3, 3]) * 1000          # mm, every 8 ms sample
    assert len(deviation) > 300                                       # 1.5 circles, ~3.9 s
    assert deviation.max() < 0.1, deviation.max()
    d = tcp[:, :3, 3] - circle.center
    swept = np.unwrap(np.arctan2(d @ circle.e2, d @ circle.e1))
    assert swept[-1] - swept[0] == pytest.approx(3 * math.pi, abs=1e-3)   # 1.5 circles
    final = matrix_to_pose_mm(twin.state().tcp_pose)
    np.testing.assert_allclose(final[:3], end[:3], atol=0.05)


def test_collinear_points_are_refused_and_nothing_moves(twin, arc):
    start, _, end = arc
    on_line = np.concatenate([(start[:3] + end[:3]) / 2 + [0.0, 0.05, 0.0], start[3:]])
    q0 = twin.state().joint_position.copy()
    result = twin.circular_move(on_line, end, 100.0, 500.0)
    assert result.code == Code.INVALID_PARAMETER
    assert "0.050 mm off one straight line" in result.message and "0.1 mm" in result.message
    np.testing.assert_array_equal(twin.state().joint_position, q0)


def _attitudes(twin, t0):
    return measured(twin, t0)[:, :3, :3]


def test_short_and_long_way_turn_the_tool_as_their_rules_say(twin, arc):
    start, mid, end = arc
    R0 = pose_mm_to_matrix(start)[:3, :3]
    turned = matrix_to_pose_mm(pose_mm_to_matrix(start) @ _about_z(math.radians(40)))
    end_turned = np.concatenate([end[:3], turned[3:]])
    for mode, most in ((0, 40.0), (1, 320.0)):
        assert twin.twin.reset().ok
        t0 = twin.state().stamp
        result = twin.circular_move(mid, end_turned, 150.0, 800.0, attitude_mode=mode)
        assert result.ok, result.message
        R = _attitudes(twin, t0)
        angles = np.degrees([rotation_angle_between(R0, r) for r in R])
        final = rotation_angle_between(R[-1], pose_mm_to_matrix(end_turned)[:3, :3])
        assert math.degrees(final) < 0.05
        # the short way never turns further than its 40°; the long way passes 180°
        if mode == 0:
            assert angles.max() < most + 0.05
        else:
            assert angles.max() > 179.0


def test_fixed_to_axis_turns_the_tool_with_the_radius(twin, arc):
    start, mid, end = arc
    odd = np.concatenate([mid[:3], [0.3, 0.2, 0.1]])                  # ignored
    result = twin.circular_move(odd, end, 150.0, 800.0, attitude_mode=3)
    assert result.ok, result.message
    expected = stop_pose(*(pose_mm_to_matrix(p) for p in (start, odd, end)), turns=0, mode=3)
    final = twin.state().tcp_pose
    assert math.degrees(rotation_angle_between(final[:3, :3], expected[:3, :3])) < 0.05
    # half a circle about the vertical: the tool has turned 180° about it
    R0 = pose_mm_to_matrix(start)[:3, :3]
    assert math.degrees(rotation_angle_between(R0, final[:3, :3])) == pytest.approx(180, abs=0.1)


def test_a_held_arc_rests_on_its_path_and_resumes_to_its_end(twin, arc):
    start, mid, end = arc
    hold, answers = MoveHold(), []
    clock = twin.clock
    mover = threading.Thread(target=lambda: answers.append(
        twin.circular_move(mid, end, 100.0, 500.0, hold=hold)))
    with clock.hold():
        t0 = clock.now()
        mover.start()
        clock.sleep(1.0)                     # sim s: under way (the arc takes ~2.7 s)
        hold.pause()
        clock.sleep(1.5)                     # paused for longer than the arc would take
        resting = twin.state()
        assert not answers                   # a paused move has not ended
        assert np.max(np.abs(resting.joint_velocity)) < 1e-3
        circle = arc_through(start[:3] / 1000, mid[:3] / 1000, end[:3] / 1000)
        assert circle.distance_from(resting.tcp_pose[:3, 3]) * 1000 < 0.1
        assert np.linalg.norm(resting.tcp_pose[:3, 3] * 1000 - end[:3]) > 50.0
        hold.resume()
    mover.join(10.0)
    assert answers and answers[0].ok, answers
    tcp = measured(twin, t0)
    assert circle.distance_from(tcp[:, :3, 3]).max() * 1000 < 0.1
    np.testing.assert_allclose(matrix_to_pose_mm(twin.state().tcp_pose)[:3], end[:3], atol=0.05)


def _about_z(angle):
    T = np.eye(4)
    T[:2, :2] = [[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]]
    return T
