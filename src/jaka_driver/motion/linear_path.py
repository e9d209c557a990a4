"""Cartesian straight-line planning for ``linear_move``: the whole path is sampled and checked
(IK, joint limits, joint speed) before anything moves (docs/interface.md, "linear_move").

Frames and units: ``T_start`` and ``T_goal`` are 4x4 homogeneous TCP poses in one frame
(whatever frame ``ik`` expects), positions in metres. Speeds m/s and rad/s, accelerations m/s²
and rad/s², joints rad and rad/s, time s. Messages give positions in mm, the driver's unit.

Kinematics is injected: ``ik(T, seed) -> q or None`` returns the joint solution nearest
``seed`` (rad) or None when there is none.
"""
from __future__ import annotations

import math
from typing import Callable, Optional

import numpy as np

from ..common.constants import MAX_TOOL_ROTATION_ACCEL, MAX_TOOL_ROTATION_SPEED, SERVO_CYCLE
from ..common.results import Code, CommandRefused
from ..common.transforms import rotation_angle_between, slerp
from .profiles import TrapezoidProfile
from .trajectory import MAX_MOTION_DURATION, JointTrajectory, time_grid

# Default orientation limits. A rotation is given the speed a point ROTATION_RADIUS from the
# axis would have at the linear speed (so a slow move also turns slowly), capped at the
# driver's tool rotation limits so that a fast move does not whip the tool round.
ROTATION_RADIUS = 0.1               # m

# Translations and rotations below these are "no motion" (float noise of an FK round trip).
_ZERO_LENGTH = 1e-12                # m
_ZERO_ANGLE = 1e-12                 # rad
# Joint speed and limit checks forgive this much float noise.
_SPEED_RTOL = 1e-9
_LIMIT_TOL = 1e-9                   # rad

IK = Callable[[np.ndarray, np.ndarray], Optional[np.ndarray]]


def orientation_limits(speed: float, accel: float) -> tuple[float, float]:
    """The default orientation limits of a line at ``speed`` m/s and ``accel`` m/s²: (angular
    speed rad/s, angular acceleration rad/s²). Every backend moves a line's orientation at
    these — the twin in :func:`plan_linear_move`, a controller through ``moveL``'s ``ori_vel``
    and ``ori_acc``."""
    return (min(speed / ROTATION_RADIUS, MAX_TOOL_ROTATION_SPEED),
            min(accel / ROTATION_RADIUS, MAX_TOOL_ROTATION_ACCEL))


class PlanningError(CommandRefused):
    """A linear move cannot be planned. ``code`` is -4 (:attr:`Code.IK_FAILED`: unreachable,
    singular, or a joint limit on the path) or -2 (:attr:`Code.INVALID_PARAMETER`); the message
    says what failed, where on the path, and the limit."""


def _invalid(message: str) -> PlanningError:
    return PlanningError(Code.INVALID_PARAMETER, message)


def _positive(name: str, value: float, unit: str) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise _invalid(f"{name} is {value:g} {unit}, expected a finite value > 0")
    return value


def _pose(name: str, T) -> np.ndarray:
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise _invalid(f"{name} must be a finite 4x4 homogeneous matrix, got shape {T.shape}")
    R = T[:3, :3]
    if np.max(np.abs(R.T @ R - np.eye(3))) > 1e-6 or np.linalg.det(R) <= 0.0:
        raise _invalid(f"{name} has a rotation part that is not a proper rotation matrix")
    return T


def _joints(name: str, value, n: int) -> np.ndarray:
    vec = np.asarray(value, dtype=float)
    if vec.shape != (n,) or not np.all(np.isfinite(vec)):
        raise _invalid(f"{name} must be {n} finite values, got shape {vec.shape}")
    return vec


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
    speed = _positive("speed", speed, "m/s")
    accel = _positive("accel", accel, "m/s²")
    cycle = _positive("cycle", cycle, "s")
    default_speed, default_accel = orientation_limits(speed, accel)
    angular_speed = default_speed if angular_speed is None \
        else _positive("angular_speed", angular_speed, "rad/s")
    angular_accel = default_accel if angular_accel is None \
        else _positive("angular_accel", angular_accel, "rad/s²")
    T_start, T_goal = _pose("T_start", T_start), _pose("T_goal", T_goal)
    q_start = np.asarray(q_start, dtype=float)
    if q_start.ndim != 1 or q_start.shape[0] == 0:
        raise _invalid(f"q_start must be a 1-D array of joint angles, got shape {q_start.shape}")
    n = q_start.shape[0]
    q_start = _joints("q_start", q_start, n)
    lower, upper = _joints("lower", lower, n), _joints("upper", upper, n)
    v_max = _joints("v_max", v_max, n)
    if np.any(v_max <= 0.0):
        raise _invalid(f"v_max must be > 0 for every joint, got {v_max.tolist()}")
    ref_q = None if ref_q is None else _joints("ref_q", ref_q, n)

    law = _path_law(T_start, T_goal, speed, accel, angular_speed, angular_accel)
    if law is None:
        return JointTrajectory(times=np.zeros(1), q=q_start[None, :], qd=np.zeros((1, n)),
                               tcp=T_goal[None, :, :])
    if law.duration > MAX_MOTION_DURATION:
        raise _invalid(f"the line would take {law.duration:.4g} s at {speed * 1000:g} mm/s, "
                       f"{accel * 1000:g} mm/s², above the limit of {MAX_MOTION_DURATION:g} s "
                       "for one move")
    times = time_grid(law.duration, cycle)
    p0, p1 = T_start[:3, 3], T_goal[:3, 3]
    u = np.asarray(law.sample(times)[0])

    tcp = np.tile(np.eye(4), (times.shape[0], 1, 1))
    tcp[:, :3, 3] = p0 + u[:, None] * (p1 - p0)
    tcp[:, :3, :3] = slerp(T_start[:3, :3], T_goal[:3, :3], u)
    tcp[-1] = T_goal                    # land on the target, not on its rounding

    q = np.empty((times.shape[0], n))
    q[0] = q_start
    for k in range(1, times.shape[0]):
        seed = ref_q if (k == 1 and ref_q is not None) else q[k - 1]
        q[k] = _solve(ik, tcp[k], seed, n, u[k])
        _check_limits(q[k], lower, upper, u[k])
        _check_speed(q[k] - q[k - 1], times[k] - times[k - 1], v_max, u[k],
                     first=(k == 1 and ref_q is not None))

    qd = np.gradient(q, times, axis=0)
    qd[0] = qd[-1] = 0.0
    return JointTrajectory(times=times, q=q, qd=qd, tcp=tcp)


def line_duration(T_start, T_goal, speed: float, accel: float) -> float:
    """Duration (s) of the straight line from ``T_start`` to ``T_goal`` (4x4, m) at ``speed``
    m/s and ``accel`` m/s² with the default orientation limits, as :func:`plan_linear_move`
    would time it — without sampling it. 0 when the poses coincide."""
    speed = _positive("speed", speed, "m/s")
    accel = _positive("accel", accel, "m/s²")
    law = _path_law(_pose("T_start", T_start), _pose("T_goal", T_goal), speed, accel,
                    *orientation_limits(speed, accel))
    return 0.0 if law is None else law.duration


def _path_law(T_start: np.ndarray, T_goal: np.ndarray, speed: float, accel: float,
              angular_speed: float, angular_accel: float) -> Optional[TrapezoidProfile]:
    """The time law of the path parameter u ∈ [0, 1], or None when there is nothing to move.
    A unit of u is the line's length (m) and its rotation angle (rad): u's limits are the
    tighter of the translation's and the rotation's."""
    length = float(np.linalg.norm(T_goal[:3, 3] - T_start[:3, 3]))
    angle = float(rotation_angle_between(T_start[:3, :3], T_goal[:3, :3]))
    if length <= _ZERO_LENGTH and angle <= _ZERO_ANGLE:
        return None
    u_speed = min(speed / length if length > _ZERO_LENGTH else math.inf,
                  angular_speed / angle if angle > _ZERO_ANGLE else math.inf)
    u_accel = min(accel / length if length > _ZERO_LENGTH else math.inf,
                  angular_accel / angle if angle > _ZERO_ANGLE else math.inf)
    return TrapezoidProfile(1.0, u_speed, u_accel)


def _where(u: float) -> str:
    return f"{100.0 * u:.1f} % of the path"


def _solve(ik: IK, T: np.ndarray, seed: np.ndarray, n: int, u: float) -> np.ndarray:
    solution = ik(T, seed.copy())
    if solution is not None:
        solution = np.asarray(solution, dtype=float)
        if solution.shape != (n,):
            raise ValueError(f"ik returned shape {solution.shape}, expected ({n},)")
    if solution is None or not np.all(np.isfinite(solution)):
        x, y, z = 1000.0 * T[:3, 3]
        raise PlanningError(Code.IK_FAILED, f"no IK solution at {_where(u)} "
                            f"(x={x:.1f}, y={y:.1f}, z={z:.1f} mm)")
    return solution


def _check_limits(q: np.ndarray, lower: np.ndarray, upper: np.ndarray, u: float) -> None:
    excess = np.maximum(lower - q, q - upper)
    i = int(np.argmax(excess))
    if excess[i] > _LIMIT_TOL:
        raise PlanningError(Code.IK_FAILED, f"joint_{i + 1} would leave its limits at "
                            f"{_where(u)}: {q[i]:.3f} rad is outside "
                            f"[{lower[i]:.2f}, {upper[i]:.2f}]")


def _check_speed(step: np.ndarray, dt: float, v_max: np.ndarray, u: float,
                 first: bool) -> None:
    needed = np.abs(step) / dt
    ratio = needed / v_max
    i = int(np.argmax(ratio))
    if ratio[i] > 1.0 + _SPEED_RTOL:
        cause = "ref_joint selects another configuration than the arm's?" if first \
            else "singularity?"
        raise PlanningError(Code.IK_FAILED, f"joint_{i + 1} would need {needed[i]:.2f} rad/s "
                            f"at {_where(u)}, limit {v_max[i]:.2f} rad/s ({cause})")
