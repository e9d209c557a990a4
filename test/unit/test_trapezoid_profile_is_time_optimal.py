"""TrapezoidProfile: reaches the distance in the time-optimal time without exceeding v_max or
a_max, falls back to a triangle when v_max is out of reach, stretches to a longer duration at
the same acceleration, refuses a shorter one, and behaves at distance 0."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaka_driver.motion.profiles import TrapezoidProfile

# Subnormal distances (< 2.2e-308) are left out: there float rounding, not the profile,
# decides the shape; 0 and the smallest normal numbers stay in.
distances = st.one_of(st.just(0.0), st.floats(2.3e-308, 100.0))
speeds = st.floats(0.01, 10.0)
accels = st.floats(0.01, 100.0)


def dense(profile, n=4001):
    """Samples on a grid that includes the corners of the speed curve, where the trapezoid
    rule integrates the piecewise-linear speed exactly."""
    corners = [profile.accel_time, profile.duration - profile.accel_time]
    t = np.unique(np.clip(np.concatenate([np.linspace(0.0, profile.duration, n), corners]),
                          0.0, profile.duration))
    return (t,) + profile.sample(t)


def test_cruising_profile_has_the_textbook_duration():
    # 2 s ramps covering 2 m each, 6 m cruise at 2 m/s = 3 s: 7 s.
    p = TrapezoidProfile(10.0, 2.0, 1.0)
    assert p.duration == pytest.approx(7.0, abs=1e-12)
    assert p.peak_speed == 2.0
    assert p.sample(2.0) == pytest.approx((2.0, 2.0, 0.0))
    assert p.sample(3.5) == pytest.approx((5.0, 2.0, 0.0))
    assert p.sample(7.0) == (10.0, 0.0, 0.0)


def test_short_distance_gives_a_triangle():
    p = TrapezoidProfile(1.0, 10.0, 1.0)
    assert p.duration == pytest.approx(2.0, abs=1e-12)
    assert p.peak_speed == pytest.approx(1.0)
    s, v, a = p.sample(np.array([0.5, 1.5]))
    np.testing.assert_allclose(s, [0.125, 0.875])
    np.testing.assert_allclose(v, [0.5, 0.5])
    np.testing.assert_allclose(a, [1.0, -1.0])


@settings(max_examples=300, deadline=None)
@given(distances, speeds, accels)
def test_profile_stays_within_limits_and_arrives(d, v_max, a_max):
    p = TrapezoidProfile(d, v_max, a_max)
    t, s, v, a = dense(p)
    assert s[-1] == d
    assert s[0] == 0.0
    assert np.all(np.diff(s) >= 0.0)
    assert np.all(v <= v_max * (1 + 1e-12)) and np.all(v >= 0.0)
    assert np.all(np.abs(a) <= a_max)
    # The reported speed is the derivative of the reported position.
    if d > 0:
        np.testing.assert_allclose(np.trapezoid(v, t), d, rtol=1e-9, atol=1e-12)
    # Time-optimal: one of the two limits is reached, and the time is the analytic minimum.
    expected = (2 * np.sqrt(d / a_max) if d * a_max <= v_max ** 2
                else d / v_max + v_max / a_max)
    assert p.duration == pytest.approx(expected, rel=1e-12, abs=1e-15)


@settings(max_examples=300, deadline=None)
@given(distances, speeds, accels, st.floats(1.0, 20.0))
def test_stretched_profile_takes_exactly_the_duration(d, v_max, a_max, factor):
    fastest = TrapezoidProfile(d, v_max, a_max)
    duration = max(fastest.duration * factor, 1e-6)
    p = TrapezoidProfile(d, v_max, a_max, duration=duration)
    assert p.duration == duration
    t, s, v, a = dense(p)
    assert s[-1] == d and s[0] == 0.0
    assert p.peak_speed <= fastest.peak_speed * (1 + 1e-12)
    assert np.all(v <= v_max * (1 + 1e-12)) and np.all(np.abs(a) <= a_max)
    if d > 0:
        np.testing.assert_allclose(np.trapezoid(v, t), d, rtol=1e-9, atol=1e-12)
        # Same shape: ramps at a_max, so only the cruise speed drops.
        assert p.accel_time == pytest.approx(p.peak_speed / a_max)


def test_stretch_solves_for_the_cruise_speed():
    # 1 m in 3 s at 1 m/s²: v (3 - v) = 1  ->  v = (3 - sqrt(5)) / 2.
    p = TrapezoidProfile(1.0, 1.0, 1.0, duration=3.0)
    assert p.peak_speed == pytest.approx((3 - np.sqrt(5)) / 2, rel=1e-12)
    assert p.sample(1.5)[0] == pytest.approx(0.5)


def test_too_short_a_duration_is_refused():
    with pytest.raises(ValueError, match=r"1\.9000 s is shorter than the 2\.0000 s"):
        TrapezoidProfile(1.0, 1.0, 1.0, duration=1.9)


def test_a_duration_short_by_float_noise_is_the_minimum():
    p = TrapezoidProfile(1.0, 1.0, 1.0, duration=2.0 - 1e-13)
    assert p.duration == 2.0


def test_zero_distance_stays_put():
    p = TrapezoidProfile(0.0, 1.0, 1.0)
    assert p.duration == 0.0
    assert p.sample(0.0) == (0.0, 0.0, 0.0)
    held = TrapezoidProfile(0.0, 1.0, 1.0, duration=2.0)
    s, v, a = held.sample(np.linspace(-1, 3, 9))
    assert not s.any() and not v.any() and not a.any()


def test_tiny_distance_is_accurate():
    p = TrapezoidProfile(1e-12, 1.0, 1.0, duration=5.0)
    assert p.sample(5.0)[0] == 1e-12
    # Area under the speed curve, ramps included, is the distance.
    assert p.peak_speed * (p.duration - p.accel_time) == pytest.approx(1e-12, rel=1e-12)
    assert p.sample(2.5)[0] == pytest.approx(0.5e-12, rel=1e-12)
    assert TrapezoidProfile(5e-324, 1.0, 2.0).sample(0.0)[0] == 5e-324


def test_outside_the_move_it_rests_at_the_ends():
    p = TrapezoidProfile(3.0, 1.0, 2.0)
    s, v, a = p.sample(np.array([-1.0, p.duration, p.duration + 5]))
    np.testing.assert_array_equal(s, [0.0, 3.0, 3.0])
    np.testing.assert_array_equal(v, 0.0)
    np.testing.assert_array_equal(a, 0.0)


@pytest.mark.parametrize("args", [(-1.0, 1.0, 1.0), (1.0, 0.0, 1.0), (1.0, 1.0, -2.0),
                                  (np.nan, 1.0, 1.0), (1.0, np.inf, 1.0)])
def test_invalid_arguments_are_refused(args):
    with pytest.raises(ValueError):
        TrapezoidProfile(*args)


def test_negative_duration_is_refused():
    with pytest.raises(ValueError, match="duration"):
        TrapezoidProfile(1.0, 1.0, 1.0, duration=-1.0)
