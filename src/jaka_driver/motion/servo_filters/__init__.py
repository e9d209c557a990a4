"""Servo filters: what the twin does to a servo stream's targets (servo_j, servo_p, the joint
stream topics) each 8 ms cycle before its drives follow them — JAKA's six, chosen with
``set_servo_move_filter`` on a controller (docs/interface.md, "set_servo_filter").

* :mod:`.spec` — :class:`FilterType`, :class:`ServoFilterSpec` and :func:`checked_spec` (the
  ranges, -2 with field, value and range);
* :mod:`.low_pass` — 1, the joint low-pass;
* :mod:`.nonlinear` — 2 and 4, the third-order non-linear filters (joint, Cartesian);
* :mod:`.mean` — 3 and 5, the multi-order mean and the speed foresight.

Every filter has ``reset(q, pose=None)`` (start at rest at the joints ``q``, rad) and
``next(q_target, pose=None)`` → the joints (rad) to command this cycle; ``pose`` (4x4, m) is a
servo_p target's, which only the Cartesian filter reads.
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from ...common.constants import SERVO_CYCLE
from .low_pass import JointLowPass
from .mean import JointMultiOrderMean, SpeedForesight
from .nonlinear import CartesianNonlinear, JointNonlinear, ThirdOrderTracker
from .spec import FilterType, ServoFilterSpec, checked_spec


class NoFilter:
    """``filter_type`` 0: the target as it came."""

    def reset(self, q, pose=None) -> None:
        pass

    def next(self, q_target, pose=None) -> np.ndarray:
        return np.asarray(q_target, float)


def make_filter(spec: ServoFilterSpec, cycle: float = SERVO_CYCLE,
                ik: Optional[Callable] = None, fk: Optional[Callable] = None):
    """The filter ``spec`` asks for; the Cartesian one needs ``ik(T, seed)`` and ``fk(q)`` (the
    active tool in the active user frame)."""
    t = spec.type
    if t == FilterType.JOINT_LPF:
        return JointLowPass(spec.cutoff, cycle)
    if t == FilterType.JOINT_NLF:
        return JointNonlinear(spec.velocity, spec.accel, spec.jerk, cycle)
    if t == FilterType.JOINT_MMF:
        return JointMultiOrderMean(spec.buffer, spec.kp, spec.kv, spec.ka)
    if t == FilterType.CARTESIAN_NLF:
        return CartesianNonlinear((spec.linear_velocity, spec.linear_accel, spec.linear_jerk),
                                  (spec.velocity, spec.accel, spec.jerk), cycle, ik, fk)
    if t == FilterType.SPEED_FORESIGHT:
        return SpeedForesight(spec.buffer, spec.kp)
    return NoFilter()


__all__ = ["FilterType", "ServoFilterSpec", "checked_spec", "make_filter", "NoFilter",
           "JointLowPass", "JointNonlinear", "CartesianNonlinear", "ThirdOrderTracker",
           "JointMultiOrderMean", "SpeedForesight"]
