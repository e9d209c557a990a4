"""``robot_description`` with a tool (common/tool_urdf.py) places the grasp frame where the
twin's MuJoCo model has its grasp site: the DH gripper's 125 mm and the suction cup's 90 mm
along the flange's z, at the home pose to 1e-9 m; the finger joints are prismatic, 0 … 47.5 mm
(half the AG-95's 95 mm stroke), and the tool's mass is in the URDF as in the twin."""
import mujoco
import numpy as np
import pinocchio as pin
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.common.tool_urdf import with_tool
from jaka_driver.sim.twin_model import build_twin_model

MODEL = load_model("zu5")


@pytest.mark.parametrize("tool, frame, mass", [("dh_pgi", "gripper_grasp", 1.0),
                                               ("suction", "suction_grasp", 0.3)])
def test_the_urdf_grasp_frame_is_the_twins_grasp_site(tool, frame, mass):
    urdf = pin.buildModelFromXML(with_tool(MODEL.urdf_xml, tool))
    data = urdf.createData()
    q = np.zeros(urdf.nq)
    q[:6] = MODEL.home
    pin.framesForwardKinematics(urdf, data, q)
    grasp = data.oMf[urdf.getFrameId(frame)].translation
    m = build_twin_model(MODEL, gripper=tool)
    d = mujoco.MjData(m)
    d.qpos[:6] = MODEL.home
    mujoco.mj_forward(m, d)
    site = d.site_xpos[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, frame)]
    assert np.allclose(grasp, site, atol=1e-9)
    flange = data.oMf[urdf.getFrameId("flange")]
    assert np.linalg.norm(grasp - flange.translation) == pytest.approx(
        0.125 if tool == "dh_pgi" else 0.09)
    assert sum(urdf.inertias[i].mass for i in range(urdf.njoints)) - sum(
        pin.buildModelFromXML(MODEL.urdf_xml).inertias[i].mass
        for i in range(7)) == pytest.approx(mass)


def test_the_finger_joints_are_prismatic_over_half_the_stroke():
    urdf = pin.buildModelFromXML(with_tool(MODEL.urdf_xml, "dh_pgi"))
    for name in ("gripper_finger_left", "gripper_finger_right"):
        j = urdf.getJointId(name)
        assert urdf.joints[j].shortname().startswith("JointModelP")     # prismatic
        assert urdf.lowerPositionLimit[urdf.joints[j].idx_q] == 0.0
        assert urdf.upperPositionLimit[urdf.joints[j].idx_q] == pytest.approx(0.0475)


def test_an_unknown_tool_is_refused_with_the_choices():
    with pytest.raises(ValueError, match="none, dh_pgi, suction"):
        with_tool(MODEL.urdf_xml, "robotiq")
