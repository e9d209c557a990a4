"""The twin's MuJoCo model, built from the same URDF as Pinocchio and rviz.

MuJoCo imports the URDF directly; what the URDF cannot say is added here: the time step,
joint damping and rotor inertia (armature), the floor and workcell, a flange force/torque
sensor when the arm carries one (:mod:`ft_sensor`), the payload (mass folded into link_6, the
flange body — or into the sensor's tool side, ``ft_tool``, so the sensor feels it), and the
joint drives (:mod:`servo`: MuJoCo actuators with gravity compensation and the URDF's torque
limits); a tool on the flange when one is mounted (``gripper``: the DH gripper,
:mod:`gripper`, or the suction cup, :mod:`suction`, after the sensor's tool side when there
is one), and the scene's parts (:mod:`parts`, free bodies after the arm: the arm's joints stay
MuJoCo's first six degrees of freedom and its first twelve actuators).
"""
from __future__ import annotations

import copy

import xml.etree.ElementTree as ET
from typing import Optional, Sequence

import mujoco
import numpy as np

from ..common.camera_spec import CameraSpec
from ..common.models import RobotModel
from ..common.sensor_spec import ForceSensorSpec
from .camera_mounts import FLANGE_BODY, add_cameras
from .collisions import ARM_BODIES, add_environment
from .ft_sensor import TOOL_BODY, add_sensor
from .gripper import add_gripper, grasp_options
from .parts import add_parts, scene_parts
from .servo import add_drives
from .suction import add_suction_cup

TIMESTEP = 0.001          # s; 1 kHz physics under an 8 ms controller cycle
JOINT_DAMPING = 2.0       # N·m·s/rad, gearbox viscous friction
ARMATURE = 0.05           # kg·m², reflected rotor inertia; also steadies the integrator
#: the tools a twin can carry on its flange (``gripper``)
GRIPPERS = ("none", "dh_pgi", "suction")


def build_twin_model(model: RobotModel, scene: Optional[str] = None, *,
                     visual: bool = False,
                     force_sensor: Optional[ForceSensorSpec] = None,
                     gripper: str = "none",
                     cameras: Sequence[CameraSpec] = ()) -> mujoco.MjModel:
    """Compile the MuJoCo model of ``model`` with a floor and the optional workcell ``scene``
    (see :mod:`collisions`; its ``parts:`` as free bodies), ``force_sensor`` on the flange
    when it is mounted, and ``gripper`` (one of :data:`GRIPPERS`) after it.

    ``visual=True`` keeps the URDF's ``<visual>`` shapes as well (geom group 1, no contacts) for
    pictures (:mod:`snapshot`); the physics twin leaves it off, it only needs collision shapes.
    ``cameras`` become MuJoCo cameras (:mod:`camera_mounts`), for the model they are rendered
    from (:mod:`camera_render`).
    """
    xml = _keep_visual(model.urdf_xml) if visual else model.urdf_xml
    spec = mujoco.MjSpec.from_string(xml)
    spec.compiler.discardvisual = not visual
    if gripper not in GRIPPERS:
        raise ValueError(f"gripper is {gripper!r}, expected one of {', '.join(GRIPPERS)}")
    add_environment(spec, scene)
    bodies = list(ARM_BODIES)
    parent = FLANGE_BODY
    if force_sensor is not None and force_sensor.mounted:
        # a tool on the sensor replaces its probe: the tool is what touches the scene
        add_sensor(spec, force_sensor, probe=gripper == "none")
        bodies.append(TOOL_BODY)
        parent = TOOL_BODY
    parts = add_parts(spec, scene_parts(scene))
    add_drives(spec, model.joint_names, model.max_effort, bodies)
    # after the arm's drives: the tool's actuators come after the arm's twelve
    tool = []
    if gripper == "dh_pgi":
        tool = add_gripper(spec, parent)
    elif gripper == "suction":
        tool = add_suction_cup(spec, parent, parts)
    for name in tool:
        spec.body(name).gravcomp = 1.0      # carried by the drives as a payload they know
    add_cameras(spec, cameras)
    m = spec.compile()
    arm_dofs = [int(m.jnt_dofadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, j)])
                for j in model.joint_names]
    if arm_dofs != list(range(6)):
        raise ValueError(f"{model.urdf_path}: the arm's joints are degrees of freedom "
                         f"{arm_dofs} of the twin, expected the first six")
    m.opt.timestep = TIMESTEP
    if gripper != "none":
        grasp_options(m)
    # The drives' damping (kv) and the joint damping are integrated implicitly: stiff
    # velocity loops stay stable at the 1 ms step.
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    m.dof_damping[:] = JOINT_DAMPING
    m.dof_armature[:] = ARMATURE
    return m


class Payload:
    """Folds a point-mass payload into ``body`` (the flange body, or the sensor's tool side:
    both have the flange's frame) and restores it.

    The body's own mass properties are kept so that setting a new payload replaces the old one
    instead of adding to it.
    """

    def __init__(self, m: mujoco.MjModel, body: str = FLANGE_BODY):
        self._m = m
        self._body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, body)
        if self._body < 0:
            raise ValueError(f"the twin has no body {body!r}")
        self._mass = float(m.body_mass[self._body])
        self._com = m.body_ipos[self._body].copy()
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, m.body_iquat[self._body])
        rot = rot.reshape(3, 3)
        self._inertia = rot @ np.diag(m.body_inertia[self._body]) @ rot.T   # body frame
        self.mass = 0.0
        self.centroid = np.zeros(3)
        # the model as built, restored exactly by reset() (mj_setConst after putting the body
        # back gives its derived constants only to the last bits)
        self._built = copy.deepcopy(m)
        self._changed = False

    def set(self, mass: float, centroid: np.ndarray) -> None:
        """``mass`` kg at ``centroid`` (m, flange frame = link_6 frame in our URDFs)."""
        m, b = self._m, self._body
        total = self._mass + mass
        com = (self._mass * self._com + mass * centroid) / total if total > 0 else self._com
        inertia = self._inertia + self._mass * _shift(self._com - com)
        inertia = inertia + mass * _shift(centroid - com)
        principal, axes = np.linalg.eigh(inertia)
        if np.linalg.det(axes) < 0:
            axes[:, 0] = -axes[:, 0]
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, axes.flatten())
        m.body_mass[b] = total
        m.body_ipos[b] = com
        m.body_iquat[b] = quat
        m.body_inertia[b] = np.maximum(principal, 1e-9)
        # mj_setConst evaluates the model at qpos0 in the data it is given: never the live one.
        mujoco.mj_setConst(m, mujoco.MjData(m))
        self.mass, self.centroid = mass, np.asarray(centroid, float).copy()
        self._changed = True

    def reset(self) -> None:
        """No payload: the flange body exactly as built (not recomputed, to the bit)."""
        if not self._changed:
            return
        m, built = self._m, self._built
        for name in dir(built):
            value = getattr(built, name, None)
            if isinstance(value, np.ndarray) and not name.startswith("_"):
                np.copyto(getattr(m, name), value)
        for name in dir(built.stat):
            if not name.startswith("_"):
                try:
                    setattr(m.stat, name, getattr(built.stat, name))
                except (AttributeError, TypeError):
                    pass
        self.mass, self.centroid, self._changed = 0.0, np.zeros(3), False


def _keep_visual(urdf_xml: str) -> str:
    """The URDF with MuJoCo's ``<compiler discardvisual="false"/>`` extension in it: the URDF
    parser drops ``<visual>`` elements while reading, so setting the flag on the spec
    afterwards is too late."""
    root = ET.fromstring(urdf_xml)
    ext = ET.SubElement(root, "mujoco")
    ET.SubElement(ext, "compiler", discardvisual="false")
    return ET.tostring(root, encoding="unicode")


def _shift(r: np.ndarray) -> np.ndarray:
    """Parallel-axis term for a unit mass at offset ``r``."""
    return float(r @ r) * np.eye(3) - np.outer(r, r)
