"""A model whose chain is a given set of the controller's kinematic parameters: the arm a
controller describes with ``get_dh_param`` (a calibration of the model's nominal chain, or
another arm's), as a :class:`~jaka_driver.common.models.RobotModel` that Pinocchio, MuJoCo and
the IK solvers load like any other.

How: every link keeps its frame relative to its joint's DH frame (so its masses, inertias and
shapes ride with it unchanged), and each revolute joint's URDF origin is rewritten so that the
joint's DH frame is where the new parameters put it. Fixed joints (the mounting, the flange)
keep their origins: the base offset and the flange offset of
:func:`~jaka_driver.kinematics.controller_dh.fit_chain` — what the convention cannot hold —
stay the model's. :func:`~.controller_dh.fit_chain` of the result gives the parameters back
(to float rounding), and its flange is ``base_offset · flange_pose(dh, q) · flange_offset``.

Also :func:`perturbed`: a plausible calibration of a parameter set (sub-millimetre lengths,
thousandths of a degree), to test a driver against an arm that is not exactly nominal.

Units: SI (m, rad); poses 4x4 in the base frame (``base_link``).
"""
from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET

import numpy as np

from ..common.models import Placement, RobotModel
from ..common.transforms import matrix_to_rpy, rpy_to_matrix
from .chain import joint_frames
from .controller_dh import DHParameters, dh_frames, fit_chain

#: Half-widths of a :func:`perturbed` calibration: lengths a and d (m), angles alpha and
#: joint_homeoff (rad). A real Zu 5's calibration moves its lengths by 0.08-0.95 mm; these keep
#: the flange within about a millimetre of the nominal chain, well inside the 5 mm tolerance.
CALIBRATION_LENGTH = 0.4e-3
CALIBRATION_ANGLE = np.radians(0.005)


def with_dh(model: RobotModel, dh: DHParameters) -> RobotModel:
    """``model`` with its joints placed by ``dh`` (the controller's parameters, SI): the same
    links, limits and masses, the URDF's revolute-joint origins rewritten. ``model.name`` is
    kept: limits, speeds and payload stay the model's."""
    nominal = fit_chain(model)
    zero = np.zeros(6)
    links, _ = joint_frames(model.chain, zero)          # each joint's link frame at q = 0
    old_frames = dh_frames(nominal.dh, zero)
    new_frames = dh_frames(dh, zero)
    # where each link now is: the same place relative to its joint's DH frame
    moved = [nominal.base_offset @ new @ np.linalg.solve(nominal.base_offset @ old, link)
             for link, old, new in zip(links, old_frames, new_frames)]
    chain, origins = [], {}
    T = np.eye(4)            # the parent link of the next joint, in the base frame
    revolute = iter(moved)
    for p in model.chain:
        if p.kind != "revolute":
            chain.append(p)
            T = T @ _pose(p)
            continue
        link = next(revolute)
        origin = np.linalg.solve(T, link)
        xyz = tuple(float(v) for v in origin[:3, 3])
        rpy = tuple(float(v) for v in matrix_to_rpy(origin[:3, :3]))
        chain.append(dataclasses.replace(p, xyz=xyz, rpy=rpy))
        origins[p.name] = (xyz, rpy)
        T = link
    return dataclasses.replace(model, urdf_xml=_with_origins(model.urdf_xml, origins),
                               chain=tuple(chain))


def perturbed(dh: DHParameters, seed: int) -> DHParameters:
    """``dh`` as a calibration might find it on one arm: each length moved by up to
    :data:`CALIBRATION_LENGTH` and each angle by up to :data:`CALIBRATION_ANGLE`, drawn from
    ``seed`` (the same seed, the same arm). alpha_0 and a_0 stay: they place joint 1 on the
    base (frame 0 is the base on joint 1's axis), which is the mounting, not the arm."""
    rng = np.random.default_rng(int(seed))
    fixed_first = np.array([0.0, 1, 1, 1, 1, 1])

    def moved(values, size):
        return values + rng.uniform(-size, size, 6)

    return DHParameters(dh.alpha + fixed_first * (moved(dh.alpha, CALIBRATION_ANGLE) - dh.alpha),
                        dh.a + fixed_first * (moved(dh.a, CALIBRATION_LENGTH) - dh.a),
                        moved(dh.d, CALIBRATION_LENGTH),
                        moved(dh.joint_homeoff, CALIBRATION_ANGLE))


def _pose(p: Placement) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = rpy_to_matrix(*p.rpy)
    T[:3, 3] = p.xyz
    return T


def _with_origins(urdf_xml: str, origins: dict) -> str:
    """The URDF with the named joints' ``<origin>`` replaced (full float precision)."""
    root = ET.fromstring(urdf_xml)
    for joint in root.iter("joint"):
        if joint.get("name") not in origins:
            continue
        xyz, rpy = origins[joint.get("name")]
        origin = joint.find("origin")
        if origin is None:
            origin = ET.SubElement(joint, "origin")
        origin.set("xyz", " ".join(repr(v) for v in xyz))
        origin.set("rpy", " ".join(repr(v) for v in rpy))
    return ET.tostring(root, encoding="unicode")


__all__ = ["CALIBRATION_ANGLE", "CALIBRATION_LENGTH", "perturbed", "with_dh"]
