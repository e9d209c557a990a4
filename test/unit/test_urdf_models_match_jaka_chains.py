"""The generated URDFs and configs keep JAKA's limits, carry plausible masses and torque limits
that hold the rated payload, load in Pinocchio and MuJoCo alike, and are what the generator
writes.

Reference values: JAKA's URDFs (position and velocity limits, as tabulated in docs/models.md),
the catalogue weights and rules of docs/models.md ("The models", "Masses and torques"). The
kinematic chains themselves are checked against JAKA's files in
test_every_model_fk_matches_jaka_chains.py.
"""
import importlib.util
import sys
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from jaka_driver.common.models import MODEL_NAMES, load_model, repo_root
from jaka_driver.common.transforms import matrix_to_rpy, rpy_to_matrix
from jaka_driver.sim.overload import HOLDING_SHARE

ROOT = Path(__file__).resolve().parents[2]

STD = ((-6.28, 6.28), (-1.48, 4.62), (-3.05, 3.05), (-1.48, 4.62), (-6.28, 6.28), (-6.28, 6.28))
# JAKA's URDFs, joint_1 … joint_6 (rad).
LIMITS = {name: STD for name in MODEL_NAMES} | {
    "a5": ((-6.28, 6.28), (-1.48, 4.628), (-3.05, 3.05), (-1.48, 4.62), (-6.28, 6.28),
           (-6.28, 6.28)),
    "a12": ((-6.28, 6.28),) * 6,
    "minicobo": ((-6.28, 6.28), (-2.09, 2.09), (-2.27, 2.27), (-6.28, 6.28), (-2.09, 2.09),
                 (-6.28, 6.28)),
}
_V314 = (3.14,) * 6
_V209 = (2.09, 2.09, 2.09, 3.14, 3.14, 3.14)
_V18 = (2.09, 2.09, 3.14, 3.14, 3.14, 3.14)
_V20 = (2.09, 2.09, 2.09, 3.84, 3.84, 3.84)
VELOCITY_LIMITS = {
    "zu3": (3.14, 3.14, 3.14, 3.84, 3.84, 3.84), "zu5": _V314, "zu7": _V314, "zu12": _V209,
    "zu18": _V18, "zu20": _V20, "zu30": _V20, "c5": _V314, "c7": _V314,
    "c12": (2.09, 2.09, 2.09, 2.62, 2.62, 2.62), "pro5": _V314, "pro7": _V314, "pro12": _V209,
    "pro16": _V209, "pro18": _V18, "s5": _V314, "s7": _V314, "s12": _V209, "a5": (3.665,) * 6,
    "a12": (2.62, 2.62, 3.67, 3.67, 3.67, 3.67), "a20": _V20, "minicobo": (1.57,) * 6,
}
CATALOGUE_MASS_KG = {"zu3": 12.0, "zu5": 23.0, "zu7": 22.0, "zu12": 41.0, "zu18": 35.0}
PAYLOAD_OFFSET_M = 0.1      # where the rated payload sits on the flange's z for the torque rule


def _pin(name):
    return pin.buildModelFromXML(load_model(name).urdf_xml)


def test_every_model_has_its_files_and_no_others():
    assert len(MODEL_NAMES) == 22 and len(set(MODEL_NAMES)) == 22
    assert {p.stem[len("jaka_"):] for p in (ROOT / "urdf").glob("jaka_*.urdf")} == set(MODEL_NAMES)
    assert {p.stem for p in (ROOT / "config").glob("*.yaml")} == set(MODEL_NAMES)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_joint_limits_names_and_tree(name):
    model = load_model(name)
    assert model.joint_names == tuple(f"joint_{i}" for i in range(1, 7))
    np.testing.assert_array_equal(np.c_[model.lower, model.upper], LIMITS[name])
    np.testing.assert_array_equal(model.max_velocity, VELOCITY_LIMITS[name])
    m = _pin(name)
    assert {"base_link", "link_0", "link_6", "flange", "tool0"} <= {f.name for f in m.frames}
    assert m.nq == 6


def test_zu_structure_flange_at_the_manual_example_is_rx180_rz_minus90():
    # JAKA's manual: q = (0, 90°, -90°, 90°, 90°, 0) → flange rpy (180°, 0, -90°); the S7's
    # flange is turned 180° about its z (JAKA's file), the A12 and MiniCobo are other layouts.
    q = [0, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2, 0]
    for name in MODEL_NAMES:
        model = load_model(name)
        if model.structure != "zu":
            continue
        m = _pin(name)
        d = m.createData()
        pin.framesForwardKinematics(m, d, np.array(q))
        R = d.oMf[m.getFrameId("flange")].rotation
        expected = rpy_to_matrix(np.pi, 0.0, np.pi / 2 if name == "s7" else -np.pi / 2)
        np.testing.assert_allclose(R, expected, atol=1e-3, err_msg=name)
        np.testing.assert_allclose(matrix_to_rpy(R)[1], 0.0, atol=1e-3)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_masses_are_the_catalogue_or_the_rule_and_inertias_are_physical(name):
    model = load_model(name)
    m = _pin(name)
    masses = [i.mass for i in m.inertias[1:]]  # link_0 is welded to the universe
    total = sum(masses) + m.inertias[0].mass
    assert total == pytest.approx(model.arm_mass_kg, rel=1e-6)
    if name in CATALOGUE_MASS_KG:
        assert model.arm_mass_kg == CATALOGUE_MASS_KG[name]
    # cobots weigh 1.5 to 10 kg per kg of payload (the smallest arms the most per kg)
    assert 1.5 <= model.arm_mass_kg / model.rated_payload_kg <= 10.0
    assert masses[1] > masses[3] > masses[5] > 0    # heavy shoulder/upper arm, light wrist
    for inertia in m.inertias[1:]:
        ev = np.linalg.eigvalsh(inertia.inertia)
        assert ev.min() > 0 and ev[0] + ev[1] >= ev[2] - 1e-12  # triangle inequality


def test_the_mass_rule_agrees_with_the_catalogue_within_its_fit():
    # docs/models.md: mass = 19.23 kg · payload^0.2461 · (upper arm + forearm / m)^0.9645
    for name, weight in CATALOGUE_MASS_KG.items():
        m = load_model(name)
        chain = np.array([p.xyz for p in m.chain])
        length = abs(chain[3][0]) + abs(chain[4][0])     # J2 → J3, J3 → J4 along the arm
        rule = 19.2327 * m.rated_payload_kg ** 0.24612 * length ** 0.964516
        assert rule == pytest.approx(weight, rel=0.06), name


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_torque_limits_hold_the_rated_payload_everywhere(name):
    model = load_model(name)
    m = _pin(name)
    frame = m.frames[m.getFrameId("flange")]
    at = frame.placement * pin.SE3(np.eye(3), np.array([0.0, 0.0, PAYLOAD_OFFSET_M]))
    m.appendBodyToJoint(frame.parentJoint, pin.Inertia.FromSphere(model.rated_payload_kg, 0.01),
                        at)
    d = m.createData()
    worst = 0.0
    for q in np.random.default_rng(11).uniform(model.lower, model.upper, (500, 6)):
        tau = pin.computeGeneralizedGravity(m, d, q)
        worst = max(worst, float(np.max(np.abs(tau) / model.max_effort)))
    assert worst <= HOLDING_SHARE
    # one module size for J1–J3, another for J4–J6
    assert len(set(model.max_effort[:3])) == 1 and len(set(model.max_effort[3:])) == 1


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_mujoco_loads_with_limited_joints_and_same_kinematics(name):
    model = load_model(name)
    mj = mujoco.MjSpec.from_string(model.urdf_xml).compile()
    assert mj.nq == 6
    assert mj.jnt_limited.all()
    np.testing.assert_allclose(mj.jnt_range, LIMITS[name])
    assert mj.ngeom >= 7
    data = mujoco.MjData(mj)
    body = mj.body("link_6").id
    pm = pin.buildModelFromXML(model.urdf_xml)
    pd = pm.createData()
    for q in np.random.default_rng(7).uniform(model.lower, model.upper, (20, 6)):
        data.qpos[:] = q
        mujoco.mj_kinematics(mj, data)
        pin.forwardKinematics(pm, pd, q)
        np.testing.assert_allclose(data.xpos[body], pd.oMi[6].translation, atol=1e-12)
        np.testing.assert_allclose(data.xmat[body].reshape(3, 3), pd.oMi[6].rotation, atol=1e-12)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_the_arm_does_not_touch_itself_at_home(name):
    model = load_model(name)
    spec = mujoco.MjSpec.from_string(model.urdf_xml)
    from jaka_driver.sim.collisions import add_environment
    add_environment(spec, None)
    mj = spec.compile()
    data = mujoco.MjData(mj)
    data.qpos[:] = model.home
    mujoco.mj_forward(mj, data)
    assert data.ncon == 0, [(mj.geom(c.geom1).name, mj.geom(c.geom2).name)
                            for c in data.contact[:data.ncon]]


def _generator():
    spec = importlib.util.spec_from_file_location("gen_urdf", ROOT / "scripts" / "gen_urdf.py")
    gen = importlib.util.module_from_spec(spec)
    sys.modules["gen_urdf"] = gen  # dataclasses look their module up there
    spec.loader.exec_module(gen)
    return gen


def test_committed_files_are_what_the_generator_writes():
    gen = _generator()
    assert tuple(gen.MODEL_NAMES) == MODEL_NAMES
    for name in MODEL_NAMES:
        assert (ROOT / "urdf" / f"jaka_{name}.urdf").read_text() == gen.render(name), (
            f"urdf/jaka_{name}.urdf is stale: run scripts/gen_urdf.py")
        assert (ROOT / "config" / f"{name}.yaml").read_text() == gen.render_config(name), (
            f"config/{name}.yaml is stale: run scripts/gen_urdf.py")


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_yaml_config_is_merged(name):
    model = load_model(name)
    digits = "".join(c for c in name if c.isdigit())
    assert model.rated_payload_kg == (float(digits) if digits else 1.0)
    assert model.max_acceleration.shape == (6,) and np.all(model.max_acceleration > 0)
    assert np.all(model.max_acceleration <= np.radians(720) + 5e-3)
    assert model.max_tcp_speed >= 1.0 and model.max_tcp_accel > 0       # m/s, m/s²
    assert model.servo_kp.shape == model.servo_kd.shape == (6,)
    assert model.io_sizes[("digital", 0, 0)] == 16 and model.io_sizes[("digital", 0, 1)] == 16
    assert model.io_sizes[("analog", 1, 1)] == 0
    assert model.io_sizes[("analog", 2, 0)] == 4
    assert model.home.shape == (6,) and np.all(model.home >= model.lower)
    assert model.structure in ("zu", "forearm_roll", "spherical_wrist")
    assert 500 <= model.reach_mm <= 2000
    with pytest.raises(ValueError):
        model.lower[0] = 0.0  # shared, cached arrays are read-only


def test_load_model_is_cached_and_rejects_unknown_names():
    assert load_model("zu5") is load_model("zu5")
    with pytest.raises(ValueError, match=r"unknown model 'zu4'; expected one of zu3, zu5, .*, "
                                         r"minicobo"):
        load_model("zu4")


def test_repo_root_follows_env(monkeypatch, tmp_path):
    monkeypatch.setenv("JAKA_DRIVER_ROOT", str(tmp_path))
    assert repo_root() == tmp_path
    monkeypatch.delenv("JAKA_DRIVER_ROOT")
    assert repo_root() == ROOT
    assert replace(load_model("zu5"), name="x").name == "x"
