"""A JAKA controller's servo mode (a part of :class:`~.twin_controller.TwinController`):
entering and leaving it, and ``servo_j`` / ``servo_p`` set-points reached in ``stepNum`` 8 ms
cycles on the twin's servo ramp, each within the joint speed limits. SI units.
"""
from __future__ import annotations

import logging
import threading
from typing import Optional

import numpy as np

from ..backend import Backend, RobotState, Twin
from ..common.constants import SERVO_CYCLE
from ..common.joint_limits import fastest_step
from ..common.models import RobotModel
from .replies import Rejected

log = logging.getLogger(__name__)

#: What fw 1.5.14 answers to servo_j outside servo mode (recorded, spelling included).
ERROR_NOT_IN_SERVO_MODE = "-1"
NOT_IN_SERVO_MODE = "{} command can only be excuted in servo move mode"


class ServoMode:
    """Servo mode and its set-points."""

    # set by TwinController.__init__
    backend: Backend
    twin: Twin
    model: RobotModel
    lock: threading.RLock
    moving: bool

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

    def servo_reference(self, what: str, state: Optional[RobotState] = None) -> np.ndarray:
        """The latest servo target (rad), the base of relative set-points (``state``: the
        state this request already read, else read now)."""
        state = state if state is not None else self.state()
        goal = self.twin.servo_goal() if state.servo_mode else None
        if goal is None:
            raise Rejected(f"{what}: not in servo mode (servo_move relFlag 1 first)")
        return goal

    def require_servo_mode(self, what: str, state: Optional[RobotState] = None) -> None:
        """servo_j outside servo mode: the recorded errorCode "-1" and text (servo_p answered
        likewise, by analogy: not recorded). ``state`` as :meth:`servo_reference`'s."""
        if not (state if state is not None else self.state()).servo_mode:
            raise Rejected(NOT_IN_SERVO_MODE.format(what.replace("_", "")),
                           ERROR_NOT_IN_SERVO_MODE)

    def servo_joints(self, q: np.ndarray, steps: int, what: str = "servo_j") -> None:
        with self.lock:
            # one read of the state for the three checks: a servo stream sends 125 of these a
            # second, and each read builds the whole state (~7 µs)
            state = self.state()
            self.require_servo_mode(what, state)
            self.require_can_move(what, servo_ok=True, state=state)
            goal = self.servo_reference(what, state)
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
