"""The controller backend's local kinematics are the arm's own, over real TCP against the
emulator: on an emulator whose arm is calibrated (its twin moves on a perturbed chain and
get_dh_param states it) they equal the controller's kine_forward / kine_inverse to a
micrometre, where the nominal chain is a fraction of a millimetre off; on an emulator whose arm
is another model's the backend names that model in one error line and refuses every motion
(-9, nothing moves) until ~kinematics says which chain is right; a line the arm cannot follow
is refused before moveL goes out."""
from __future__ import annotations

import logging

import numpy as np
import pytest

from support.emulated_arm import LINK_TIMEOUTS
from support.move_helpers import run_move

from jaka_driver.common.models import load_model
from jaka_driver.common.results import Code
from jaka_driver.common.transforms import pose_to_matrix
from jaka_driver.controller import ControllerBackend
from jaka_driver.emulator import Emulator
from jaka_driver.emulator.calibration import arm_model
from jaka_driver.kinematics import Kinematics
from jaka_driver.kinematics.controller_dh import CALIBRATION_TOLERANCE
from jaka_driver.motion.profiles import SyncJointProfile
from jaka_driver.motion.trajectory import JointTrajectory

ZU5 = load_model("zu5")
HOME = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0.0])
RNG = np.random.default_rng(25)


def started(emu, **kwargs) -> ControllerBackend:
    backend = ControllerBackend(ZU5, "127.0.0.1", emu.command_port, emu.status_port,
                                **{**LINK_TIMEOUTS, **kwargs})
    backend.start()
    assert backend.state().enabled
    return backend


@pytest.fixture(scope="module")
def calibrated():
    with Emulator(arm_model(ZU5, calibration="7"), command_port=0, status_port=0,
                  start="enabled") as emulator:
        backend = started(emulator)
        yield emulator, backend
        backend.shutdown()


def test_local_fk_and_ik_are_the_calibrated_controllers(calibrated):
    emu, backend = calibrated
    assert 0.2e-3 < backend.identity.difference < CALIBRATION_TOLERANCE
    assert backend.describe()["kinematics"] == "auto: the controller's parameters"
    local, nominal = backend.kinematics, Kinematics(ZU5)
    worst_fk = worst_ik = 0.0
    nominal_off = []
    for q in RNG.uniform(-2.0, 2.0, (12, 6)):
        theirs = backend.forward_kinematics(q)          # kine_forward, over the wire
        assert theirs.ok, theirs.message
        worst_fk = max(worst_fk, np.abs(local.flange_pose(q)[:3, 3] - theirs.value[:3, 3]).max())
        nominal_off.append(np.abs(nominal.flange_pose(q)[:3, 3] - theirs.value[:3, 3]).max())
        seed = q + RNG.uniform(-0.05, 0.05, 6)
        answer = backend.inverse_kinematics(theirs.value, seed)   # kine_inverse
        assert answer.ok, answer.message
        ours = local.ik(theirs.value, seed=seed)
        assert ours.success, ours.message
        worst_ik = max(worst_ik, np.abs(local.flange_pose(answer.value)[:3, 3]
                                        - local.flange_pose(ours.q)[:3, 3]).max())
    assert worst_fk < 1e-6           # m: the wire's rounding
    assert worst_ik < 2e-6           # m: both solutions put the flange on the same point
    assert min(nominal_off) > 1e-5 and max(nominal_off) > 2e-4   # the nominal chain is off


def test_a_line_on_the_calibrated_arm_is_checked_and_runs(calibrated):
    emu, backend = calibrated
    assert run_move(backend.start_joint_move(HOME, 2.0, 8.0)).ok
    here = backend.state().tcp_pose
    target = here @ pose_to_matrix([0.05, -0.03, 0.04, 0.0, 0.0, 0.3])
    result = run_move(backend.start_linear_move(target, 0.1, 0.5))
    assert result.ok, result.message
    np.testing.assert_allclose(backend.state().tcp_pose[:3, 3], target[:3, 3], atol=2e-4)
    # 2 m away: no IK at some sample, refused -4 by the local check (the controller's own
    # refusal would be 2); the arm stays (its drives hold it within µrad)
    q = emu.backend.state().joint_position.copy()
    far = target.copy()
    far[:3, 3] += [2.0, 0.0, 0.0]
    refused = backend.start_linear_move(far, 0.1, 0.5)
    assert refused.code == Code.IK_FAILED and "no IK solution at" in refused.message
    np.testing.assert_allclose(emu.backend.state().joint_position, q, atol=1e-4)


def test_another_models_arm_is_named_and_nothing_moves_until_told(caplog):
    with Emulator(arm_model(ZU5, dh_from="zu7"), command_port=0, status_port=0,
                  start="enabled") as emu:
        with caplog.at_level(logging.INFO, logger="jaka_driver.controller"):
            backend = started(emu)
        try:
            errors = [r.getMessage() for r in caplog.records if r.levelno == logging.ERROR]
            assert len(errors) == 1, errors
            line = errors[0]
            assert "model:=zu5 does not match the arm" in line
            assert "a zu7's (the same chain as c7, pro7)" in line
            assert "restart with model:=zu7" in line and "kinematics:=controller" in line
            q = emu.backend.state().joint_position.copy()
            tool = backend.state().tcp_pose
            step = JointTrajectory.from_profile(
                SyncJointProfile(q, q + 0.05, np.full(6, 0.5), np.full(6, 2.0)), 0.008)
            attempts = {
                "joint_move": lambda: backend.start_joint_move(q + 0.1, 1.0, 2.0),
                "linear_move": lambda: backend.start_linear_move(
                    tool @ pose_to_matrix([0.02, 0, 0, 0, 0, 0]), 0.05, 0.2),
                "jog": lambda: backend.jog(0, 0, 1, 0.1),
                "servo mode": lambda: backend.servo_enable(True),
                "servo_j": lambda: backend.servo_j(q),
                "servo_p": lambda: backend.servo_p(tool),
                "trajectory": lambda: backend.start_trajectory(step),
            }
            for what, attempt in attempts.items():
                result = attempt()
                assert result.code == Code.WRONG_MODE, (what, result)
                assert result.message.startswith(f"{what} refused: the arm is a zu7's")
                assert "model:=zu7" in result.message
            assert not backend.state().servo_mode
            np.testing.assert_allclose(emu.backend.state().joint_position, q, atol=1e-4)
            # not motion: the controller's own kinematics still answer
            assert backend.forward_kinematics(q).ok
        finally:
            backend.shutdown()

        # told which is right: the model's chain, or the controller's parameters
        for choice in ("model", "controller"):
            backend = started(emu, kinematics=choice)
            try:
                assert backend.describe()["kinematics"].startswith(choice)
                moved = run_move(backend.start_joint_move(HOME, 2.0, 8.0))
                assert moved.ok, (choice, moved.message)
                fk = backend.forward_kinematics(HOME).value
                off = np.abs(backend.kinematics.flange_pose(HOME)[:3, 3] - fk[:3, 3]).max()
                # the controller's parameters are the zu7 arm's; the zu5's chain is not
                assert (off < 1e-6) if choice == "controller" else (off > 0.05), (choice, off)
            finally:
                backend.shutdown()
