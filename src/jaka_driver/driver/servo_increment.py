"""``~servo_increment``: servo_j / servo_p requests read as increments, as JAKA's driver code
sends them (its servo_j and servo_p call the SDK in INCR mode), so programs written for it —
JAKA's ``servoj_demo`` sends ``{0.001, 0, 0, 0, 0, 0.001}`` 200 times — run unchanged. The
interface document (and this driver by default) reads them as absolute targets.

Relative to what: to the **last target commanded** in this servo session, as a controller in
incremental servo mode accumulates its command position — not to the measured position, which
lags the target by the drives' tracking error: N increments of d move the arm by exactly N·d
however fast they come. The first increment after ``servo_move_enable`` (and the first after a
refused one) is relative to the measured position.

Units are those of JAKA's driver code, which passes the request straight to the SDK:
servo_j rad per joint; servo_p mm for x, y, z and rad for the RPY angles, added to the last
target's position (active user frame) and to its RPY angles component by component.
The absolute target then takes the driver's ordinary path (limits, speed check, the cycle).
"""
from __future__ import annotations

import threading
from typing import Optional, Sequence

import numpy as np

from ..common.results import CommandRefused, Result
from ..common.transforms import matrix_to_pose, pose_to_matrix
from . import checks as check


class ServoIncrements:
    """Turns increments into the absolute targets :class:`RobotDriver` takes. Thread-safe:
    one increment at a time, so two callers never add to the same reference."""

    def __init__(self, driver):
        self._driver = driver
        self._lock = threading.Lock()
        self._joints: Optional[np.ndarray] = None   # rad, last joint target
        self._tcp: Optional[np.ndarray] = None      # m + RPY rad, last TCP target (user frame)

    def reset(self) -> None:
        """Forget the last targets (servo mode entered or left)."""
        with self._lock:
            self._joints = self._tcp = None

    def servo_j(self, pose: Sequence[float]) -> Result:
        """Joint increment (rad) → absolute target → ``driver.servo_j``."""
        with self._lock:
            try:
                delta = check.vector("pose", pose)
            except CommandRefused as refusal:
                return refusal.result()
            reference = (self._joints if self._joints is not None
                         else self._driver.state().joint_position)
            target = np.asarray(reference, dtype=float) + delta
            result = self._driver.servo_j(target.tolist())
            self._joints = target if result.ok else None
            self._tcp = None            # the next servo_p starts from the arm's TCP
            return result

    def servo_p(self, pose: Sequence[float]) -> Result:
        """TCP increment (mm, RPY rad) → absolute target (m + RPY) → ``driver.servo_p``."""
        with self._lock:
            try:
                delta = check.vector("pose", pose)
            except CommandRefused as refusal:
                return refusal.result()
            if self._tcp is not None:
                reference = self._tcp
            elif self._joints is not None:
                fk = self._driver.get_fk(self._joints.tolist())      # mm + rotvec
                reference = (matrix_to_pose(pose_to_matrix(fk.value, length_scale=1e-3),
                                            rotation="rpy") if fk.ok else self._measured_tcp())
            else:
                reference = self._measured_tcp()
            target = reference + np.concatenate([delta[:3] * 1e-3, delta[3:]])
            result = self._driver.servo_p(target.tolist())
            self._tcp = target if result.ok else None
            self._joints = None         # the next servo_j starts from the arm's joints
            return result

    def _measured_tcp(self) -> np.ndarray:
        return matrix_to_pose(self._driver.state().tcp_pose, rotation="rpy")
