"""Servo mode through the door: entering and leaving it, the targets of each 8 ms cycle
(``servo_j``, ``servo_p``, and the joint stream topics' absolute targets), read as absolute
targets or, with servo increments (jaka_driver.conventions), as increments of the last target;
each target checked against the limits and the step from the last one; and the servo filter
the targets pass through from the next servo mode on.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from ..common.results import Code, CommandRefused, Result
from ..common.transforms import rpy_to_matrix
from ..conventions import ServoIncrements
from ..motion.servo_filters import checked_spec
from . import checks as check
from .door import Door, RequestPart, answers


class ServoRequests(RequestPart):
    """Servo mode, its targets and the servo filter (see the module)."""

    def __init__(self, door: Door):
        super().__init__(door)
        backend = door.backend
        self._increments = ServoIncrements(self._servo_j, self._servo_p, backend.state,
                                           backend.forward_kinematics) \
            if door.conventions.servo_increment else None

    def forget(self) -> None:
        """A new stream starts from where the arm is: no last target, no gap (servo mode
        entered or left, a twin reset)."""
        self.door.servo.reset()
        if self._increments is not None:
            self._increments.reset()

    @answers
    def servo_move_enable(self, enable: bool) -> Result:
        """Enter or leave servo mode."""
        if enable:
            self.door.no_blocking_move("servo mode")
            self.door.not_jogging()
            self.door.ready(allow_servo_mode=True)
        self.forget()
        return self.backend.servo_enable(bool(enable))

    @answers(react=False)
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
        st = self.door.ready(servo=True)
        reference, gap = self.door.servo.reference(st.joint_position)
        check.servo_step(self.model, q, reference)
        result = self.backend.servo_j(q, increment)
        if result.ok:
            self.door.servo.accepted(q)
        return with_gap(result, gap, self.door.servo.timeout)

    @answers(react=False)
    def servo_j_target(self, pose: Sequence[float]) -> Result:
        """An absolute joint target (rad) under servo_j's rules and path, whatever
        ``servo_increment`` says: the joint stream topics' (their messages are positions)."""
        return self._servo_j(pose)

    @answers(react=False)
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
        st = self.door.ready(servo=True)
        target = np.eye(4)
        target[:3, :3] = rpy_to_matrix(*p[3:])
        target[:3, 3] = p[:3]
        _, gap = self.door.servo.reference(st.joint_position)
        if gap is None:   # after a gap the arm held still: the step is from where it stands
            check.servo_tcp_step(self.model, target, st.tcp_pose)
        result = self.backend.servo_p(target, increment)
        if result.ok:
            # the joint target, when the backend solved the IK itself (the twin), else the
            # measured joints: the reference for a servo_j that may follow
            self.door.servo.accepted(result.value if result.value is not None
                                 else st.joint_position)
        return with_gap(result, gap, self.door.servo.timeout)

    @answers
    def set_servo_filter(self, filter_type: int, lpf_cutoff_hz: float = 0.0,
                         nlf_max_vr: float = 0.0, nlf_max_ar: float = 0.0,
                         nlf_max_jr: float = 0.0, nlf_max_vp: float = 0.0,
                         nlf_max_ap: float = 0.0, nlf_max_jp: float = 0.0,
                         mmf_buffer: int = 0, mmf_kp: float = 0.0, mmf_kv: float = 0.0,
                         mmf_ka: float = 0.0) -> Result:
        """The filter servo targets pass through from the next servo mode on: JAKA's
        ``filter_type`` 0–5 with the parameters it uses (docs/interface.md,
        "set_servo_filter": rad/s… for joints and rotations, mm/s… for the TCP, Hz, cycles);
        refused in servo mode, as a controller refuses it."""
        spec = checked_spec(self.model, filter_type, dict(
            lpf_cutoff_hz=lpf_cutoff_hz, nlf_max_vr=nlf_max_vr, nlf_max_ar=nlf_max_ar,
            nlf_max_jr=nlf_max_jr, nlf_max_vp=nlf_max_vp, nlf_max_ap=nlf_max_ap,
            nlf_max_jp=nlf_max_jp, mmf_buffer=mmf_buffer, mmf_kp=mmf_kp, mmf_kv=mmf_kv,
            mmf_ka=mmf_ka))
        if self.backend.state().servo_mode:
            raise CommandRefused(Code.WRONG_MODE, "servo filter refused in servo mode: leave "
                                 "it first (servo_move_enable false), as a controller asks")
        return self.backend.set_servo_filter(spec)


def with_gap(result: Result, gap, timeout: float) -> Result:
    if gap is None:
        return result
    return Result(result.code, f"{result.message} (the servo stream had stopped for "
                  f"{gap:.2f} s, timeout {timeout:g} s: the arm held its last target)",
                  result.value)
