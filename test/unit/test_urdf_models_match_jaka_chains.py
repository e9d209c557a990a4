"""The generated URDFs keep JAKA's official kinematics and load in Pinocchio and MuJoCo.

Reference values: docs/models.md, "Kinematic chains" (joint chains, flange pose at q = 0) and
"Joint position limits".
"""
import importlib.util
import sys
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from jaka_driver.models import MODEL_NAMES, load_model, repo_root
from jaka_driver.transforms import matrix_to_rpy, rpy_to_matrix

ROOT = Path(__file__).resolve().parents[2]

# Flange position at q = 0 in mm, relative to the base (docs/models.md); orientation rpy
# (90°, 0, 0).
FLANGE_AT_ZERO_MM = {
    "zu3": (474.0, 8.5, 33.05),
    "zu5": (798.5, 7.0, 6.65),
    "zu7": (663.5, 8.0, 6.65),
    "zu12": (1166.5, 28.0, 27.65),
    "zu18": (910.0, 50.5, 27.65),
}
VELOCITY_LIMITS = {
    "zu3": (3.14, 3.14, 3.14, 3.84, 3.84, 3.84),
    "zu5": (3.14,) * 6,
    "zu7": (3.14,) * 6,
    "zu12": (2.09, 2.09, 2.09, 3.14, 3.14, 3.14),
    "zu18": (2.09, 2.09, 3.14, 3.14, 3.14, 3.14),
}
CATALOGUE_MASS_KG = {"zu3": 12.0, "zu5": 23.0, "zu7": 22.0, "zu12": 41.0, "zu18": 35.0}
LOWER = (-6.28, -1.48, -3.05, -1.48, -6.28, -6.28)
UPPER = (6.28, 4.62, 3.05, 4.62, 6.28, 6.28)


def _pin_flange(name, q):
    m = pin.buildModelFromUrdf(str(load_model(name).urdf_path))
    d = m.createData()
    pin.framesForwardKinematics(m, d, np.asarray(q, float))
    return m, d.oMf[m.getFrameId("flange")].homogeneous


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_flange_pose_at_zero_matches_jaka(name):
    _, T = _pin_flange(name, np.zeros(6))
    np.testing.assert_allclose(T[:3, 3] * 1e3, FLANGE_AT_ZERO_MM[name], atol=0.05)
    # The official URDFs write pi/2 as 1.5708, hence 1e-3 rad and not 1e-9.
    np.testing.assert_allclose(matrix_to_rpy(T[:3, :3]), np.radians([90.0, 0.0, 0.0]), atol=1e-3)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_flange_pose_at_manual_example_is_rx180_rz_minus90(name):
    # docs/models.md: q = (0, 1.57, -1.57, 1.57, 1.57, 0) → rpy ≈ (180°, 0, -90°).
    _, T = _pin_flange(name, [0, 1.57, -1.57, 1.57, 1.57, 0])
    expected = rpy_to_matrix(np.pi, 0.0, -np.pi / 2)
    np.testing.assert_allclose(T[:3, :3], expected, atol=5e-3)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_joint_limits_names_and_tree(name):
    model = load_model(name)
    assert model.joint_names == tuple(f"joint_{i}" for i in range(1, 7))
    np.testing.assert_array_equal(model.lower, LOWER)
    np.testing.assert_array_equal(model.upper, UPPER)
    np.testing.assert_array_equal(model.max_velocity, VELOCITY_LIMITS[name])
    m, _ = _pin_flange(name, np.zeros(6))
    frames = {f.name for f in m.frames}
    assert {"base_link", "link_0", "link_6", "flange", "tool0"} <= frames
    assert m.nq == 6 and all(m.joints[i].shortname() == "JointModelRZ" for i in range(1, 7))


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_masses_match_catalogue_and_inertias_are_physical(name):
    m, _ = _pin_flange(name, np.zeros(6))
    masses = [i.mass for i in m.inertias[1:]]  # link_0 is welded to the universe
    total = sum(masses) + m.inertias[0].mass
    assert abs(total - CATALOGUE_MASS_KG[name]) <= 0.15 * CATALOGUE_MASS_KG[name]
    # Heavy shoulder/upper arm, light wrist.
    assert masses[1] > masses[3] > masses[5] > 0
    for inertia in m.inertias[1:]:
        ev = np.linalg.eigvalsh(inertia.inertia)
        assert ev.min() > 0 and ev[0] + ev[1] >= ev[2] - 1e-12  # triangle inequality


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_effort_limits_are_realistic(name):
    effort = load_model(name).max_effort
    assert np.all(effort[:3] >= 60) and np.all(effort[:3] <= 500)
    assert np.all(effort[3:] >= 10) and np.all(effort[3:] <= 80)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_mujoco_loads_with_limited_joints_and_same_kinematics(name):
    model = load_model(name)
    spec = mujoco.MjSpec.from_string(model.urdf_xml)
    mj = spec.compile()
    assert mj.nq == 6
    assert mj.jnt_limited.all()
    np.testing.assert_allclose(mj.jnt_range[:, 0], LOWER)
    np.testing.assert_allclose(mj.jnt_range[:, 1], UPPER)
    assert mj.ngeom >= 7
    data = mujoco.MjData(mj)
    body = mj.body("link_6").id
    pm = pin.buildModelFromXML(model.urdf_xml)
    pd = pm.createData()
    for q in np.random.default_rng(7).uniform(LOWER, UPPER, (20, 6)):
        data.qpos[:] = q
        mujoco.mj_kinematics(mj, data)
        pin.forwardKinematics(pm, pd, q)
        np.testing.assert_allclose(data.xpos[body], pd.oMi[6].translation, atol=1e-12)
        np.testing.assert_allclose(data.xmat[body].reshape(3, 3), pd.oMi[6].rotation, atol=1e-12)


def test_committed_urdfs_are_what_the_generator_writes():
    spec = importlib.util.spec_from_file_location("gen_urdf", ROOT / "scripts" / "gen_urdf.py")
    gen = importlib.util.module_from_spec(spec)
    sys.modules["gen_urdf"] = gen  # dataclasses look their module up there
    spec.loader.exec_module(gen)
    for name in MODEL_NAMES:
        assert (ROOT / "urdf" / f"jaka_{name}.urdf").read_text() == gen.render(name), (
            f"urdf/jaka_{name}.urdf is stale: run scripts/gen_urdf.py")


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_yaml_config_is_merged(name):
    model = load_model(name)
    assert model.rated_payload_kg == float(name[2:])
    assert model.max_acceleration.shape == (6,) and np.all(model.max_acceleration > 0)
    assert np.all(model.max_acceleration <= np.radians(720) + 5e-3)
    assert model.max_tcp_speed_mm_s == {"zu3": 1500, "zu5": 3000, "zu7": 2500, "zu12": 3000,
                                        "zu18": 3500}[name]
    assert model.max_tcp_accel_mm_s2 > 0
    assert model.servo_kp.shape == model.servo_kd.shape == (6,)
    assert model.io_sizes[("digital", 0, 0)] == 16 and model.io_sizes[("digital", 0, 1)] == 16
    assert model.io_sizes[("analog", 1, 1)] == 0
    assert model.io_sizes[("analog", 2, 0)] == 4
    with pytest.raises(ValueError):
        model.lower[0] = 0.0  # shared, cached arrays are read-only


def test_load_model_is_cached_and_rejects_unknown_names():
    assert load_model("zu5") is load_model("zu5")
    with pytest.raises(ValueError, match=r"unknown model 'zu4'; expected one of zu3, zu5, zu7, zu12, zu18"):
        load_model("zu4")


def test_repo_root_follows_env(monkeypatch, tmp_path):
    monkeypatch.setenv("JAKA_DRIVER_ROOT", str(tmp_path))
    assert repo_root() == tmp_path
    monkeypatch.delenv("JAKA_DRIVER_ROOT")
    assert repo_root() == ROOT
    assert replace(load_model("zu5"), name="x").name == "x"
