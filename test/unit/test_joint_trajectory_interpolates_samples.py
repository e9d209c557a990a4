"""JointTrajectory: samples every cycle ending exactly at the end, linear interpolation between
samples, clamped outside the motion, and one representation for profiles and planned paths."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaka_driver.motion.profiles import SyncJointProfile
from jaka_driver.motion.trajectory import MAX_MOTION_DURATION, JointTrajectory, time_grid

CYCLE = 0.008


@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, 30.0), st.sampled_from([0.001, 0.004, 0.008, 0.01]))
def test_time_grid_steps_by_the_cycle_and_ends_at_the_duration(duration, cycle):
    t = time_grid(duration, cycle)
    assert t[0] == 0.0 and t[-1] == duration
    steps = np.diff(t)
    if duration > 0:
        assert np.all(steps > 0)
        np.testing.assert_allclose(steps[:-1], cycle, rtol=1e-6)
        # No sliver at the end: the last interval is between half a cycle and 1.5 cycles
        # (shorter only when the whole motion is shorter than that).
        assert steps[-1] <= 1.5 * cycle * (1 + 1e-9)
        assert steps[-1] >= min(0.5 * cycle, duration) * (1 - 1e-9)


def test_time_grid_merges_a_sliver_into_the_last_interval():
    np.testing.assert_allclose(time_grid(0.0161, 0.008), [0.0, 0.008, 0.0161])
    np.testing.assert_allclose(time_grid(0.0201, 0.008), [0.0, 0.008, 0.016, 0.0201])
    np.testing.assert_allclose(time_grid(0.024, 0.008), [0.0, 0.008, 0.016, 0.024])


def test_from_profile_matches_the_profile_at_its_samples():
    p = SyncJointProfile(np.zeros(6), [1.0, -0.5, 0.2, 0, 0, 0.3], 1.5, 4.0)
    traj = JointTrajectory.from_profile(p, CYCLE)
    assert traj.duration == p.duration
    q, qd, _ = p.sample(traj.times)
    np.testing.assert_array_equal(traj.q, q)
    np.testing.assert_array_equal(traj.qd, qd)
    np.testing.assert_array_equal(traj.q[-1], p.q_goal)
    assert not traj.qd[0].any() and not traj.qd[-1].any()


def test_sample_interpolates_linearly_and_clamps():
    traj = JointTrajectory(times=[0.0, 1.0, 3.0], q=[[0.0, 0.0], [1.0, 2.0], [3.0, 2.0]],
                           qd=[[0.0, 0.0], [1.0, 1.0], [0.0, 0.0]])
    q, qd = traj.sample(0.5)
    np.testing.assert_allclose(q, [0.5, 1.0])
    np.testing.assert_allclose(qd, [0.5, 0.5])
    q, qd = traj.sample(np.array([-1.0, 2.0, 3.0, 9.0]))
    np.testing.assert_allclose(q, [[0, 0], [2, 2], [3, 2], [3, 2]])
    np.testing.assert_allclose(qd, [[0, 0], [0.5, 0.5], [0, 0], [0, 0]])
    assert traj.duration == 3.0


def test_a_single_sample_is_already_in_position():
    traj = JointTrajectory.from_profile(SyncJointProfile(np.ones(6), np.ones(6), 1, 1), CYCLE)
    assert traj.duration == 0.0 and traj.times.shape == (1,)
    q, qd = traj.sample(0.3)
    np.testing.assert_array_equal(q, np.ones(6))
    assert q.shape == (6,) and traj.sample(np.zeros(4))[0].shape == (4, 6)


@pytest.mark.parametrize("kwargs, match", [
    (dict(times=[0.0, 0.0]), "increase"),
    (dict(times=[0.1, 0.2]), "start at 0"),
    (dict(qd=np.zeros((2, 3))), "q .* and qd"),
    (dict(tcp=np.zeros((3, 4, 4))), "tcp"),
])
def test_inconsistent_arrays_are_refused(kwargs, match):
    args = dict(times=[0.0, 1.0], q=np.zeros((2, 6)), qd=np.zeros((2, 6)))
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        JointTrajectory(**args)


def test_time_grid_refuses_a_motion_longer_than_the_cap():
    """The guard on memory: 1e6 s would be 1.25e8 samples."""
    assert time_grid(MAX_MOTION_DURATION, 0.008)[-1] == MAX_MOTION_DURATION
    with pytest.raises(ValueError, match="above the limit of 600 s"):
        time_grid(1e6, 0.008)
