"""The twin's joint servo drives: what a JAKA joint module does between two 8 ms setpoints.

Each physics step the drive interpolates linearly from the previous setpoint to the new one
(reached at the end of the 8 ms cycle) and applies

    τ = M(q)·(q̈_ff + Kp·e + Kd·ė) + b(q, q̇) + c·q̇    clipped to ±max_effort,

a PD position loop with inertia, bias (gravity, Coriolis) and viscous-friction (c)
feed-forward — a computed-torque drive. Kp and Kd are in 1/s² and 1/s (ωn², 2ζωn). With the gains of config/<model>.yaml (natural frequency ≈ 10–20 Hz) the arm tracks a
setpoint stream to well under a milliradian while staying a rigid body that collisions and
payloads act on. Torques go through ``qfrc_applied`` so torque limits are ours, not an
actuator model's.
"""
from __future__ import annotations

import mujoco
import numpy as np


class JointServo:
    """Setpoint interpolation and the control law for a 6-joint arm."""

    def __init__(self, m: mujoco.MjModel, kp: np.ndarray, kd: np.ndarray,
                 max_effort: np.ndarray, cycle: float):
        self._m = m
        self.kp = np.asarray(kp, float)
        self.kd = np.asarray(kd, float)
        self.max_effort = np.asarray(max_effort, float)
        self._min_effort = -self.max_effort
        self.cycle = cycle
        self._from = np.zeros(6)
        self._to = np.zeros(6)
        self._velocity = np.zeros(6)
        self._accel = np.zeros(6)
        self._elapsed = 0.0
        self.released = False        # drag mode: gravity compensation only
        self._buf = np.zeros(6)
        # Viscous joint friction is a passive force, not part of qfrc_bias; a drive
        # compensates it like gravity, or every joint lags at speed.
        self._damping = m.dof_damping[:6].copy()

    def reset(self, q: np.ndarray) -> None:
        """Hold ``q`` (rad) from now on."""
        self._from = q.copy()
        self._to = q.copy()
        self._velocity[:] = 0.0
        self._accel[:] = 0.0
        self._elapsed = self.cycle

    def new_setpoint(self, q: np.ndarray) -> None:
        """The setpoint (rad) to reach at the end of the next cycle."""
        velocity = (q - self._to) / self.cycle
        self._accel = (velocity - self._velocity) / self.cycle
        self._velocity = velocity
        self._from = self._to
        self._to = q.copy()
        self._elapsed = 0.0

    @property
    def setpoint(self) -> np.ndarray:
        """The setpoint being approached (rad)."""
        return self._to

    @property
    def desired(self) -> np.ndarray:
        """Where the drive wants the joint now (rad): the setpoint interpolated this cycle."""
        s = self._elapsed / self.cycle
        return self._from + s * (self._to - self._from)

    @property
    def setpoint_velocity(self) -> np.ndarray:
        return self._velocity

    def torque(self, d: mujoco.MjData, dt: float) -> np.ndarray:
        """Joint torques (N·m) for this step; call after ``mj_step1`` (bias forces fresh).

        Runs 1000 times a second in Python: written for few numpy calls (each costs ~1 µs of
        overhead, more than the arithmetic on 6 values)."""
        self._elapsed = min(self._elapsed + dt, self.cycle)
        qvel = d.qvel[:6]
        if self.released:
            tau = d.qfrc_bias[:6] - 2.0 * qvel   # float, with a little viscous feel
        else:
            s = self._elapsed / self.cycle
            if s < 1.0:
                a = (self._accel + self.kp * (self._from + s * (self._to - self._from)
                                              - d.qpos[:6])
                     + self.kd * (self._velocity - qvel))
            else:   # setpoint reached: hold it
                a = self.kp * (self._to - d.qpos[:6]) - self.kd * qvel
            mujoco.mj_mulM(self._m, d, self._buf, a)
            tau = self._buf + d.qfrc_bias[:6] + self._damping * qvel
        return np.clip(tau, self._min_effort, self.max_effort)
