"""The robot_description served with cameras (scripts/robot_description, the launch file's
``command``): every camera's ``<name>_optical_frame`` is where its configuration puts it, from
``flange`` for a wrist camera and from ``base_link`` for a fixed one — read back from the URDF
by Pinocchio, as hand–eye code would."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from jaka_driver.common.camera_spec import cameras_of_scene
from jaka_driver.common.models import load_model
from jaka_driver.common.installation import Installation, mounted_description
from jaka_driver.common.robot_description import description, main

CELL = str(Path(__file__).resolve().parents[2] / "config" / "scenes" / "camera_table.yaml")


def _placement(data, model, frame: str) -> np.ndarray:
    return data.oMf[model.getFrameId(frame)].homogeneous


def test_each_optical_frame_is_where_the_configuration_puts_it():
    urdf = description("zu5", CELL, wrist_camera=True)
    model = pin.buildModelFromXML(urdf)
    data = model.createData()
    q = np.array([0.3, 1.2, -1.1, 1.4, 1.0, 0.5])
    pin.framesForwardKinematics(model, data, q)
    specs = cameras_of_scene(CELL, wrist_camera=True)
    assert {s.name for s in specs} == {"top", "wrist", "wrist_camera"}
    for s in specs:
        optical = _placement(data, model, s.optical_frame)
        parent = _placement(data, model, s.parent_frame)
        assert np.allclose(np.linalg.inv(parent) @ optical, s.optical_pose(), atol=1e-8), s.name


def test_without_cameras_the_generated_urdf_is_served_as_it_is(capsys):
    assert description("zu5") == load_model("zu5").urdf_xml
    assert main(["zu5", "--scene", "", "--wrist-camera", "false"]) == 0
    # the script adds only the world frame above base_link (upright) to the generated URDF
    served = capsys.readouterr().out.strip()
    assert served == mounted_description(load_model("zu5").urdf_xml, Installation()).strip()
