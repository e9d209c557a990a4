"""Checks at the door, in one place: each raises :class:`CommandRefused` (-2) with a message that
names the field, the value and the limit, and returns the value converted to numpy / Python
types. RobotDriver calls them before anything moves; the joint-limit and joint-speed tests they
share with the backends (which repeat them in their own terms) are
:mod:`jaka_driver.common.joint_limits`.

Units: joints rad, speeds rad/s or mm/s, accelerations rad/s² or mm/s², poses 4x4 in m unless a
name says mm, durations s.

Move durations: :func:`joint_move_duration`, :func:`linear_move_duration` and
:func:`circular_move_duration` are the driver's plan of a move's duration, by the law every
backend times it with (:mod:`jaka_driver.motion.profiles`,
:func:`jaka_driver.motion.linear_path.line_duration`,
:func:`jaka_driver.motion.circular_path.circle_duration`); the driver hands the result to the backend,
which plays it (the twin) or sends it as a speed (a controller). A move slower than
:data:`~jaka_driver.motion.trajectory.MAX_MOTION_DURATION` (10 min) comes from a units mistake
(``mvvelo`` 1e-7, ``mvtime`` 3e38) and is refused; so is an ``mvtime`` shorter than the move
needs — here, where the request names the field at fault (docs/interface.md, "Result codes"),
and nowhere else.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np

from ..common.constants import MAX_TOOL_ROTATION_SPEED, SERVO_CYCLE
from ..common.joint_limits import fastest_step
from ..common.models import IO_PATHS, IO_SIGNALS, IO_TYPES, PAYLOAD_MARGIN, RobotModel, io_level
from ..common.results import CommandRefused, invalid
from ..common.transforms import pose_mm_to_matrix
from ..common.values import finite, integer_in, joint_targets, unit_text as _u, vector
from ..motion.circular_path import MAX_TURNS, circle_duration
from ..motion.linear_path import line_duration
from ..motion.profiles import SyncJointProfile
from ..motion.trajectory import MAX_MOTION_DURATION

#: A requested speed or acceleration above this many times the model's limit is taken for a
#: unit mistake (deg for rad, m for mm) and refused instead of silently clamped.
ABSURD_FACTOR = 10.0

JOG_AXES = ("X", "Y", "Z", "RX", "RY", "RZ")
TOOL_REACH_MM = 1000.0          # |tool offset| bound
USER_REACH_MM = 10000.0         # |user frame origin| bound
CENTROID_REACH_MM = 1000.0      # |payload centroid| from the flange
ANALOG_LIMIT = 10.0             # V; analog outputs are ±10 V


def speed(name: str, value: float, limit: float, unit: str, *, default: float | None = None,
          notes: list[str] | None = None) -> float:
    """A positive speed or acceleration, clamped to ``limit`` (with a note).

    ``value == 0`` takes ``default`` when one is given (noted); otherwise zero, negative,
    non-finite and absurd (> ABSURD_FACTOR × limit) values are refused.
    """
    value = finite(name, value, unit)
    if value == 0 and default is not None:
        if notes is not None:
            notes.append(f"{name} 0 → default {default:g}{_u(unit)}")
        return default
    if value <= 0:
        raise invalid(f"{name} is {value:g}{_u(unit)}, expected > 0 (limit {limit:g}{_u(unit)})")
    if value > ABSURD_FACTOR * limit:
        raise invalid(f"{name} is {value:g}{_u(unit)}, more than {ABSURD_FACTOR:g}× the model "
                      f"limit {limit:g}{_u(unit)} (wrong units?)")
    if value > limit:
        if notes is not None:
            notes.append(f"{name} {value:g} clamped to the limit {limit:g}{_u(unit)}")
        return limit
    return value


def io_signal(value: str) -> str:
    signal = str(value).strip().lower()
    if signal not in IO_SIGNALS:
        raise invalid(f"signal is {value!r}, expected 'digital' or 'analog'")
    return signal


def io_address(model: RobotModel, signal: str, path: int, io_type: int, index: int) -> None:
    """The IO point exists on this model (sizes in config/<model>.yaml)."""
    integer_in("type", io_type, 0, 2)
    integer_in("path", path, 0, 1)
    count = model.io_sizes.get((signal, int(io_type), int(path)), 0)
    where = f"{IO_TYPES[int(io_type)]} {signal} {IO_PATHS[int(path)]}puts"
    if count == 0:
        raise invalid(f"the {where} do not exist on {model.name} (index {index})")
    if not 0 <= int(index) < count:
        raise invalid(f"index is {index}, {where} are 0–{count - 1}")

def io_value(signal: str, value: float, analog_limit: float | None = None) -> float:
    """The value an IO point of ``signal`` is set to (:func:`~jaka_driver.common.models.io_level`:
    digital non-zero → 1); an analog value (V) within ±``analog_limit`` when one is given
    (:data:`ANALOG_LIMIT` for outputs)."""
    v = finite("value", value)
    if signal != "digital" and analog_limit is not None and abs(v) > analog_limit:
        raise invalid(f"value is {v:g}, analog outputs are ±{analog_limit:g} V")
    return io_level(signal, v)


# ---- joints: servo steps -------------------------------------------------------------------
def servo_step(model: RobotModel, q: np.ndarray, reference: np.ndarray) -> None:
    """A servo_j target (rad) reachable from ``reference`` within one cycle."""
    too_fast = fastest_step(model, reference, q)
    if too_fast is not None:
        j, speed_needed = too_fast
        raise invalid(f"{model.joint_names[j]} step of {abs(q - reference)[j]:.4f} rad in one "
                      f"{SERVO_CYCLE * 1000:g} ms cycle needs {speed_needed:.2f} rad/s, limit "
                      f"{model.max_velocity[j]:.2f} rad/s; the arm holds")


def servo_tcp_step(model: RobotModel, target: np.ndarray, tcp: np.ndarray) -> None:
    """A servo_p target (4x4, m) whose origin is within one cycle of ``tcp`` at the model's
    TCP speed limit."""
    tcp_speed = np.linalg.norm(target[:3, 3] - tcp[:3, 3]) / SERVO_CYCLE
    if tcp_speed > model.max_tcp_speed:
        raise invalid(f"pose step needs {tcp_speed * 1000:.0f} mm/s in one "
                      f"{SERVO_CYCLE * 1000:g} ms cycle, limit {model.max_tcp_speed * 1000:.0f} "
                      "mm/s; the arm holds")


# ---- jog, frames, payload -----------------------------------------------------------------------
def jog_speed(model: RobotModel, coord: int, axis: int, field: str, value: float,
              notes: list[str]) -> tuple[str, str, float]:
    """(axis label, unit of the request, speed in SI: rad/s or m/s) of a jog along ``axis``
    of ``coord`` (0 joint, 1 base, 2 tool); ``value`` is in rad/s, or mm/s for X–Z."""
    if coord == 0:
        label, unit = model.joint_names[axis], "rad/s"
        return label, unit, speed(field, value, float(model.max_velocity[axis]), unit,
                                  notes=notes)
    if axis < 3:
        return JOG_AXES[axis], "mm/s", speed(field, value, model.max_tcp_speed * 1000.0,
                                             "mm/s", notes=notes) / 1000.0
    return JOG_AXES[axis], "rad/s", speed(field, value, MAX_TOOL_ROTATION_SPEED, "rad/s",
                                          notes=notes)


def twist_speeds(model: RobotModel, linear: np.ndarray, angular: np.ndarray) -> None:
    """A velocity jog's twist within jog's limits: the TCP's speed (m/s) at most the model's,
    the rotation's (rad/s) at most the tool rotation cap."""
    # plain floats: a teleop's twist comes 125 times a second (numpy's norm costs more)
    v, w = math.hypot(*linear.tolist()), math.hypot(*angular.tolist())
    if v > model.max_tcp_speed:
        raise invalid(f"twist.linear is {v:.4g} m/s, limit {model.max_tcp_speed:g} m/s")
    if w > MAX_TOOL_ROTATION_SPEED:
        raise invalid(f"twist.angular is {w:.4g} rad/s, limit {MAX_TOOL_ROTATION_SPEED:.4g} "
                      "rad/s")


def frame_pose(pose: Sequence[float], reach_mm: float) -> np.ndarray:
    """A tool or user frame (mm + rotation vector) as a 4x4 (m), its origin within
    ``reach_mm``."""
    p = vector("pose", pose)
    distance = float(np.linalg.norm(p[:3]))
    if distance > reach_mm:
        raise invalid(f"pose origin is {distance:.1f} mm away, limit {reach_mm:g} mm")
    return pose_mm_to_matrix(p)


def payload(model: RobotModel, mass: float, centroid_mm: Sequence[tuple[str, float]]
            ) -> tuple[float, np.ndarray]:
    """(mass kg, centroid m in the flange frame) of a payload; ``centroid_mm`` is the
    (field name, value mm) of xc, yc, zc. The mass may be up to 1.5 × the rated payload."""
    m = finite("mass", mass, "kg")
    limit = model.max_payload_kg
    if not 0 <= m <= limit:
        raise invalid(f"mass is {m:g} kg, expected 0–{limit:g} kg ({PAYLOAD_MARGIN:g} × rated "
                      f"payload of {model.name})")
    c = np.array([finite(n, v, "mm") for n, v in centroid_mm])
    if np.linalg.norm(c) > CENTROID_REACH_MM:
        raise invalid(f"centroid is {np.linalg.norm(c):.1f} mm from the flange, limit "
                      f"{CENTROID_REACH_MM:g} mm")
    return m, c / 1000.0


# ---- move durations -----------------------------------------------------------------------------
# A requested duration this little shorter than the minimum is float noise (profiles.py).
_DURATION_RTOL = 1e-9


def joint_move_duration(q_start: np.ndarray, q_goal: np.ndarray, speed: np.ndarray,
                     accel: np.ndarray, mvtime: Optional[float],
                     mvvelo: float, mvacc: float) -> float:
    """Duration (s) of the joint move ``q_start`` → ``q_goal`` at the per-joint ``speed`` and
    ``accel`` the backend will use (request clamped to the model), stretched to ``mvtime``
    when given. Raises -2 naming ``mvtime``, ``mvvelo`` or ``mvacc`` (as requested) when the
    move would be too short or too long."""
    fastest = SyncJointProfile(q_start, q_goal, speed, accel)
    needed = fastest.predicted_duration
    if mvtime is not None:
        if mvtime < needed * (1.0 - _DURATION_RTOL):
            k = fastest.limiting_joint
            raise invalid(f"mvtime is {mvtime:.3f} s, shorter than the {needed:.3f} s this move "
                          f"needs (limit: joint_{k + 1} moves "
                          f"{abs(q_goal[k] - q_start[k]):.3f} rad at most {speed[k]:.2f} rad/s, "
                          f"{accel[k]:.2f} rad/s²)")
        if mvtime > MAX_MOTION_DURATION:
            raise invalid(f"mvtime is {mvtime:.4g} s, above the limit of "
                          f"{MAX_MOTION_DURATION:g} s for one move")
        return max(mvtime, needed)
    if needed > MAX_MOTION_DURATION:
        field, value, unit = _slow_field(mvvelo, mvacc, "rad/s", "rad/s²",
                                         speed_is_short=_fits_at_any_speed(q_start, q_goal,
                                                                           accel))
        raise invalid(f"{field} is {value:g} {unit}: the move would take {needed:.4g} s, above "
                      f"the limit of {MAX_MOTION_DURATION:g} s for one move")
    return needed


def linear_move_duration(T_start: np.ndarray, T_goal: np.ndarray, speed: float, accel: float,
                      mvvelo: float, mvacc: float) -> float:
    """Duration (s) of the straight line ``T_start`` → ``T_goal`` (m) at ``speed`` m/s and
    ``accel`` m/s² (request clamped to the model). Raises -2 naming ``mvvelo`` or ``mvacc``
    when it would be longer than the limit."""
    needed = line_duration(T_start, T_goal, speed, accel)
    if needed > MAX_MOTION_DURATION:
        quick = line_duration(T_start, T_goal, max(speed, 1.0), accel)
        field, value, unit = _slow_field(mvvelo, mvacc, "mm/s", "mm/s²",
                                         speed_is_short=quick <= MAX_MOTION_DURATION)
        raise invalid(f"{field} is {value:g} {unit}: the {1000 * _length(T_start, T_goal):.1f} "
                      f"mm line would take {needed:.4g} s, above the limit of "
                      f"{MAX_MOTION_DURATION:g} s for one move")
    return needed


def turns(value: float) -> float:
    """A circular move's extra turns: 0–:data:`MAX_TURNS`, whole or partial."""
    n = finite("turns", value)
    if not 0.0 <= n <= MAX_TURNS:
        raise invalid(f"turns is {n:g}, expected 0–{MAX_TURNS:g} (extra circles after the end "
                      "point, whole or partial)")
    return n


def circular_move_duration(T_start: np.ndarray, T_mid: np.ndarray, T_end: np.ndarray,
                           speed: float, accel: float, n_turns: float, mode: int,
                           mvvelo: float, mvacc: float) -> float:
    """Duration (s) of the circular move ``T_start`` → ``T_mid`` → ``T_end`` (m) at ``speed``
    m/s and ``accel`` m/s² (request clamped to the model). Raises -2 for collinear points and
    naming ``mvvelo`` or ``mvacc`` when it would be longer than the limit."""
    try:
        needed = circle_duration(T_start, T_mid, T_end, speed, accel, n_turns, mode)
    except CommandRefused as refusal:
        raise invalid(refusal.message) from None
    if needed > MAX_MOTION_DURATION:
        quick = circle_duration(T_start, T_mid, T_end, max(speed, 1.0), accel, n_turns, mode)
        field, value, unit = _slow_field(mvvelo, mvacc, "mm/s", "mm/s²",
                                         speed_is_short=quick <= MAX_MOTION_DURATION)
        raise invalid(f"{field} is {value:g} {unit}: the arc would take {needed:.4g} s, above "
                      f"the limit of {MAX_MOTION_DURATION:g} s for one move")
    return needed


def _fits_at_any_speed(q_start, q_goal, accel) -> bool:
    """Would the move fit in the limit at any speed? Then the speed is what made it long."""
    quick = SyncJointProfile(q_start, q_goal, np.full_like(accel, 1e3), accel)
    return quick.predicted_duration <= MAX_MOTION_DURATION


def _slow_field(mvvelo: float, mvacc: float, v_unit: str, a_unit: str, *,
                speed_is_short: bool) -> tuple[str, float, str]:
    """The field to blame: the speed when a faster one would fit, else the acceleration."""
    return ("mvvelo", mvvelo, v_unit) if speed_is_short else ("mvacc", mvacc, a_unit)


def _length(T_start: np.ndarray, T_goal: np.ndarray) -> float:
    return float(np.linalg.norm(T_goal[:3, 3] - T_start[:3, 3]))

