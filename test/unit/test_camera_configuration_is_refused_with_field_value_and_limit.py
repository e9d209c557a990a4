"""A camera's configuration (a scene file's ``cameras:``, ``~wrist_camera``) is checked at start:
a wrong entry is refused with the field, the value and the limit; K is the projection MuJoCo
renders (checked on pictures by test/integration/test_twin_cameras_see_where_camera_info_says.py)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from jaka_driver.common.camera_spec import (LINK_TO_OPTICAL, WRIST_CAMERA, cameras_from,
                                            cameras_of_scene, euler_xyz)
from jaka_driver.common.pinhole import intrinsics, project, unproject

GOOD = {"name": "top", "width": 160, "height": 120, "fovy": 60, "rate": 10}


@pytest.mark.parametrize("field, value, says", [
    ("width", 5000, "width is 5000 px, outside 16–4096 px"),
    ("height", 8, "height is 8 px, outside 16–4096 px"),
    ("width", 64.5, "width is 64.5, expected a whole number of px in 16–4096"),
    ("rate", 0, "rate is 0, outside 0.1–60"),
    ("rate", 200, "rate is 200, outside 0.1–60"),
    ("fovy", 179, "fovy is 179, outside 1–170"),
    ("mount", "elbow", "mount is 'elbow', expected one of world, flange"),
    ("pos", [0, 1], "pos is [0, 1], expected 3 numbers within ±10"),
    ("point_cloud", "yes", "point_cloud is 'yes', expected true or false"),
    ("colour", True, "unknown field 'colour'"),
    ("name", "top camera", "name is 'top camera', expected letters, digits and _"),
])
def test_a_wrong_field_is_refused_naming_it_its_value_and_its_limit(field, value, says):
    with pytest.raises(ValueError, match="cameras\\[0\\]") as refused:
        cameras_from([{**GOOD, field: value}])
    assert says in str(refused.value)


def test_two_cameras_of_one_name_are_refused():
    with pytest.raises(ValueError, match="two cameras are named 'top'"):
        cameras_from([GOOD, GOOD])


def test_a_scene_file_s_cameras_and_the_wrist_camera(tmp_path):
    scene = tmp_path / "cell.yaml"
    scene.write_text("obstacles: []\ncameras:\n  - {name: top, width: 160, height: 120, "
                     "fx: 100, rate: 5, pos: [0, 0, 1], euler: [0, 1.5707963267948966, 0]}\n")
    top, wrist = cameras_of_scene(str(scene), wrist_camera=True)
    assert (top.mount, top.parent_frame, wrist.name, wrist.parent_frame) == \
        ("world", "base_link", WRIST_CAMERA["name"], "flange")
    # fx given: fovy is the one whose fy is fx
    assert intrinsics(top.width, top.height, top.fovy)[1, 1] == pytest.approx(100.0)
    # looking down: the optical z is the base's -z, its x the base's -y (image right)
    R = top.optical_pose()[:3, :3]
    assert np.allclose(R[:, 2], [0, 0, -1]) and np.allclose(R[:, 0], [0, -1, 0])
    scene.write_text("cameras:\n  - {name: top, width: 10}\n")
    with pytest.raises(ValueError, match=f"{scene}: cameras\\[0\\] \\(top\\): width is 10 px"):
        cameras_of_scene(str(scene))


def test_euler_reads_as_the_scene_file_s_obstacles_do():
    mujoco = pytest.importorskip("mujoco")
    e = np.array([0.3, -0.7, 1.1])
    quat, R = np.zeros(4), np.zeros(9)
    mujoco.mju_euler2Quat(quat, e, "xyz")
    mujoco.mju_quat2Mat(R, quat)
    assert np.allclose(euler_xyz(e), R.reshape(3, 3), atol=1e-12)
    assert np.allclose(LINK_TO_OPTICAL[:3, :3] @ [0, 0, 1], [1, 0, 0])   # optical z = link x


def test_k_projects_and_unprojects_back():
    K = intrinsics(160, 120, 60.0)
    assert K[0, 0] == K[1, 1] == pytest.approx(60.0 / math.tan(math.radians(30)))
    assert (K[0, 2], K[1, 2]) == (79.5, 59.5)      # the centre, OpenCV's pixel convention
    depth = np.full((120, 160), 2.0, np.float32)
    depth[5, 7] = np.nan
    points = unproject(K, depth)
    assert np.allclose(project(K, points[30, 100]), [100, 30])
    assert np.isnan(points[5, 7]).all()
