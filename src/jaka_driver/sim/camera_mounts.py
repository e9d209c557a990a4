"""The twin's configured cameras as MuJoCo cameras (:func:`add_cameras`), fixed in the world or
on the flange body, in the model the cameras are rendered from (:mod:`.camera_render`).

MuJoCo cameras look along their -z with y up; the optical frame
(jaka_driver.common.camera_spec) looks along z with y down: a half turn about x apart.
"""
from __future__ import annotations

from typing import Sequence

import mujoco
import numpy as np

from ..common.camera_spec import CameraSpec

FLANGE_BODY = "link_6"      # the flange's frame is link_6's in every model's URDF
#: the optical frame's axes in the MuJoCo camera's frame (a half turn about x)
OPTICAL_IN_MUJOCO = np.diag([1.0, -1.0, -1.0])


def _mujoco_camera_quat(spec: CameraSpec) -> np.ndarray:
    """The MuJoCo camera's orientation (w x y z) in its parent body."""
    optical = spec.optical_pose()[:3, :3]
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, (optical @ OPTICAL_IN_MUJOCO).ravel())
    return quat


def add_cameras(spec: mujoco.MjSpec, cameras: Sequence[CameraSpec]) -> None:
    """A MuJoCo camera per configured camera, fixed in the world or on the flange body."""
    for c in cameras:
        body = spec.worldbody if c.mount == "world" else spec.body(FLANGE_BODY)
        cam = body.add_camera()
        cam.name = c.name
        cam.pos = list(c.optical_pose()[:3, 3])
        cam.quat = list(_mujoco_camera_quat(c))
        cam.fovy = c.fovy
