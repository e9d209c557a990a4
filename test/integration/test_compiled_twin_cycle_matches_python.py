"""The twin's cycle compiled (sim/joint_drives.c) computes what its numpy path computes.

Two zu5 twins, one stepping its cycles through the C library ``make setup`` builds and one
through numpy, get the same commands: a servo sine on every joint, a drag phase (drives
released: gravity compensation and drag damping only), a jump of the setpoint the drives
cannot follow within a cycle, and a closed-brakes phase. After every cycle the joints,
velocities, torques and the following error the overload check reads must be equal to the
last bit. Real MuJoCo; the cycles are stepped one by one here (no real-time thread).
"""
import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.sim import native_drives
from jaka_driver.sim import SimBackend
from jaka_driver.sim.motions import ServoTarget


def _twin(compiled: bool, **backend) -> SimBackend:
    twin = SimBackend(load_model("zu5"), **backend)
    if not compiled:
        twin._physics.servo._native = None
    return twin


def _trace(twin: SimBackend) -> list[np.ndarray]:
    """Every cycle's joints (rad), velocities (rad/s), torques (N·m) and following error."""
    physics, servo = twin._physics, twin._physics.servo
    center = servo.setpoint.copy()
    target = ServoTarget(center, physics)
    physics.switch(target)
    rows = []

    def cycle():
        physics.step_cycle()
        sample = physics.sample()
        joint, lag = servo.following_error(physics.d)
        rows.append(np.concatenate([sample.q, sample.qd, sample.tau, [joint, lag]]))

    for k in range(150):                                    # 0.5 Hz sine, 0.3 rad/s peak
        target.set(center + 0.1 * np.sin(np.pi * k * physics.cycle))
        cycle()
    servo.released = True                                   # drag: the arm sags, damped
    for _ in range(40):
        cycle()
    servo.released = False
    physics.hold_here()
    physics.switch(target)
    target.set(physics.sample().q + np.array([0.0, 0.2, 0.0, 0.0, 0.0, 0.1]))
    for _ in range(20):                                     # a jump: lag, then tracking
        cycle()
    physics.engage_brakes()
    for _ in range(5):
        cycle()
    return rows


def test_the_compiled_library_is_built_and_steps_the_twin():
    assert native_drives.load() is not None, (
        f"{native_drives.library_path()} missing or refused: make setup builds it")
    assert SimBackend(load_model("zu5"))._physics.servo.compiled


def test_compiled_and_numpy_cycles_agree_to_the_last_bit():
    compiled, python = _trace(_twin(True)), _trace(_twin(False))
    assert len(compiled) == len(python) == 215
    moved = np.max(np.abs(compiled[189][:6] - compiled[0][:6]))
    assert moved > 0.05, f"the trace barely moves the arm ({moved:.3f} rad): it proves nothing"
    lags = [row[-1] for row in compiled]
    assert max(lags) > 0.01, "the jump never opened a following error"
    for k, (c, p) in enumerate(zip(compiled, python)):
        assert np.array_equal(c, p), f"cycle {k}: largest difference {np.max(np.abs(c - p))}"


def test_with_a_grippers_fingers_the_cycles_still_agree_to_the_last_bit():
    """The DH gripper's two finger joints make MuJoCo's model 8 degrees of freedom: the
    feed-forward takes the arm's rows of M·(q̈, 0) in both paths."""
    compiled = _trace(_twin(True, gripper="dh_pgi"))
    python = _trace(_twin(False, gripper="dh_pgi"))
    assert _twin(True, gripper="dh_pgi")._mj_model.nv == 8
    for k, (c, p) in enumerate(zip(compiled, python)):
        assert np.array_equal(c, p), f"cycle {k}: largest difference {np.max(np.abs(c - p))}"


def test_a_library_built_for_another_mujoco_is_refused(monkeypatch):
    monkeypatch.setattr(native_drives.mujoco, "mj_version", lambda: 3_003_007)
    assert native_drives.load.__wrapped__() is None


def test_a_file_that_is_not_the_library_is_refused(tmp_path, monkeypatch):
    fake = tmp_path / "libjaka_drives.so"
    fake.write_bytes(b"not a shared object")
    monkeypatch.setenv("JAKA_DRIVES_LIB", str(fake))
    assert native_drives.load.__wrapped__() is None
