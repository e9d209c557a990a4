"""plan_circular_move on the fake gantry (exact kinematics): every planned sample lies on the circle
through the three points, in the order start → middle → end, ends on the end pose, adds whole or
partial turns as docs/interface.md says; collinear points are refused (-2, with the distance and
the 0.1 mm tolerance), an arc out of reach -4; each of the four attitude rules turns the tool
as it says; the speed on the arc keeps the centripetal acceleration within the acceleration."""
import math

import numpy as np
import pytest

from gantry_arm import gantry_fk, gantry_ik, gantry_ik_unwrapped, log, pose, rot
from jaka_driver.common.results import Code
from jaka_driver.common.transforms import rotation_angle_between
from jaka_driver.motion.cartesian_path import PlanningError
from jaka_driver.motion.circular_path import (COLLINEAR_TOLERANCE, arc_through, attitude_law,
                                              circle_duration, plan_circle,
                                              plan_circular_move, stop_pose)

LOWER, UPPER = np.full(6, -7.0), np.full(6, 7.0)
V_MAX = np.full(6, 3.14)
SPEED, ACCEL = 0.1, 0.5          # m/s, m/s²

# a half circle of radius 50 mm in the plane z = 0.3 m, the tool turning 0.3 rad about z
T0 = pose([0.40, 0.0, 0.3], [0.0, 0.0, 0.0])
T1 = pose([0.45, 0.05, 0.3], [0.0, 0.0, 0.15])
T2 = pose([0.50, 0.0, 0.3], [0.0, 0.0, 0.3])


def plan(T_start=T0, T_mid=T1, T_end=T2, turns=0.0, mode=0, ik=gantry_ik_unwrapped, **kw):
    return plan_circular_move(T_start, T_mid, T_end, kw.pop("speed", SPEED),
                              kw.pop("accel", ACCEL), gantry_ik(T_start, None), ik, LOWER,
                              UPPER, V_MAX, turns=turns, mode=mode, **kw)


def angles_on(arc, points):
    d = points - arc.center
    return np.unwrap(np.arctan2(d @ arc.e2, d @ arc.e1))


def test_every_sample_lies_on_the_circle_in_the_order_start_middle_end():
    traj = plan()
    fk = np.array([gantry_fk(q) for q in traj.q])
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3])
    assert arc.radius == pytest.approx(0.05)
    assert arc.distance_from(fk[:, :3, 3]).max() < 1e-9
    phi = angles_on(arc, fk[:, :3, 3])
    assert np.all(np.diff(phi) >= -1e-12)                       # one sense, never back
    assert phi[0] == pytest.approx(0.0, abs=1e-12)
    assert phi[-1] == pytest.approx(arc.end_angle) == pytest.approx(math.pi)
    assert phi.min() < arc.mid_angle < phi.max()                 # through the middle point
    np.testing.assert_array_equal(traj.tcp[-1], T2)


def test_the_arc_taken_is_the_one_through_the_middle_point():
    below = pose([0.45, -0.05, 0.3])                             # the other half circle
    fk = np.array([gantry_fk(q) for q in plan(T_mid=below, T_end=pose(T2[:3, 3])).q])
    assert fk[:, 1, 3].max() < 1e-12 and fk[:, 1, 3].min() == pytest.approx(-0.05, abs=1e-4)


def test_collinear_points_are_refused_with_the_distance_and_the_tolerance():
    off = pose([0.45, 0.00005, 0.3])                             # 0.05 mm off the line
    with pytest.raises(PlanningError) as refused:
        plan(T_mid=off)
    assert refused.value.code == Code.INVALID_PARAMETER
    assert "0.050 mm off one straight line" in refused.value.message
    assert f"at least {COLLINEAR_TOLERANCE * 1000:g} mm" in refused.value.message   # 0.1
    with pytest.raises(PlanningError, match="collinear"):
        plan(T_mid=T0)                                           # a point twice
    arc = arc_through(T0[:3, 3], [0.45, 0.0002, 0.3], T2[:3, 3])  # 0.2 mm off: a circle
    assert arc.radius > 1.0


def test_whole_turns_add_whole_circles_and_end_on_the_end_point():
    one = plan(turns=1)
    assert one.duration > plan().duration + 2 * math.pi * 0.05 / SPEED * 0.99
    fk = np.array([gantry_fk(q) for q in one.q])
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3], 1)
    phi = angles_on(arc, fk[:, :3, 3])
    assert phi[-1] == pytest.approx(3 * math.pi)
    np.testing.assert_array_equal(one.tcp[-1], T2)


def test_a_partial_turn_stops_that_share_of_a_circle_beyond_the_end_point():
    end = stop_pose(T0, T1, T2, turns=0.25, mode=0)
    np.testing.assert_allclose(end[:3, 3], [0.45, -0.05, 0.3], atol=1e-12)   # 3/4 round
    np.testing.assert_allclose(end[:3, :3], T2[:3, :3], atol=1e-12)   # the end attitude
    traj = plan(turns=0.25)
    np.testing.assert_allclose(gantry_fk(traj.q[-1]), end, atol=1e-9)


def test_short_way_turns_the_tool_less_than_half_a_turn_about_one_axis():
    R0, R2 = rot([0, 0, 0]), rot([0, 0, 2.5])
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3])
    law = attitude_law(R0, R0, R2, arc, 0)
    assert law.angle == pytest.approx(2.5)
    for u in (0.25, 0.5, 0.75):
        np.testing.assert_allclose(log(R0.T @ law.at(np.asarray(u))), [0, 0, 2.5 * u],
                                   atol=1e-12)
    np.testing.assert_allclose(law.at(np.asarray(1.0)), R2, atol=1e-12)


def test_long_way_turns_the_other_sense_by_the_rest_of_the_turn():
    R0, R2 = rot([0, 0, 0]), rot([0, 0, 2.5])
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3])
    law = attitude_law(R0, R0, R2, arc, 1)
    assert law.angle == pytest.approx(2 * math.pi - 2.5)
    half = law.at(np.asarray(0.5))
    np.testing.assert_allclose(log(R0.T @ half), [0, 0, -(2 * math.pi - 2.5) / 2], atol=1e-12)
    np.testing.assert_allclose(law.at(np.asarray(1.0)), R2, atol=1e-12)
    same = attitude_law(R0, R0, R0, arc, 1)                      # equal attitudes: a whole turn
    assert same.angle == pytest.approx(2 * math.pi)
    np.testing.assert_allclose(same.at(np.asarray(0.25)), rot(arc.axis * math.pi / 2),
                               atol=1e-12)


def test_by_middle_takes_the_way_that_passes_nearer_the_middle_attitude():
    R0, R2 = rot([0, 0, 0]), rot([0, 0, 2.5])
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3])
    u_mid = arc.mid_angle / arc.angle                             # 0.5 on a half circle
    short_mid, long_mid = rot([0, 0, 2.5 * u_mid]), rot([0, 0, -(2 * math.pi - 2.5) * u_mid])
    by_short = attitude_law(R0, short_mid, R2, arc, 2)
    by_long = attitude_law(R0, long_mid, R2, arc, 2)
    assert by_short.angle == pytest.approx(2.5) and "short way" in by_short.chosen
    assert by_long.angle == pytest.approx(2 * math.pi - 2.5) and "long way" in by_long.chosen
    assert rotation_angle_between(by_long.at(np.asarray(u_mid)), long_mid) < 1e-12


def test_fixed_to_axis_turns_the_tool_with_the_radius():
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3], turns=0.5)
    R0 = rot([0.3, -0.2, 0.1])
    law = attitude_law(R0, rot([1, 1, 1]), rot([0, 2, 0]), arc, 3)   # mid and end ignored
    assert law.angle == pytest.approx(arc.angle)
    for u in (0.0, 0.3, 0.7, 1.0):
        radial = arc.points(u * arc.angle) - arc.center
        radial_in_tool = law.at(np.asarray(u)).T @ radial
        np.testing.assert_allclose(radial_in_tool, R0.T @ (T0[:3, 3] - arc.center),
                                   atol=1e-12)


def test_an_attitude_mode_outside_0_to_3_is_refused():
    with pytest.raises(PlanningError, match="attitude_mode is 4, expected 0–3"):
        plan(mode=4)


def test_turns_outside_the_range_are_refused():
    for turns in (-1, math.nan, 101):
        with pytest.raises(PlanningError, match="turns is"):
            plan(turns=turns)


def test_speed_keeps_the_centripetal_acceleration_within_the_acceleration():
    small = 0.01                                                 # radius 10 mm
    a, m, b = pose([0.0, 0.0, 0.3]), pose([small, small, 0.3]), pose([2 * small, 0.0, 0.3])
    accel = 0.2                                                  # √(0.2 · 0.01) = 44.7 mm/s
    traj = plan_circular_move(a, m, b, 0.5, accel, gantry_ik(a, None), gantry_ik, LOWER,
                              UPPER, V_MAX)
    fk = np.array([gantry_fk(q)[:3, 3] for q in traj.q])
    speed = np.linalg.norm(np.diff(fk, axis=0), axis=1) / np.diff(traj.times)
    assert speed.max() <= math.sqrt(accel * small) * 1.001
    assert speed.max() == pytest.approx(math.sqrt(accel * small), rel=0.01)
    assert traj.duration == pytest.approx(circle_duration(a, m, b, 0.5, accel))


def test_a_joint_limit_on_the_arc_is_refused_where_it_is_met():
    with pytest.raises(PlanningError, match=r"cannot be followed: joint_6 would leave its "
                                            r"limits at \d+\.\d % of the arc"):
        plan_circular_move(T0, T1, T2, SPEED, ACCEL, gantry_ik(T0, None), gantry_ik_unwrapped,
                           LOWER, np.array([7, 7, 7, 7, 7, 0.1]), V_MAX)


def test_an_arc_out_of_reach_is_refused_where_it_leaves():
    def short_arm(T, seed):
        return None if T[1, 3] > 0.04 else gantry_ik(T, seed)
    with pytest.raises(PlanningError) as refused:
        plan(ik=short_arm)
    assert refused.value.code == Code.IK_FAILED
    assert "leaves the workspace" in refused.value.message
    assert "% of the arc" in refused.value.message


def test_the_plan_without_samples_times_the_move_as_the_samples_do():
    for mode in range(4):
        p = plan_circle(T0, T1, T2, SPEED, ACCEL, 0.4, mode)
        assert plan(turns=0.4, mode=mode).duration == pytest.approx(p.duration, abs=1e-12)
