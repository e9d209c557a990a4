"""What a JAKA controller does, on the MuJoCo twin: the emulator's controller logic in SI units.

The twin (:class:`~jaka_driver.sim.backend.SimBackend`) already moves like the arm; this layer
adds what a controller has and the twin does not: refusing motion in the wrong state, moves that
are accepted at once and finish later (``inpos``), stored frames that are activated separately
from being set, the servo ``stepNum`` interpolation, the speed override, the payload and
collision settings to report back. Every method takes SI values (rad, m, 4x4 poses of the active
tool in the active user frame) and raises :class:`Rejected` with the controller's message when
the command is refused; wire parsing lives in :mod:`.handlers`.

Thread-safe: commands are serialised by one lock (a controller executes one at a time); the
status snapshot reads without it.
"""
from __future__ import annotations

import threading
from typing import Optional

import numpy as np

from ..completion import Completion
from ..constants import SERVO_CYCLE
from ..frames import TOOL, USER_FRAME, FrameTable
from ..results import Result
from ..sim.backend import SimBackend
from ..sim.motions import ServoTarget
from ..validation import fastest_step, outside_limits

#: ``errorCode`` strings of the emulator. "1": the request itself is wrong (unknown command,
#: missing or malformed field); "2": a valid command refused in the current state.
ERROR_REQUEST = "1"
ERROR_REFUSED = "2"

FRAME_IDS = range(0, 16)          # tool and user frame slots of the controller
MAX_CLSN_LEVEL = 5
JOG_ROTATION_SPEED_MAX = np.pi    # rad/s


class Rejected(Exception):
    """A command the controller refuses: ``code`` (``errorCode``) and ``message``
    (``errorMsg``)."""

    def __init__(self, message: str, code: str = ERROR_REFUSED):
        super().__init__(message)
        self.code = code
        self.message = message


class RampedServoTarget(ServoTarget):
    """Servo mode with ``stepNum``: a target may be reached over ``n`` cycles, interpolated
    linearly, as the controller does; ``set`` (one cycle) is the twin's own behaviour."""

    def __init__(self, q: np.ndarray):
        super().__init__(q)
        self._ramp: Optional[tuple[np.ndarray, np.ndarray, int, int]] = None

    def set(self, q: np.ndarray) -> None:
        with self._lock:
            self._ramp = None
            self.target = q.copy()

    def ramp(self, q: np.ndarray, steps: int) -> None:
        with self._lock:
            self._ramp = (self.target.copy(), q.copy(), 0, steps)

    @property
    def goal(self) -> np.ndarray:
        with self._lock:
            return (self._ramp[1] if self._ramp is not None else self.target).copy()

    def next(self, q_sp, qd_sp, q_meas, qd_meas):
        with self._lock:
            if self._ramp is not None:
                start, end, k, n = self._ramp
                k += 1
                self.target = start + (end - start) * (k / n)
                self._ramp = None if k >= n else (start, end, k, n)
        return super().next(q_sp, qd_sp, q_meas, qd_meas)


class TwinController:
    """A JAKA controller whose arm is ``twin``."""

    def __init__(self, twin: SimBackend, version: str = "jaka_driver emulator"):
        self.twin = twin
        self.model = twin.model
        self.version = f"{version} ({twin.model.name} twin)"
        self.lock = threading.RLock()
        self._pending: Optional[Completion] = None    # the accepted move, until it ends
        self.frames = FrameTable()
        self.payload_mass = 0.0
        self.payload_centroid_mm = np.zeros(3)
        self.collision_level = twin.collision_level
        self.rapid_rate = 1.0
        self.servo_filter = 0

    # ---- state --------------------------------------------------------------------------
    @property
    def inpos(self) -> bool:
        """No accepted move is still under way and the arm is not being driven."""
        pending = self._pending
        return (pending is None or pending.done) and not self.twin.state().moving

    def require_can_move(self, what: str, servo_ok: bool = False) -> None:
        t = self.twin
        if t.emergency_stop:
            raise Rejected(f"{what}: emergency stop is pressed")
        if not t.powered:
            raise Rejected(f"{what}: robot is powered off")
        if not t.enabled:
            raise Rejected(f"{what}: robot is not enabled")
        if t.collision or t.protective_stop:
            raise Rejected(f"{what}: protective stop ({t.error_message}); call clear_error")
        if t.drag_mode:
            raise Rejected(f"{what}: robot is in drag mode")
        if t.servo_mode and not servo_ok:
            raise Rejected(f"{what}: robot is in servo mode (servo_move relFlag 0 first)")

    def require_still(self, what: str) -> None:
        # The live motion source, not the last physics sample: a command right after leaving
        # servo mode must not be refused because of a sample taken 2 ms earlier.
        pending = self._pending
        if (pending is not None and not pending.done) or self.twin.physics.motion.active:
            raise Rejected(f"{what}: the robot is moving (stop_program first)")

    def check_limits(self, q: np.ndarray, what: str) -> None:
        m = self.model
        i = outside_limits(m, q, tolerance=1e-9)   # the wire's degrees round-trip to ~1e-12
        if i is not None:
            raise Rejected(f"{what}: joint {i + 1} target {np.degrees(q[i]):.3f} deg is outside "
                           f"[{np.degrees(m.lower[i]):.1f}, {np.degrees(m.upper[i]):.1f}] deg",
                           ERROR_REQUEST)

    def commanded_joints(self) -> np.ndarray:
        """The servo setpoint (rad): where the controller is driving the arm."""
        return self.twin.physics.servo.setpoint.copy()

    def commanded_tcp(self) -> np.ndarray:
        tool, user = self.twin.frames()
        return self.twin.kin.tcp_pose(self.commanded_joints(), tool, user)

    # ---- power ------------------------------------------------------------------------------
    def set_power(self, on: bool) -> None:
        with self.lock:
            if on and self.twin.emergency_stop:
                raise Rejected("power_on: emergency stop is pressed; release it first")
            self.twin.set_power(on)

    def set_enabled(self, on: bool) -> None:
        with self.lock:
            if on and self.twin.emergency_stop:
                raise Rejected("enable_robot: emergency stop is pressed")
            if on and not self.twin.powered:
                raise Rejected("enable_robot: robot is powered off (power_on first)")
            self.twin.set_enabled(on)

    def clear_error(self) -> None:
        with self.lock:
            if self.twin.emergency_stop:
                raise Rejected("clear_error: emergency stop is pressed; release it first")
            self.twin.clear_error()

    # ---- moves ----------------------------------------------------------------------------------
    def _accepted(self, started: Result, what: str) -> None:
        if not started.ok:
            raise Rejected(f"{what}: {started.message}")
        self._pending = started.value[0]

    def joint_move(self, q: np.ndarray, speed: float, accel: float) -> None:
        with self.lock:
            self.require_can_move("joint_move")
            self.require_still("joint_move")
            self.check_limits(q, "joint_move")
            self._accepted(self.twin.start_joint_move(q, speed * self.rapid_rate, accel),
                           "joint_move")

    def linear_move(self, target: np.ndarray, speed: float, accel: float) -> None:
        with self.lock:
            self.require_can_move("moveL")
            self.require_still("moveL")
            self._accepted(self.twin.start_linear_move(target, speed * self.rapid_rate, accel),
                           "moveL")

    def jog(self, coord: int, axis: int, direction: int, speed: float) -> None:
        """Continuous jog; ``coord`` as the twin numbers it (0 joint, 1 base, 2 tool)."""
        with self.lock:
            self.require_can_move("jog")
            if coord == 0:
                speed = min(speed, float(self.model.max_velocity[axis]))
            elif axis < 3:
                speed = min(speed, self.model.max_tcp_speed_mm_s / 1000.0)
            else:
                speed = min(speed, JOG_ROTATION_SPEED_MAX)
            result = self.twin.jog(coord, axis, direction, speed * self.rapid_rate)
            if not result.ok:
                raise Rejected(f"jog: {result.message}")

    def jog_stop(self) -> None:
        with self.lock:
            self.twin.jog_stop()

    def stop(self) -> None:
        with self.lock:
            self.twin.stop_move()

    # ---- servo mode -----------------------------------------------------------------------------
    def set_servo_mode(self, on: bool) -> None:
        with self.lock:
            if not on:
                self.twin.servo_enable(False)
                return
            if self.twin.servo_mode:
                return
            self.require_can_move("servo_move", servo_ok=True)
            self.require_still("servo_move")
            result = self.twin.servo_enable(True)
            if not result.ok:
                raise Rejected(f"servo_move: {result.message}")
            # The twin's servo target reaches each set-point in one cycle; the controller can
            # also spread one over stepNum cycles, so swap in the ramping variant.
            physics = self.twin.physics
            physics.switch(RampedServoTarget(physics.servo.setpoint))

    def _servo_target(self, what: str) -> RampedServoTarget:
        motion = self.twin.physics.motion
        if not self.twin.servo_mode or not isinstance(motion, RampedServoTarget):
            raise Rejected(f"{what}: not in servo mode (servo_move relFlag 1 first)")
        return motion

    def servo_reference(self, what: str) -> np.ndarray:
        """The latest servo target (rad), the base of relative set-points."""
        return self._servo_target(what).goal

    def servo_joints(self, q: np.ndarray, steps: int, what: str = "servo_j") -> None:
        with self.lock:
            self.require_can_move(what, servo_ok=True)
            target = self._servo_target(what)
            self.check_limits(q, what)
            too_fast = fastest_step(self.model, target.goal, q, steps * SERVO_CYCLE)
            if too_fast is not None:
                j, speed = too_fast
                raise Rejected(f"{what}: joint {j + 1} would move at "
                               f"{np.degrees(speed):.1f} deg/s, limit "
                               f"{np.degrees(self.model.max_velocity[j]):.1f} deg/s")
            if steps == 1:
                target.set(q)
            else:
                target.ramp(q, steps)

    def servo_pose(self, pose: np.ndarray, steps: int) -> None:
        with self.lock:
            seed = self.servo_reference("servo_p")
            solution = self.twin.inverse_kinematics(pose, seed)
            if not solution.ok:
                raise Rejected(f"servo_p: {solution.message}")
            self.servo_joints(solution.value, steps, "servo_p")

    # ---- frames, payload, settings ------------------------------------------------------------
    def set_tool_offset(self, tool_id: int, pose: np.ndarray) -> None:
        with self.lock:
            self.frames.store(TOOL, tool_id, pose)
            if self.twin.tool_id == tool_id:
                self.twin.set_tool_frame(tool_id, pose)   # re-apply the active tool

    def activate_tool(self, tool_id: int) -> None:
        with self.lock:
            self.twin.set_tool_frame(tool_id, self.frames.get(TOOL, tool_id))

    def set_user_offset(self, user_id: int, pose: np.ndarray) -> None:
        with self.lock:
            self.frames.store(USER_FRAME, user_id, pose)
            if self.twin.user_id == user_id:
                self.twin.set_user_frame(user_id, pose)

    def activate_user(self, user_id: int) -> None:
        with self.lock:
            self.twin.set_user_frame(user_id, self.frames.get(USER_FRAME, user_id))

    def set_payload(self, mass: float, centroid_mm: np.ndarray) -> None:
        with self.lock:
            self.twin.set_payload(self.twin.tool_id, mass, centroid_mm / 1000.0)
            self.payload_mass, self.payload_centroid_mm = mass, centroid_mm.copy()

    def set_collision_level(self, level: int) -> None:
        with self.lock:
            self.twin.set_collision_level(level)
            self.collision_level = level

    def set_servo_filter(self, filter_type: int) -> None:
        with self.lock:
            if self.twin.servo_mode:
                raise Rejected("set_servo_move_filter: not allowed in servo mode")
            self.servo_filter = filter_type

    def io_count(self, signal: str, io_type: int, path: int) -> int:
        return int(self.model.io_sizes.get((signal, io_type, path), 0))

    def check_io(self, signal: str, io_type: int, path: int, index: int, what: str) -> None:
        count = self.io_count(signal, io_type, path)
        if not 0 <= index < count:
            kind = "output" if path else "input"
            raise Rejected(f"{what}: {signal} {kind} index {index} of type {io_type} does not "
                           f"exist (this type has {count})", ERROR_REQUEST)

    # ---- emulator-only faults -------------------------------------------------------------------
    def emergency_stop(self, pressed: bool) -> str:
        with self.lock:
            result = (self.twin.press_emergency_stop() if pressed
                      else self.twin.release_emergency_stop())
            return result.message

    def protective_stop(self, reason: str) -> str:
        with self.lock:
            return self.twin.trigger_protective_stop(reason).message

    def set_input(self, signal: str, io_type: int, index: int, value: float) -> None:
        with self.lock:
            self.check_io(signal, io_type, 0, index, "emulator_set_input")
            self.twin.set_input(signal, io_type, index, value)
