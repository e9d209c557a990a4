"""The twin's drives are MuJoCo actuators stepped 8 steps per cycle; what a client sees of them:

* a servo target takes effect in the cycle after the one it arrived in (causal); a step from
  rest is done to within 10 % at that cycle's end and settled on (1e-4 rad) 5 cycles later;
* a moving setpoint (a 0.5 Hz sine of 0.63 rad/s peak on every joint) is tracked to well
  under the 1e-4 rad a servo client checks, at every cycle's end;
* at rest the joint efforts are the gravity torques (the drives hold the arm, gravity
  compensation included, within the torque limits).

Real MuJoCo twin (zu5), its cycles stepped one by one here instead of by the real-time thread
(the thread is not started), so every number is deterministic.
"""
import mujoco
import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.sim import SimBackend
from jaka_driver.sim.motions import ServoTarget


@pytest.fixture
def twin():
    backend = SimBackend(load_model("zu5"))
    for _ in range(5):
        backend._physics.step_cycle()
    return backend


def test_a_servo_target_moves_the_arm_in_the_cycle_after_it_arrived(twin):
    physics = twin._physics
    q0 = physics.sample().q.copy()
    target = ServoTarget(q0, physics)
    physics.switch(target)
    physics.step_cycle()
    goal = q0 + np.array([0.004, -0.003, 0.002, 0.004, -0.004, 0.005])   # ~0.5 rad/s
    target.set(goal)        # arrives during this cycle...
    physics.step_cycle()    # ...which still holds the previous setpoint
    assert np.max(np.abs(physics.sample().q - q0)) < 1e-6
    physics.step_cycle()    # the next cycle moves the arm to it: from rest, a 0.5 rad/s
    moved = (physics.sample().q - q0) / (goal - q0)    # step ends within 10 % of it...
    assert np.all(moved > 0.9) and np.all(moved < 1.1)
    for _ in range(5):      # ...and settles on it (the velocity steps, 60 rad/s² for one
        physics.step_cycle()    # cycle, are beyond any arm's acceleration)
    assert np.max(np.abs(physics.sample().q - goal)) < 1e-4


def test_a_moving_setpoint_is_tracked_within_a_cycle(twin):
    physics = twin._physics
    center = physics.sample().q.copy()
    target = ServoTarget(center, physics)
    physics.switch(target)
    worst, previous = 0.0, None
    for k in range(500):                             # 4 s, from rest into a 0.5 Hz sine
        q = center + 0.2 * np.sin(np.pi * k * physics.cycle)
        target.set(q)
        physics.step_cycle()
        if previous is not None and k >= 125:
            worst = max(worst, float(np.max(np.abs(physics.sample().q - previous))))
        previous = q
    assert worst < 3e-5


def test_at_rest_the_efforts_are_the_gravity_torques(twin):
    physics = twin._physics
    d = mujoco.MjData(physics.m)
    d.qpos[:6] = physics.sample().q
    mujoco.mj_forward(physics.m, d)                  # qvel = 0: the bias is gravity alone
    effort = physics.sample().tau
    np.testing.assert_allclose(effort, d.qfrc_bias[:6], atol=1e-3)
    assert np.all(np.abs(effort) <= twin.model.max_effort)
