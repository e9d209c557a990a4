"""The twin mounted on a wall or a ceiling (docs/interface.md, "Mounting"), in simulated time
through RobotDriver's door: MuJoCo's gravity turns with the installation angle while the base
stays the frame of every pose. At home the arm's weight is held by J2 and J3 upright; on a wall
(90° about x: gravity along the base's −y) the same moment falls on J1, about the base's z; on
a ceiling J2 and J3 hold it the other way. The sensor's compensated reading of a known payload
is zero in every pose on the wall, payload identification finds the payload there (2 %, 2 mm),
drag mode leaves the arm floating where it is,
the drives hold the rated payload there, and the refusals name field, value and limit."""
import math

import numpy as np
import pytest

from jaka_driver.common.results import Code
from support.sensor_twin import MODEL, fresh, sensor_driver  # noqa: F401 - the fixture

WALL, CEILING = math.pi / 2, math.pi
POSES = [MODEL.home, MODEL.home + [0, 0, 0, 0, -np.pi / 2, 0],
         MODEL.home + [0.6, 0.3, -0.4, 0.8, 0, 1.2]]


@pytest.fixture
def arm(sensor_driver):
    """A fresh twin at home, its sensor on; upright again afterwards (a mounting outlasts a
    reset: it is the cell's)."""
    yield from fresh(sensor_driver, sensor_on=True)
    assert sensor_driver.set_installation_angle(0.0, 0.0).ok


def held(driver, seconds=0.25, kind=None):
    """Joint efforts (N·m) — or the sensor's ``kind`` reading — averaged over ``seconds``."""
    driver.clock.sleep(0.3)                 # settled after a change
    samples, last = [], driver.state().stamp
    while len(samples) < round(seconds / 0.008):
        driver.clock.sleep(0.04)
        for st in driver.states_since(last):
            samples.append(st.joint_effort if kind is None else getattr(st.force, kind))
            last = st.stamp
    return np.mean(samples, axis=0)


def test_joint_efforts_show_gravity_along_the_axis_the_tilt_says(arm):
    upright = held(arm)
    assert abs(upright[0]) < 0.05 and upright[1] > 10.0          # J1 free, J2 holds
    assert arm.set_installation_angle(WALL, 0.0).ok
    wall = held(arm)
    assert wall[0] == pytest.approx(upright[1], rel=0.01)         # J1 holds that moment now
    assert np.all(np.abs(wall[1:4]) < 0.05)
    assert arm.set_installation_angle(CEILING, 0.0).ok
    ceiling = held(arm)
    assert ceiling[1:4] == pytest.approx(-upright[1:4], rel=0.01, abs=0.05)
    assert np.allclose(arm.state().joint_position, MODEL.home, atol=2e-3)   # nothing sagged
    reading = arm.installation_angle().value
    assert reading.quaternion == pytest.approx([1.0, 0, 0, 0], abs=1e-9)
    assert reading.rpy == pytest.approx([math.pi, 0, 0])


def test_on_the_wall_the_sensor_reads_a_known_payload_as_zero_in_every_pose(arm):
    assert arm.set_installation_angle(WALL, math.radians(30)).ok
    assert arm.force.zero_sensor().ok                             # zeroed without the payload
    assert arm.set_payload(0, 2.0, 0, 0, 50).ok
    assert arm.force.set_sensor_payload(2.0, [0, 0, 50]).ok
    for q in POSES:
        assert arm.joint_move(list(q), 1.0, 2.0).ok
        real, actual = held(arm, kind="real"), held(arm, kind="actual")
        assert np.linalg.norm(actual[:3]) == pytest.approx(2.0 * 9.81, rel=0.02)
        assert np.linalg.norm(real[:3]) < 0.02 * 2.0 * 9.81, (q, real)
        assert np.linalg.norm(real[3:]) < 0.02 * 2.0 * 9.81 * 0.05, (q, real)


def test_on_the_wall_payload_identification_finds_the_payload(arm):
    assert arm.set_installation_angle(WALL, 0.0).ok
    assert arm.set_payload(0, 2.0, 0, 0, 50).ok                   # the sensor is not zeroed
    result = arm.force.identify_payload(np.concatenate(POSES[1:] + [MODEL.home + [
        0, 0, 0, 0, 0.9, 1.2]]).tolist())
    assert result.ok, result.message
    mass, centroid_mm = result.value
    assert abs(mass - 2.0) <= 0.02 * 2.0
    assert np.linalg.norm(centroid_mm - [0, 0, 50]) <= 2.0


def test_in_drag_mode_on_the_wall_the_arm_floats_where_it_is(arm):
    assert arm.set_installation_angle(WALL, 0.0).ok
    assert arm.joint_move(list(POSES[2]), 1.0, 2.0).ok
    assert arm.drag_mode(True).ok
    try:
        arm.clock.sleep(1.0)
        assert np.allclose(arm.state().joint_position, POSES[2], atol=2e-3)
    finally:
        assert arm.drag_mode(False).ok


def test_on_the_wall_the_drives_hold_the_rated_payload(arm):
    assert arm.set_installation_angle(WALL, 0.0).ok
    result = arm.set_payload(0, MODEL.max_payload_kg, 0, 0, 50)
    assert result.ok, result.message
    assert arm.joint_move(list(POSES[1]), 1.0, 2.0).ok
    held(arm)
    st = arm.state()
    assert not (st.protective_stop or st.collision), st.error_message
    assert np.allclose(st.joint_position, POSES[1], atol=2e-3)


@pytest.mark.parametrize("tilt, rot, named", [(-0.1, 0.0, "tilt_x is -0.1 rad"),
                                              (3.2, 0.0, "tilt_x is 3.2 rad"),
                                              (0.0, 6.3, "rot_z is 6.3 rad"),
                                              (float("nan"), 0.0, "tilt_x is nan")])
def test_an_angle_out_of_range_is_refused_naming_field_value_and_limit(arm, tilt, rot, named):
    result = arm.set_installation_angle(tilt, rot)
    assert result.code == Code.INVALID_PARAMETER and named in result.message
    assert "expected [0, " in result.message
    assert arm.installation_angle().value.tilt_x == 0.0           # nothing changed
