"""The door of the driver: every service request passes through :class:`RobotDriver`.

Order of checks (docs/design.md, "The picture"): validate the request → check the robot state →
let the backend plan the whole motion → only then move. A refused command changes nothing.

The methods take the values of the service requests in their own units (docs/interface.md,
"Units and frames": rad, mm, rotation vectors; servo_p m + RPY — or, built with
``conventions=JAKA_CODE``, those of JAKA's driver code: jaka_driver.conventions) and answer a
:class:`Result`; they never raise. They are safe to call from many threads at once, as rospy does.

RobotDriver is assembled from parts, one per subject, each handed the door's core
(:class:`~.door.Door`: the backend, the motion lock, the watchdogs, the state checks) and
passed each request of its subject: moves (:mod:`.moves`), jogs (:mod:`.jogs`), servo mode and
the servo filter (:mod:`.servo_requests`), settings and kinematics (:mod:`.arm_settings`).
Each facet of the backend has its one door, offered as an attribute: the twin's own requests
``driver.twin`` (:mod:`.twin_requests`), robot programs ``driver.programs``
(:mod:`.program_requests`), the force/torque sensor and force control ``driver.force``
(:mod:`.force_requests`), trajectory recording ``driver.recording`` (:mod:`.recording_requests`),
the tool connector ``driver.tool_io`` (:mod:`.tool_io_requests`) and the gripper on it
``driver.gripper`` (:mod:`.gripper_requests`), the cameras ``driver.cameras``
(:mod:`.camera_requests`). What a request does is documented in its part.
"""
from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from ..backend import Backend
from ..backend.robot_state import RobotState
from ..common.results import Result
from ..conventions import DOCUMENT, Conventions
from ..devices import ConnectorSetup
from ..programs.executor import MoveHold
from .arm_settings import SettingRequests
from .camera_requests import CameraRequests
from .door import Door
from .force_requests import ForceRequests
from .gripper_requests import GripperRequests, NoGripper
from .jogs import JogRequests
from .moves import MoveRequests
from .program_requests import ProgramRequests
from .program_steps import ProgramSteps
from .recording_requests import RecordingRequests
from .servo_requests import ServoRequests
from .tool_io_requests import ToolIORequests
from .twin_requests import TwinRequests


class RobotDriver:
    """Validation, state checks and watchdogs in front of a :class:`Backend`."""

    def __init__(self, backend: Backend, *, jog_timeout: float = 3.0, servo_timeout: float = 0.1,
                 servo_increment: bool = False, conventions: Conventions = DOCUMENT,
                 twist_timeout: float = 0.1, gripper: str = "none",
                 gripper_setup=None):
        """``conventions``: how requests are read where JAKA's document and JAKA's driver code
        differ (jaka_driver.conventions); ``servo_increment`` adds servo increments to them
        (servo_j / servo_p take increments, as JAKA's driver code sends them).
        ``twist_timeout``: s after the last twist before a velocity jog stops.
        ``gripper``: the gripper on the tool connector (driver/gripper_requests.py: ``none``
        or ``dh_pgi``), hung on it as ``gripper_setup`` (a devices.ConnectorSetup) says."""
        self.backend = backend
        self.model = backend.model
        #: every timeout runs on the backend's time (wall, or the twin's sim time)
        self.clock = backend.clock
        self.conventions = conventions.with_servo_increment(servo_increment)
        self._door = door = Door(backend, self.conventions, jog_timeout=jog_timeout,
                                 servo_timeout=servo_timeout, twist_timeout=twist_timeout)
        self._moves = MoveRequests(door)
        self._jogs = JogRequests(door)
        self._servo = ServoRequests(door)
        #: robot programs (driver/program_requests.py): load, play, pause, resume, stop, variables
        self.programs = ProgramRequests(door)
        self._settings = SettingRequests(door)
        #: what only a twin can do (driver/twin_requests.py): -9 without a twin
        self.twin = TwinRequests(door, self._servo.forget)
        #: the force/torque sensor and force control (driver/force_requests.py)
        self.force = ForceRequests(door, self._moves.run_move)
        #: trajectory recording and its replay programs (driver/recording_requests.py)
        self.recording = RecordingRequests(door)
        #: the tool connector: supply, pins, RS485 channels, frames, signals
        #: (driver/tool_io_requests.py)
        self.tool_io = ToolIORequests(door)
        #: the gripper on the tool connector (driver/gripper_requests.py)
        self.gripper = NoGripper() if gripper == "none" else GripperRequests(
            door, gripper, gripper_setup or ConnectorSetup())
        if self.gripper.absent is None:
            # a twin's reset switches the tool supply off and deletes the signals: the gripper
            # is set up again as at the node's start
            self.twin.after_reset(self.gripper.set_up)
        #: the twin's cameras (driver/camera_requests.py)
        self.cameras = CameraRequests(door)
        if backend.programs is not None:     # a program's steps come through this door
            backend.programs.bind(ProgramSteps(self))

    # ---- life cycle and what the backend reports -----------------------------------------
    def start(self) -> None:
        self.backend.start()

    def shutdown(self) -> None:
        self._door.close()
        self.backend.shutdown()

    def state(self) -> RobotState:
        return self.backend.state()

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        """See :meth:`Backend.wait_for_sample`."""
        return self.backend.wait_for_sample(after, timeout)

    def states_since(self, after: float) -> list[RobotState]:
        """See :meth:`Backend.states_since`."""
        return self.backend.states_since(after)

    def frames(self) -> tuple[np.ndarray, np.ndarray]:
        """The active (tool, user frame) 4x4 poses, m: flange → tool, base → user frame."""
        return self.backend.frames()

    def describe(self) -> dict:
        """Facts for diagnostics (:meth:`Backend.describe`)."""
        return self.backend.describe()

    @property
    def moving(self) -> bool:
        """A blocking move, a jog or a velocity jog of this driver runs."""
        return self._door.moving

    @property
    def twist_timeout(self) -> float:
        return self._door.twist.timeout

    # ---- moves: MoveRequests (moves.py) ----------------------------------------------------
    def joint_move(self, pose: Sequence[float], mvvelo: float, mvacc: float,
                   mvtime: float = 0.0, hold: MoveHold | None = None) -> Result:
        return self._moves.joint_move(pose, mvvelo, mvacc, mvtime, hold)

    def linear_move(self, pose: Sequence[float], mvvelo: float, mvacc: float,
                    coord_mode: int = 0, has_ref: bool = False,
                    ref_joint: Sequence[float] = (), hold: MoveHold | None = None) -> Result:
        return self._moves.linear_move(pose, mvvelo, mvacc, coord_mode, has_ref, ref_joint, hold)

    def circular_move(self, pose_mid: Sequence[float], pose_end: Sequence[float],
                      mvvelo: float, mvacc: float, turns: float = 0.0,
                      attitude_mode: int = 0, coord_mode: int = 0,
                      hold: MoveHold | None = None) -> Result:
        return self._moves.circular_move(pose_mid, pose_end, mvvelo, mvacc, turns,
                                         attitude_mode, coord_mode, hold)

    def follow_trajectory(self, trajectory,
                          monitor: Callable[[float, RobotState], "str | None"],
                          period: float = 0.02, start_at: float | None = None) -> Result:
        return self._moves.follow_trajectory(trajectory, monitor, period, start_at)

    def stop_move(self) -> Result:
        return self._moves.stop_move()

    # ---- jogs: JogRequests (jogs.py) ---------------------------------------------------------
    def jog(self, coord_mode: int, index: int, mvvelo: float, mvacc: float = 0.0) -> Result:
        return self._jogs.jog(coord_mode, index, mvvelo, mvacc)

    def velocity_jog(self, linear: Sequence[float], angular: Sequence[float],
                     in_tool: bool) -> Result:
        return self._jogs.velocity_jog(linear, angular, in_tool)

    # ---- servo mode, its targets, the filter: ServoRequests (servo_requests.py) ---------------
    def servo_move_enable(self, enable: bool) -> Result:
        return self._servo.servo_move_enable(enable)

    def servo_j(self, pose: Sequence[float]) -> Result:
        return self._servo.servo_j(pose)

    def servo_j_target(self, pose: Sequence[float]) -> Result:
        return self._servo.servo_j_target(pose)

    def servo_p(self, pose: Sequence[float]) -> Result:
        return self._servo.servo_p(pose)

    def set_servo_filter(self, filter_type: int, **params: float) -> Result:
        """The filter and its parameters by name (:meth:`.servo_requests.ServoRequests.
        set_servo_filter`)."""
        return self._servo.set_servo_filter(filter_type, **params)

    # ---- settings and kinematics: SettingRequests (arm_settings.py) --------------------------
    def set_speed_ratio(self, ratio: float) -> Result:
        return self._settings.set_speed_ratio(ratio)

    def speed_ratio(self) -> float:
        return self._settings.speed_ratio()

    def set_toolframe(self, pose: Sequence[float], tool_num: int) -> Result:
        return self._settings.set_toolframe(pose, tool_num)

    def set_userframe(self, pose: Sequence[float], user_num: int) -> Result:
        return self._settings.set_userframe(pose, user_num)

    def set_payload(self, tool_num: int, mass: float, xc: float, yc: float, zc: float) -> Result:
        return self._settings.set_payload(tool_num, mass, xc, yc, zc)

    def drag_mode(self, on: bool) -> Result:
        return self._settings.drag_mode(on)

    def set_collisionlevel(self, is_enable: bool, value: int) -> Result:
        return self._settings.set_collisionlevel(is_enable, value)

    def collision_level(self) -> Result:
        return self._settings.collision_level()

    def set_installation_angle(self, tilt_x: float, rot_z: float) -> Result:
        return self._settings.set_installation_angle(tilt_x, rot_z)

    def installation_angle(self) -> Result:
        return self._settings.installation_angle()

    def set_io(self, signal: str, type: int, index: int, value: float) -> Result:  # noqa: A002
        return self._settings.set_io(signal, type, index, value)

    def get_io(self, signal: str, path: int, type: int, index: int) -> Result:  # noqa: A002
        return self._settings.get_io(signal, path, type, index)

    def clear_err(self) -> Result:
        return self._settings.clear_err()

    def set_power(self, on: bool) -> Result:
        return self._settings.set_power(on)

    def set_enabled(self, on: bool) -> Result:
        return self._settings.set_enabled(on)

    def get_fk(self, joint: Sequence[float]) -> Result:
        return self._settings.get_fk(joint)

    def get_ik(self, ref_joint: Sequence[float], cartesian_pose: Sequence[float]) -> Result:
        return self._settings.get_ik(ref_joint, cartesian_pose)
