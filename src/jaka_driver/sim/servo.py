"""The twin's joint servo drives: what a JAKA joint module does between two 8 ms setpoints,
computed by MuJoCo itself.

Each joint has two actuators (added to the model by :func:`add_drives`):

* a **position loop** whose reference is MuJoCo's own actuator state: an integrator
  (``dyntype="integrator"``) whose input is the setpoint velocity of the cycle, so within the
  cycle the reference runs linearly from the previous setpoint to the new one and reaches it
  at the cycle's end, exactly as a joint module interpolates its setpoints;
  force ``kp·(ref − q) − kv·q̇``, the damping treated implicitly by the ``implicitfast``
  integrator; a step's force uses the reference at the step's start, as it uses ``q``;
* a **feed-forward motor**, set once per cycle: ``kv·q̇_sp`` (the damping's share of the
  setpoint velocity, so a moving setpoint is not braked), ``M(q)·q̈_sp`` (inertia),
  ``c·q̇_sp`` (viscous joint friction) and the Coriolis and centrifugal torques. With it a
  moving setpoint is tracked within one cycle: on a 0.5 Hz sine of 0.63 rad/s peak the joints
  are within 2e-5 rad of each setpoint at the end of its cycle (``bench``, twin physics).

Gravity is compensated by MuJoCo (``gravcomp`` on the arm's bodies, routed through the
actuators with ``actuatorgravcomp``), so it counts against the drive's torque limit: each
joint's total actuator torque is clamped to ``±max_effort`` (``actuatorfrcrange``), which is
what makes an overload sag. The gains of config/<model>.yaml are accelerations
(kp = ωn² in 1/s², kd = 2ζωn in 1/s); at the start of each cycle they are scaled by the
diagonal of the joint-space inertia at the current pose (N·m/rad, N·m·s/rad), so every
joint keeps its natural frequency whatever the arm's reach and payload.

With these drives a cycle is one ``mj_step(m, d, nstep=8)`` and no Python runs between the
steps; with the compiled cycle (:mod:`native_drives`, ``joint_drives.c``) none runs around
them either: set-up, steps and the torques and following error the checks read are one C
call. Units: rad, rad/s, rad/s², N·m.
"""
from __future__ import annotations

import ctypes
from typing import Optional, Sequence

import mujoco
import numpy as np

from .native_drives import Drives, NativeDrives

DRAG_DAMPING = 2.0          # N·m·s/rad: the little viscous feel of a released (drag) arm


def add_drives(spec: mujoco.MjSpec, joint_names: Sequence[str], max_effort: np.ndarray,
               arm_bodies: Sequence[str]) -> None:
    """Add the position-loop and feed-forward actuators of every joint (in this order:
    actuators ``0..n-1`` are the position loops, ``n..2n-1`` the feed-forward motors),
    gravity compensation of ``arm_bodies`` and the joints' torque limits (N·m)."""
    for name in arm_bodies:
        spec.body(name).gravcomp = 1.0
    for name, limit in zip(joint_names, max_effort):
        joint = spec.joint(name)
        joint.actgravcomp = True
        joint.actfrclimited = True
        joint.actfrcrange = [-float(limit), float(limit)]
    for name in joint_names:
        loop = spec.add_actuator()
        loop.name = f"{name}_position"
        loop.trntype = mujoco.mjtTrn.mjTRN_JOINT
        loop.target = name
        loop.dyntype = mujoco.mjtDyn.mjDYN_INTEGRATOR
        loop.gaintype = mujoco.mjtGain.mjGAIN_FIXED
        loop.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        loop.actearly = False       # a step's force uses the reference at its start, as q
        loop.actlimited = False
        loop.ctrllimited = False
        loop.forcelimited = False   # the joint's total is clamped instead
    for name in joint_names:
        motor = spec.add_actuator()
        motor.name = f"{name}_feedforward"
        motor.trntype = mujoco.mjtTrn.mjTRN_JOINT
        motor.target = name
        motor.set_to_motor()
        motor.ctrllimited = False
        motor.forcelimited = False


class JointServo:
    """Setpoints and gains of the 6 joint drives, and the cycle that steps them: one C call
    when the compiled cycle is built (:mod:`native_drives`), else the same numbers in numpy.

    The state lives in one :class:`native_drives.Drives` structure that both paths read and
    write; ``setpoint``/``setpoint_velocity`` are read-only live views of it (they change
    at every cycle: copy to keep)."""

    def __init__(self, m: mujoco.MjModel, kp: np.ndarray, kd: np.ndarray, cycle: float,
                 native: Optional[NativeDrives] = None):
        if m.nu < 12:
            raise ValueError(f"the twin has {m.nu} actuators, expected the arm's 12 first "
                             "(see add_drives)")
        self._m = m
        self.cycle = cycle
        s = self._drives = Drives()
        s.kp[:] = np.asarray(kp, float).tolist()
        s.kd[:] = np.asarray(kd, float).tolist()
        # Viscous joint friction is a passive force, not part of the bias; a drive
        # compensates it, or every joint lags at speed.
        s.damping[:] = m.dof_damping[:6].tolist()
        s.drag_damping = DRAG_DAMPING
        s.cycle = cycle
        # Where the diagonal of the joint-space inertia sits in ``d.M`` (lower-triangular CSR
        # rows: the diagonal ends each row).
        s.diag[:] = (m.M_rowadr + m.M_rownnz - 1)[:6].tolist()
        s.steps = max(1, round(cycle / m.opt.timestep))
        self._address = ctypes.addressof(s)
        view = np.ctypeslib.as_array
        self._kp, self._kd, self._damping = view(s.kp), view(s.kd), view(s.damping)
        self._from, self._to = view(s.from_), view(s.to)
        self._velocity, self._accel, self._next = view(s.velocity), view(s.accel), view(s.next)
        self._tau, self._diag = view(s.tau), view(s.diag)
        #: N·m, the drives' torques over the last cycle (read-only view)
        self.tau = self._tau.view()
        self.tau.flags.writeable = False
        self._measured = False      # the following error in _drives is of the setpoint now
        self._setpoint, self._setpoint_velocity = self._to.view(), self._velocity.view()
        self._setpoint.flags.writeable = False
        self._setpoint_velocity.flags.writeable = False
        # The C cycle takes MuJoCo's structures by address (``_address`` of the bindings);
        # bindings without it step in numpy.
        self._native = native if hasattr(m, "_address") else None
        self._d_addr = None
        self._views = None

    @property
    def compiled(self) -> bool:
        """True when the cycle runs in C (:mod:`native_drives`)."""
        return self._native is not None

    @property
    def steps(self) -> int:
        """Physics steps per cycle."""
        return self._drives.steps

    @property
    def released(self) -> bool:
        """Drag mode: the drives compensate gravity only."""
        return bool(self._drives.released)

    @released.setter
    def released(self, value: bool) -> None:
        self._drives.released = int(bool(value))

    def reset(self, q: np.ndarray) -> None:
        """Hold ``q`` (rad) from now on."""
        self._measured = False
        self._from[:] = q
        self._to[:] = q
        self._velocity[:] = 0.0
        self._accel[:] = 0.0

    def new_setpoint(self, q: np.ndarray) -> None:
        """The setpoint (rad) to reach at the end of the next cycle."""
        self._measured = False
        self._next[:] = q
        if self._native is not None:
            self._native.new_setpoint(self._address)
            return
        velocity = (self._next - self._to) / self.cycle
        self._accel[:] = (velocity - self._velocity) / self.cycle
        self._velocity[:] = velocity
        self._from[:] = self._to
        self._to[:] = self._next

    @property
    def setpoint(self) -> np.ndarray:
        """The setpoint being approached (rad), reached at the end of the cycle."""
        return self._setpoint

    @property
    def setpoint_velocity(self) -> np.ndarray:
        return self._setpoint_velocity

    def following_error(self, d: mujoco.MjData) -> tuple[int, float]:
        """(joint index, rad) of the joint in ``d`` furthest from the setpoint: as the last
        :meth:`step` measured it at the cycle's end, or measured now if the setpoint has
        changed since (a stop that holds elsewhere) or no step ran (brakes closed)."""
        if not self._measured:
            lag = np.abs(self._to - d.qpos[:6])
            k = int(np.argmax(lag))
            return k, float(lag[k])
        return self._drives.lag_joint, self._drives.lag

    def step(self, d: mujoco.MjData) -> None:
        """One cycle: write its gains, feed-forward and reference into ``d`` and the model
        (``d.M`` is that of the current pose), step it (``steps`` × ``mj_step``), then
        record the drive torques (``tau``) and the following error."""
        if self._native is not None:
            if self._d_addr is None or self._d_addr[0] is not d:
                self._d_addr = (d, self._m._address, d._address)
            self._native.cycle(self._d_addr[1], self._d_addr[2], self._address)
        else:
            self._begin_cycle(d)
            mujoco.mj_step(self._m, d, nstep=self.steps)
            self._tau[:] = d.qfrc_actuator[:6]
            lag = np.abs(self._to - d.qpos[:6])
            self._drives.lag_joint = k = int(np.argmax(lag))
            self._drives.lag = float(lag[k])
        self._measured = True

    def _begin_cycle(self, d: mujoco.MjData) -> None:
        """The Python path of the cycle's set-up (joint_drives.c does the same in C).

        Views of MuJoCo's arrays are made once, and the arithmetic writes into them (each
        numpy call costs ~1 µs, more than the work)."""
        if self._views is None or self._views[0] is not d:
            m = self._m
            self._views = (d, m.actuator_gainprm[:6, 0], m.actuator_biasprm[:6, 1],
                           m.actuator_biasprm[:6, 2], d.act[:6], d.ctrl[:6], d.ctrl[6:12],
                           d.qfrc_bias[:6], d.qfrc_gravcomp[:6], np.zeros(6))
        _, gain, bias_p, bias_v, act, ctrl_v, ctrl_ff, bias, gravity, kv = self._views
        inertia = d.M[self._diag]
        if self.released:
            gain[:] = 0.0
            bias_p[:] = 0.0
            bias_v[:] = -DRAG_DAMPING
            ctrl_ff[:] = 0.0
        else:
            np.multiply(self._kp, inertia, out=gain)
            np.negative(gain, out=bias_p)
            np.multiply(self._kd, inertia, out=kv)
            np.negative(kv, out=bias_v)
            if self._m.nv == 6:
                mujoco.mj_mulM(self._m, d, ctrl_ff, self._accel)
            else:
                # a tool's fingers or the scene's parts add degrees of freedom after the
                # arm's: the arm's rows of M·(q̈_sp, 0)
                full = np.zeros(self._m.nv)
                accel = np.zeros(self._m.nv)
                accel[:6] = self._accel
                mujoco.mj_mulM(self._m, d, full, accel)
                ctrl_ff[:] = full[:6]
            # + the damping's and the joint friction's share of the setpoint velocity, and the
            # Coriolis and centrifugal torques (the bias less the gravity MuJoCo compensates)
            ctrl_ff += (kv + self._damping) * self._velocity + bias - gravity
        act[:] = self._from
        ctrl_v[:] = self._velocity
