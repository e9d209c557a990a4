"""The twin's drives have torque limits; what they cannot hold must not leave the arm moving.

* ``set_payload`` refuses a payload the drives could not hold still at the current pose (-2,
  naming the mass, the joint and its limit) and changes nothing;
* the holding torque it predicts is the torque the drives then apply (N·m);
* a move into a pose where the payload cannot be held ends in a protective stop on brakes:
  the move answers -12, the arm stands still (velocity exactly 0), motion is refused until
  ``clear_err``, which opens the brakes only when the drives can hold the arm.

Real MuJoCo twin (zu5) in its real-time thread, no ROS.
"""
import time

import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.sim import SimBackend
from jaka_driver.sim.overload import FOLLOWING_ERROR_LIMIT, holding_torque
from support.move_helpers import run_move


@pytest.fixture
def twin():
    backend = SimBackend(load_model("zu5"))
    backend.start()
    time.sleep(0.2)
    yield backend
    backend.shutdown()


def still_for(twin, seconds: float) -> float:
    """Largest joint speed (rad/s) seen over ``seconds``."""
    fastest, end = 0.0, time.monotonic() + seconds
    while time.monotonic() < end:
        fastest = max(fastest, float(np.max(np.abs(twin.state().joint_velocity))))
        time.sleep(0.004)
    return fastest


def test_a_payload_the_wrist_cannot_hold_here_is_refused_and_changes_nothing(twin):
    before = twin.state().joint_position.copy()
    # 7.5 kg (1.5 × rated, what set_payload's field check allows) 850 mm out sideways
    reply = twin.set_payload(3, 7.5, np.array([-0.0317, -0.6, -0.6]))
    assert reply.code == -2
    assert "mass 7.5 kg" in reply.message and "joint_4" in reply.message
    assert f"{twin.model.max_effort[3]:g} N·m limit" in reply.message
    assert twin._payload.mass == 0.0 and twin.state().tool_id == 0
    assert still_for(twin, 0.3) < 1e-3
    assert np.max(np.abs(twin.state().joint_position - before)) < 1e-4


def test_predicted_holding_torque_is_what_the_drives_apply(twin):
    centroid = np.array([0.05, 0.0, 0.1])
    with twin._physics.lock:
        predicted = holding_torque(twin._mj_model, twin._physics.d.qpos[:6].copy(), twin._payload,
                                   4.0, centroid)
    assert twin.set_payload(1, 4.0, centroid).ok
    time.sleep(0.4)
    np.testing.assert_allclose(twin.state().joint_effort, predicted, atol=0.05)


def test_overload_on_the_way_is_a_protective_stop_on_brakes(twin):
    # 7.5 kg 1 m out along the tool axis (the most set_payload's field checks allow): held
    # with the tool pointing down, not once joint_5 tilts it towards horizontal
    assert twin.set_payload(1, 7.5, np.array([0.0, 0.0, 1.0])).ok
    target = twin.state().joint_position + np.array([0, 0, 0, 0, 1.2, 0])
    reply = run_move(twin.start_joint_move(target, 1.0, 2.0))
    assert reply.code == -12 and "joint_5" in reply.message and "brakes" in reply.message
    assert f"limit {FOLLOWING_ERROR_LIMIT:g} rad" in reply.message
    st = twin.state()
    assert st.protective_stop and twin._physics.braked
    braked_at = st.joint_position.copy()
    assert still_for(twin, 0.5) == 0.0
    np.testing.assert_array_equal(twin.state().joint_position, braked_at)

    # brakes open only for an arm the drives can hold
    assert twin.set_payload(1, 1.0, np.array([0.0, 0.0, 0.1])).ok
    assert twin.clear_error().ok and not twin._physics.braked
    assert still_for(twin, 0.3) < 0.01
    back = run_move(twin.start_joint_move(braked_at - np.array([0, 0, 0, 0, 0.5, 0]), 1.0, 2.0))
    assert back.ok, back.message


def test_clear_err_keeps_the_brakes_on_an_arm_it_could_not_hold(twin):
    assert twin.set_payload(1, 7.5, np.array([0.0, 0.0, 1.0])).ok
    run_move(twin.start_joint_move(twin.state().joint_position + np.array([0, 0, 0, 0, 1.2, 0]),
                                   1.0, 2.0))
    assert twin._physics.braked
    # heavier still, as if the payload were changed on a braked arm: the brakes stay closed
    with twin._physics.lock:
        twin._payload.set(9.0, np.array([0.0, 0.0, 1.0]))
    reply = twin.clear_error()
    assert reply.code == -12 and "protective stop stands" in reply.message
    assert twin._physics.braked and twin.state().protective_stop
    assert still_for(twin, 0.3) == 0.0
