"""What a JAKA controller does, on the MuJoCo twin: the emulator's controller logic in SI units.

The twin (a backend that offers :class:`~jaka_driver.backend.Twin`: the MuJoCo twin) already
moves like the arm; this layer adds what a controller has and the twin does not: refusing motion
in the wrong state, a motion queue (a move is acknowledged at once and runs after the ones
before it; ``inpos`` once the queue is done — docs/protocol.md, "Motion queue"; the queue and
its thread are :mod:`.motion_queue`, what may be queued is decided here), stored frames that are
activated separately from being set, the servo ``stepNum`` interpolation, the speed override
(the twin's speed ratio), the payload and collision settings to report back, the servo filter
applied to the twin's servo stream, and the programs the twin's engine runs on this
controller's rules (:mod:`.program_steps`): while one runs or is paused, motion commands are
refused and ``stop_program`` ends it. Every method takes SI values (rad, m, 4x4 poses of the active
tool in the active user frame) and raises :class:`~.replies.Rejected` with the controller's
message when the command is refused; wire parsing lives in :mod:`.handlers`.

It uses only the backend's face: the contract (commands, ``state()``) and ``backend.twin`` (the
commanded setpoint, the servo ramp, IO, faults), never the simulation's internals.

Thread-safe: commands are serialised by one lock (a controller executes one at a time); the
status snapshot reads without it. The queue's thread starts each queued move, under that lock,
when the one before it has ended.
"""
from __future__ import annotations

import logging
import threading
import time
from typing import Callable, Optional, Tuple

import numpy as np

from ..backend import Backend, Programs, ProgramState, RobotState
from ..common.constants import MAX_TOOL_ROTATION_SPEED, SERVO_CYCLE
from ..common.frames import TOOL, USER_FRAME, FrameTable
from ..common.joint_limits import fastest_step, outside_limits
from ..common.results import CommandRefused
from ..motion.circular_path import arc_through
from ..motion.servo_filters import ServoFilterSpec
from ..protocol.fields import IDENTITY_FIELDS
from .motion_queue import MotionQueue
from .profiles import DEFAULT_PROFILE, ControllerProfile, profile_named
from .replies import ERROR_REFUSED, ERROR_REQUEST, Rejected
from .torque_sensor import TorqueSensorSettings

log = logging.getLogger(__name__)

#: What fw 1.5.14 answers to servo_j outside servo mode (recorded, spelling included).
ERROR_NOT_IN_SERVO_MODE = "-1"
NOT_IN_SERVO_MODE = "{} command can only be excuted in servo move mode"

#: Tool and user frame slots: the rows of get_tool_offsets / get_user_offsets (ids 0..10, as
#: JAKA's SDK reads them; 0 is the flange / the base itself and cannot be set).
FRAME_IDS = range(0, 11)
MAX_CLSN_LEVEL = 5


class TwinController:
    """A JAKA controller whose arm is ``backend``, a twin (``backend.twin`` is not None)."""

    def __init__(self, backend: Backend, profile: Optional[ControllerProfile] = None):
        """``profile``: the controller generation (default: the recorded Zu 5s, fw 1.5.14)."""
        if backend.twin is None:
            raise ValueError("the emulator needs a backend that offers a twin (backend.twin)")
        self.backend = backend
        self.twin = backend.twin
        self.model = backend.model
        self.profile = profile = profile or profile_named(DEFAULT_PROFILE)
        #: what get_version answers: the profile's firmware in a real controller's form, so
        #: clients that parse it work
        self.version = profile.version
        #: where a person reads it (get_version's robot_name, the log): this is the emulator
        self.identity = f"jaka_driver emulator ({self.model.name} MuJoCo twin), not a controller"
        self.lock = threading.RLock()
        #: the queued moves, started one after another by its own thread
        self.queue = MotionQueue(self.lock)
        self.tio_vout = (0, 0)                        # (enable 0/1, voltage code 0 24 V, 1 12 V)
        self.sensor = TorqueSensorSettings()
        self.frames = FrameTable()
        self.payload_mass = 0.0
        self.payload_centroid_mm = np.zeros(3)
        self.collision_level = self.twin.collision_level
        self.servo_filter: Tuple[int, dict] = (0, {})   # (filter_type, its parameters)

    @property
    def rapid_rate(self) -> float:
        """The speed override (``rapid_rate``), 0 < r ≤ 1: the twin's speed ratio, so moves and
        jogs are scaled by the one law the driver plans with (time × 1/r: speeds × r,
        accelerations × r²); servo set-points are not scaled."""
        return self.backend.speed_ratio()

    @rapid_rate.setter
    def rapid_rate(self, rate: float) -> None:
        with self.lock:
            self.backend.set_speed_ratio(float(rate))

    def identity_fields(self) -> dict:
        """get_version's seven identity strings (JAKA's SDK logs them at login; a number there
        aborts its login). Version 0.0 stands for a part the twin does not have."""
        values = (self.version, "jaka_driver-emulator", "none", f"emulator-{self.model.name}",
                  self.identity, "0.0", "0.0")
        return dict(zip(IDENTITY_FIELDS, values))

    def apply_start(self, start: str) -> None:
        """Put the arm in a start state of :data:`~.profiles.START_STATES` (the twin itself
        starts powered on and enabled)."""
        with self.lock:
            self.backend.set_power(start != "off")
            self.backend.set_enabled(start == "enabled")

    def close(self) -> None:
        self.queue.close()

    # ---- state --------------------------------------------------------------------------
    @property
    def moving(self) -> bool:
        """Queued moves wait, or one is being started or runs."""
        return self.queue.moving

    @property
    def queued(self) -> int:
        """Moves waiting behind the running one."""
        return self.queue.queued

    @property
    def motion_line(self) -> int:
        """Moves started so far."""
        return self.queue.motion_line

    @property
    def inpos(self) -> bool:
        """The queue is done and the arm is not being driven."""
        return not self.moving and not self.twin.motion_active

    def wait_idle(self, timeout: float) -> bool:
        """Block until the queue is done (``wait_complete``); False on timeout."""
        deadline = time.monotonic() + timeout
        while not self.inpos and time.monotonic() < deadline:
            time.sleep(0.01)
        return self.inpos

    def state(self) -> RobotState:
        """The arm's latest sample, its flags read now."""
        return self.backend.state()

    @property
    def programs(self) -> Programs:
        """The programs the twin runs (``backend.programs``)."""
        return self.backend.programs

    def program_running(self) -> bool:
        """A program runs or is paused."""
        programs = self.backend.programs
        return programs is not None and programs.status().state != ProgramState.IDLE

    def require_can_move(self, what: str, servo_ok: bool = False,
                         program_step: bool = False) -> None:
        """Refuse ``what`` unless the arm may move: no stop, powered, enabled, no protective
        stop, not in drag or (unless ``servo_ok``) servo mode, and no program running or paused
        (unless this is a step of it)."""
        if not program_step and self.program_running():
            raise Rejected(f"{what}: a program is {self.programs.status().state.word} "
                           "(stop_program first)")
        t = self.state()
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
        # The live motion source, not the last sample: a command right after leaving
        # servo mode must not be refused because of a sample taken 2 ms earlier.
        if self.moving or self.twin.motion_active:
            raise Rejected(f"{what}: the robot is moving (stop_program first)")

    def check_limits(self, q: np.ndarray, what: str) -> None:
        m = self.model
        i = outside_limits(m, q, tolerance=1e-9)   # the wire's degrees round-trip to ~1e-12
        if i is not None:
            # "call joint_move failed" is a real controller's text (recorded); the rest says why
            raise Rejected(f"call {what} failed: joint {i + 1} target "
                           f"{np.degrees(q[i]):.3f} deg is outside "
                           f"[{np.degrees(m.lower[i]):.1f}, {np.degrees(m.upper[i]):.1f}] deg",
                           ERROR_REFUSED)   # a controller answers "2" (call ... failed)

    def commanded_joints(self) -> np.ndarray:
        """The servo setpoint (rad): where the controller is driving the arm."""
        return self.twin.commanded_joints()

    def commanded_tcp(self) -> np.ndarray:
        """The TCP of the servo setpoint (4x4, m)."""
        return self.twin.commanded_tcp()

    def forward_kinematics(self, q: np.ndarray, what: str) -> np.ndarray:
        """The TCP (4x4, m) at joints ``q`` (rad): the arm's own kinematics, as a controller's."""
        result = self.backend.forward_kinematics(q)
        if not result.ok:
            raise Rejected(f"{what}: {result.message}")
        return result.value

    def inverse_kinematics(self, pose: np.ndarray, ref: np.ndarray, what: str) -> np.ndarray:
        """Joints (rad) reaching ``pose`` (4x4, m) nearest ``ref`` (rad)."""
        result = self.backend.inverse_kinematics(pose, ref)
        if not result.ok:
            raise Rejected(f"{what}: {result.message}")
        return result.value

    def on_limit(self) -> bool:
        """A joint within 0.1° of its limit (what ``is_on_limit`` reports, and the status
        packet's ``on_soft_limit``): the twin's own sample says."""
        return self.state().on_limit

    # ---- power ------------------------------------------------------------------------------
    def set_power(self, on: bool) -> None:
        with self.lock:
            if on and self.state().emergency_stop:
                raise Rejected("power_on: emergency stop is pressed; release it first")
            self.backend.set_power(on)

    def set_enabled(self, on: bool) -> None:
        with self.lock:
            st = self.state()
            if on and st.emergency_stop:
                raise Rejected("enable_robot: emergency stop is pressed")
            if on and not st.powered:
                raise Rejected("enable_robot: robot is powered off (power_on first)")
            self.backend.set_enabled(on)

    def clear_error(self) -> None:
        with self.lock:
            if self.state().emergency_stop:
                raise Rejected("clear_error: emergency stop is pressed; release it first")
            self.backend.clear_error()

    # ---- moves ----------------------------------------------------------------------------------
    def joint_move(self, target: Callable[[], np.ndarray], speed: float, accel: float,
                   what: str = "joint_move") -> None:
        """Queue a joint move; ``target()`` gives its goal (rad) when its turn comes (so a
        relative move adds to where the move before it ended)."""
        with self.lock:
            self.require_can_move(what)
            if not self.moving:
                self.check_limits(target(), what)   # refuse at once what is known to be wrong
            self.queue.enqueue(what, lambda: self._start_joint_move(target(), speed, accel,
                                                                    what))

    def _start_joint_move(self, q: np.ndarray, speed: float, accel: float,
                          what: str) -> Result:
        self.check_limits(q, what)
        return self.backend.start_joint_move(q, speed, accel)

    def end_move(self, pose: np.ndarray, speed: float, accel: float) -> None:
        """Queue a joint-interpolated move to the Cartesian ``pose`` (4x4, m); the joints are
        solved when its turn comes, near where the move before it ended."""
        def target() -> np.ndarray:
            solution = self.backend.inverse_kinematics(pose, self.commanded_joints())
            if not solution.ok:
                raise Rejected(f"end_move: {solution.message}")
            return solution.value
        # Queued as a joint move: an unreachable pose is refused at once when idle, as a joint
        # target outside the limits is.
        self.joint_move(target, speed, accel, what="end_move")

    def linear_move(self, target: Callable[[], np.ndarray], speed: float, accel: float) -> None:
        """Queue a straight-line move; ``target()`` gives its pose (4x4, m) when its turn
        comes."""
        with self.lock:
            self.require_can_move("moveL")
            self.queue.enqueue("moveL", lambda: self.backend.start_linear_move(target(), speed,
                                                                               accel))

    def circular_move(self, poses: Callable[[], Tuple[np.ndarray, np.ndarray]], speed: float,
                      accel: float, turns: float, mode: int) -> None:
        """Queue a circular move (``movc``); ``poses()`` gives its (middle, end) poses (4x4, m)
        when its turn comes. The twin plans the exact arc and checks its whole path then; when
        the arm is idle, three points on one line or too many turns are refused at once, as a
        joint target outside the limits is."""
        with self.lock:
            self.require_can_move("movc")
            if not self.moving:
                mid, end = poses()
                try:
                    arc_through(self.commanded_tcp()[:3, 3], mid[:3, 3], end[:3, 3], turns)
                except CommandRefused as refusal:
                    raise Rejected(f"movc: {refusal.message}", ERROR_REFUSED) from None
            self.queue.enqueue("movc", lambda: self.backend.start_circular_move(
                *poses(), speed, accel, turns, mode))

    def jog(self, coord: int, axis: int, direction: int, speed: float) -> None:
        """Continuous jog; ``coord`` as the twin numbers it (0 joint, 1 base, 2 tool)."""
        with self.lock:
            self.require_can_move("jog")
            if coord == 0:
                speed = min(speed, float(self.model.max_velocity[axis]))
            elif axis < 3:
                speed = min(speed, self.model.max_tcp_speed)
            else:
                speed = min(speed, MAX_TOOL_ROTATION_SPEED)
            result = self.backend.jog(coord, axis, direction, speed)
            if not result.ok:
                raise Rejected(f"jog: {result.message}")

    def jog_stop(self) -> None:
        """``jog_mode`` 0 ends any jog: continuous ones brake, incremental and absolute ones
        (queued moves labelled ``jog``) are stopped with the queue."""
        with self.lock:
            self.backend.jog_stop()
            if self.queue.running_label == "jog" and self.moving:
                self.stop()

    def stop(self) -> None:
        """``stop_program``: the program (if one runs or is paused) ends, the queue is
        emptied, the arm decelerates to rest."""
        if self.program_running():
            # outside the lock: the program's step may be waiting for it to start its move
            self.programs.stop()
        with self.lock:
            self.queue.clear()
            self.backend.stop_move()

    # ---- servo mode -----------------------------------------------------------------------------
    def set_servo_mode(self, on: bool) -> None:
        """Enter or leave servo mode. Entering while queued moves run is acknowledged and does
        nothing, as fw 1.5.14 was recorded doing: ``is_in_servomove`` stays false."""
        with self.lock:
            if not on:
                self.backend.servo_enable(False)
                return
            if self.state().servo_mode:
                return
            self.require_can_move("servo_move", servo_ok=True)
            if self.moving or self.twin.motion_active:
                log.info("emulator: servo_move enable while the arm moves: acknowledged, "
                         "servo mode not entered (as recorded on fw 1.5.14)")
                return
            result = self.backend.servo_enable(True)
            if not result.ok:
                raise Rejected(f"servo_move: {result.message}")

    def servo_reference(self, what: str) -> np.ndarray:
        """The latest servo target (rad), the base of relative set-points."""
        goal = self.twin.servo_goal() if self.state().servo_mode else None
        if goal is None:
            raise Rejected(f"{what}: not in servo mode (servo_move relFlag 1 first)")
        return goal

    def require_servo_mode(self, what: str) -> None:
        """servo_j outside servo mode: the recorded errorCode "-1" and text (servo_p answered
        likewise, by analogy: not recorded)."""
        if not self.state().servo_mode:
            raise Rejected(NOT_IN_SERVO_MODE.format(what.replace("_", "")),
                           ERROR_NOT_IN_SERVO_MODE)

    def servo_joints(self, q: np.ndarray, steps: int, what: str = "servo_j") -> None:
        with self.lock:
            self.require_servo_mode(what)
            self.require_can_move(what, servo_ok=True)
            goal = self.servo_reference(what)
            self.check_limits(q, what)
            too_fast = fastest_step(self.model, goal, q, steps * SERVO_CYCLE)
            if too_fast is not None:
                j, speed = too_fast
                raise Rejected(f"{what}: joint {j + 1} would move at "
                               f"{np.degrees(speed):.1f} deg/s, limit "
                               f"{np.degrees(self.model.max_velocity[j]):.1f} deg/s")
            result = self.twin.servo_ramp(q, steps)
            if not result.ok:
                raise Rejected(f"{what}: {result.message}")

    def servo_pose(self, pose: np.ndarray, steps: int) -> None:
        with self.lock:
            self.require_servo_mode("servo_p")
            seed = self.servo_reference("servo_p")
            solution = self.backend.inverse_kinematics(pose, seed)
            if not solution.ok:
                raise Rejected(f"servo_p: {solution.message}")
            self.servo_joints(solution.value, steps, "servo_p")

    # ---- frames, payload, settings ------------------------------------------------------------
    def set_tool_offset(self, tool_id: int, pose: np.ndarray) -> None:
        with self.lock:
            self.frames.store(TOOL, tool_id, pose)
            if self.state().tool_id == tool_id:
                self.backend.set_tool_frame(tool_id, pose)   # re-apply the active tool

    def activate_tool(self, tool_id: int) -> None:
        with self.lock:
            self.backend.set_tool_frame(tool_id, self.frames.get(TOOL, tool_id))

    def set_user_offset(self, user_id: int, pose: np.ndarray) -> None:
        with self.lock:
            self.frames.store(USER_FRAME, user_id, pose)
            if self.state().user_id == user_id:
                self.backend.set_user_frame(user_id, pose)

    def activate_user(self, user_id: int) -> None:
        with self.lock:
            self.backend.set_user_frame(user_id, self.frames.get(USER_FRAME, user_id))

    def set_payload(self, mass: float, centroid_mm: np.ndarray) -> None:
        with self.lock:
            self.backend.set_payload(self.state().tool_id, mass, centroid_mm / 1000.0)
            self.payload_mass, self.payload_centroid_mm = mass, centroid_mm.copy()

    def set_drag_mode(self, on: bool) -> None:
        with self.lock:
            if on and self.program_running():
                raise Rejected("torque_control_enable: a program is running (stop_program "
                               "first)")
            result = self.backend.set_drag_mode(on)
            if not result.ok:
                raise Rejected(f"torque_control_enable: {result.message}")

    def set_collision_level(self, level: int) -> None:
        with self.lock:
            self.backend.set_collision_level(level)
            self.collision_level = level

    def set_servo_filter(self, filter_type: int, params: dict, spec: ServoFilterSpec) -> None:
        """The servo filter ``spec`` on the twin's servo stream from the next servo mode on
        (JAKA's manual: set outside servo mode); ``filter_type`` and ``params`` as the wire
        sent them, kept to report."""
        with self.lock:
            if self.state().servo_mode:
                raise Rejected("set_servo_move_filter: not allowed in servo mode")
            result = self.backend.set_servo_filter(spec)
            if not result.ok:
                raise Rejected(f"set_servo_move_filter: {result.message}")
            self.servo_filter = (filter_type, dict(params))

    # ---- programs -----------------------------------------------------------------------------
    def play_program(self) -> None:
        """Run the loaded program: the arm must be free to move and still."""
        with self.lock:
            self.require_can_move("play_program")
            self.require_still("play_program")
            self._program_answer("play_program", self.programs.play())

    def resume_program(self) -> None:
        with self.lock:
            self.require_can_move("resume_program", program_step=True)
            self._program_answer("resume_program", self.programs.resume())

    def pause_program(self) -> None:
        self._program_answer("pause_program", self.programs.pause())

    @staticmethod
    def _program_answer(what: str, result) -> None:
        if not result.ok:
            raise Rejected(f"{what}: {result.message}")

    def set_output(self, signal: str, io_type: int, index: int, value: float) -> None:
        """Output ``index`` (from 0; checked with :meth:`check_io`) = ``value``."""
        with self.lock:
            self.backend.set_io(signal, io_type, index, value)

    def read_io(self, signal: str, path: int, io_type: int, index: int) -> float:
        """An input (``path`` 0) or output (1), ``index`` from 0 (checked with
        :meth:`check_io`)."""
        return self.backend.get_io(signal, path, io_type, index).value

    def torqsensor(self, st: RobotState) -> list:
        """The status packet's ``torqsensor`` for the sample ``st``: the stored settings, and,
        when the arm carries a sensor (the backend's ``force``), the twin's sensor payload and
        the sample's three readings (:meth:`.torque_sensor.TorqueSensorSettings.monitor`)."""
        force = self.backend.force
        if force.absent is not None:
            return self.sensor.monitor()
        payload = force.settings().tool_payload
        return self.sensor.monitor((payload.mass, payload.centroid * 1000.0, st.force))

    def tcp_speed(self, st: RobotState) -> float:
        """m/s of the active tool's origin in the sample ``st``."""
        return self.twin.tcp_speed(st)

    def io_values(self) -> dict:
        """Every IO array as it stands (:meth:`jaka_driver.backend.Twin.io_snapshot`)."""
        return self.twin.io_snapshot()

    def io_count(self, signal: str, io_type: int, path: int) -> int:
        return int(self.model.io_sizes.get((signal, io_type, path), 0))

    def check_io(self, signal: str, io_type: int, path: int, index: int, what: str) -> None:
        count = self.io_count(signal, io_type, path)
        kind = "output" if path else "input"
        if count == 0:
            raise Rejected(f"{what}: IO type {io_type} has no {signal} {kind}s on this "
                           "controller", ERROR_REQUEST)
        if not 0 <= index < count:
            raise Rejected(f"{what}: {signal} {kind} index {index + 1} of type {io_type} does not "
                           f"exist (this type has {count}, numbered from 1)", ERROR_REQUEST)

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
        """Input ``index`` (from 0; checked with :meth:`check_io`) = ``value``, as the world
        outside would drive it."""
        with self.lock:
            self.twin.set_input(signal, io_type, index, value)
