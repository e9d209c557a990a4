"""The twin's DH-Robotics parallel gripper: its MuJoCo bodies on the flange and the device on
the tool connector that moves them, driven only by Modbus RTU frames on its RS485 channel.

**Built** (:func:`add_gripper`): a housing ``gripper_base`` on the tool body (the flange, or
the force/torque sensor's tool side so that the sensor feels it), two fingers on slide joints
``gripper_finger_left`` / ``_right`` (0 closed … half the stroke open, each; coupled by a
joint equality as DH's rack and pinion couples them), each with a pad
of higher contact ``priority`` (its friction and ``condim`` win against any part), and one
position actuator per finger whose force limit is the gripper's force setting. The figures are
DH-Robotics' AG-95 datasheet's (:data:`SPEC`, docs/twin.md cites them). A site
``gripper_grasp`` sits between the pads: the grasp point.

**Driven** (:class:`DhGripper`, a tool-connector device: sim/tool_device.py's ``ToolDevice``):
frames go through :func:`jaka_driver.devices.modbus_frames.read_request` (6 bytes without CRC,
8 with a right CRC; a wrong CRC is ignored) and the register map of
:mod:`jaka_driver.devices.register_maps`; nothing moves before initialisation; unpowered it
answers nothing and holds no force. Each 8 ms cycle (:meth:`DhGripper.on_cycle`) the fingers'
reference runs toward the commanded opening at the commanded speed, and the grip state follows
what the fingers did: moving, reached, caught (stopped on something before the target) or
dropped (closed on past where it had caught).

Units: m, N, s; positions and openings on the registers in ‰ of the stroke.
"""
from __future__ import annotations

from typing import Optional, Sequence

import mujoco
import numpy as np

from ..devices.modbus_frames import read_request
from ..common.tool_shapes import GRIPPER as SPEC
from ..common.tool_shapes import GripperSpec
from ..devices.register_maps import DH_PGI, GripState, RegisterMap

BASE = "gripper_base"
FINGERS = ("gripper_finger_left", "gripper_finger_right")
PADS = ("gripper_pad_left", "gripper_pad_right")
GRASP_SITE = "gripper_grasp"


#: a finger at rest is within this of its reference (m); the registers' ‰ are 0.095 mm
AT_TARGET = 0.001
#: a stopped finger this far behind its reference is blocked (m)
BLOCKED = 0.002
#: slower than this a finger has stopped (m/s)
STOPPED = 0.002
#: the pads' contact: time constant (s) and damping ratio; impedance from, to, over (m)
PAD_SOLREF = (0.002, 1.0)
PAD_SOLIMP = (0.99, 0.999, 0.001)
#: the wrist bodies the housing may overlap where it leaves the flange
_NEIGHBOURS = ("link_4", "link_5", "link_6")


def add_gripper(spec: mujoco.MjSpec, parent: str, gs: GripperSpec = SPEC) -> list[str]:
    """Add the gripper's housing, fingers, pads, grasp site and finger actuators to ``spec`` on
    body ``parent``; returns the bodies it added (for gravity compensation: the arm's drives
    carry them as a payload they know)."""
    base = spec.body(parent).add_body()
    base.name = BASE
    housing = base.add_geom()
    housing.name = "gripper_housing"
    housing.type = mujoco.mjtGeom.mjGEOM_BOX
    housing.size = list(gs.housing)
    housing.pos = [0.0, 0.0, gs.housing[2]]
    housing.mass = gs.mass - 2 * gs.finger_mass
    housing.rgba = [0.2, 0.2, 0.22, 1.0]
    site = base.add_site()
    site.name = GRASP_SITE
    site.pos = [0.0, 0.0, gs.grasp_z]
    finger_length = gs.grasp_z + gs.pad[2] - 2 * gs.housing[2]
    for name, pad_name, sign in ((FINGERS[0], PADS[0], 1.0), (FINGERS[1], PADS[1], -1.0)):
        finger = base.add_body()
        finger.name = name
        joint = finger.add_joint()
        joint.name = name
        joint.type = mujoco.mjtJoint.mjJNT_SLIDE
        joint.axis = [0.0, sign, 0.0]
        joint.range = [0.0, gs.travel]
        joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        joint.damping = [5.0, 0.0, 0.0] if _vector_damping(joint) else 5.0
        # the drive's motor and screw as seen at the finger: what keeps a pad pressed on a
        # stiff contact from ringing at the 1 ms step
        joint.armature = gs.armature
        # the finger: a bar from the housing down to the pad, behind it
        bar = finger.add_geom()
        bar.type = mujoco.mjtGeom.mjGEOM_BOX
        bar.size = [gs.pad[0], 0.004, finger_length / 2]
        bar.pos = [0.0, sign * (2 * gs.pad[1] + 0.004), 2 * gs.housing[2] + finger_length / 2]
        bar.mass = gs.finger_mass * 0.6
        bar.rgba = [0.5, 0.5, 0.55, 1.0]
        pad = finger.add_geom()
        pad.name = pad_name
        pad.type = mujoco.mjtGeom.mjGEOM_BOX
        pad.size = list(gs.pad)
        pad.pos = [0.0, sign * gs.pad[1], gs.grasp_z]
        pad.mass = gs.finger_mass * 0.4
        pad.friction = [gs.pad_friction, 0.005, 0.0001]
        pad.condim = 4                  # torsional friction: a held part does not turn
        pad.priority = 1                # the pad's friction, condim and solref win
        # a stiff contact (2 ms time constant, the shortest the 1 ms step takes; impedance
        # near 1): a light part squeezed by 160 N would sink millimetres into MuJoCo's default
        pad.solref = list(PAD_SOLREF)
        pad.solimp = list(PAD_SOLIMP) + [0.5, 2.0]
        pad.rgba = [0.1, 0.1, 0.1, 1.0]
        act = spec.add_actuator()
        act.name = name
        act.trntype = mujoco.mjtTrn.mjTRN_JOINT
        act.target = name
        # force kp·(ref − q) − kv·q̇, the damping implicit (implicitfast)
        act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
        act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        kv = 2.0 * np.sqrt(gs.kp * (gs.finger_mass + gs.armature))
        act.gainprm[0] = gs.kp
        act.biasprm[1] = -gs.kp
        act.biasprm[2] = -kv
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.forcerange = [-gs.force_max, gs.force_max]
    # the fingers move together (DH's rack and pinion): a part held between two pads pushing
    # with the same force would otherwise drift sideways with them
    coupling = spec.add_equality()
    coupling.name = "gripper_fingers_coupled"
    coupling.type = mujoco.mjtEq.mjEQ_JOINT
    coupling.objtype = mujoco.mjtObj.mjOBJ_JOINT
    coupling.name1, coupling.name2 = FINGERS
    coupling.data[0:5] = [0.0, 1.0, 0.0, 0.0, 0.0]
    for a, b in ((FINGERS[0], FINGERS[1]), (BASE, FINGERS[0]), (BASE, FINGERS[1])):
        exclude = spec.add_exclude()
        exclude.bodyname1, exclude.bodyname2 = a, b
    for other in _NEIGHBOURS + (parent,):
        for body in (BASE,) + FINGERS:
            if other != body:
                exclude = spec.add_exclude()
                exclude.bodyname1, exclude.bodyname2 = other, body
    return [BASE, *FINGERS]


def _vector_damping(joint) -> bool:
    """MuJoCo 4 made a joint's damping a 3-vector."""
    return np.ndim(joint.damping) > 0


def grasp_options(m: mujoco.MjModel) -> None:
    """The contact settings that make a friction grasp hold through a fast move: MuJoCo's
    elliptic friction cone, a high ``impratio`` (friction as stiff as the normal force) and
    no-slip iterations, where the pyramidal cone's small creep would let a part slide."""
    m.opt.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    m.opt.impratio = 10.0
    m.opt.noslip_iterations = 3


class DhGripper:
    """The DH gripper of the twin ``m`` / ``d`` on the tool connector (see the module).

    Calls come from the physics thread or under a hold of simulated time, never two at once
    (the tool connector's rule): no lock here. ``channel`` is the RS485 channel its cable is on
    (1 = RS485L, the AI pins, as JAKA's demos wire it)."""

    def __init__(self, m: mujoco.MjModel, d: mujoco.MjData, registers: RegisterMap = DH_PGI,
                 gs: GripperSpec = SPEC, channel: int = 1):
        self._m, self._d = m, d
        self.registers = registers
        self.spec = gs
        self.channel = channel
        self.slave = registers.slave
        self._joints = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, n) for n in FINGERS]
        self._acts = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, n) for n in FINGERS]
        if min(self._joints + self._acts) < 0:
            raise ValueError("the twin's model has no DH gripper (sim/gripper.add_gripper)")
        self._qadr = [int(m.jnt_qposadr[j]) for j in self._joints]
        self._vadr = [int(m.jnt_dofadr[j]) for j in self._joints]
        self.volts = 0.0
        self.reset()

    # ---- state --------------------------------------------------------------------------
    def reset(self) -> None:
        """As a gripper just mounted and unpowered: not initialised, fingers limp where MuJoCo's
        reset put them (open), the settings at their defaults. The supply stays as it is."""
        defaults = self.registers.defaults
        self.initialised = False
        self.initialising = False
        self.force_pct = int(defaults.get("force", 100))
        self.speed_pct = int(defaults.get("speed", 100))
        self.position_cmd = int(defaults.get("position", 1000))
        self.grip_state = GripState.REACHED
        self._reference = self.finger_positions().mean()
        self._target = self._reference
        self._last = self.finger_positions()
        self.frames_taken = 0
        self._limp()

    @property
    def powered(self) -> bool:
        return self.volts > 0.0

    def finger_positions(self) -> np.ndarray:
        """Each finger's travel from closed (m)."""
        return np.array([self._d.qpos[a] for a in self._qadr])

    def opening(self) -> float:
        """The distance between the pads (m)."""
        return float(self.finger_positions().sum())

    def position_permille(self) -> int:
        """The opening on the registers: ‰ of the stroke."""
        return int(round(np.clip(self.opening() / self.spec.stroke, 0.0, 1.0) * 1000))

    # ---- ToolDevice ---------------------------------------------------------------------
    def power(self, volts: float) -> None:
        was = self.powered
        self.volts = float(volts)
        if was and not self.powered:
            self.initialised = self.initialising = False   # a power cycle loses the calibration
            self._limp()

    def rs485(self, channel: int, frame: bytes, baudrate: int) -> None:
        if not self.powered or channel != self.channel:
            return
        request = read_request(frame)
        if request is None or request.slave != self.slave or request.function not in (6, 16):
            return
        self.frames_taken += 1
        for i, value in enumerate(request.values):
            self._write(request.address + i, value)

    def read_register(self, channel: int, sig_type: int, address: int) -> Optional[int]:
        if not self.powered or channel != self.channel or sig_type not in (3, 4):
            return None
        reads, writes = self.registers.reads, self.registers.writes
        if address == reads["init_state"]:
            return int(self.initialised)
        if address == reads["grip_state"]:
            return int(self.grip_state)
        if address == reads["position"]:
            return self.position_permille()
        if address == writes["force"]:
            return self.force_pct
        if address == writes["speed"]:
            return self.speed_pct
        if address == writes["position"]:
            return self.position_cmd
        if address == writes["init"]:
            return int(self.initialised)
        return None

    def tool_outputs(self, levels: Sequence[float]) -> None:
        """The DH gripper takes no tool DO (its digital-IO variant is another model)."""

    def tool_inputs(self) -> dict[int, float]:
        return {}

    def on_cycle(self) -> None:
        """The fingers' reference one cycle further toward the target at the set speed, the
        force limit, and the grip state from what the fingers did."""
        if not self.powered or not (self.initialised or self.initialising):
            return
        cycle = 8 * self._m.opt.timestep
        step = self.spec.max_speed * self.speed_pct / 100.0 * cycle
        delta = self._target - self._reference
        self._reference += float(np.clip(delta, -step, step))
        force = self.spec.figures.force(self.force_pct, self.registers.force_range)
        for a in self._acts:
            self._d.ctrl[a] = self._reference
            self._m.actuator_forcerange[a] = (-force, force)
        ramping = abs(self._target - self._reference) > 1e-9
        fingers = self.finger_positions()
        # from the cycle's displacement: what a gripper's encoder sees
        speed = float(np.abs(fingers - self._last).max()) / cycle
        self._last = fingers
        at_target = abs(fingers.sum() / 2.0 - self._target) < AT_TARGET
        if self.initialising:
            if not ramping and at_target and speed < STOPPED:
                self.initialising, self.initialised = False, True
                self.grip_state = GripState.REACHED
            return
        # stopped while the reference has run on past them: something is between the pads
        blocked = speed < STOPPED and abs(self._reference - fingers.mean()) > BLOCKED
        if self.grip_state == GripState.MOVING:
            if blocked:
                self.grip_state = GripState.CAUGHT
            elif not ramping and speed < STOPPED and at_target:
                self.grip_state = GripState.REACHED
        elif self.grip_state == GripState.CAUGHT and at_target:
            self.grip_state = GripState.DROPPED     # closed on past where the part was

    # ---- the register map ---------------------------------------------------------------
    def _write(self, address: int, value: int) -> None:
        role = self.registers.role_of_write(address)
        lo_f, hi_f = self.registers.force_range
        lo_s, hi_s = self.registers.speed_range
        lo_p, hi_p = self.registers.position_range
        if role == "init" and value in self.registers.init_values:
            # DH's initialisation: the fingers find their ends and stop open
            self.initialised, self.initialising = False, True
            self._reference = float(self.finger_positions().mean())
            self._target = self.spec.travel
            self.grip_state = GripState.MOVING
        elif role == "force" and lo_f <= value <= hi_f:
            self.force_pct = int(value)
        elif role == "speed" and lo_s <= value <= hi_s:
            self.speed_pct = int(value)
        elif role == "position" and lo_p <= value <= hi_p:
            self.position_cmd = int(value)
            if self.initialised:      # nothing moves before initialisation
                self._reference = float(self.finger_positions().mean())
                self._target = self.spec.travel * value / 1000.0
                self.grip_state = GripState.MOVING
        # "save" keeps the settings in the gripper's flash: nothing the twin forgets on its own

    def _limp(self) -> None:
        """No drive force: the fingers stay where they are, pushed by nothing."""
        for a in self._acts:
            self._m.actuator_forcerange[a] = (0.0, 0.0)
