"""The arithmetic of the twin's force control, checked against hand computations: a payload's
load on the sensor, the least-squares identification (exact without noise, within 2 %/2 mm
with the sensor's noise, refusing poses that cannot tell centroid from offset), the admittance
law (equilibrium at the constant force, dead band, speed cap, rebound), a wrench moved to the
TCP, and velocity compliance's bands."""
import numpy as np
import pytest

from jaka_driver.backend.force import COMPLIANT_SPEED, ForceFrame, SensorPayload, \
    VelocityCompliance
from jaka_driver.common.transforms import rotvec_to_matrix
from jaka_driver.sim.force_control import DEAD_BAND, AxisLaws, wrench_at_tcp
from jaka_driver.backend.force import gravity_wrench
from jaka_driver.sim.payload_identification import MIN_SPREAD, estimate_payload, spread

DOWN = np.diag([1.0, -1.0, -1.0])            # sensor z along the world's -z
ACROSS = rotvec_to_matrix([0.0, np.pi / 2, 0.0]) @ DOWN
TILTED = rotvec_to_matrix([np.pi / 4, 0.0, 0.0]) @ DOWN


def test_a_payload_hanging_down_loads_the_sensor_with_its_weight_and_moment():
    payload = SensorPayload(2.0, np.array([0.01, 0.0, 0.05]))
    w = gravity_wrench(payload, DOWN)
    assert w[:3] == pytest.approx([0.0, 0.0, 19.62])       # along the sensor's +z: outwards
    assert w[3:] == pytest.approx(np.cross([0.01, 0.0, 0.05], [0.0, 0.0, 19.62]))


def test_identification_is_exact_without_noise_and_within_2_percent_and_2_mm_with_it():
    truth = SensorPayload(1.3, np.array([0.02, -0.01, 0.08]))
    offset = np.array([1.2, -0.8, 2.5, 0.04, -0.03, 0.02])
    poses = [DOWN, ACROSS, TILTED, rotvec_to_matrix([0.3, -0.5, 1.0]) @ DOWN]
    clean = [gravity_wrench(truth, r) + offset for r in poses]
    found, bias, residual = estimate_payload(poses, clean)
    assert found.mass == pytest.approx(truth.mass, abs=1e-9)
    assert found.centroid == pytest.approx(truth.centroid, abs=1e-9)
    assert bias == pytest.approx(offset, abs=1e-9) and residual < 1e-9
    rng = np.random.default_rng(1)
    noise = np.array([0.05] * 3 + [0.002] * 3)
    noisy = [w + rng.normal(0, 1, 6) * noise for w in clean]
    found, _, _ = estimate_payload(poses, noisy)
    assert abs(found.mass - truth.mass) <= 0.02 * truth.mass
    assert np.linalg.norm(found.centroid - truth.centroid) <= 0.002


def test_poses_turning_the_sensor_about_one_axis_cannot_be_identified():
    about_z = [DOWN @ rotvec_to_matrix([0, 0, a]) for a in (0.0, 1.0, 2.0)]
    assert spread(about_z) < 1e-6 < MIN_SPREAD
    assert spread([DOWN, ACROSS, rotvec_to_matrix([np.pi / 2, 0, 0]) @ DOWN]) > 0.3


def test_the_admittance_law_rests_at_the_constant_force_and_ignores_noise_on_free_axes():
    laws = AxisLaws([0.1 / 40] * 6, [0, 0, 10.0, 0, 0, 0], [0.0] * 6)
    at_rest = laws.twist(np.array([0, 0, -10.0, 0, 0, 0]), np.zeros(6))
    assert at_rest == pytest.approx(np.zeros(6))            # pressing 10 N: the reading is -10
    free_space = laws.twist(np.zeros(6), np.zeros(6))
    assert free_space[2] == pytest.approx(0.1 / 40 * 10)    # towards the surface, 25 mm/s
    small = laws.twist(DEAD_BAND * 0.9, np.zeros(6))
    assert small[[0, 1, 3, 4, 5]] == pytest.approx(np.zeros(5))
    hard = laws.twist(np.array([400.0, 0, 0, 0, 0, 0]), np.zeros(6))
    assert hard[0] == pytest.approx(COMPLIANT_SPEED[0])     # capped at the compliant speed


def test_the_rebound_pulls_back_to_the_start():
    laws = AxisLaws([0.1 / 40] + [0] * 5, [0.0] * 6, [500.0] + [0] * 5)
    pulled = laws.twist(np.zeros(6), np.array([0.01, 0, 0, 0, 0, 0]))     # 10 mm away
    assert pulled[0] == pytest.approx(-0.1 / 40 * 5.0)     # 5 N back at 0.5 N/mm


def test_a_wrench_moves_to_the_tcp_in_the_tool_or_the_base_frame():
    tool = np.eye(4)
    tool[:3, 3] = [0.0, 0.0, 0.1]                           # TCP 100 mm out along z
    flange = np.eye(4)
    flange[:3, :3] = DOWN
    w = np.array([5.0, 0.0, 0.0, 0.0, 0.5, 0.0])            # about the flange: M_y 0.5
    at_tcp = wrench_at_tcp(w, tool, flange, ForceFrame.TOOL)
    assert at_tcp == pytest.approx([5.0, 0, 0, 0, 0.5 - 0.1 * 5.0, 0])   # M − p × F
    in_base = wrench_at_tcp(w, tool, flange, ForceFrame.WORLD)
    assert in_base == pytest.approx([5.0, 0, 0, 0, 0, 0])


def test_velocity_compliance_slows_in_bands_up_to_the_condition():
    two = VelocityCompliance(1, (0.6, 0.3, 0.0, 0.0))       # bands of a third
    assert [two.speed_factor(s) for s in (0.1, 0.4, 0.7, 0.99)] == [1.0, 0.6, 0.3, 0.3]
    four = VelocityCompliance(3, (0.8, 0.6, 0.4, 0.2))      # bands of a fifth
    assert [four.speed_factor(s) for s in (0.1, 0.3, 0.5, 0.7, 0.9)] == \
        [1.0, 0.8, 0.6, 0.4, 0.2]
