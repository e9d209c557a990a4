"""The door of the driver: every service request passes through :class:`RobotDriver`.

Order of checks (docs/design.md, "The picture"): validate the request → check the robot state →
let the backend plan the whole motion → only then move. A refused command changes nothing.

The methods take the values of the service requests in their own units (docs/interface.md,
"Units and frames": rad, mm, rotation vectors; servo_p m + RPY — or, built with
``conventions=JAKA_CODE``, those of JAKA's driver code: jaka_driver.conventions) and answer a
:class:`Result`; they never raise. They are safe to call from many threads at once, as rospy does.
"""
from __future__ import annotations

import logging
import threading
from contextlib import contextmanager
from typing import Callable, Sequence

import numpy as np

from ..backend import Backend, Camera, Twin
from ..backend.robot_state import RobotState
from ..common.constants import move_deadline
from ..common.results import Code, CommandRefused, Result, invalid
from ..common.transforms import rpy_to_matrix
from ..conventions import DOCUMENT, Conventions, ServoIncrements, cartesian
from ..conventions.jog_speed import explained, jog_speed_field
from . import checks as check
from .answers import answers as _answers
from .force_requests import ForceRequests
from .watchdogs import JogWatchdog, ServoStream

log = logging.getLogger(__name__)

#: Why a twin's own request is refused on a controller (-9).
NOT_A_TWIN = ("refused: this backend is a controller, not a twin (reset, pause and step are "
              "the twin's own)")
NOT_A_TWIN_FAULTS = ("refused: this backend is a controller, not a twin (faults and inputs "
                     "are injected on a twin only)")
#: the most cycles one step request runs (80 s of sim time)
MAX_STEP = 10000


class RobotDriver:
    """Validation, state checks and watchdogs in front of a :class:`Backend`."""

    def __init__(self, backend: Backend, *, jog_timeout: float = 3.0, servo_timeout: float = 0.1,
                 servo_increment: bool = False, conventions: Conventions = DOCUMENT,
                 twist_timeout: float = 0.1):
        """``conventions``: how requests are read where JAKA's document and JAKA's driver code
        differ (jaka_driver.conventions); ``servo_increment`` adds servo increments to them
        (servo_j / servo_p take increments, as JAKA's driver code sends them).
        ``twist_timeout``: s after the last twist before a velocity jog stops."""
        self.backend = backend
        self.model = backend.model
        #: every timeout below runs on the backend's time (wall, or the twin's sim time)
        self.clock = backend.clock
        self.conventions = conventions.with_servo_increment(servo_increment)
        self._move_lock = threading.Lock()   # one blocking move at a time
        self._jog = JogWatchdog(self._jog_expired, timeout=jog_timeout, clock=self.clock)
        self._servo = ServoStream(timeout=servo_timeout, clock=self.clock)
        self._twist = JogWatchdog(self._twist_expired, timeout=twist_timeout, clock=self.clock)
        self._increments = ServoIncrements(self._servo_j, self._servo_p, backend.state,
                                           backend.forward_kinematics) \
            if self.conventions.servo_increment else None
        #: the force/torque sensor and force control (driver/force_requests.py)
        self.force = ForceRequests(self)

    # ---- life cycle --------------------------------------------------------------------
    def start(self) -> None:
        self.backend.start()

    def shutdown(self) -> None:
        self._jog.close()
        self._twist.close()
        self.backend.shutdown()

    def state(self) -> RobotState:
        return self.backend.state()

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        """See :meth:`Backend.wait_for_sample`."""
        return self.backend.wait_for_sample(after, timeout)

    def states_since(self, after: float) -> list[RobotState]:
        """See :meth:`Backend.states_since`."""
        return self.backend.states_since(after)

    # ---- state machine -----------------------------------------------------------------
    def _ready(self, *, servo: bool = False, allow_servo_mode: bool = False) -> RobotState:
        """The arm may move: connected, no e-stop, powered, enabled, no error, right mode."""
        st = self.backend.state()
        if not st.connected:
            raise CommandRefused(Code.NOT_CONNECTED, "not connected to the controller")
        if st.emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed")
        if not st.powered:
            raise CommandRefused(Code.NOT_POWERED, "robot is not powered (call power)")
        if not st.enabled:
            raise CommandRefused(Code.NOT_ENABLED, "robot is not enabled (call enable)")
        if st.in_error:
            raise CommandRefused(Code.MOTION_STOPPED, f"{self._error_text(st)} stands; "
                                 "call clear_err before moving")
        if st.drag_mode:
            raise CommandRefused(Code.WRONG_MODE, "refused in drag mode")
        if servo and not st.servo_mode:
            raise CommandRefused(Code.SERVO_MODE_OFF, "servo mode is off (call servo_move_enable)")
        if not servo and not allow_servo_mode and st.servo_mode:
            raise CommandRefused(Code.WRONG_MODE, "refused in servo mode "
                                 "(leave it with servo_move_enable false)")
        return st

    @staticmethod
    def _error_text(st: RobotState) -> str:
        if st.collision:
            return "collision alarm"
        if st.protective_stop:
            return "protective stop"
        return f"error {st.error_code:#x} {st.error_message}".strip()

    def _not_jogging(self) -> None:
        if self._jog.session is not None:
            raise CommandRefused(Code.BUSY, "a jog is running (stop_move, or wait 3 s after "
                                 "the last jog call)")
        if self._twist.session is not None:
            raise CommandRefused(Code.BUSY, "a velocity jog is running (stop_move, or stop "
                                 f"sending twists: it stops {self._twist.timeout:g} s after "
                                 "the last)")

    @contextmanager
    def _blocking_move(self, what: str):
        if not self._move_lock.acquire(blocking=False):
            raise CommandRefused(Code.BUSY, f"{what} refused: another move is running")
        try:
            yield
        finally:
            self._move_lock.release()

    @property
    def moving(self) -> bool:
        return (self._move_lock.locked() or self._jog.session is not None
                or self._twist.session is not None)

    # ---- motion ------------------------------------------------------------------------
    @_answers
    def joint_move(self, pose: Sequence[float], mvvelo: float, mvacc: float,
                   mvtime: float = 0.0) -> Result:
        """Synchronised joint move to ``pose`` (rad) at ``mvvelo`` rad/s, ``mvacc`` rad/s²;
        ``mvtime`` > 0 stretches it to that many seconds. Blocks."""
        q = check.joint_targets("pose", pose, self.model)
        notes: list[str] = []
        v = check.speed("mvvelo", mvvelo, float(np.max(self.model.max_velocity)), "rad/s",
                        notes=notes)
        a = check.speed("mvacc", mvacc, float(np.max(self.model.max_acceleration)), "rad/s²",
                        default=self.model.default_joint_accel, notes=notes)
        duration = check.finite("mvtime", mvtime, "s")
        if duration < 0:
            raise invalid(f"mvtime is {duration:g} s, expected ≥ 0 (0 = as fast as allowed)")
        planned = check.joint_move_duration(self.backend.state().joint_position, q,
                                            np.minimum(v, self.model.max_velocity),
                                            np.minimum(a, self.model.max_acceleration),
                                            duration or None, mvvelo, mvacc) / self._ratio()
        result = self._run_move("joint_move", lambda st: self.backend.start_joint_move(
            q, v, a, planned))
        return _with_notes(result, notes)

    @_answers
    def linear_move(self, pose: Sequence[float], mvvelo: float, mvacc: float,
                    coord_mode: int = 0, has_ref: bool = False,
                    ref_joint: Sequence[float] = ()) -> Result:
        """Straight-line move to ``pose`` (mm + rotation vector, or RPY with ``jaka_code``
        conventions) at ``mvvelo`` mm/s, ``mvacc`` mm/s²; ``coord_mode`` 0 user frame, 1 base
        frame, 2 relative in the tool frame (``jaka_code``: always 0, no IK seed, as JAKA's
        code passes neither on). Blocks."""
        target_mm = check.vector("pose", pose)
        notes: list[str] = []
        if not self.conventions.linear_move_frame_fields:
            if coord_mode or has_ref:
                notes.append(f"coord_mode {coord_mode} and has_ref {bool(has_ref)} not read "
                             f"(conventions {self.conventions.name}: the target is absolute, "
                             "in the active user frame, as JAKA's driver code moves)")
            coord_mode, has_ref = 0, False
        mode = check.integer_in("coord_mode", coord_mode, 0, 2)
        _note(notes, cartesian.reading_note(self.conventions, "pose", target_mm))
        # the request's mm: limits and refusals speak its unit, SI from here on
        v = check.speed("mvvelo", mvvelo, self.model.max_tcp_speed * 1000.0, "mm/s",
                        notes=notes) / 1000.0
        a = check.speed("mvacc", mvacc, self.model.max_tcp_accel * 1000.0, "mm/s²",
                        default=self.model.default_tcp_accel * 1000.0, notes=notes) / 1000.0
        ref_q = check.joint_targets("ref_joint", ref_joint, self.model) if has_ref else None

        def start(st: RobotState) -> Result:
            target = cartesian.pose_to_matrix_mm(self.conventions, target_mm)
            if mode == 1:
                _, user = self.backend.frames()
                target = np.linalg.inv(user) @ target
            elif mode == 2:
                target = st.tcp_pose @ target
            planned = check.linear_move_duration(st.tcp_pose, target, v, a, mvvelo,
                                                 mvacc) / self._ratio()
            return self.backend.start_linear_move(target, v, a, ref_q, planned)

        return _with_notes(self._run_move("linear_move", start), notes)

    @_answers
    def jog(self, coord_mode: int, index: int, mvvelo: float, mvacc: float = 0.0) -> Result:
        """Continuous jog (docs/interface.md, "jog"): coord 0 joint / 1 base / 2 tool; index
        0–11, odd = negative; speed ``mvvelo`` (rad/s, or mm/s for X–Z; ``mvacc`` with
        ``jaka_code`` conventions). Kept alive by calling again."""
        coord = check.integer_in("coord_mode", coord_mode, 0, 2)
        idx = check.integer_in("index", index, 0, 11)
        axis, direction = idx // 2, (-1 if idx % 2 else 1)
        notes: list[str] = []
        name, raw = jog_speed_field(self.conventions, mvvelo, mvacc, notes)
        try:
            label, unit, speed = check.jog_speed(self.model, coord, axis, name, raw, notes)
        except CommandRefused as refusal:
            raise explained(refusal, self.conventions) from None
        if self._move_lock.locked():
            raise CommandRefused(Code.BUSY, "jog refused: a blocking move is running")
        if self._twist.session is not None:
            raise CommandRefused(Code.BUSY, "jog refused: a velocity jog is running")
        self._ready()
        session = self._jog.session
        same = session is not None and (session.coord, session.index) == (coord, idx)
        result = self.backend.jog(coord, axis, direction, speed)
        if not result.ok:
            self._jog.clear()
            return result
        self._jog.kick(coord, idx, speed)
        sign = "+" if direction > 0 else "-"
        what = "still jogging" if same else "jogging"
        shown = speed * 1000 if unit == "mm/s" else speed
        return _with_notes(Result.success(f"{what} {label}{sign} at {shown:g} {unit} "
                                          f"(stops {self._jog.timeout:g} s after the last call)"),
                           notes)

    @_answers
    def follow_trajectory(self, trajectory, monitor: Callable[[float, RobotState],
                                                               "str | None"],
                          period: float = 0.02) -> Result:
        """Execute a planned joint trajectory (FollowJointTrajectory). Every ``period`` s
        (of :attr:`clock`) ``monitor(t, state)`` is called with the time since the start; a
        string it returns aborts: the arm is stopped and the result is -12 with that reason.
        Blocks. At a speed ratio r < 1 the trajectory is played r times as fast in time (a
        controller's servo stream is never scaled by its rate, so the driver scales it, for
        every backend alike) and ``monitor`` still sees the trajectory's own time."""
        ratio = self._ratio()
        if ratio != 1.0:
            trajectory = trajectory.time_scaled(ratio)
            original = monitor
            monitor = lambda t, st: original(t * ratio, st)     # noqa: E731
        return self._run_move("trajectory", lambda st: self.backend.start_trajectory(trajectory),
                              monitor, period)

    def _run_move(self, what: str, start: Callable[[RobotState], Result],
                  monitor: "Callable[[float, RobotState], str | None] | None" = None,
                  period: float = 0.02) -> Result:
        """The one place a move is waited for: checks the arm may move, ``start(state)`` asks
        the backend to start it (``Result.value`` = completion, planned duration s), then waits
        for the completion. A move still running ``constants.move_deadline(planned)`` s after
        its start, or one ``monitor`` objects to, is stopped and answered -12; a stop_move or
        fault meanwhile finishes the completion with -12 itself."""
        self._not_jogging()
        with self._blocking_move(what):
            started = start(self._ready())
            if not started.ok:
                return started
            completion, planned = started.value
            deadline = move_deadline(planned)
            clock = self.clock                  # wall time, or the twin's sim time
            t0 = clock.now()
            while True:
                remaining = deadline - (clock.now() - t0)
                # without a monitor there is nothing to do until the move ends or overruns
                wait = min(period, remaining) if monitor is not None else remaining
                result = completion.wait(max(wait, 1e-3), clock)
                if result is not None:
                    return result
                elapsed = clock.now() - t0
                reason = monitor(elapsed, self.backend.state()) if monitor else None
                if reason is None and elapsed > deadline:
                    reason = (f"{what} not in position {elapsed:.2f} s after its start "
                              f"(planned {planned:.2f} s, allowed {deadline:.2f} s); stopped")
                if reason is not None:
                    self.backend.stop_move()
                    completion.wait(1.0, clock)
                    return Result.failure(Code.MOTION_STOPPED, reason)

    def _jog_expired(self) -> None:
        log.info("jog stopped: no jog call for %.1f s", self._jog.timeout)
        self.backend.jog_stop()

    @_answers(react=False)
    def velocity_jog(self, linear: Sequence[float], angular: Sequence[float],
                     in_tool: bool) -> Result:
        """Follow the twist ``linear`` (m/s) + ``angular`` (rad/s), in the base frame or the
        tool frame (``in_tool``), until twists stop coming (the twist watchdog: ``twist_timeout``
        s after the last, the arm ramps to rest). Speeds are checked as jog's: the TCP's at
        most the model's, the rotation's at most the tool rotation cap."""
        v = check.vector("twist.linear", linear, 3)
        w = check.vector("twist.angular", angular, 3)
        check.twist_speeds(self.model, v, w)
        if self._move_lock.locked():
            raise CommandRefused(Code.BUSY, "velocity jog refused: a blocking move is running")
        if self._jog.session is not None:
            raise CommandRefused(Code.BUSY, "velocity jog refused: a jog is running")
        # a controller follows the twist in servo mode (controller/twist_stream.py), entered
        # by the jog's first twist: the next ones find it on
        self._ready(allow_servo_mode=self._twist.session is not None)
        result = self.backend.velocity_jog(np.concatenate([v, w]), bool(in_tool))
        if not result.ok:
            self._twist.clear()
            return result
        self._twist.kick(2 if in_tool else 1, -1, float(np.linalg.norm(v)))
        return result

    def _twist_expired(self) -> None:
        log.info("velocity jog stopping: no twist for %.2f s", self._twist.timeout)
        self.backend.jog_stop()

    @property
    def twist_timeout(self) -> float:
        return self._twist.timeout

    @_answers
    def stop_move(self) -> Result:
        """Decelerate whatever moves; a blocking move returns -12."""
        self._jog.clear()
        self._twist.clear()
        return self.backend.stop_move()

    # ---- speed ratio ---------------------------------------------------------------------
    def _ratio(self) -> float:
        ratio = float(self.backend.speed_ratio())
        return ratio if 0.0 < ratio <= 1.0 else 1.0

    @_answers
    def set_speed_ratio(self, ratio: float) -> Result:
        """Scale joint_move, linear_move, jog, velocity jogs and trajectories by ``ratio``
        in (0, 1], a controller's rapid rate: time × 1/ratio (speeds × ratio, accelerations ×
        ratio²). Servo targets are not scaled. Refused while the arm moves (a running move
        was planned at the old ratio)."""
        r = check.finite("ratio", ratio)
        if not 0.0 < r <= 1.0:
            raise invalid(f"ratio is {r:g}, expected in (0, 1] (1 = full speed)")
        if self.moving:
            raise CommandRefused(Code.BUSY, "speed ratio refused while the arm moves: set it "
                                 "between moves")
        return self.backend.set_speed_ratio(r)

    def speed_ratio(self) -> float:
        """The ratio the robot runs at (the controller's, read back)."""
        return float(self.backend.speed_ratio())

    # ---- what only a twin can do (backend.twin): faults, inputs, its time, the camera -----------
    @property
    def has_twin(self) -> bool:
        """The backend offers what only a twin can do (:class:`~jaka_driver.backend.Twin`):
        the node then serves its fault, input and snapshot services."""
        return self.backend.twin is not None

    def _twin(self, refusal: str) -> Twin:
        """The backend's twin; without one, a -9 refusal saying ``refusal``."""
        twin = self.backend.twin
        if twin is None:
            raise CommandRefused(Code.WRONG_MODE, refusal)
        return twin

    @_answers
    def emergency_stop(self, pressed: bool) -> Result:
        """Press (True) or release (False) the twin's emergency stop. In sim time it happens
        between two cycles, at the sim time the request arrived, as every request does."""
        twin = self._twin(f"emergency stop {NOT_A_TWIN_FAULTS}")
        return twin.press_emergency_stop() if pressed else twin.release_emergency_stop()

    @_answers
    def protective_stop(self) -> Result:
        """A protective stop on the twin, as after a collision; clear_err recovers."""
        return self._twin(f"protective stop {NOT_A_TWIN_FAULTS}").trigger_protective_stop()

    @_answers
    def set_input(self, signal: str, type: int, index: int, value: float) -> Result:  # noqa: A002
        """Drive the twin's input ``index`` (from 0) of ``signal`` on IO ``type`` to ``value``
        as the outside world would (digital non-zero → 1, analog V)."""
        sig = check.io_signal(signal)
        check.io_address(self.model, sig, 0, type, index)
        v = check.io_value(sig, value)
        return self._twin(f"set_input {NOT_A_TWIN_FAULTS}").set_input(sig, int(type),
                                                                       int(index), v)

    @_answers
    def reset_twin(self, joints: Sequence[float] = ()) -> Result:
        """A twin back to a fresh start (:meth:`jaka_driver.backend.Twin.reset`) at ``joints``
        (rad; empty: home); the driver forgets its jogs and servo stream. -9 without a twin.
        In sim time it happens between two cycles, at the sim time the request arrived."""
        twin = self._twin(f"reset {NOT_A_TWIN}")
        q = check.joint_targets("joints", joints, self.model) if len(joints) else None
        self._jog.clear()
        self._twist.clear()
        self._servo.reset()
        if self._increments is not None:
            self._increments.reset()
        return twin.reset(q)

    @_answers
    def pause_twin(self, pause: bool) -> Result:
        """Stop (True) or run on (False) the twin's simulated time."""
        twin = self._twin(NOT_A_TWIN)
        return twin.pause() if pause else twin.unpause()

    @_answers
    def step_twin(self, cycles: int) -> Result:
        """While paused, run ``cycles`` (1–:data:`MAX_STEP`) 8 ms cycles; ``Result.value`` is the
        sim time (s) after them."""
        twin = self._twin(NOT_A_TWIN)
        if not 1 <= cycles <= MAX_STEP:
            raise invalid(f"cycles is {cycles}, expected 1–{MAX_STEP}")
        return twin.step(cycles)

    def camera(self, width: int, height: int) -> Camera:
        """The twin's offscreen camera (:meth:`jaka_driver.backend.Twin.camera`: made in the
        thread that renders with it; raises ImportError or RuntimeError where rendering is
        unavailable, RuntimeError without a twin)."""
        twin = self.backend.twin
        if twin is None:
            raise RuntimeError(f"no camera: {NOT_A_TWIN_FAULTS}")
        return twin.camera(width, height)

    # ---- what the backend reports of itself ---------------------------------------------------
    def frames(self) -> tuple[np.ndarray, np.ndarray]:
        """The active (tool, user frame) 4x4 poses, m: flange → tool, base → user frame."""
        return self.backend.frames()

    def describe(self) -> dict:
        """Facts for diagnostics (:meth:`Backend.describe`)."""
        return self.backend.describe()

    @_answers
    def servo_move_enable(self, enable: bool) -> Result:
        """Enter or leave servo mode."""
        if enable:
            if self._move_lock.locked():
                raise CommandRefused(Code.BUSY, "servo mode refused: a blocking move is running")
            self._not_jogging()
            self._ready(allow_servo_mode=True)
        self._servo.reset()
        if self._increments is not None:
            self._increments.reset()
        return self.backend.servo_enable(bool(enable))

    @_answers(react=False)
    def servo_j(self, pose: Sequence[float]) -> Result:
        """Joint target for the next 8 ms cycle: absolute (rad), or with servo increments
        (``conventions``) an increment (rad) of the last target."""
        if self._increments is not None:
            return self._increments.servo_j(check.vector("pose", pose))
        return self._servo_j(pose)

    def _servo_j(self, pose: Sequence[float], increment: np.ndarray | None = None) -> Result:
        """Absolute joint target (rad) for the next 8 ms cycle (``increment``: the increment it
        came from, handed on to the backend)."""
        q = check.joint_targets("pose", pose, self.model)
        st = self._ready(servo=True)
        reference, gap = self._servo.reference(st.joint_position)
        check.servo_step(self.model, q, reference)
        result = self.backend.servo_j(q, increment)
        if result.ok:
            self._servo.accepted(q)
        return _with_gap(result, gap, self._servo.timeout)

    @_answers(react=False)
    def servo_j_target(self, pose: Sequence[float]) -> Result:
        """An absolute joint target (rad) under servo_j's rules and path, whatever
        ``servo_increment`` says: the joint stream topics' (their messages are positions)."""
        return self._servo_j(pose)

    @_answers(react=False)
    def servo_p(self, pose: Sequence[float]) -> Result:
        """TCP target for the next cycle: absolute (m + RPY rad, active user frame), or with
        servo increments (``conventions``) an increment (mm, RPY rad) of the last target."""
        if self._increments is not None:
            return self._increments.servo_p(check.vector("pose", pose))
        return self._servo_p(pose)

    def _servo_p(self, pose: Sequence[float], increment: np.ndarray | None = None) -> Result:
        """Absolute TCP target (m + RPY rad, active user frame) for the next cycle
        (``increment``: m + RPY rad it came from, handed on to the backend)."""
        p = check.vector("pose", pose)
        st = self._ready(servo=True)
        target = np.eye(4)
        target[:3, :3] = rpy_to_matrix(*p[3:])
        target[:3, 3] = p[:3]
        _, gap = self._servo.reference(st.joint_position)
        if gap is None:   # after a gap the arm held still: the step is from where it stands
            check.servo_tcp_step(self.model, target, st.tcp_pose)
        result = self.backend.servo_p(target, increment)
        if result.ok:
            # the joint target, when the backend solved the IK itself (the twin), else the
            # measured joints: the reference for a servo_j that may follow
            self._servo.accepted(result.value if result.value is not None
                                 else st.joint_position)
        return _with_gap(result, gap, self._servo.timeout)

    # ---- frames, payload, settings --------------------------------------------------------
    @_answers
    def set_toolframe(self, pose: Sequence[float], tool_num: int) -> Result:
        """Tool ``tool_num`` (1–11, 0 = flange) = ``pose`` (mm + rotvec, flange frame)."""
        num = check.integer_in("tool_num", tool_num, 0, 11)
        frame = np.eye(4) if num == 0 else check.frame_pose(pose, check.TOOL_REACH_MM)
        return self.backend.set_tool_frame(num, frame)

    @_answers
    def set_userframe(self, pose: Sequence[float], user_num: int) -> Result:
        """User frame ``user_num`` (1–10, 0 = base) = ``pose`` (mm + rotvec, base frame)."""
        num = check.integer_in("user_num", user_num, 0, 10)
        frame = np.eye(4) if num == 0 else check.frame_pose(pose, check.USER_REACH_MM)
        return self.backend.set_user_frame(num, frame)

    @_answers
    def set_payload(self, tool_num: int, mass: float, xc: float, yc: float, zc: float) -> Result:
        """Payload ``mass`` kg at (xc, yc, zc) mm in the flange frame; activates tool_num."""
        num = check.integer_in("tool_num", tool_num, 0, 11)
        m, centroid = check.payload(self.model, mass, (("xc", xc), ("yc", yc), ("zc", zc)))
        return self.backend.set_payload(num, m, centroid)

    @_answers
    def drag_mode(self, on: bool) -> Result:
        """Free drive on or off; refused in servo mode or while moving."""
        if on:
            if self.moving:
                raise CommandRefused(Code.BUSY, "drag mode refused while the arm moves")
            self._ready()
        return self.backend.set_drag_mode(bool(on))

    @_answers
    def set_collisionlevel(self, is_enable: bool, value: int) -> Result:
        """Detection off, or ``value`` 10–100 → level 1–4 (≤25, ≤50, ≤75, ≤100)."""
        if not is_enable:
            return self.backend.set_collision_level(0)
        v = check.integer_in("value", value, 10, 100)
        level = 1 if v <= 25 else 2 if v <= 50 else 3 if v <= 75 else 4
        return self.backend.set_collision_level(level)

    @_answers
    def set_io(self, signal: str, type: int, index: int, value: float) -> Result:  # noqa: A002
        """Set an output (docs/interface.md, "set_io"); digital non-zero → 1."""
        sig = check.io_signal(signal)
        check.io_address(self.model, sig, 1, type, index)
        v = check.io_value(sig, value, analog_limit=check.ANALOG_LIMIT)
        return self.backend.set_io(sig, int(type), int(index), v)

    @_answers
    def get_io(self, signal: str, path: int, type: int, index: int) -> Result:  # noqa: A002
        """Read an IO point (docs/interface.md, "get_io"); value in ``Result.value``."""
        sig = check.io_signal(signal)
        check.io_address(self.model, sig, path, type, index)
        return self.backend.get_io(sig, int(path), int(type), int(index))

    @_answers
    def clear_err(self) -> Result:
        """Clear a collision / protective stop / error; refused under e-stop."""
        if self.backend.state().emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed: release it "
                                 "first")
        self._jog.clear()
        return self.backend.clear_error()

    @_answers
    def set_power(self, on: bool) -> Result:
        if not on:
            self._jog.clear()
            self._twist.clear()
        elif self.backend.state().emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed")
        return self.backend.set_power(bool(on))

    @_answers
    def set_enabled(self, on: bool) -> Result:
        st = self.backend.state()
        if on and st.emergency_stop:
            raise CommandRefused(Code.EMERGENCY_STOP, "emergency stop is pressed")
        if on and not st.powered:
            raise CommandRefused(Code.NOT_POWERED, "robot is not powered (call power)")
        if not on:
            self._jog.clear()
        return self.backend.set_enabled(bool(on))

    # ---- kinematics ---------------------------------------------------------------------------
    @_answers
    def get_fk(self, joint: Sequence[float]) -> Result:
        """Pose (mm + rotvec, or RPY with ``jaka_code`` conventions) of the active tool in the
        active user frame at ``joint``."""
        q = check.vector("joint", joint)
        result = self.backend.forward_kinematics(q)
        if not result.ok:
            return result
        return Result.success(result.message,
                              cartesian.matrix_to_pose_mm(self.conventions, result.value))

    @_answers
    def get_ik(self, ref_joint: Sequence[float], cartesian_pose: Sequence[float]) -> Result:
        """Joints (rad) nearest ``ref_joint`` reaching ``cartesian_pose`` (mm + rotvec, or RPY
        with ``jaka_code`` conventions); an empty ``ref_joint`` seeds from the current
        joints."""
        if len(ref_joint) == 0:
            ref = self.backend.state().joint_position
        else:
            ref = check.vector("ref_joint", ref_joint)
        pose = check.vector("cartesian_pose", cartesian_pose)
        target = cartesian.pose_to_matrix_mm(self.conventions, pose)
        notes: list[str] = []
        _note(notes, cartesian.reading_note(self.conventions, "cartesian_pose", pose))
        result = self.backend.inverse_kinematics(target, ref)
        if not result.ok:
            return _with_notes(result, notes)
        return _with_notes(Result.success(result.message, [float(x) for x in result.value]),
                           notes)


def _note(notes: list[str], note: str | None) -> None:
    if note:
        notes.append(note)


def _with_notes(result: Result, notes: list[str]) -> Result:
    if not notes:
        return result
    return Result(result.code, f"{result.message} ({'; '.join(notes)})", result.value)


def _with_gap(result: Result, gap, timeout: float) -> Result:
    if gap is None:
        return result
    return Result(result.code, f"{result.message} (the servo stream had stopped for "
                  f"{gap:.2f} s, timeout {timeout:g} s: the arm held its last target)",
                  result.value)
