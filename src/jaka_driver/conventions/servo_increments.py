"""servo_j / servo_p requests read as increments, as JAKA's driver code sends them (its servo_j
and servo_p call the SDK in INCR mode), so programs written for it — JAKA's ``servoj_demo``
sends ``{0.001, 0, 0, 0, 0, 0.001}`` 200 times — run unchanged. The interface document (and
this driver by default) reads them as absolute targets. On with ``~conventions:=jaka_code``, or
alone with ``~servo_increment``.

Relative to what: to the **last target commanded** in this servo session, as a controller in
incremental servo mode accumulates its command position — not to the measured position, which
lags the target by the drives' tracking error: N increments of d move the arm by exactly N·d
however fast they come. The first increment after ``servo_move_enable`` (and the first after a
refused one) is relative to the measured position.

Units are those of JAKA's driver code, which passes the request straight to the SDK:
servo_j rad per joint; servo_p mm for x, y, z and rad for the RPY angles, added to the last
target's position (active user frame) and to its RPY angles component by component.
The absolute target then takes the driver's ordinary path (limits, speed check, the cycle),
the increment with it (SI: rad; m + RPY rad), so that a backend that can hand the controller
the increment itself does (relative servo commands on the wire, as JAKA's SDK sends them).

Part of RobotDriver's servo path (``RobotDriver(..., conventions=...)``): which reading a
request gets is the driver's convention, below the node. The reference pose is converted once,
from the arm's 4x4 (measured, or the FK of the last joint target) to m + RPY.
"""
from __future__ import annotations

import threading
from typing import Callable, Optional, Sequence

import numpy as np

from ..backend import RobotState
from ..common.results import Result
from ..common.transforms import matrix_to_pose

#: (absolute target, the increment it came from) (rad, or m + RPY rad) → the driver's answer;
#: a refusal raises
Absolute = Callable[[np.ndarray, np.ndarray], Result]


class ServoIncrements:
    """Turns increments into absolute targets for ``servo_j`` / ``servo_p`` (the driver's
    absolute servo path), from the last target or, without one, from ``state()``; the TCP of a
    joint target is ``forward_kinematics`` (4x4, m). Thread-safe: one increment at a time, so
    two callers never add to the same reference."""

    def __init__(self, servo_j: Absolute, servo_p: Absolute, state: Callable[[], RobotState],
                 forward_kinematics: Callable[[np.ndarray], Result]):
        self._servo_j, self._servo_p = servo_j, servo_p
        self._state, self._fk = state, forward_kinematics
        self._lock = threading.Lock()
        self._joints: Optional[np.ndarray] = None   # rad, last joint target
        self._tcp: Optional[np.ndarray] = None      # m + RPY rad, last TCP target (user frame)

    def reset(self) -> None:
        """Forget the last targets (servo mode entered or left)."""
        with self._lock:
            self._joints = self._tcp = None

    def servo_j(self, pose: Sequence[float]) -> Result:
        """Joint increment (rad, six finite values: checked by the caller) → absolute target →
        the driver's servo_j."""
        with self._lock:
            delta = np.asarray(pose, dtype=float)
            reference = self._joints if self._joints is not None \
                else self._state().joint_position
            target = np.asarray(reference, dtype=float) + delta
            self._joints = self._tcp = None   # the next servo_p starts from the arm's TCP
            result = self._servo_j(target, delta)
            self._joints = target if result.ok else None
            return result

    def servo_p(self, pose: Sequence[float]) -> Result:
        """TCP increment (mm, RPY rad; checked by the caller) → absolute target (m + RPY) →
        the driver's servo_p."""
        with self._lock:
            delta = np.asarray(pose, dtype=float)
            increment = np.concatenate([delta[:3] * 1e-3, delta[3:]])   # m + RPY rad
            target = self._tcp_reference() + increment
            self._joints = self._tcp = None   # the next servo_j starts from the arm's joints
            result = self._servo_p(target, increment)
            self._tcp = target if result.ok else None
            return result

    def _tcp_reference(self) -> np.ndarray:
        """m + RPY rad: the last TCP target, else the TCP of the last joint target, else the
        arm's."""
        if self._tcp is not None:
            return self._tcp
        pose = None
        if self._joints is not None:
            fk = self._fk(self._joints)
            pose = fk.value if fk.ok else None
        if pose is None:
            pose = self._state().tcp_pose
        return matrix_to_pose(pose, rotation="rpy")
