"""The ``robot_description`` a launch serves: a model's URDF (``urdf/jaka_<model>.urdf``, as
generated) with a ``world`` frame above ``base_link`` turned by the installation angle
(:func:`.installation.mounted_description`), the tool on its flange (:mod:`.tool_urdf`: the gripper's or suction cup's links,
its grasp frame) and the twin's cameras added at load time — for each camera ``<name>``, a link
``<name>_link`` on a fixed joint under ``base_link`` (a fixed camera) or ``flange`` (a wrist
camera), and ``<name>_optical_frame`` under it (jaka_driver.common.camera_spec says which way
each looks). Hand–eye code and robot_state_publisher read the camera's mounting from there;
the node publishes the same transforms on ``/tf_static`` (ros/camera_topics.py), so TF has
them also where no robot_state_publisher runs.

``rosrun jaka_driver robot_description zu5 --scene cell.yaml --wrist-camera true --tool dh_pgi
--installation-angle "[1.5708, 0]"`` prints it
(launch/jaka_driver.launch loads it so).
"""
from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from typing import Optional, Sequence

import numpy as np

from .camera_spec import LINK_TO_OPTICAL, CameraSpec, cameras_of_scene
from .installation import Installation, installation, mounted_description
from .results import CommandRefused
from .models import load_model
from .tool_urdf import TOOLS, with_tool
from .transforms import matrix_to_rpy


def _joint(robot: ET.Element, name: str, parent: str, child: str, pose: np.ndarray) -> None:
    ET.SubElement(robot, "link", name=child)
    joint = ET.SubElement(robot, "joint", name=name, type="fixed")
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    xyz = " ".join(f"{v:.9g}" for v in pose[:3, 3])
    rpy = " ".join(f"{v:.9g}" for v in matrix_to_rpy(pose[:3, :3]))
    ET.SubElement(joint, "origin", xyz=xyz, rpy=rpy)


def with_cameras(urdf_xml: str, cameras: Sequence[CameraSpec]) -> str:
    """``urdf_xml`` with the links and fixed joints of ``cameras`` (see the module)."""
    if not cameras:
        return urdf_xml
    robot = ET.fromstring(urdf_xml)
    for c in cameras:
        _joint(robot, f"{c.name}_joint", c.parent_frame, c.link_frame, c.link_pose())
        _joint(robot, f"{c.name}_optical_joint", c.link_frame, c.optical_frame,
               np.asarray(LINK_TO_OPTICAL))
    return ET.tostring(robot, encoding="unicode")


def description(model: str, scene: Optional[str] = None, wrist_camera: bool = False,
                tool: str = "none") -> str:
    """The URDF of ``model`` with ``tool`` on its flange (one of :data:`.tool_urdf.TOOLS`), the
    cameras of ``scene`` and the wrist camera."""
    return with_cameras(with_tool(load_model(model).urdf_xml, tool),
                        cameras_of_scene(scene, wrist_camera))


def mounting_argument(text: str) -> Installation:
    """The launch argument ``installation_angle``: ``[tilt_x, rot_z]`` in rad (YAML); empty or
    ``none``: upright. Raises ValueError naming the value and the range."""
    import yaml
    text = text.strip()
    if text.lower() == "none":
        return Installation()
    try:
        angles = yaml.safe_load(text) if text else None
        return Installation() if not angles else installation(*angles)
    except (yaml.YAMLError, TypeError, ValueError, CommandRefused) as exc:
        raise ValueError(f"installation_angle {text!r}: {getattr(exc, 'message', exc)}; "
                         "expected [tilt_x, rot_z] in rad") from None


def main(argv: Optional[Sequence[str]] = None) -> int:
    import argparse
    parser = argparse.ArgumentParser(prog="robot_description", description="Print a model's "
                                     "URDF with the tool and the twin's cameras' links added.")
    parser.add_argument("model")
    parser.add_argument("--scene", default="", help="the twin's scene file (its cameras:)")
    parser.add_argument("--wrist-camera", default="false", help="true: add wrist_camera")
    parser.add_argument("--tool", default="none", choices=TOOLS,
                        help="the tool on the flange (the twin's ~gripper)")
    parser.add_argument("--installation-angle", default="", metavar="'[TILT_X, ROT_Z]'",
                        help="rad; empty: upright (a world frame above base_link either way)")
    args = parser.parse_args(argv)
    try:
        mounting = mounting_argument(args.installation_angle)
        scene = None if args.scene.strip().lower() in ("", "none") else args.scene
        print(mounted_description(
            description(args.model.lower(), scene,
                        args.wrist_camera.strip().lower() in ("true", "1", "yes"), args.tool),
            mounting))
    except (ValueError, OSError) as exc:
        print(f"robot_description: {exc}", file=sys.stderr)
        return 2
    return 0
