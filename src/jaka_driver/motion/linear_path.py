"""Cartesian straight-line planning for ``linear_move``: the whole path is sampled and checked
(IK, joint limits, joint speed: :mod:`.cartesian_path`) before anything moves
(docs/interface.md, "linear_move").

Frames and units: ``T_start`` and ``T_goal`` are 4x4 homogeneous TCP poses in one frame
(whatever frame ``ik`` expects), positions in metres. Speeds m/s and rad/s, accelerations m/s²
and rad/s², joints rad and rad/s, time s. Messages give positions in mm, the driver's unit.

Kinematics is injected: ``ik(T, seed) -> q or None`` returns the joint solution nearest
``seed`` (rad) or None when there is none.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from ..common.constants import MAX_TOOL_ROTATION_ACCEL, MAX_TOOL_ROTATION_SPEED, SERVO_CYCLE
from ..common.transforms import rotation_angle_between, slerp
from .cartesian_path import (IK, JointBounds, PlanningError, follow_tcp_path,  # noqa: F401
                             invalid, path_time_law, pose, positive)
from .profiles import TrapezoidProfile
from .trajectory import MAX_MOTION_DURATION, JointTrajectory, time_grid

# Default orientation limits. A rotation is given the speed a point ROTATION_RADIUS from the
# axis would have at the linear speed (so a slow move also turns slowly), capped at the
# driver's tool rotation limits so that a fast move does not whip the tool round.
ROTATION_RADIUS = 0.1               # m


def orientation_limits(speed: float, accel: float) -> tuple[float, float]:
    """The default orientation limits of a line at ``speed`` m/s and ``accel`` m/s²: (angular
    speed rad/s, angular acceleration rad/s²). Every backend moves a line's orientation at
    these — the twin in :func:`plan_linear_move`, a controller through ``moveL``'s ``ori_vel``
    and ``ori_acc``."""
    return (min(speed / ROTATION_RADIUS, MAX_TOOL_ROTATION_SPEED),
            min(accel / ROTATION_RADIUS, MAX_TOOL_ROTATION_ACCEL))


def plan_linear_move(T_start, T_goal, speed: float, accel: float, q_start, ik: IK, lower,
                     upper, v_max, cycle: float = SERVO_CYCLE, ref_q=None,
                     angular_speed: Optional[float] = None,
                     angular_accel: Optional[float] = None) -> JointTrajectory:
    """Plan a straight-line TCP move from ``T_start`` (the pose at ``q_start``) to ``T_goal``.

    The position follows the segment, the orientation the slerp between the two, both driven
    by one path parameter ``u(t) ∈ [0, 1]`` with a trapezoid time law. ``u``'s limits make the
    TCP's linear speed / acceleration stay within ``speed`` (m/s) / ``accel`` (m/s²) and its
    angular speed / acceleration within ``angular_speed`` (rad/s) / ``angular_accel``
    (rad/s²); whichever of translation and rotation needs longer sets the time. Defaults:
    :func:`orientation_limits`.

    The path is sampled every ``cycle`` s (see :func:`time_grid`). Sample 0 is ``q_start``
    itself (the arm is there; solving IK for it would only add error). Each further sample is
    solved by ``ik`` seeded with the previous solution — the first with ``ref_q`` when given —
    and checked: a solution exists, it lies within ``[lower, upper]`` (rad), and no joint
    moves faster than ``v_max`` (rad/s) since the previous sample; a configuration flip or a
    singularity shows up as such a jump. The last sample is ``T_goal`` exactly.

    Returns a :class:`JointTrajectory` with ``qd`` from finite differences (0 at both ends,
    where the TCP is at rest) and the planned ``tcp`` poses. Raises :class:`PlanningError`
    with code -4 when the path cannot be followed and -2 for invalid parameters.
    """
    speed = positive("speed", speed, "m/s")
    accel = positive("accel", accel, "m/s²")
    cycle = positive("cycle", cycle, "s")
    default_speed, default_accel = orientation_limits(speed, accel)
    angular_speed = default_speed if angular_speed is None \
        else positive("angular_speed", angular_speed, "rad/s")
    angular_accel = default_accel if angular_accel is None \
        else positive("angular_accel", angular_accel, "rad/s²")
    T_start, T_goal = pose("T_start", T_start), pose("T_goal", T_goal)
    arm = JointBounds(q_start, lower, upper, v_max, ref_q)

    law = _path_law(T_start, T_goal, speed, accel, angular_speed, angular_accel)
    if law is None:
        return JointTrajectory(times=np.zeros(1), q=arm.q_start[None, :],
                               qd=np.zeros((1, arm.n)), tcp=T_goal[None, :, :])
    if law.duration > MAX_MOTION_DURATION:
        raise invalid(f"the line would take {law.duration:.4g} s at {speed * 1000:g} mm/s, "
                      f"{accel * 1000:g} mm/s², above the limit of {MAX_MOTION_DURATION:g} s "
                      "for one move")
    times = time_grid(law.duration, cycle)
    p0, p1 = T_start[:3, 3], T_goal[:3, 3]
    u = np.asarray(law.sample(times)[0])

    tcp = np.tile(np.eye(4), (times.shape[0], 1, 1))
    tcp[:, :3, 3] = p0 + u[:, None] * (p1 - p0)
    tcp[:, :3, :3] = slerp(T_start[:3, :3], T_goal[:3, :3], u)
    tcp[-1] = T_goal                    # land on the target, not on its rounding
    return follow_tcp_path(times, tcp, u, ik, arm, "path")


def line_duration(T_start, T_goal, speed: float, accel: float) -> float:
    """Duration (s) of the straight line from ``T_start`` to ``T_goal`` (4x4, m) at ``speed``
    m/s and ``accel`` m/s² with the default orientation limits, as :func:`plan_linear_move`
    would time it — without sampling it. 0 when the poses coincide."""
    speed = positive("speed", speed, "m/s")
    accel = positive("accel", accel, "m/s²")
    law = _path_law(pose("T_start", T_start), pose("T_goal", T_goal), speed, accel,
                    *orientation_limits(speed, accel))
    return 0.0 if law is None else law.duration


def _path_law(T_start: np.ndarray, T_goal: np.ndarray, speed: float, accel: float,
              angular_speed: float, angular_accel: float) -> Optional[TrapezoidProfile]:
    """The time law of the path parameter u ∈ [0, 1], or None when there is nothing to move.
    A unit of u is the line's length (m) and its rotation angle (rad): u's limits are the
    tighter of the translation's and the rotation's."""
    length = float(np.linalg.norm(T_goal[:3, 3] - T_start[:3, 3]))
    angle = float(rotation_angle_between(T_start[:3, :3], T_goal[:3, :3]))
    return path_time_law(length, angle, speed, accel, angular_speed, angular_accel)
