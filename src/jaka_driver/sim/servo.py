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
steps. Units: rad, rad/s, rad/s², N·m.
"""
from __future__ import annotations

from typing import Sequence

import mujoco
import numpy as np

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
    """Setpoints and gains of the 6 joint drives; everything it computes is per cycle."""

    def __init__(self, m: mujoco.MjModel, kp: np.ndarray, kd: np.ndarray, cycle: float):
        if m.nu != 12:
            raise ValueError(f"the twin has {m.nu} actuators, expected 12 (see add_drives)")
        self._m = m
        self.kp = np.asarray(kp, float)
        self.kd = np.asarray(kd, float)
        self.cycle = cycle
        self._from = np.zeros(6)
        self._to = np.zeros(6)
        self._velocity = np.zeros(6)
        self._accel = np.zeros(6)
        self.released = False        # drag mode: gravity compensation only
        self._kv = np.zeros(6)
        self._views = None
        # Viscous joint friction is a passive force, not part of the bias; a drive
        # compensates it, or every joint lags at speed.
        self._damping = m.dof_damping[:6].copy()
        # Where the diagonal of the joint-space inertia sits in ``d.M`` (lower-triangular CSR
        # rows: the diagonal ends each row).
        self._diag = (m.M_rowadr + m.M_rownnz - 1)[:6].copy()

    def reset(self, q: np.ndarray) -> None:
        """Hold ``q`` (rad) from now on."""
        self._from = q.copy()
        self._to = q.copy()
        self._velocity = np.zeros(6)
        self._accel = np.zeros(6)

    def new_setpoint(self, q: np.ndarray) -> None:
        """The setpoint (rad) to reach at the end of the next cycle."""
        velocity = (q - self._to) / self.cycle
        self._accel = (velocity - self._velocity) / self.cycle
        self._velocity = velocity
        self._from = self._to
        self._to = q.copy()

    @property
    def setpoint(self) -> np.ndarray:
        """The setpoint being approached (rad), reached at the end of the cycle."""
        return self._to

    @property
    def setpoint_velocity(self) -> np.ndarray:
        return self._velocity

    def begin_cycle(self, d: mujoco.MjData) -> None:
        """Write the coming cycle's reference, feed-forward and gains into ``d`` and the
        model; call right before stepping the cycle (``d.M`` is that of the current pose).

        Runs 125 times a second in Python: views of MuJoCo's arrays are made once, and the
        arithmetic writes into them (each numpy call costs ~1 µs, more than the work)."""
        if self._views is None or self._views[0] is not d:
            m = self._m
            self._views = (d, m.actuator_gainprm[:6, 0], m.actuator_biasprm[:6, 1],
                           m.actuator_biasprm[:6, 2], d.act[:6], d.ctrl[:6], d.ctrl[6:12],
                           d.qfrc_bias[:6], d.qfrc_gravcomp[:6])
        _, gain, bias_p, bias_v, act, ctrl_v, ctrl_ff, bias, gravity = self._views
        inertia = d.M[self._diag]
        if self.released:
            gain[:] = 0.0
            bias_p[:] = 0.0
            bias_v[:] = -DRAG_DAMPING
            ctrl_ff[:] = 0.0
        else:
            np.multiply(self.kp, inertia, out=gain)
            np.negative(gain, out=bias_p)
            np.multiply(self.kd, inertia, out=self._kv)
            np.negative(self._kv, out=bias_v)
            mujoco.mj_mulM(self._m, d, ctrl_ff, self._accel)
            # + the damping's and the joint friction's share of the setpoint velocity, and the
            # Coriolis and centrifugal torques (the bias less the gravity MuJoCo compensates)
            ctrl_ff += (self._kv + self._damping) * self._velocity + bias - gravity
        act[:] = self._from
        ctrl_v[:] = self._velocity
