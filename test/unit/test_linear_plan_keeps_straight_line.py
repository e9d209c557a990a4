"""plan_linear_move on fake arms with exact kinematics: the planned TCP stays on the straight
line and the slerp, within the linear and angular speed/acceleration limits; an unreachable
point, a singularity, a joint limit or a configuration flip is refused with -4 and a message
that says where; invalid parameters with -2.

The main fake arm is a 6-DoF "Cartesian gantry": joints 1-3 are the TCP position (m),
joints 4-6 the rotation vector of its orientation, so FK and IK are closed-form and exact.
"""
import re

import numpy as np
import pytest

from jaka_driver.common.results import CommandRefused
from jaka_driver.motion.linear_path import PlanningError, line_duration, plan_linear_move

from gantry_arm import gantry_fk, gantry_ik, log, pose, rot  # noqa: F401

LOWER, UPPER = np.full(6, -2.0), np.full(6, 2.0)
V_MAX = np.full(6, 3.14)
SPEED, ACCEL = 0.1, 0.5          # m/s, m/s²


def plan(T0, T1, ik=gantry_ik, q0=None, **kw):
    q0 = gantry_ik(T0, None) if q0 is None else q0
    args = dict(lower=LOWER, upper=UPPER, v_max=V_MAX)
    args.update(kw)
    speed, accel = args.pop("speed", SPEED), args.pop("accel", ACCEL)
    return plan_linear_move(T0, T1, speed, accel, q0, ik, args.pop("lower"),
                            args.pop("upper"), args.pop("v_max"), **args)


T0 = pose([0.1, -0.2, 0.3], [0.1, 0.2, 0.0])
T1 = pose([0.4, 0.1, 0.2], [0.1, 0.2, 0.0] + 0.5 * np.array([0.0, 0.6, 0.8]))


def test_planned_tcp_lies_on_the_line_and_the_slerp():
    traj = plan(T0, T1)
    p0, p1 = T0[:3, 3], T1[:3, 3]
    direction = (p1 - p0) / np.linalg.norm(p1 - p0)
    fk = np.array([gantry_fk(q) for q in traj.q])
    offsets = fk[:, :3, 3] - p0
    along = offsets @ direction
    off_line = np.linalg.norm(offsets - along[:, None] * direction, axis=1)
    assert off_line.max() < 1e-9
    assert np.all(np.diff(along) >= -1e-12)
    np.testing.assert_allclose(traj.tcp, fk, atol=1e-12)
    np.testing.assert_array_equal(traj.tcp[-1], T1)
    np.testing.assert_allclose(fk[-1], T1, atol=1e-12)
    np.testing.assert_array_equal(traj.q[0], gantry_ik(T0, None))
    # Orientation: rotated about one fixed axis, by the same fraction as the position.
    fraction = along / np.linalg.norm(p1 - p0)
    total = log(T0[:3, :3].T @ T1[:3, :3])
    for R, f in zip(fk[:, :3, :3], fraction):
        np.testing.assert_allclose(log(T0[:3, :3].T @ R), f * total, atol=1e-9)


def test_tcp_speed_and_acceleration_stay_within_limits():
    traj = plan(T0, T1)
    length = np.linalg.norm(T1[:3, 3] - T0[:3, 3])
    # Translation dominates here: the textbook trapezoid over the path length.
    assert traj.duration == pytest.approx(length / SPEED + SPEED / ACCEL, rel=1e-12)
    p = traj.tcp[:, :3, 3]
    dt = np.diff(traj.times)
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1) / dt
    assert speed.max() <= SPEED * (1 + 1e-9)
    assert speed.max() == pytest.approx(SPEED, rel=1e-6)
    h = dt[0]                                     # uniform except the last interval
    second = np.linalg.norm(p[2:-1] - 2 * p[1:-2] + p[:-3], axis=1) / h ** 2
    assert second.max() <= ACCEL * (1 + 1e-6)
    assert np.all(np.abs(traj.qd) <= V_MAX)
    assert not traj.qd[0].any() and not traj.qd[-1].any()


def angular_speeds(traj):
    R = traj.tcp[:, :3, :3]
    steps = [np.linalg.norm(log(a.T @ b)) for a, b in zip(R[:-1], R[1:])]
    return np.array(steps) / np.diff(traj.times)


def test_rotation_dominated_move_respects_the_angular_limits():
    start = pose([0.3, 0.0, 0.3])
    goal = pose([0.301, 0.0, 0.3], [0, 0, np.pi / 2])
    # Defaults at 0.1 m/s, 0.5 m/s²: 1 rad/s, 5 rad/s².
    traj = plan(start, goal)
    assert traj.duration == pytest.approx(np.pi / 2 / 1.0 + 1.0 / 5.0, rel=1e-9)
    assert angular_speeds(traj).max() <= 1.0 * (1 + 1e-9)
    slow = plan(start, goal, angular_speed=0.5, angular_accel=2.0)
    assert slow.duration == pytest.approx(np.pi / 2 / 0.5 + 0.5 / 2.0, rel=1e-9)
    assert angular_speeds(slow).max() <= 0.5 * (1 + 1e-9)
    np.testing.assert_array_equal(slow.tcp[-1], goal)


def test_default_angular_speed_is_capped():
    start, goal = pose([0.3, 0.0, 0.3]), pose([0.3, 0.0, 0.3], [0, 0, 2.0])
    # Uncapped these would be 10 rad/s and 100 rad/s²; the caps are π rad/s and 2π rad/s².
    traj = plan(start, goal, speed=1.0, accel=10.0, v_max=np.full(6, 4.0))
    assert traj.duration == pytest.approx(2.0 / np.pi + np.pi / (2 * np.pi), rel=1e-9)


def test_unreachable_point_is_refused_with_where_it_fails():
    def walled_ik(T, seed):                       # nothing beyond x = 0.3 m
        return None if T[0, 3] > 0.3 else gantry_ik(T, seed)

    with pytest.raises(PlanningError) as err:
        plan(pose([0.0, 0.1, 0.2]), pose([0.5, 0.1, 0.2]), ik=walled_ik)
    assert err.value.code == -4 and isinstance(err.value, CommandRefused)
    m = re.fullmatch(r"no IK solution at (\d+\.\d) % of the path "
                     r"\(x=(\d+\.\d), y=100\.0, z=200\.0 mm\)", str(err.value))
    assert m, str(err.value)
    assert 60.0 <= float(m.group(1)) <= 61.0
    assert 300.0 <= float(m.group(2)) <= 301.0


def test_singularity_is_refused_naming_the_joint():
    # A wrist joint that points at a pivot 1 mm beside the line: passing it, joint 4 swings
    # by nearly π within a few mm, at ~100 rad/s.
    def pivot_ik(T, seed):
        x, y, z = T[:3, 3]
        return np.array([x, y, z, np.arctan2(y, x - 0.25), 0.0, 0.0])

    start, goal = pose([0.0, 0.001, 0.2]), pose([0.5, 0.001, 0.2])
    lower, upper = np.full(6, -7.0), np.full(6, 7.0)
    with pytest.raises(PlanningError) as err:
        plan(start, goal, ik=pivot_ik, q0=pivot_ik(start, None), lower=lower, upper=upper)
    assert err.value.code == -4
    m = re.fullmatch(r"joint_4 would need (\S+) rad/s at (\S+) % of the path, "
                     r"limit 3\.14 rad/s \(singularity\?\)", str(err.value))
    assert m, str(err.value)
    assert float(m.group(1)) > 3.14
    assert 40.0 < float(m.group(2)) < 50.0


def test_joint_limit_on_the_path_is_refused():
    upper = UPPER.copy()
    upper[0] = 0.4
    with pytest.raises(PlanningError) as err:
        plan(pose([0.0, 0.1, 0.2]), pose([0.5, 0.1, 0.2]), upper=upper)
    assert err.value.code == -4
    m = re.fullmatch(r"joint_1 would leave its limits at (\S+) % of the path: (\S+) rad is "
                     r"outside \[-2\.00, 0\.40\]", str(err.value))
    assert m, str(err.value)
    assert 80.0 <= float(m.group(1)) <= 81.0


def test_each_sample_is_seeded_by_the_previous_solution():
    seeds, solutions = [], []

    def spy_ik(T, seed):
        seeds.append(np.array(seed))
        solutions.append(gantry_ik(T, seed))
        return solutions[-1]

    ref = gantry_ik(T0, None) + 1e-4
    plan(T0, T1, ik=spy_ik, ref_q=ref)
    np.testing.assert_array_equal(seeds[0], ref)
    for seed, previous in zip(seeds[1:], solutions[:-1]):
        np.testing.assert_array_equal(seed, previous)
    seeds.clear()
    q0 = gantry_ik(T0, None)
    plan(T0, T1, ik=spy_ik, q0=q0)
    np.testing.assert_array_equal(seeds[0], q0)


def test_ref_joint_for_another_configuration_is_refused():
    def two_branch_ik(T, seed):                   # joint 6 flips with the seed's sign
        return np.array([*T[:3, 3], 0.0, 0.0, 0.5 if seed[5] >= 0 else -0.5])

    start, goal = pose([0.0, 0.1, 0.2]), pose([0.2, 0.1, 0.2])
    q0 = two_branch_ik(start, np.ones(6))
    same = plan(start, goal, ik=two_branch_ik, q0=q0, ref_q=q0)
    assert np.all(same.q[:, 5] == 0.5)
    with pytest.raises(PlanningError, match=r"joint_6 would need 125\.00 rad/s at .*ref_joint"):
        plan(start, goal, ik=two_branch_ik, q0=q0, ref_q=-q0)


def test_no_motion_is_a_single_sample():
    q0 = gantry_ik(T0, None)
    traj = plan(T0, T0.copy(), q0=q0)
    assert traj.duration == 0.0
    np.testing.assert_array_equal(traj.q, [q0])


def test_trajectory_is_playable_by_time():
    traj = plan(T0, T1)
    q, qd = traj.sample(traj.duration / 2)
    np.testing.assert_allclose(gantry_fk(q)[:3, 3], (T0[:3, 3] + T1[:3, 3]) / 2, atol=1e-6)


@pytest.mark.parametrize("kwargs, match", [
    (dict(speed=0.0), "speed is 0 m/s"),
    (dict(accel=-1.0), "accel is -1 m/s²"),
    (dict(speed=np.nan), "speed is nan"),
    (dict(cycle=0.0), "cycle"),
    (dict(angular_speed=-1.0), "angular_speed"),
    (dict(v_max=np.zeros(6)), "v_max"),
    (dict(lower=np.zeros(5)), "lower must be 6"),
    (dict(ref_q=np.zeros(7)), "ref_q must be 6"),
])
def test_invalid_parameters_are_refused_with_minus_two(kwargs, match):
    with pytest.raises(PlanningError, match=match) as err:
        plan(T0, T1, **kwargs)
    assert err.value.code == -2


def test_a_pose_that_is_not_a_rotation_is_refused():
    bad = T1.copy()
    bad[:3, :3] *= 2.0
    with pytest.raises(PlanningError, match="T_goal") as err:
        plan(T0, bad)
    assert err.value.code == -2


def test_line_duration_is_the_planned_duration_without_sampling():
    assert line_duration(T0, T1, SPEED, ACCEL) == pytest.approx(plan(T0, T1).duration, abs=1e-12)
    assert line_duration(T0, T0.copy(), SPEED, ACCEL) == 0.0


def test_a_line_longer_than_the_motion_cap_is_refused_before_sampling():
    """1e-9 m/s over 0.3 m would be ~1e8 s of 8 ms samples: refused at once, -2."""
    with pytest.raises(PlanningError, match=r"above the limit of 600 s") as err:
        plan(T0, T1, speed=1e-9)
    assert err.value.code == -2
