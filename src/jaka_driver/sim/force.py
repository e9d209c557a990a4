"""The twin's force capability: :class:`~jaka_driver.backend.force.Force` on a
:class:`~.backend.SimBackend` whose arm carries a sensor, offered as ``backend.force`` — the
transport of :class:`~jaka_driver.backend.force_rules.ForceRules` (the modes, what may start
while what runs, the refusals and answers are written there, once for both backends).

A facet of the backend, as :mod:`.twin` is: it acts on the same physics loop, flags, kinematics
and frames, each handed to it by the backend that owns them. What it keeps: the settings
(:class:`ForceSettings`), the sensor (:class:`~.ft_sensor.SensorReadings`), the
identification's status. What it starts: force control and identification, as motion sources
of the physics thread (:mod:`.force_control`, :mod:`.payload_identification`) — so the mode
is the running source's, never a flag that could disagree with the arm.

:meth:`SimForce.check` runs every cycle in the physics thread, after the contact and overload
checks: it reads the sensor, stops the arm on the soft limit or the compliance condition (a
protective stop, as a controller's: the flags' ``force_stopped`` event), and paces a running move under velocity compliance.
Units: the facet's (jaka_driver.backend.force).
"""
from __future__ import annotations

import dataclasses
from typing import Callable, Optional, Sequence, Tuple

import mujoco
import numpy as np

from ..backend.clock import SimClock, WallClock
from ..backend.completion import Completion
from ..backend.force import (WRENCH_NAMES, AdmittanceAxis, ForceFrame, ForceMode,
                             ForceSettings, SensorPayload, ToolDriveAxis, VelocityCompliance,
                             frame_name, wrench_text)
from ..backend.force_rules import RUNNING_MODES, ForceRules, fresh_settings, wrench_used
from ..common.constants import IN_POSITION, SERVO_CYCLE
from ..common.models import RobotModel
from ..common.results import Code, CommandRefused, Result
from ..common.sensor_spec import ForceSensorSpec
from ..kinematics import Kinematics
from ..motion.profiles import joint_move_profile
from ..motion.trajectory import JointTrajectory
from ..motion.velocity_jog import VelocityJog
from .arm_flags import ArmFlags
from .force_control import AxisLaws, ForceControlRun, wrench_at_tcp
from .ft_sensor import ZERO_SAMPLES, SensorReadings
from .payload_identification import MIN_SPREAD, IdentificationRun, spread
from .physics import PhysicsLoop

#: share of the joints' speed and acceleration limits an identification moves at
IDENTIFY_SPEED_SHARE = 0.3
#: poses measured on the way to one given end pose (JAKA's request names only the end)
WAY_POSES = 3
#: s (the backend's clock) a zeroing may take: its samples take 0.128 s
ZERO_TIMEOUT = 2.0
#: a move's pace changes by at most this much per cycle under velocity compliance (0 → 1 in
#: 0.16 s: a slowdown is a deceleration, never a jump)
PACE_STEP = 0.05


class SimForce(ForceRules):
    """Force control with the sensor ``spec`` on the twin of ``model`` (see the module): its
    ``clock``, ``physics`` loop, ``flags``; ``kinematics`` at the active ``frames()`` (the
    backend's: tool and user frame, 4x4, m); ``velocity_jog(in_tool)`` the backend's velocity
    jog, which force control drives (its ramp at the speed ratio, as ~twist_command's). The
    rules are :class:`~jaka_driver.backend.force_rules.ForceRules`'; this is their transport."""

    def __init__(self, spec: ForceSensorSpec, model: RobotModel, clock: SimClock | WallClock,
                 physics: PhysicsLoop, flags: ArmFlags, kinematics: Kinematics,
                 frames: Callable[[], tuple], velocity_jog: Callable[[bool], VelocityJog]):
        super().__init__(spec)
        self._model = model
        self._clock = clock
        self._physics = physics
        self._flags = flags
        self._kin = kinematics
        self._frames = frames
        self._velocity_jog = velocity_jog
        self.readings = SensorReadings(physics.m, spec, SERVO_CYCLE)

    def reset(self) -> None:
        """A fresh sensor and force control: off, every setting at its default (call with the
        physics lock held, between cycles)."""
        self.readings.reset()
        self._kept.reset(fresh_settings(self._spec))
        self._velocity_on = False

    # ---- what it is and does --------------------------------------------------------------
    def settings(self) -> ForceSettings:
        return dataclasses.replace(self._kept.value, sensor_on=self.readings.on,
                                   filter_hz=self.readings.filter_hz,
                                   tool_payload=self.readings.payload, mode=self._mode())

    def sensor_on(self) -> bool:
        return self.readings.on

    def running_mode(self) -> Optional[str]:
        motion = self._physics.motion
        if isinstance(motion, ForceControlRun) and motion.active and not motion.stopping:
            return motion.mode          # (stopping: off, the arm ramps to rest)
        if isinstance(motion, IdentificationRun) and motion.active:
            return ForceMode.IDENTIFYING
        return None

    def _require_arm_still(self, what: str) -> None:
        motion = self._physics.motion
        if motion.active:
            raise CommandRefused(Code.BUSY, f"{what} refused: {motion.busy_reason}")

    # ---- the sensor, on the physics thread ------------------------------------------------------
    def _send_sensor_on(self, on: bool) -> str:
        with self._physics.lock:
            self.readings.on = on
        return ""

    def _send_zero(self) -> str:
        with self._physics.lock:
            done = self.readings.start_zero()
        if not self._clock.wait(done, ZERO_TIMEOUT):
            raise CommandRefused(Code.COMMUNICATION_ERROR, f"zeroing did not end within "
                                 f"{ZERO_TIMEOUT:g} s (the twin's cycles stalled)")
        return (f"sensor zeroed over {ZERO_SAMPLES * SERVO_CYCLE:.3f} s: offset "
                + wrench_text(self.readings.offset))

    def _send_tool_payload(self, payload: SensorPayload) -> Tuple[SensorPayload, str]:
        with self._physics.lock:
            self.readings.payload = payload
        return payload, ""

    def _send_filter(self, cutoff_hz: float) -> Tuple[float, str]:
        with self._physics.lock:
            self.readings.set_filter(cutoff_hz)
        return cutoff_hz, ""

    def _send_soft_limit(self, limit: np.ndarray) -> Tuple[np.ndarray, str]:
        self._kept.update(soft_limit=limit)
        return limit, ""

    # ---- settings of force control: kept here, read by the control law each cycle ----------
    def _send_admittance(self, axis: int, config: AdmittanceAxis) -> Tuple[AdmittanceAxis, str]:
        self._kept.update_row("admittance", axis, config)
        return config, ""

    def _send_tool_drive(self, axis: int, config: ToolDriveAxis) -> Tuple[ToolDriveAxis, str]:
        self._kept.update_row("tool_drive", axis, config)
        return config, ""

    def _send_compliance_type(self, compensation: bool, kind: int) -> str:
        return ""

    def _send_velocity_compliance(self, config: VelocityCompliance) -> str:
        return ""

    def _send_frame(self, frame: int) -> str:
        return ""

    def _send_tool_drive_frame(self, frame: int) -> str:
        return ""

    def _send_condition(self, wrench: np.ndarray) -> str:
        return ""

    # ---- running force control: a motion source of the physics thread --------------------------
    def _start_velocity_compliance(self) -> None:
        """Nothing to start: :meth:`check` paces the moves while it is on."""

    def _start_run(self, mode: str, label: str, frame: int, s: ForceSettings) -> None:
        self._require_arm_still(label)
        if mode == ForceMode.TOOL_DRIVE:
            laws = AxisLaws.of(s.tool_drive, lambda a: a.rigidity, lambda a: 0.0)
        else:
            laws = AxisLaws.of(s.admittance, lambda a: a.ft_user,
                               (lambda a: a.constant) if mode == ForceMode.CONSTANT_FORCE
                               else (lambda a: 0.0))
        compensated = s.compensation
        tool, _ = self._frames()
        kin = self._kin
        readings = self.readings

        def wrench():
            reading = readings.latest
            return None if reading is None else wrench_used(reading, compensated)

        physics = self._physics
        with self._flags.lock:
            q0 = physics.servo.setpoint.copy()
            # the velocity jog of ~twist_command (its ramp scaled by the speed ratio, as a jog's)
            jog = self._velocity_jog(frame == ForceFrame.TOOL)
            run = ForceControlRun(mode, laws, frame, jog, wrench,
                                  lambda q: kin.tcp_pose(q, tool), kin.flange_pose, tool, q0,
                                  SERVO_CYCLE)
            physics.switch(run)

    def _stop(self, mode: str) -> None:
        """The running force control ramps the arm to rest (velocity compliance: nothing
        runs, its flag ends)."""
        with self._flags.lock:
            motion = self._physics.motion
            if isinstance(motion, ForceControlRun) and motion.active and not motion.stopping \
                    and motion.mode == mode:
                motion.stop()

    def _send_disable(self, mode: str) -> None:
        if mode in RUNNING_MODES:
            self._stop(mode)

    # ---- payload identification ----------------------------------------------------------------------
    def _identify(self, what: str, poses: Sequence[np.ndarray]) -> Result:
        self._require_arm_still(what)
        physics = self._physics
        q0 = physics.servo.setpoint.copy()
        targets = [np.asarray(p, float) for p in poses]
        if len(targets) == 1:       # JAKA's end pose: measured on the way there too
            targets = [q0 + (targets[0] - q0) * k / WAY_POSES for k in range(1, WAY_POSES + 1)]
        rotations = [self._kin.flange_pose(q)[:3, :3] for q in [q0] + targets]
        gravity = self.readings.gravity.copy()       # the mounting's, base frame
        quality = spread(rotations, gravity)
        if quality < MIN_SPREAD:
            return Result.failure(Code.INVALID_PARAMETER, f"poses turn the sensor too little "
                                  f"to tell the centroid from the offset (spread {quality:.3f}, "
                                  f"needs ≥ {MIN_SPREAD:g}): give poses pointing the tool in at "
                                  "least three different directions")
        m = self._model
        v, a = m.max_velocity * IDENTIFY_SPEED_SHARE, m.max_acceleration * IDENTIFY_SPEED_SHARE
        segments, start = [], q0
        for q in targets:
            segments.append(JointTrajectory.from_profile(joint_move_profile(start, q, v, a),
                                                         SERVO_CYCLE))
            start = q
        readings = self.readings

        def measure():
            reading = readings.latest
            return None if reading is None else (reading.general.copy(),
                                                 readings.rotation.copy())

        completion = Completion()
        with self._flags.lock:
            if physics.motion.active:
                return Result.failure(Code.BUSY, "payload identification refused: "
                                      f"{physics.motion.busy_reason}")
            run = IdentificationRun(segments, SERVO_CYCLE, IN_POSITION, measure, completion,
                                    self._kept.report)
            run.gravity = gravity
            physics.switch(run)
        return Result.success(f"payload identification started through {len(targets) + 1} "
                              f"poses (planned {run.planned:.1f} s)", (completion, run.planned))

    # ---- every cycle, in the physics thread --------------------------------------------------------
    def check(self, d: mujoco.MjData) -> None:
        """Read the sensor; stop on the soft limit or the compliance condition; pace a move
        under velocity compliance."""
        reading = self.readings.read(d)
        if reading is None:
            return
        flags = self._flags
        s = self._kept.value
        over = np.abs(reading.actual) > s.soft_limit
        if over.any() and not (flags.protective_stop or flags.collision):
            i = int(np.argmax(over))
            flags.force_stopped(f"force/torque sensor soft limit: {WRENCH_NAMES[i]} "
                          f"{reading.actual[i]:.1f} beyond {s.soft_limit[i]:g}")
            return
        motion = self._physics.motion
        if not motion.active or not np.any(s.condition > 0):
            return
        frame = s.tool_drive_frame if self._mode() == ForceMode.TOOL_DRIVE else s.frame
        tool, _ = self._frames()
        flange = np.eye(4)
        flange[:3, :3] = self.readings.rotation
        w = wrench_at_tcp(wrench_used(reading, s.compensation), tool, flange, frame)
        checked = s.condition > 0
        share = np.where(checked, np.abs(w) / np.where(checked, s.condition, 1.0), 0.0)
        i = int(np.argmax(share))
        if share[i] > 1.0:
            flags.force_stopped(f"compliance condition: {WRENCH_NAMES[i]} {w[i]:.1f} beyond "
                          f"{s.condition[i]:g} ({frame_name(frame)} frame)")
            return
        if self._velocity_on:
            target = s.velocity.speed_factor(float(share[i]))
            motion.pace = float(np.clip(target, motion.pace - PACE_STEP,
                                        motion.pace + PACE_STEP))
