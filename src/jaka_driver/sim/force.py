"""The twin's force capability: :class:`~jaka_driver.backend.force.Force` on a
:class:`~.backend.SimBackend` whose arm carries a sensor, offered as ``backend.force``.

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
from typing import Callable, Optional, Sequence

import mujoco
import numpy as np

from ..backend.clock import SimClock, WallClock
from ..backend.completion import Completion
from ..backend.force import (AXES, WRENCH_NAMES, AdmittanceAxis, ComplianceType, Force,
                             ForceFrame, ForceMode, ForceSettings, IdentificationStatus,
                             KeptSettings,
                             SensorPayload, ToolDriveAxis, VelocityCompliance, frame_name,
                             wrench_text)
from ..common.constants import IN_POSITION, SERVO_CYCLE
from ..common.models import RobotModel
from ..common.results import Code, Result
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


class SimForce(Force):
    """Force control with the sensor ``spec`` on the twin of ``model`` (see the module): its
    ``clock``, ``physics`` loop, ``flags``; ``kinematics`` at the active ``frames()`` (the
    backend's: tool and user frame, 4x4, m); ``velocity_jog(in_tool)`` the backend's velocity
    jog, which force control drives (its ramp at the speed ratio, as ~twist_command's)."""

    def __init__(self, spec: ForceSensorSpec, model: RobotModel, clock: SimClock | WallClock,
                 physics: PhysicsLoop, flags: ArmFlags, kinematics: Kinematics,
                 frames: Callable[[], tuple], velocity_jog: Callable[[bool], VelocityJog]):
        self._spec = spec
        self._model = model
        self._clock = clock
        self._physics = physics
        self._flags = flags
        self._kin = kinematics
        self._frames = frames
        self._velocity_jog = velocity_jog
        self.readings = SensorReadings(physics.m, spec, SERVO_CYCLE)
        self._kept = KeptSettings(self._fresh())
        self._velocity_on = False

    def _fresh(self) -> ForceSettings:
        return ForceSettings(mounted=True, range=self._spec.range.copy(),
                             soft_limit=self._spec.range.copy())

    def reset(self) -> None:
        """A fresh sensor and force control: off, every setting at its default (call with the
        physics lock held, between cycles)."""
        self.readings.reset()
        self._kept.reset(self._fresh())
        self._velocity_on = False

    # ---- what it is and does --------------------------------------------------------------
    @property
    def absent(self) -> Optional[str]:
        return None

    def settings(self) -> ForceSettings:
        return dataclasses.replace(self._kept.value, sensor_on=self.readings.on,
                                   filter_hz=self.readings.filter_hz,
                                   tool_payload=self.readings.payload, mode=self._mode())

    def _mode(self) -> str:
        motion = self._physics.motion
        if isinstance(motion, ForceControlRun) and motion.active and not motion.stopping:
            return motion.mode          # (stopping: off, the arm ramps to rest)
        if isinstance(motion, IdentificationRun) and motion.active:
            return ForceMode.IDENTIFYING
        return ForceMode.VELOCITY_COMPLIANCE if self._velocity_on else ForceMode.OFF

    def identification_status(self) -> IdentificationStatus:
        return self._kept.identification

    # ---- refusals only the facet can make ---------------------------------------------------------
    def _sensor_off(self, what: str) -> Optional[Result]:
        if not self.readings.on:
            return Result.failure(Code.WRONG_MODE, f"{what} refused: the force/torque sensor "
                                  "is off (switch it on first)")
        return None

    def _force_active(self, what: str) -> Optional[Result]:
        mode = self._mode()
        if mode != ForceMode.OFF:
            return Result.failure(Code.BUSY, f"{what} refused while {mode.replace('_', ' ')} "
                                  "runs (disable_force_control first)")
        return None

    def _arm_moving(self, what: str) -> Optional[Result]:
        motion = self._physics.motion
        if motion.active:
            return Result.failure(Code.BUSY, f"{what} refused: {motion.busy_reason}")
        return None

    # ---- the sensor ------------------------------------------------------------------------------------
    def set_sensor_on(self, on: bool) -> Result:
        if not on:
            refused = self._force_active("switching the sensor off")
            if refused:
                return refused
        with self._physics.lock:
            self.readings.on = bool(on)
        return Result.success(f"force/torque sensor {'on' if on else 'off'}")

    def zero(self) -> Result:
        refused = self._sensor_off("zeroing") or self._force_active("zeroing")
        if refused:
            return refused
        with self._physics.lock:
            done = self.readings.start_zero()
        if not self._clock.wait(done, ZERO_TIMEOUT):
            return Result.failure(Code.COMMUNICATION_ERROR, f"zeroing did not end within "
                                  f"{ZERO_TIMEOUT:g} s (the twin's cycles stalled)")
        return Result.success(f"sensor zeroed over {ZERO_SAMPLES * SERVO_CYCLE:.3f} s: offset "
                              + wrench_text(self.readings.offset))

    def set_tool_payload(self, mass: float, centroid: np.ndarray) -> Result:
        refused = self._force_active("the sensor's tool payload")
        if refused:
            return refused
        payload = SensorPayload(float(mass), np.asarray(centroid, float).copy())
        with self._physics.lock:
            self.readings.payload = payload
        c = payload.centroid * 1000.0
        return Result.success(f"sensor tool payload {mass:g} kg at ({c[0]:.1f}, {c[1]:.1f}, "
                              f"{c[2]:.1f}) mm")

    def set_filter(self, cutoff_hz: float) -> Result:
        with self._physics.lock:
            self.readings.set_filter(cutoff_hz)
        return Result.success("sensor filter off" if cutoff_hz == 0 else
                              f"sensor filter {cutoff_hz:g} Hz")

    def set_soft_limit(self, limit: np.ndarray) -> Result:
        self._kept.update(soft_limit=np.asarray(limit, float).copy())
        return Result.success("sensor soft limit " + wrench_text(limit))

    # ---- settings of force control ----------------------------------------------------------------
    def set_admittance(self, axis: int, config: AdmittanceAxis) -> Result:
        refused = self._force_active("changing the admittance")
        if refused:
            return refused
        self._kept.update_row("admittance", axis, config)
        return Result.success(f"admittance {AXES[axis]}: " + (
            f"on, ft_user {config.ft_user:g}, rebound {config.rebound:g}, constant "
            f"{config.constant:g}" if config.enabled else "off"))

    def set_compliance_type(self, compensation: bool, kind: int) -> Result:
        refused = self._force_active("changing the compliance type")
        if refused:
            return refused
        self._kept.update(compensation=bool(compensation), compliance_type=int(kind))
        return Result.success(f"compliance type {ComplianceType(kind).name.lower()}, "
                              f"{'compensated' if compensation else 'uncompensated'} wrench")

    def set_velocity_compliance(self, config: VelocityCompliance) -> Result:
        self._kept.update(velocity=config)
        return Result.success(f"velocity compliance level {config.level}, rates "
                              f"{', '.join(f'{r:g}' for r in config.rates)}")

    def set_tool_drive(self, axis: int, config: ToolDriveAxis) -> Result:
        refused = self._force_active("changing the tool drive")
        if refused:
            return refused
        self._kept.update_row("tool_drive", axis, config)
        return Result.success(f"tool drive {AXES[axis]}: " + (
            f"on, rigidity {config.rigidity:g}, rebound {config.rebound:g}"
            if config.enabled else "off"))

    def set_frame(self, frame: int) -> Result:
        refused = self._force_active("changing the force-control frame")
        if refused:
            return refused
        self._kept.update(frame=int(frame))
        return Result.success(f"force control in the {frame_name(frame)} frame")

    def set_tool_drive_frame(self, frame: int) -> Result:
        refused = self._force_active("changing the tool drive frame")
        if refused:
            return refused
        self._kept.update(tool_drive_frame=int(frame))
        return Result.success(f"tool drive in the {frame_name(frame)} frame")

    def set_condition(self, wrench: np.ndarray) -> Result:
        self._kept.update(condition=np.asarray(wrench, float).copy())
        checked = [f"{WRENCH_NAMES[i]} {v:g}" for i, v in enumerate(wrench) if v > 0]
        return Result.success("compliance condition " + (", ".join(checked) if checked else
                                                         "off (nothing checked)"))

    # ---- running force control ------------------------------------------------------------------------
    def enable_admittance(self, on: bool) -> Result:
        if not on:
            return self._end(ForceMode.ADMITTANCE, ForceMode.CONSTANT_FORCE,
                             ForceMode.VELOCITY_COMPLIANCE)
        s = self.settings()
        if s.compliance_type == ComplianceType.VELOCITY:
            refused = self._sensor_off("velocity compliance") or self._force_active(
                "velocity compliance")
            if refused:
                return refused
            self._velocity_on = True
            return Result.success("velocity compliance on: moves slow down as the wrench nears "
                                  "the compliance condition")
        constant = s.compliance_type == ComplianceType.CONSTANT_FORCE
        laws = AxisLaws.of(s.admittance, lambda a: a.ft_user,
                           (lambda a: a.constant) if constant else (lambda a: 0.0))
        mode = ForceMode.CONSTANT_FORCE if constant else ForceMode.ADMITTANCE
        return self._start(mode, laws, s.frame, s.compensation)

    def enable_tool_drive(self, on: bool) -> Result:
        if not on:
            return self._end(ForceMode.TOOL_DRIVE)
        s = self.settings()
        laws = AxisLaws.of(s.tool_drive, lambda a: a.rigidity, lambda a: 0.0)
        return self._start(ForceMode.TOOL_DRIVE, laws, s.tool_drive_frame, s.compensation)

    def disable(self) -> Result:
        return self._end(ForceMode.ADMITTANCE, ForceMode.CONSTANT_FORCE,
                         ForceMode.VELOCITY_COMPLIANCE, ForceMode.TOOL_DRIVE, quiet=True)

    def _start(self, mode: str, laws: AxisLaws, frame: int, compensated: bool) -> Result:
        label = mode.replace("_", " ")
        refused = (self._sensor_off(label) or self._force_active(label)
                   or self._arm_moving(label))
        if refused:
            return refused
        tool, _ = self._frames()
        kin = self._kin
        readings = self.readings

        def wrench():
            reading = readings.latest
            if reading is None:
                return None
            return reading.real if compensated else reading.actual

        physics = self._physics
        with self._flags.lock:
            q0 = physics.servo.setpoint.copy()
            # the velocity jog of ~twist_command (its ramp scaled by the speed ratio, as a jog's)
            jog = self._velocity_jog(frame == ForceFrame.TOOL)
            run = ForceControlRun(mode, laws, frame, jog, wrench,
                                  lambda q: kin.tcp_pose(q, tool), kin.flange_pose, tool, q0,
                                  SERVO_CYCLE)
            physics.switch(run)
        return Result.success(f"{label} on in the {frame_name(frame)} frame")

    def _end(self, *modes: str, quiet: bool = False) -> Result:
        """End force control if it runs in one of ``modes``: the arm ramps to rest."""
        ended = []
        if ForceMode.VELOCITY_COMPLIANCE in modes and self._velocity_on:
            self._velocity_on = False
            ended.append("velocity compliance")
        with self._flags.lock:
            motion = self._physics.motion
            if isinstance(motion, ForceControlRun) and motion.active and not motion.stopping \
                    and motion.mode in modes:
                motion.stop()
                ended.append(motion.mode.replace("_", " "))
        if ended:
            return Result.success(f"{' and '.join(ended)} off: the arm comes to rest")
        return Result.success("no force control was on" if quiet else
                              f"{' / '.join(m.replace('_', ' ') for m in modes)} was not on")

    # ---- payload identification ----------------------------------------------------------------------
    def start_identification(self, poses: Sequence[np.ndarray]) -> Result:
        refused = (self._sensor_off("payload identification")
                   or self._force_active("payload identification")
                   or self._arm_moving("payload identification"))
        if refused:
            return refused
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
        w = wrench_at_tcp(reading.real if s.compensation else reading.actual, tool, flange,
                          frame)
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
