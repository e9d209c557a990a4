"""A PyKDL chain built from a robot model's URDF, for comparing solvers on the same arm.

The chain runs from the URDF root to ``tip`` (default ``flange``, the frame our IK solves for).
Each URDF joint becomes two KDL segments: a fixed one carrying the joint's ``<origin>`` (the
pose of the joint frame in the parent link, m and fixed-axis roll-pitch-yaw rad, which is KDL's
``Rotation.RPY`` convention), then — for a revolute joint — one that turns about the joint's
``<axis>`` through the joint frame's origin. KDL joint order is therefore the URDF's movable
joints from root to tip, J1..J6 for a JAKA arm.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import PyKDL as kdl


def _floats(text: str | None, default: str) -> list[float]:
    return [float(v) for v in (text or default).split()]


def _joint_path(root: ET.Element, tip: str) -> list[ET.Element]:
    """URDF ``<joint>`` elements from the root link down to link ``tip``."""
    by_child = {j.find("child").get("link"): j for j in root.iter("joint")}
    path, link = [], tip
    while link in by_child:
        joint = by_child[link]
        path.append(joint)
        link = joint.find("parent").get("link")
    if not path:
        raise ValueError(f"the URDF has no joint leading to link {tip!r}")
    return path[::-1]


def chain_from_urdf(urdf_xml: str, tip: str = "flange") -> tuple[kdl.Chain, list[str]]:
    """The KDL chain root → ``tip`` and the names of its movable joints in chain order.

    Only revolute and fixed joints are supported (all a JAKA arm has); anything else raises
    ``ValueError`` rather than building a wrong chain.
    """
    chain, names = kdl.Chain(), []
    for joint in _joint_path(ET.fromstring(urdf_xml), tip):
        name, kind = joint.get("name"), joint.get("type")
        origin = joint.find("origin")
        xyz = _floats(origin.get("xyz") if origin is not None else None, "0 0 0")
        rpy = _floats(origin.get("rpy") if origin is not None else None, "0 0 0")
        frame = kdl.Frame(kdl.Rotation.RPY(*rpy), kdl.Vector(*xyz))
        chain.addSegment(kdl.Segment(f"{name}_origin", kdl.Joint(kdl.Joint.Fixed), frame))
        if kind == "fixed":
            continue
        if kind != "revolute":
            raise ValueError(f"joint {name}: type {kind!r} is not supported")
        axis = np.array(_floats(joint.find("axis").get("xyz") if joint.find("axis") is not None
                                else None, "1 0 0"))
        axis /= np.linalg.norm(axis)
        turn = kdl.Joint(name, kdl.Vector(0.0, 0.0, 0.0), kdl.Vector(*axis.tolist()),
                         kdl.Joint.RotAxis)
        chain.addSegment(kdl.Segment(name, turn, kdl.Frame.Identity()))
        names.append(name)
    return chain, names


def jnt_array(values) -> kdl.JntArray:
    """A KDL ``JntArray`` holding ``values`` (rad)."""
    values = list(values)
    out = kdl.JntArray(len(values))
    for i, v in enumerate(values):
        out[i] = float(v)
    return out


def frame_from_matrix(T: np.ndarray) -> kdl.Frame:
    """A KDL ``Frame`` from a 4x4 homogeneous matrix (m)."""
    R = T[:3, :3].tolist()
    rot = kdl.Rotation(*R[0], *R[1], *R[2])
    return kdl.Frame(rot, kdl.Vector(*T[:3, 3].tolist()))


def matrix_from_frame(F: kdl.Frame) -> np.ndarray:
    """A 4x4 homogeneous matrix (m) from a KDL ``Frame``."""
    T = np.eye(4)
    for i in range(3):
        for j in range(3):
            T[i, j] = F.M[i, j]
        T[i, 3] = F.p[i]
    return T
