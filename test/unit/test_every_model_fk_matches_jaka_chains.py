"""The driver's forward kinematics of every model equals JAKA's own chain, computed without the
driver: test/data/jaka_chains/flange_poses.json (made by the numpy script beside it from JAKA's
URDF rows as written; README there) gives the flange pose at 12 joint vectors per model, and
the driver's FK — the one behind get_fk — must agree within 0.05 mm and 1e-6 rad.

Also: the nominal chain the model exposes (RobotModel.chain, read back from the generated URDF)
describes the same arm as Pinocchio sees, through kinematics.chain's own numpy FK, so a
comparison with another description of the arm (a controller's DH parameters) can use it.
"""
import json
from pathlib import Path

import numpy as np
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model
from jaka_driver.common.transforms import rotation_angle_between
from jaka_driver.kinematics import Kinematics
from jaka_driver.kinematics.chain import axes_at_zero, joint_frames

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "jaka_chains" / "flange_poses.json"
POSES = json.loads(FIXTURE.read_text())
POSITION_TOL_M = 0.05e-3
ROTATION_TOL_RAD = 1e-6


def test_the_fixture_covers_every_model():
    assert sorted(POSES) == sorted(MODEL_NAMES)
    assert all(len(records) == 12 for records in POSES.values())


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_flange_pose_equals_jaka_chain(name):
    kin = Kinematics(load_model(name))
    for rec in POSES[name]:
        T = kin.flange_pose(rec["q"])
        gap = np.linalg.norm(T[:3, 3] - rec["position_m"])
        angle = rotation_angle_between(T[:3, :3], np.array(rec["rotation"]))
        assert gap <= POSITION_TOL_M, f"{name} at {rec['q']}: {gap * 1e3:.4f} mm off"
        assert angle <= ROTATION_TOL_RAD, f"{name} at {rec['q']}: {angle:.2e} rad off"


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_exposed_chain_is_the_urdf_chain(name):
    model = load_model(name)
    kin = Kinematics(model)
    assert [p.kind for p in model.chain] == ["fixed"] + ["revolute"] * 6 + ["fixed"]
    for rec in POSES[name][:4]:
        frames, flange = joint_frames(model.chain, rec["q"])
        np.testing.assert_allclose(flange, kin.flange_pose(rec["q"]), atol=1e-12)
    axes, flange0 = axes_at_zero(model.chain)
    assert all(abs(np.linalg.norm(a.direction) - 1.0) < 1e-12 for a in axes)
    np.testing.assert_allclose(flange0[:3, 3], POSES[name][0]["position_m"], atol=1e-12)
