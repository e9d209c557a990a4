"""What a JAKA controller refuses in the arm's state, and what it reads of the arm (a part of
:class:`~.twin_controller.TwinController`): the state refusals every motion command goes
through (:meth:`ArmRules.require_can_move`, ``require_still``, the joint limits), power and
enable, the commanded setpoint, the arm's own kinematics. SI units; a refusal raises
:class:`~.replies.Rejected` with the controller's message.
"""
from __future__ import annotations

import threading
from typing import Optional

import numpy as np

from ..backend import Backend, Programs, ProgramState, RobotState, Twin
from ..common.joint_limits import outside_limits
from ..common.models import RobotModel
from .replies import ERROR_REFUSED, Rejected


class ArmRules:
    """The controller's state refusals, power and the arm's readings, on ``self.backend``."""

    # set by TwinController.__init__
    backend: Backend
    twin: Twin
    model: RobotModel
    lock: threading.RLock
    moving: bool

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
                         program_step: bool = False, state: Optional[RobotState] = None
                         ) -> None:
        """Refuse ``what`` unless the arm may move: no stop, powered, enabled, no protective
        stop, not in drag or (unless ``servo_ok``) servo mode, and no program running or paused
        (unless this is a step of it). ``state``: the state the request already read, else
        read now."""
        if not program_step and self.program_running():
            raise Rejected(f"{what}: a program is {self.programs.status().state.word} "
                           "(stop_program first)")
        t = state if state is not None else self.state()
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
