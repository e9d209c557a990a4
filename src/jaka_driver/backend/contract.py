"""The backend contract: what the MuJoCo twin and the real-controller backend both implement.

The node never asks which backend it has. Requests reach a backend through
:class:`jaka_driver.driver.RobotDriver`, which has already validated them (lengths, finiteness,
ranges, joint limits), converted units (SI inside: metres, radians, 4x4 poses) and checked the
robot state (e-stop, power, modes, busy). A backend therefore implements capabilities, not
policy; anything it cannot do it answers with a failure :class:`Result`, never silently.

Frames: a Cartesian pose handed to or returned by a backend is a 4x4 homogeneous matrix in
metres. Unless a method says otherwise, it is the pose of the *active tool* expressed in the
*active user frame* (docs/interface.md, "Units and frames").

Concurrency: every method may be called from any thread (rospy serves each service connection
in its own thread). No method blocks for the length of a motion: moves are *started* and
answer a completion with the planned duration; the one place that waits for them, and stops
one that overruns, is :class:`jaka_driver.driver.RobotDriver`. ``state()`` never blocks.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from typing import TYPE_CHECKING, Optional

import numpy as np

from ..common.models import RobotModel
from ..common.results import Code, Result
from .clock import WallClock
from .cameras import HOW_TO_ADD, Cameras, NoCameras
from .force import Force, NoForceSensor
from .programs import Programs
from .recording import NoRecording, Recording
from .tool_io import NoToolIO, ToolIO
from .robot_state import RobotState
from .twin import Twin

if TYPE_CHECKING:
    from ..common.installation import Installation
    from ..motion.servo_filters import ServoFilterSpec
    from ..motion.trajectory import JointTrajectory


def not_available(what: str) -> Result:
    """The answer of a backend that cannot do ``what`` (-9)."""
    return Result.failure(Code.WRONG_MODE, f"{what} is not available on this backend")


class Backend(ABC):
    """One robot: a twin or a controller connection."""

    #: What only a digital twin can do (:class:`~.twin.Twin`: faults, simulated inputs, the
    #: camera, what a controller built on the twin reads), or None: the one capability a backend
    #: offers besides this contract. Ask for it; never ask which backend this is.
    twin: Optional[Twin] = None
    #: Robot programs (:class:`~.programs.Programs`: load, play, pause, resume, stop, state,
    #: user variables), or None where the backend has none. A controller runs its own; the
    #: twin runs the driver's program engine, whose steps go through the executor the driver
    #: binds (:meth:`Programs.bind`). Ask for it; never ask which backend this is.
    programs: Optional[Programs] = None

    #: The flange force/torque sensor and force control on it (:class:`~.force.Force`), never
    #: None: an arm without a sensor refuses every force request and says why.
    force: Force = NoForceSensor("no force/torque sensor: this backend drives none")
    #: Trajectory recording and its replay programs (:class:`~.recording.Recording`), never
    #: None: a backend that cannot record refuses every request and says why.
    recording: Recording = NoRecording("trajectory recording is not available on this backend")

    #: The tool connector (:class:`~.tool_io.ToolIO`: tool power, pin modes, RS485 channels,
    #: frames, Modbus signals), never None: a backend without one refuses with -9.
    tool_io: ToolIO = NoToolIO("no tool connector: this backend drives none")

    #: The cameras (:class:`~.cameras.Cameras`), never None: a backend without any refuses
    #: every camera request and says why.
    cameras: Cameras = NoCameras(f"no camera on this backend ({HOW_TO_ADD})")

    def __init__(self, model: RobotModel):
        self.model = model

    # ---- life cycle -------------------------------------------------------------------
    @abstractmethod
    def start(self) -> None:
        """Bring the robot up (twin: physics thread, powered and enabled; controller:
        connect, power on, enable). Returns once a first state sample exists."""

    @abstractmethod
    def shutdown(self) -> None:
        """Stop motion, threads and connections. Idempotent."""

    @abstractmethod
    def state(self) -> RobotState:
        """The latest sample; never blocks."""

    #: The backend's time (:mod:`.clock`): every timeout the driver keeps runs on it. The
    #: wall clock, unless a twin owns time (sim_time; then ``RobotState.stamp`` is sim time).
    clock = WallClock()

    @abstractmethod
    def wait_for_sample(self, after: float, timeout: float) -> bool:
        """Block until a sample stamped later than ``after`` (s, as ``RobotState.stamp``)
        exists, at most ``timeout`` s; True if one does. The new sample wakes the wait (the
        twin's cycle, a controller's status packet): the node publishes each sample the moment
        it exists, with no clock of its own."""

    def states_since(self, after: float) -> list[RobotState]:
        """The samples stamped later than ``after`` (s), oldest first — every one a backend
        still holds, so a reader that fell behind misses none (the twin keeps a few hundred
        cycles). Default: the latest, if it is newer."""
        st = self.state()
        return [st] if st.stamp > after else []

    def describe(self) -> dict:
        """Facts for diagnostics: ``backend`` (what it is, for people), the model, and each
        backend's own (version, connection, rates)."""
        return {"model": self.model.name}

    # ---- power --------------------------------------------------------------------------
    @abstractmethod
    def set_power(self, on: bool) -> Result:
        """Power the arm on or off."""

    @abstractmethod
    def set_enabled(self, on: bool) -> Result:
        """Enable (servos hold the arm) or disable it."""

    # ---- motion ---------------------------------------------------------------------------
    @abstractmethod
    def start_joint_move(self, q_target: np.ndarray, speed: float, accel: float,
                         duration: Optional[float] = None) -> Result:
        """Start a synchronised joint move to ``q_target`` (rad) with peak speed ``speed``
        (rad/s) and acceleration ``accel`` (rad/s²), both already clamped to the model, taking
        ``duration`` s: the driver's plan of it (:func:`jaka_driver.driver.checks.
        joint_move_duration`, the law of :func:`jaka_driver.motion.profiles.joint_move_profile`
        from where the arm stands, stretched to ``mvtime``); None: the fastest by the same
        law. A backend never refuses a duration: the driver did. Returns at once;
        ``Result.value`` is
        ``(completion, planned_duration_s)``: the :class:`jaka_driver.backend.completion.Completion`
        finishes with success once in position (``constants.IN_POSITION``), or -12 if stopped.
        ``speed`` and ``accel`` are the request's; the backend runs them at its speed ratio,
        and ``duration`` is already the plan at that ratio.
        :class:`jaka_driver.driver.RobotDriver` does the waiting (and stops an overrun)."""

    @abstractmethod
    def start_linear_move(self, target: np.ndarray, speed: float, accel: float,
                          ref_q: Optional[np.ndarray] = None,
                          duration: Optional[float] = None) -> Result:
        """Start a straight-line TCP move to ``target`` (4x4, active tool in the active user
        frame, m) at ``speed`` m/s and ``accel`` m/s²; ``ref_q`` seeds the IK; ``duration`` (s)
        is the driver's plan of it (:func:`jaka_driver.motion.linear_path.line_duration`), for
        a backend that does not time the line itself (None: the same law from where the arm
        stands). The whole path is checked before anything moves (-4 if unreachable). Returns
        at once, like :meth:`start_joint_move`."""

    def start_circular_move(self, mid: np.ndarray, end: np.ndarray, speed: float, accel: float,
                            turns: float = 0.0, mode: int = 0,
                            duration: Optional[float] = None) -> Result:
        """Start a circular TCP move from where the TCP stands through ``mid`` to ``end`` (4x4,
        active tool in the active user frame, m) at ``speed`` m/s and ``accel`` m/s², ``turns``
        more times round (whole or partial) with attitude rule ``mode`` 0–3 — JAKA's ``movc``,
        whose rules :mod:`jaka_driver.motion.circular_path` defines; ``duration`` (s) is the
        driver's plan of it (:func:`jaka_driver.motion.circular_path.circle_duration`). The
        whole arc is checked before anything moves (-2 collinear points, -4 out of reach).
        Returns at once, like :meth:`start_joint_move`. Default: -9 (not available)."""
        return not_available("circular_move")

    def pause_motion(self) -> Result:
        """Bring the running move (joint, linear, circular) to rest on its own path, as a
        controller's program pause does, and hold it there; its completion stays open.
        Success also when nothing moves. Default: -9 (not available)."""
        return not_available("pausing a move")

    def resume_motion(self) -> Result:
        """Continue a move :meth:`pause_motion` paused, along the rest of its path to the end
        it was planned to. Default: -9 (not available)."""
        return not_available("resuming a move")

    def set_servo_filter(self, spec: "ServoFilterSpec") -> Result:
        """Filter servo targets (servo_j, servo_p, the joint stream) with ``spec``
        (:mod:`jaka_driver.motion.servo_filters`, already checked), from the next servo mode
        on, as JAKA's ``set_servo_move_filter``. Default: -9 (not available)."""
        return not_available("servo filters")

    @abstractmethod
    def start_trajectory(self, trajectory: "JointTrajectory") -> Result:
        """Start following ``trajectory`` (joint samples every 8 ms from the current setpoint,
        :class:`jaka_driver.motion.trajectory.JointTrajectory`) and return at once;
        ``Result.value`` is ``(completion, duration_s)`` where ``completion``
        (:class:`jaka_driver.backend.completion.Completion`) finishes with success once in position,
        or -12 if stopped. :meth:`stop_move` stops it."""

    @abstractmethod
    def jog(self, coord: int, axis: int, direction: int, speed: float) -> Result:
        """Start (or keep) a continuous jog: ``coord`` 0 joint, 1 base, 2 tool; ``axis`` 0–5
        (joint, or X Y Z RX RY RZ); ``direction`` ±1; ``speed`` rad/s or m/s. Returns at once;
        the caller (RobotDriver) owns the 3 s watchdog and calls :meth:`jog_stop`."""

    @abstractmethod
    def jog_stop(self) -> Result:
        """Decelerate a jog (a velocity jog too) to rest."""

    @abstractmethod
    def velocity_jog(self, twist: np.ndarray, in_tool: bool) -> Result:
        """Start (or keep following) a velocity jog: the TCP moves at ``twist`` (vx vy vz m/s,
        wx wy wz rad/s), in the base frame or the tool frame (``in_tool``), ramped at the jog's
        accelerations and slowed before joint limits and singularities by the one law of
        :mod:`jaka_driver.motion.velocity_jog`, at the speed ratio. Returns at once (success:
        ``value`` says why the last step was slowed, None when it was not); the caller
        (RobotDriver) owns its short watchdog and calls :meth:`jog_stop`."""

    # ---- speed ratio ----------------------------------------------------------------------
    @abstractmethod
    def set_speed_ratio(self, ratio: float) -> Result:
        """Scale the moves the robot plans — joint and linear moves, jogs, velocity jogs —
        as a controller's rapid rate does: time × 1/``ratio`` (speeds × ratio, accelerations
        × ratio²), ``ratio`` in (0, 1] (checked by the driver). Servo targets are not scaled;
        trajectories are scaled by the driver (they are servo streams on a controller)."""

    @abstractmethod
    def speed_ratio(self) -> float:
        """The ratio the robot runs at now (a controller's as it reports it)."""

    @abstractmethod
    def servo_enable(self, on: bool) -> Result:
        """Enter or leave servo mode."""

    @abstractmethod
    def servo_j(self, q_target: np.ndarray, increment: Optional[np.ndarray] = None) -> Result:
        """Absolute joint target (rad) to reach within one 8 ms cycle (already speed-checked).
        ``increment`` (rad): when the client sent an increment (servo increments), the one
        ``q_target`` was computed from; a backend may hand the controller the increment
        instead, as JAKA's SDK does, or ignore it."""

    @abstractmethod
    def servo_p(self, target: np.ndarray, increment: Optional[np.ndarray] = None) -> Result:
        """Absolute TCP target (4x4, active tool in active user frame, m) for one cycle;
        -4 when there is no IK solution, -2 when it implies over-speed. ``increment``
        (m + RPY rad): as for :meth:`servo_j`."""

    @abstractmethod
    def stop_move(self) -> Result:
        """Decelerate any motion to rest; the completion of a started move finishes with -12."""

    # ---- frames, payload, settings ----------------------------------------------------------
    @abstractmethod
    def set_tool_frame(self, tool_id: int, pose: np.ndarray) -> Result:
        """Store tool ``tool_id`` (1–11; 0 = the flange) as ``pose`` (flange→tool, 4x4, m) and
        make it the active tool."""

    @abstractmethod
    def set_user_frame(self, user_id: int, pose: np.ndarray) -> Result:
        """Store user frame ``user_id`` (1–10; 0 = the base) as ``pose`` (base→user, 4x4, m)
        and make it the active user frame."""

    @abstractmethod
    def frames(self) -> tuple[np.ndarray, np.ndarray]:
        """(active tool pose flange→tool, active user frame pose base→user), 4x4, metres."""

    @abstractmethod
    def set_payload(self, tool_id: int, mass: float, centroid: np.ndarray) -> Result:
        """Payload ``mass`` (kg) at ``centroid`` (m, flange frame); activates ``tool_id``."""

    @abstractmethod
    def set_drag_mode(self, on: bool) -> Result:
        """Free drive on or off."""

    def collision_level(self) -> Result:
        """The collision sensitivity level the arm holds (0 off, 1–5), in ``Result.value``:
        the controller's read back. Default: -9."""
        return not_available("reading the collision level")

    def set_installation_angle(self, mounting: "Installation") -> Result:
        """Mount the arm as ``mounting`` says (:class:`~jaka_driver.common.installation.
        Installation`, checked): gravity turns with it, the base stays the frame of every pose.
        Default: -9 (not available)."""
        return not_available("the installation angle")

    def installation_angle(self) -> Result:
        """How the arm is mounted, as the arm reports it: ``Result.value`` an
        :class:`~jaka_driver.common.installation.Installation`. Default: -9."""
        return not_available("the installation angle")

    @abstractmethod
    def set_collision_level(self, level: int) -> Result:
        """Collision sensitivity level 0 (off) or 1–4 (25/50/75/100 N)."""

    @abstractmethod
    def set_io(self, signal: str, io_type: int, index: int, value: float) -> Result:
        """Set output ``index`` of ``signal`` ("digital"/"analog") on ``io_type`` (0 cabinet,
        1 tool, 2 extension). Digital values are 0/1."""

    @abstractmethod
    def get_io(self, signal: str, path: int, io_type: int, index: int) -> Result:
        """Read an input (``path`` 0) or output (1); the value is in ``Result.value``."""

    @abstractmethod
    def clear_error(self) -> Result:
        """Clear a collision, protective stop or error; the arm returns to ready."""

    # ---- kinematics ----------------------------------------------------------------------------
    @abstractmethod
    def forward_kinematics(self, q: np.ndarray) -> Result:
        """Pose (4x4, m) of the active tool in the active user frame at joints ``q`` (rad)."""

    @abstractmethod
    def inverse_kinematics(self, target: np.ndarray, ref_q: np.ndarray) -> Result:
        """Joints (rad) reaching ``target`` (4x4, active tool in active user frame), nearest
        ``ref_q``; -4 when unreachable."""
