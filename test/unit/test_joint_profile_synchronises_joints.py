"""SyncJointProfile (joint_move): all joints start and arrive together along a straight line
in joint space, never exceed any joint's speed or acceleration limit, arrive at the predicted
time, stretch to a requested duration and refuse one that is too short."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaka_driver.motion.profiles import SyncJointProfile
from jaka_driver.motion.trajectory import JointTrajectory

N = 6


def vectors(lo, hi):
    return st.lists(st.floats(lo, hi), min_size=N, max_size=N).map(np.array)


positions = vectors(-3.0, 3.0)
speed_limits = vectors(0.1, 3.5)
accel_limits = vectors(0.5, 30.0)


def dense(profile, n=3001):
    t = np.linspace(0.0, profile.duration, n)
    return (t,) + profile.sample(t)


def check_synchronised(p, q0, q1, v_max, a_max):
    t, q, qd, qdd = dense(p)
    delta = q1 - q0
    np.testing.assert_array_equal(q[-1], q1)
    if p.duration > 0:
        np.testing.assert_array_equal(q[0], q0)
    else:                                 # nothing (float-expressible) to move: already there
        assert np.all(np.abs(q1 - q0) < 1e-300)
    # One normalised progress for every moving joint = a straight line in joint space, and
    # every joint starts at t = 0 and arrives at t = duration.
    moving = np.abs(delta) > 1e-9
    if moving.any():
        progress = (q[:, moving] - q0[moving]) / delta[moving]
        np.testing.assert_allclose(progress, progress[:, :1].repeat(moving.sum(), 1),
                                   atol=1e-9)
        assert np.all(progress[1:-1] > 0) and np.all(progress[:-1] < 1)
    # Limits, from the analytic derivatives and from finite differences of the positions.
    assert np.all(np.abs(qd) <= v_max * (1 + 1e-9))
    assert np.all(np.abs(qdd) <= a_max * (1 + 1e-9))
    if p.duration > 0:
        fd_speed = np.abs(np.diff(q, axis=0)) / np.diff(t)[:, None]
        assert np.all(fd_speed <= v_max * (1 + 1e-6) + 1e-12)
    assert np.all(p.peak_velocity <= v_max * (1 + 1e-12))
    assert np.all(p.peak_acceleration <= a_max * (1 + 1e-12))
    return t, q, qd, qdd


@settings(max_examples=200, deadline=None)
@given(positions, positions, speed_limits, accel_limits)
def test_all_joints_start_and_arrive_together_within_limits(q0, q1, v_max, a_max):
    p = SyncJointProfile(q0, q1, v_max, a_max)
    check_synchronised(p, q0, q1, v_max, a_max)
    if p.limiting_joint is not None:
        # Time-optimal: some joint runs at one of its limits.
        usage = np.maximum(p.peak_velocity / v_max, p.peak_acceleration / a_max)
        assert usage.max() == pytest.approx(1.0, rel=1e-9)


def test_a_speed_limited_joint_does_not_impose_its_acceleration_on_others():
    # Joint 1 is the slowest alone (10 rad at 1 rad/s: 10.01 s) because of its speed limit;
    # its ramps take 0.01 s at 100 rad/s². Scaling that time law onto joint 2 (1 rad) would
    # accelerate joint 2 at 10 rad/s², ten times its limit: the common law must also honour
    # joint 2's acceleration bound.
    q0, q1 = np.zeros(2), np.array([10.0, 1.0])
    v_max, a_max = np.array([1.0, 10.0]), np.array([100.0, 1.0])
    p = SyncJointProfile(q0, q1, v_max, a_max)
    check_synchronised(p, q0, q1, v_max, a_max)
    assert p.peak_acceleration[1] == pytest.approx(1.0)
    assert p.limiting_joint == 0


@settings(max_examples=100, deadline=None)
@given(positions, positions, speed_limits, accel_limits)
def test_predicted_duration_is_the_sampled_arrival_time(q0, q1, v_max, a_max):
    p = SyncJointProfile(q0, q1, v_max, a_max)
    assert p.duration == p.predicted_duration

    def arrived(t):
        return bool(np.all(p.sample(t)[0] == q1))

    # Once there, it stays there...
    coarse = np.linspace(0.0, 2 * p.duration + 1.0, 2001)
    there = np.all(p.sample(coarse)[0] == q1, axis=1)
    assert there[np.argmax(there):].all()
    # ... so the arrival time can be found by bisection, without asking the profile.
    lo, hi = 0.0, 1000.0
    assert arrived(hi)
    if arrived(lo):
        hi = lo
    while hi - lo > 1e-9:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if arrived(mid) else (mid, hi)
    # Within 1 µs: in the last ~1e-8 s the remaining distance is below float resolution.
    assert hi == pytest.approx(p.predicted_duration, abs=1e-6)
    # The executor's trajectory ends exactly then, on the goal.
    traj = JointTrajectory.from_profile(p, 0.008)
    assert traj.duration == p.duration
    np.testing.assert_array_equal(traj.q[-1], q1)


def test_known_move_has_the_expected_duration():
    # Joint 2 limits: 2 rad at 1 rad/s, 2 rad/s² -> 0.5 s ramps + 1.5 s cruise = 2.5 s.
    p = SyncJointProfile(np.zeros(6), [0.5, 2.0, 0, 0, 0, -1.0], 1.0, 2.0)
    assert p.predicted_duration == pytest.approx(2.5)
    assert p.limiting_joint == 1
    np.testing.assert_allclose(p.peak_velocity, [0.25, 1.0, 0, 0, 0, 0.5])


@settings(max_examples=100, deadline=None)
@given(positions, positions, speed_limits, accel_limits, st.floats(1.0, 5.0))
def test_stretched_move_takes_the_requested_duration(q0, q1, v_max, a_max, factor):
    fastest = SyncJointProfile(q0, q1, v_max, a_max)
    duration = fastest.duration * factor + 0.01
    p = SyncJointProfile(q0, q1, v_max, a_max, duration=duration)
    assert p.duration == duration
    assert p.predicted_duration == fastest.duration
    check_synchronised(p, q0, q1, v_max, a_max)
    assert np.all(p.peak_velocity <= fastest.peak_velocity * (1 + 1e-12))
    q_before = p.sample(duration - 0.01)[0]
    moving = np.abs(q1 - q0) > 1e-6
    assert np.all(q_before[moving] != q1[moving])


def test_too_short_a_duration_is_refused_with_the_minimum():
    with pytest.raises(ValueError, match=r"1\.000 s is shorter than the 2\.500 s.*joint_2"):
        SyncJointProfile(np.zeros(6), [0.5, 2.0, 0, 0, 0, -1.0], 1.0, 2.0, duration=1.0)


def test_no_motion_arrives_at_once_or_holds_for_the_duration():
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    p = SyncJointProfile(q, q, 1.0, 1.0)
    assert p.duration == 0.0 and p.limiting_joint is None
    np.testing.assert_array_equal(p.sample(0.0)[0], q)
    held = SyncJointProfile(q, q, 1.0, 1.0, duration=2.0)
    qs, qds, _ = held.sample(np.linspace(0, 3, 7))
    np.testing.assert_array_equal(qs, np.tile(q, (7, 1)))
    assert not qds.any()


def test_scalar_sample_gives_joint_vectors():
    p = SyncJointProfile(np.zeros(6), np.ones(6), 1.0, 1.0)
    q, qd, qdd = p.sample(0.5)
    assert q.shape == qd.shape == qdd.shape == (6,)


@pytest.mark.parametrize("kwargs, match", [
    (dict(q_goal=np.ones(5)), "q_goal"),
    (dict(v_max=[1, 1, 1, 0, 1, 1]), "v_max of joint_4"),
    (dict(a_max=-1.0), "a_max of joint_1"),
    (dict(q_goal=[0, 0, np.nan, 0, 0, 0]), "NaN"),
])
def test_invalid_arguments_are_refused(kwargs, match):
    args = dict(q_start=np.zeros(6), q_goal=np.ones(6), v_max=1.0, a_max=1.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        SyncJointProfile(**args)
