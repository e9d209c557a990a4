"""Every model's twin carries its rated payload: with the payload set, a joint_move at the
model's full joint speed and acceleration into the stretched-out arm and a fast linear_move (half its TCP speed limit, at
its full TCP acceleration) end where they were sent, the drives following their setpoints
closely all the way (no overload stop); and get_fk / get_ik answer JAKA's chain and find the
reference's own configuration again.

RobotDriver on the real MuJoCo twin of each model, in simulated time at full speed
(real_time_factor 0), no ROS. get_fk is compared with test/data/jaka_chains/flange_poses.json
(JAKA's chains composed independently of the driver).
"""
import json
from pathlib import Path

import numpy as np
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.driver import RobotDriver
from jaka_driver.sim import SimBackend
from jaka_driver.common.transforms import (matrix_to_pose_mm, pose_mm_to_matrix,
                                          rotation_angle_between)

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "jaka_chains" / "flange_poses.json"
POSES = json.loads(FIXTURE.read_text())
PAYLOAD_CENTROID_MM = (0.0, 0.0, 100.0)    # the rated payload 100 mm out on the flange axis
TRACKING_RAD = 0.01          # largest lag of a joint behind its setpoint, at any cycle
ARRIVED_RAD = 2e-3           # where a joint_move ends, against its target
ARRIVED_MM = 1.0             # where a linear_move ends, against its target


@pytest.fixture(params=MODEL_NAMES)
def kinematics(request):
    """The driver on a twin that is built but not started: get_fk and get_ik need no motion
    (and the kinematics run at full speed, not beside a free-running physics thread)."""
    return RobotDriver(SimBackend(load_model(request.param)))


@pytest.fixture(params=MODEL_NAMES)
def twin(request):
    backend = SimBackend(load_model(request.param), sim_time=True, real_time_factor=0)
    driver = RobotDriver(backend)
    driver.start()
    lags = []
    servo = backend._physics.servo
    backend._physics.on_cycle.append(lambda d: lags.append(servo.following_error(d)[1]))
    driver.lags = lags
    yield driver
    driver.shutdown()


def test_get_fk_is_jaka_chain_and_get_ik_returns_the_reference_configuration(kinematics):
    twin = kinematics
    model = twin.model
    for rec in POSES[model.name]:
        q = np.array(rec["q"])
        fk = twin.get_fk(q)
        assert fk.ok, fk.message
        T = pose_mm_to_matrix(fk.value)
        assert np.linalg.norm(T[:3, 3] - rec["position_m"]) <= 0.05e-3
        assert rotation_angle_between(T[:3, :3], np.array(rec["rotation"])) <= 1e-6
        if np.linalg.svd(twin.backend._kin.jacobian(q), compute_uv=False)[-1] < 0.01:
            continue        # next to a singularity the reference's branch is not well defined
        ik = twin.get_ik(np.clip(q + 0.02, model.lower, model.upper), fk.value)
        assert ik.ok, ik.message
        np.testing.assert_allclose(ik.value, q, atol=1e-6)


def test_joint_move_at_full_speed_into_the_stretched_arm_with_the_rated_payload(twin):
    # The payload's torque is largest with the arm stretched out horizontally: the move ends
    # there, the upper arm 0.2 rad above horizontal (the MiniCobo's stands up at q = 0: its J2
    # leans 1.4 rad), reached at the model's full joint speed and acceleration.
    model = twin.model
    assert twin.set_payload(1, model.rated_payload_kg, *PAYLOAD_CENTROID_MM).ok
    lean = 1.4 if model.structure == "spherical_wrist" else 0.2
    target = np.clip([0.8, lean, 0.0, 0.6, -0.7, 1.0], model.lower, model.upper)
    twin.lags.clear()
    reply = twin.joint_move(target, float(np.max(model.max_velocity)),
                            float(np.max(model.max_acceleration)))
    assert reply.ok, reply.message
    st = twin.state()
    assert not st.protective_stop and not st.collision
    np.testing.assert_allclose(st.joint_position, target, atol=ARRIVED_RAD)
    assert max(twin.lags) < TRACKING_RAD, f"lagged {max(twin.lags):.4f} rad"


def test_fast_linear_move_with_the_rated_payload(twin):
    model = twin.model
    assert twin.set_payload(1, model.rated_payload_kg, *PAYLOAD_CENTROID_MM).ok
    start = twin.state().tcp_pose
    target = start.copy()
    # m, base frame: 200 mm on a 1 m arm, in proportion on the smaller ones
    target[:3, 3] += np.array([0.10, -0.10, -0.15]) * min(1.0, model.reach_mm / 1000.0)
    twin.lags.clear()
    # half the TCP speed limit, or half the speed at which a joint would reach its own limit
    # along this line where it starts, if less: at the full TCP limit a small arm's joints
    # could not follow the line (the MiniCobo's turn at 90 °/s), and the planner refuses that
    direction = np.r_[target[:3, 3] - start[:3, 3], 0, 0, 0]
    rates = np.linalg.pinv(twin.backend._kin.jacobian(twin.state().joint_position)) @ (
        direction / np.linalg.norm(direction))                  # rad per m of path
    speed = min(500.0 * model.max_tcp_speed,                   # mm/s, the request's unit
                500.0 * float(np.min(model.max_velocity / np.abs(rates))))
    reply = twin.linear_move(matrix_to_pose_mm(target), speed, model.max_tcp_accel * 1000.0,
                             coord_mode=1)
    assert reply.ok, reply.message
    st = twin.state()
    assert not st.protective_stop and not st.collision
    assert np.linalg.norm(st.tcp_pose[:3, 3] - target[:3, 3]) * 1000 < ARRIVED_MM
    assert rotation_angle_between(st.tcp_pose[:3, :3], target[:3, :3]) < 2e-3
    assert max(twin.lags) < TRACKING_RAD, f"lagged {max(twin.lags):.4f} rad"
