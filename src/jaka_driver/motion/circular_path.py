"""Circular moves (``circular_move``, JAKA's ``movc``): an arc from where the TCP stands through
a middle point to an end point, with whole or partial extra turns and one of JAKA's four
attitude rules, checked along its whole path before anything moves (IK every cycle, joint
limits, joint speeds, no joint jump: :mod:`.cartesian_path`). docs/interface.md,
"circular_move", has the rules as users read them.

**The circle.** The three positions (start, ``T_mid``, ``T_end``) define it; they must lie at
least :data:`COLLINEAR_TOLERANCE` (0.1 mm) off one straight line — the height of their
triangle on its longest side — else the move is refused (-2). The tool goes from the start
through the middle point to the end point (the arc that contains the middle point), then
``turns`` more times round the same circle in the same sense: the whole angle is
``θ_end + 2π·turns``. A whole ``turns`` ends at the end point; a fractional one ends that share
of a circle beyond it (``turns`` 0.25 passes the end point and stops a quarter circle later) —
JAKA's SDK sends ``circle_cnt`` as a double, and an overlap of part of a circle is what a
seam or a dispensing bead needs.

**The attitude** (``mode``, JAKA's ``circle_mode``), with R0, R1, R2 the start, middle and end
orientations and u ∈ [0, 1] the share of the whole arc done:

- 0 :attr:`AttitudeMode.SHORT` — R0 to R2 the short way (the rotation of angle φ ≤ 180°
  about the axis of R0ᵀR2), in proportion to u; R1 is not used.
- 1 :attr:`AttitudeMode.LONG` — R0 to R2 the long way: about the same axis, the other sense,
  by 360° − φ (equal attitudes: one whole turn about the arc's axis).
- 2 :attr:`AttitudeMode.BY_MIDDLE` — whichever of 0 and 1 puts the tool nearer R1 when it
  passes the middle point (the smaller angle between the two); the answer says which.
- 3 :attr:`AttitudeMode.FIXED_TO_AXIS` — the tool keeps its attitude relative to the arc: it
  turns with the radius, about the arc's axis, by the arc's own angle (R(u) = Rot(n, u·Θ)·R0
  in the poses' frame, n the arc's axis). R1 and R2 are not used; the end attitude is where
  that rotation leaves the tool.

With a whole ``turns`` modes 0–2 end exactly at R2, and mode 3 at Rot(n, Θ)·R0.

**Timing.** One path parameter u(t) with a trapezoid time law (as a line,
:func:`.cartesian_path.path_time_law`): along the arc of length ``R·Θ`` at most ``speed`` and
``accel`` — and at most √(``accel``·R), so that the centripetal acceleration v²/R stays within
``accel`` too; the attitude at the line's orientation limits
(:func:`.linear_path.orientation_limits`), or for mode 3, whose rotation is the arc's own, at
the tool rotation caps only. Whichever needs longer sets the time.

Units: poses 4x4 in metres in one frame (the active user frame), speeds m/s, accelerations
m/s², angles rad, time s; messages in mm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum
from typing import Callable

import numpy as np

from ..common.constants import MAX_TOOL_ROTATION_ACCEL, MAX_TOOL_ROTATION_SPEED, SERVO_CYCLE
from ..common.results import Code
from ..common.transforms import matrix_to_rotvec, rotation_angle_between, rotvec_to_matrix
from .cartesian_path import (IK, JointBounds, PlanningError, follow_tcp_path, invalid,
                             path_time_law, pose, positive)
from .linear_path import orientation_limits
from .profiles import TrapezoidProfile
from .trajectory import MAX_MOTION_DURATION, JointTrajectory, time_grid

#: m — three points closer than this to one straight line (the height of their triangle on
#: its longest side) define no circle: the move is refused
COLLINEAR_TOLERANCE = 1e-4
#: the most extra turns one move may make
MAX_TURNS = 100.0
_WHOLE = 1e-9               # a turns value this close to a whole number is whole
_SAME_ATTITUDE = 1e-9       # rad: start and end attitudes this close are equal


class AttitudeMode(IntEnum):
    """JAKA's ``circle_mode``: how the tool's attitude changes along the arc (module doc)."""

    SHORT = 0
    LONG = 1
    BY_MIDDLE = 2
    FIXED_TO_AXIS = 3


@dataclass(frozen=True)
class Arc:
    """A circle through three points and the angle the tool travels on it: centre (m), radius
    (m), unit axis (the sense start → middle → end is positive about it), the unit vectors of
    its plane (``e1`` towards the start, ``e2 = axis × e1``), the middle point's and the end
    point's angles from the start (rad, 0 < ``mid_angle`` < ``end_angle`` < 2π) and the whole
    angle travelled (``end_angle`` + 2π·turns)."""

    center: np.ndarray
    radius: float
    axis: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    mid_angle: float
    end_angle: float
    angle: float

    def points(self, phi) -> np.ndarray:
        """Positions (…, 3) m at the angles ``phi`` (rad) from the start."""
        phi = np.asarray(phi, dtype=float)[..., None]
        return self.center + self.radius * (np.cos(phi) * self.e1 + np.sin(phi) * self.e2)

    def distance_from(self, p) -> np.ndarray:
        """How far (m) the positions ``p`` (…, 3) are from the circle."""
        d = np.asarray(p, dtype=float) - self.center
        height = d @ self.axis
        in_plane = np.linalg.norm(d - height[..., None] * self.axis, axis=-1)
        return np.hypot(height, in_plane - self.radius)

    @property
    def length(self) -> float:
        """m along the arc travelled."""
        return self.radius * self.angle


def arc_through(p_start, p_mid, p_end, turns: float = 0.0) -> Arc:
    """The :class:`Arc` from ``p_start`` through ``p_mid`` to ``p_end`` (m) and ``turns`` more
    times round. Raises :class:`PlanningError` (-2) when the points are collinear (within
    :data:`COLLINEAR_TOLERANCE`) or ``turns`` is outside 0–:data:`MAX_TURNS`."""
    turns = float(turns)
    if not (math.isfinite(turns) and 0.0 <= turns <= MAX_TURNS):
        raise invalid(f"turns is {turns:g}, expected 0–{MAX_TURNS:g} (extra whole or partial "
                      "circles after the end point)")
    p0, p1, p2 = (np.asarray(p, dtype=float) for p in (p_start, p_mid, p_end))
    a, b = p1 - p0, p2 - p0
    normal = np.cross(a, b)
    longest = max(np.linalg.norm(a), np.linalg.norm(b), np.linalg.norm(p2 - p1))
    height = float(np.linalg.norm(normal)) / longest if longest > 0.0 else 0.0
    if height < COLLINEAR_TOLERANCE:
        raise invalid(f"pose_mid and pose_end are collinear with the start: the three points "
                      f"are {height * 1000:.3f} mm off one straight line, at least "
                      f"{COLLINEAR_TOLERANCE * 1000:g} mm needed to define a circle")
    axis = normal / np.linalg.norm(normal)
    # the circumcentre: p0 + ((|a|² b − |b|² a) × n) / (2 |n|²)
    aa, bb = a @ a, b @ b
    center = p0 + (np.cross(normal, a) * bb + np.cross(b, normal) * aa) / (2.0 * (normal @ normal))
    radius = float(np.linalg.norm(p0 - center))
    e1 = (p0 - center) / radius
    e2 = np.cross(axis, e1)

    def angle_of(p: np.ndarray) -> float:
        d = p - center
        return float(np.arctan2(d @ e2, d @ e1)) % (2.0 * math.pi)

    end_angle = angle_of(p2)
    return Arc(center=center, radius=radius, axis=axis, e1=e1, e2=e2, mid_angle=angle_of(p1),
               end_angle=end_angle, angle=end_angle + 2.0 * math.pi * turns)


@dataclass(frozen=True)
class Attitude:
    """The tool's orientation along the arc: ``at(u)`` (…, 3, 3) for u ∈ [0, 1], the angle
    (rad) it turns in all, and what was chosen, in words (for the answer)."""

    at: Callable[[np.ndarray], np.ndarray]
    angle: float
    chosen: str


def attitude_law(R_start, R_mid, R_end, arc: Arc, mode: int) -> Attitude:
    """The attitude rule ``mode`` (:class:`AttitudeMode`, module doc) on ``arc``."""
    try:
        mode = AttitudeMode(int(mode))
    except ValueError:
        raise invalid(f"attitude_mode is {mode}, expected 0–3 (0 short way, 1 long way, "
                      "2 by the middle pose, 3 fixed to the arc's axis)") from None
    R0 = np.asarray(R_start, dtype=float)
    if mode == AttitudeMode.FIXED_TO_AXIS:
        def fixed(u):
            turn = rotvec_to_matrix(np.asarray(u, dtype=float)[..., None] * arc.angle * arc.axis)
            return turn @ R0
        return Attitude(fixed, arc.angle, "attitude fixed to the arc's axis")
    short = _rotation(R0, R_end, long_way=False, arc=arc)
    if mode == AttitudeMode.SHORT:
        return short
    long = _rotation(R0, R_end, long_way=True, arc=arc)
    if mode == AttitudeMode.LONG:
        return long
    u_mid = arc.mid_angle / arc.angle
    off = [rotation_angle_between(law.at(np.asarray(u_mid)), R_mid) for law in (short, long)]
    law = short if off[0] <= off[1] else long
    return Attitude(law.at, law.angle, f"{law.chosen} (by the middle pose: "
                    f"{math.degrees(min(off)):.1f}° from it at the middle point, the other "
                    f"way {math.degrees(max(off)):.1f}°)")


def _rotation(R0: np.ndarray, R_end, *, long_way: bool, arc: Arc) -> Attitude:
    """R0 to ``R_end`` about the axis of their relative rotation, the short or the long way."""
    rel = matrix_to_rotvec(R0.T @ np.asarray(R_end, dtype=float))
    phi = float(np.linalg.norm(rel))
    if not long_way:
        step = rel
        words = f"attitude the short way ({math.degrees(phi):.1f}°)"
    elif phi < _SAME_ATTITUDE:
        step = 2.0 * math.pi * (R0.T @ arc.axis)   # equal attitudes: a whole turn about the axis
        words = "attitude the long way (a whole turn about the arc's axis)"
    else:
        step = -(2.0 * math.pi - phi) * rel / phi
        words = f"attitude the long way ({360.0 - math.degrees(phi):.1f}°)"

    def at(u):
        return R0 @ rotvec_to_matrix(np.asarray(u, dtype=float)[..., None] * step)
    return Attitude(at, float(np.linalg.norm(step)), words)


def _time_law(arc: Arc, attitude: Attitude, mode: int, speed: float,
              accel: float) -> TrapezoidProfile:
    """The law of u: the arc's speed at most ``speed`` and √(accel·R), its acceleration at
    most ``accel``, the attitude's at the limits of the module doc."""
    along = min(speed, math.sqrt(accel * arc.radius))
    if int(mode) == AttitudeMode.FIXED_TO_AXIS:
        angular = (MAX_TOOL_ROTATION_SPEED, MAX_TOOL_ROTATION_ACCEL)
    else:
        angular = orientation_limits(speed, accel)
    return path_time_law(arc.length, attitude.angle, along, accel, *angular)


@dataclass(frozen=True)
class CirclePlan:
    """What a circular move will do before it is sampled: the arc, the attitude rule and the
    time law (``duration`` s)."""

    arc: Arc
    attitude: Attitude
    law: TrapezoidProfile

    @property
    def duration(self) -> float:
        return self.law.duration


def plan_circle(T_start, T_mid, T_end, speed: float, accel: float, turns: float = 0.0,
                mode: int = 0) -> CirclePlan:
    """The arc, attitude and timing of a circular move from ``T_start`` through ``T_mid`` to
    ``T_end`` (4x4, m) at ``speed`` m/s and ``accel`` m/s² — without sampling it (the driver's
    plan of its duration, and the first step of :func:`plan_circular_move`)."""
    speed = positive("speed", speed, "m/s")
    accel = positive("accel", accel, "m/s²")
    T0, T1, T2 = pose("T_start", T_start), pose("T_mid", T_mid), pose("T_end", T_end)
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3], turns)
    attitude = attitude_law(T0[:3, :3], T1[:3, :3], T2[:3, :3], arc, mode)
    return CirclePlan(arc, attitude, _time_law(arc, attitude, mode, speed, accel))


def circle_duration(T_start, T_mid, T_end, speed: float, accel: float, turns: float = 0.0,
                    mode: int = 0) -> float:
    """Duration (s) of the circular move as :func:`plan_circular_move` times it."""
    return plan_circle(T_start, T_mid, T_end, speed, accel, turns, mode).duration


def plan_circular_move(T_start, T_mid, T_end, speed: float, accel: float, q_start, ik: IK,
                       lower, upper, v_max, turns: float = 0.0, mode: int = 0,
                       cycle: float = SERVO_CYCLE, ref_q=None) -> JointTrajectory:
    """Plan the circular move from ``T_start`` (the pose at ``q_start``) through ``T_mid`` to
    ``T_end`` (module doc), sampled every ``cycle`` s and checked along its whole path
    (:func:`.cartesian_path.follow_tcp_path`: ``ik``, ``lower``/``upper`` rad, ``v_max`` rad/s,
    ``ref_q`` the first sample's IK seed). Raises :class:`PlanningError`: -2 for collinear
    points or invalid parameters, -4 when the arc leaves the workspace or the limits."""
    cycle = positive("cycle", cycle, "s")
    plan = plan_circle(T_start, T_mid, T_end, speed, accel, turns, mode)
    arm = JointBounds(q_start, lower, upper, v_max, ref_q)
    if plan.duration > MAX_MOTION_DURATION:
        raise invalid(f"the arc would take {plan.duration:.4g} s at {speed * 1000:g} mm/s, "
                      f"{accel * 1000:g} mm/s², above the limit of {MAX_MOTION_DURATION:g} s "
                      "for one move")
    times = time_grid(plan.duration, cycle)
    u = np.asarray(plan.law.sample(times)[0])
    tcp = np.tile(np.eye(4), (times.shape[0], 1, 1))
    tcp[:, :3, 3] = plan.arc.points(u * plan.arc.angle)
    tcp[:, :3, :3] = plan.attitude.at(u)
    if abs(turns - round(turns)) <= _WHOLE:       # land on the end point, not its rounding
        tcp[-1, :3, 3] = np.asarray(T_end, dtype=float)[:3, 3]
        if int(mode) != AttitudeMode.FIXED_TO_AXIS:
            tcp[-1, :3, :3] = np.asarray(T_end, dtype=float)[:3, :3]
    try:
        return follow_tcp_path(times, tcp, u, ik, arm, "arc")
    except PlanningError as exc:
        if exc.code == Code.INVALID_PARAMETER:
            raise
        leaves = "leaves the workspace: " if exc.message.startswith("no IK solution") else ""
        raise PlanningError(exc.code, f"the arc (radius {plan.arc.radius * 1000:.1f} mm) "
                            f"{leaves or 'cannot be followed: '}{exc.message}") from None


def stop_pose(T_start, T_mid, T_end, turns: float = 0.0, mode: int = 0) -> np.ndarray:
    """Where (4x4, m) a circular move ends: ``T_end`` for a whole ``turns`` in modes 0–2, else
    the point and attitude the arc and the attitude rule reach."""
    T0, T1, T2 = pose("T_start", T_start), pose("T_mid", T_mid), pose("T_end", T_end)
    arc = arc_through(T0[:3, 3], T1[:3, 3], T2[:3, 3], turns)
    attitude = attitude_law(T0[:3, :3], T1[:3, :3], T2[:3, :3], arc, mode)
    T = np.eye(4)
    T[:3, 3] = arc.points(arc.angle)
    T[:3, :3] = attitude.at(np.asarray(1.0))
    return T

