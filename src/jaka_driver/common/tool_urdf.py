"""The arm's URDF with its tool on the flange, for ``robot_description`` (rviz, TF through
robot_state_publisher, MoveIt): the DH gripper (housing ``gripper_base``, prismatic finger
joints ``gripper_finger_left`` / ``_right`` along the flange's ±y, 0 closed … half the stroke
each, as the node publishes them on ``joint_states``) or the suction cup (``suction_cup``),
each with a frame at its grasp point (``gripper_grasp`` / ``suction_grasp``). The shapes and
masses are the twin's (:mod:`.tool_shapes`). ``scripts/robot_description MODEL
--tool TOOL`` prints it for the launch file (:mod:`.robot_description`, with the cameras).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET

from .tool_shapes import GRIPPER, SUCTION

TOOLS = ("none", "dh_pgi", "suction")


def _xyz(*v: float) -> str:
    return " ".join(f"{x:.6g}" for x in v)


def _link(robot: ET.Element, name: str, box=None, cylinder=None, xyz=(0, 0, 0), mass=0.0,
          rgba="0.2 0.2 0.22 1") -> None:
    link = ET.SubElement(robot, "link", name=name)
    if box is None and cylinder is None:
        return
    if mass > 0.0:
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "origin", xyz=_xyz(*xyz), rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=f"{mass:.6g}")
        i = mass * 1e-4
        ET.SubElement(inertial, "inertia", ixx=f"{i:.3g}", ixy="0", ixz="0", iyy=f"{i:.3g}",
                      iyz="0", izz=f"{i:.3g}")
    for kind in ("visual", "collision"):
        element = ET.SubElement(link, kind)
        ET.SubElement(element, "origin", xyz=_xyz(*xyz), rpy="0 0 0")
        geometry = ET.SubElement(element, "geometry")
        if box is not None:
            ET.SubElement(geometry, "box", size=_xyz(*(2 * h for h in box)))
        else:
            ET.SubElement(geometry, "cylinder", radius=f"{cylinder[0]:.6g}",
                          length=f"{2 * cylinder[1]:.6g}")
        if kind == "visual":
            material = ET.SubElement(element, "material", name=f"{name}_colour")
            ET.SubElement(material, "color", rgba=rgba)


def _joint(robot: ET.Element, name: str, parent: str, child: str, kind="fixed",
           xyz=(0, 0, 0), axis=None, upper=0.0, effort=0.0, velocity=0.0) -> None:
    joint = ET.SubElement(robot, "joint", name=name, type=kind)
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    ET.SubElement(joint, "origin", xyz=_xyz(*xyz), rpy="0 0 0")
    if axis is not None:
        ET.SubElement(joint, "axis", xyz=_xyz(*axis))
        ET.SubElement(joint, "limit", lower="0", upper=f"{upper:.6g}", effort=f"{effort:.6g}",
                      velocity=f"{velocity:.6g}")


def with_tool(urdf_xml: str, tool: str) -> str:
    """``urdf_xml`` with ``tool`` (one of :data:`TOOLS`) on its ``flange`` link."""
    if tool not in TOOLS:
        raise ValueError(f"tool {tool!r}; expected one of {', '.join(TOOLS)}")
    if tool == "none":
        return urdf_xml                 # served as generated
    robot = ET.fromstring(urdf_xml)
    if tool == "dh_pgi":
        g = GRIPPER
        _link(robot, "gripper_base", box=g.housing, xyz=(0, 0, g.housing[2]),
              mass=g.mass - 2 * g.finger_mass)
        _joint(robot, "flange-gripper_base", "flange", "gripper_base")
        for name, sign in (("gripper_finger_left", 1.0), ("gripper_finger_right", -1.0)):
            length = g.grasp_z + g.pad[2] - 2 * g.housing[2]
            _link(robot, name, box=(g.pad[0], g.pad[1] + 0.002, length / 2),
                  xyz=(0, sign * (g.pad[1] + 0.002), 2 * g.housing[2] + length / 2),
                  mass=g.finger_mass, rgba="0.5 0.5 0.55 1")
            _joint(robot, name, "gripper_base", name, kind="prismatic", axis=(0, sign, 0),
                   upper=g.travel, effort=g.force_max, velocity=g.max_speed)
        _link(robot, "gripper_grasp")
        _joint(robot, "gripper_base-gripper_grasp", "gripper_base", "gripper_grasp",
               xyz=(0, 0, g.grasp_z))
    elif tool == "suction":
        s = SUCTION
        _link(robot, "suction_cup", cylinder=(s.stem[0], s.grasp_z / 2),
              xyz=(0, 0, s.grasp_z / 2), mass=s.mass)
        _joint(robot, "flange-suction_cup", "flange", "suction_cup")
        _link(robot, "suction_grasp")
        _joint(robot, "suction_cup-suction_grasp", "suction_cup", "suction_grasp",
               xyz=(0, 0, s.grasp_z))
    return ET.tostring(robot, encoding="unicode")

