"""JogVelocity: ramps to the commanded jog speed at the given acceleration, holds it, ramps
down to rest on stop and through zero on a reversal, never overshooting."""
import numpy as np
import pytest

from jaka_driver.motion.jog import JogVelocity

DT = 0.008


def run(ramp, seconds):
    return np.array([ramp.update(DT) for _ in range(int(round(seconds / DT)))])


def test_accelerates_to_the_jog_speed_and_holds_it():
    ramp = JogVelocity(accel=2.0)
    ramp.command(0.5)
    speeds = run(ramp, 1.0)
    np.testing.assert_allclose(np.diff(speeds).max(), 2.0 * DT)
    assert speeds.max() == 0.5                       # no overshoot
    first = int(np.argmax(speeds == 0.5))
    assert first * DT == pytest.approx(0.25 - DT, abs=DT)
    assert np.all(speeds[first:] == 0.5)


def test_stop_decelerates_smoothly_to_rest():
    ramp = JogVelocity(accel=2.0, speed=0.5)
    ramp.command(0.5)
    assert ramp.stopping_distance == pytest.approx(0.0625)
    ramp.stop()
    speeds = run(ramp, 0.5)
    assert np.all(np.diff(speeds) <= 0) and np.all(np.diff(speeds) >= -2.0 * DT - 1e-15)
    assert speeds[-1] == 0.0 and ramp.at_rest
    travelled = np.sum(speeds) * DT
    assert travelled == pytest.approx(0.0625, abs=0.5 * DT)


def test_reversal_passes_through_zero_at_the_acceleration():
    ramp = JogVelocity(accel=1.0, speed=0.2)
    ramp.command(-0.2)
    speeds = run(ramp, 0.6)
    assert np.all(np.abs(np.diff(speeds)) <= 1.0 * DT + 1e-15)
    assert speeds[-1] == -0.2 and speeds.min() == -0.2


def test_invalid_acceleration_or_speed_is_refused():
    with pytest.raises(ValueError):
        JogVelocity(accel=0.0)
    with pytest.raises(ValueError):
        JogVelocity(accel=1.0).command(float("nan"))
