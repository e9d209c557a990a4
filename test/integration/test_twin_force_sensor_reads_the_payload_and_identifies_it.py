"""The twin's flange force/torque sensor, in simulated time through RobotDriver's door: a 2 kg
payload at (0, 0, 50) mm on a sensor zeroed without it reads its weight (19.62 N) and its
moment r × F in the sensor frame within 2 % with the tool axis vertical and horizontal;
identification through four poses finds the mass within 2 % and the centroid within 2 mm, and
made the sensor's tool payload the compensated wrench reads ~0 in another pose; a twin reset
puts the sensor back to a fresh one.

Expected values are computed by hand from the pose: the weight m·g in the sensor frame is
Rᵀ (0, 0, −9.81) m, R the flange's rotation (Pinocchio's FK of the joints), its moment c × F."""
import numpy as np
import pytest

from jaka_driver.kinematics import Kinematics
from support.sensor_twin import MODEL, fresh, twin_with_sensor

KIN = Kinematics(MODEL)
MASS = 2.0
CENTROID = np.array([0.0, 0.0, 0.05])         # m, sensor (flange) frame
VERTICAL = MODEL.home                         # the tool points down
HORIZONTAL = MODEL.home + [0, 0, 0, 0, -np.pi / 2, 0]   # the tool along the base's x
#: four poses, the tool down and turned 45° three ways (spread 0.23)
POSES = [MODEL.home + d for d in ([0, 0, 0, 0, -0.8, 0], [0, 0, 0, 0.8, 0, 0],
                                  [0, 0, 0, 0, 0.9, 1.2])]


@pytest.fixture(scope="module")
def driver():
    with twin_with_sensor() as d:
        yield d


@pytest.fixture
def arm(driver):
    """A fresh twin at home, its sensor on."""
    yield from fresh(driver, sensor_on=True)


def mean_reading(driver, seconds=0.25, kind="actual"):
    """The reading averaged over ``seconds`` of samples (noise 0.05 N per sample)."""
    samples, last = [], driver.state().stamp
    while len(samples) < round(seconds / 0.008):
        driver.clock.sleep(0.04)
        for st in driver.states_since(last):
            samples.append(getattr(st.force, kind))
            last = st.stamp
    return np.mean(samples, axis=0)


def expected_load(q, mass, centroid):
    weight = mass * KIN.flange_pose(q)[:3, :3].T @ np.array([0.0, 0.0, -9.81])
    return np.concatenate([weight, np.cross(centroid, weight)])


def move_to(driver, q):
    result = driver.joint_move(list(q), 1.0, 2.0)
    assert result.ok, result.message
    driver.clock.sleep(0.3)          # at rest: no inertia in the reading


def test_a_2_kg_payload_reads_its_weight_and_moment_within_2_percent_in_two_poses(arm):
    assert arm.force.zero_sensor().ok                       # zeroed without the payload
    assert arm.set_payload(0, MASS, *(CENTROID * 1000)).ok
    weight = MASS * 9.81
    for name, q in (("vertical", VERTICAL), ("horizontal", HORIZONTAL)):
        move_to(arm, q)
        read, expected = mean_reading(arm), expected_load(q, MASS, CENTROID)
        force_error = np.linalg.norm(read[:3] - expected[:3])
        moment_error = np.linalg.norm(read[3:] - expected[3:])
        print(f"{name}: F {np.round(read[:3], 3)} N (expected {np.round(expected[:3], 3)}), "
              f"M {np.round(read[3:], 4)} N·m (expected {np.round(expected[3:], 4)})")
        assert abs(np.linalg.norm(read[:3]) - weight) <= 0.02 * weight, (name, read)
        assert force_error <= 0.02 * weight, (name, read, expected)
        # the moment's scale is the weight at the centroid's distance: 0.98 N·m
        assert moment_error <= 0.02 * weight * np.linalg.norm(CENTROID), (name, read, expected)
    # horizontal, the weight is across the tool and its moment is 0.98 N·m
    assert np.linalg.norm(expected_load(HORIZONTAL, MASS, CENTROID)[3:]) == \
        pytest.approx(weight * 0.05, rel=1e-6)


def test_identification_finds_the_payload_within_2_percent_and_2_mm(arm):
    assert arm.set_payload(0, MASS, *(CENTROID * 1000)).ok   # the sensor is not zeroed
    progress = []
    result = arm.force.identify_payload(np.concatenate(POSES).tolist(), apply=True,
                                        feedback=lambda s: progress.append(s.progress))
    assert result.ok, result.message
    mass, centroid_mm = result.value
    print(f"identified {mass:.4f} kg at {np.round(centroid_mm, 3)} mm: {result.message}")
    assert abs(mass - MASS) <= 0.02 * MASS
    assert np.linalg.norm(centroid_mm - CENTROID * 1000) <= 2.0
    assert progress and progress == sorted(progress) and progress[-1] < 1.0
    status = arm.force.identification_status()
    assert status.state == 0 and status.progress == 1.0 and status.result.mass == mass
    # applied: the compensated wrench is the sensor's offset alone, the same in any pose
    assert arm.force.zero_sensor().ok
    move_to(arm, HORIZONTAL)
    real = mean_reading(arm, kind="real")
    assert np.linalg.norm(real[:3]) <= 0.02 * MASS * 9.81, real


def test_identification_refuses_poses_that_turn_the_sensor_too_little(arm):
    turned_about_the_tool_axis = [MODEL.home + [0, 0, 0, 0, 0, a] for a in (1.0, 2.0)]
    before = arm.state().joint_position.copy()
    result = arm.force.identify_payload(np.concatenate(turned_about_the_tool_axis).tolist())
    assert result.code == -2 and "too little" in result.message, result.message
    arm.clock.sleep(0.1)
    assert np.allclose(arm.state().joint_position, before, atol=1e-4)   # nothing moved


def test_a_reset_gives_back_a_fresh_sensor(arm):
    assert arm.force.set_filter(5.0).ok and arm.force.zero_sensor().ok
    assert arm.twin.reset().ok
    s = arm.force.settings().value
    assert not s.sensor_on and s.filter_hz == 0 and s.mode == "off"
    assert arm.state().force is None
