"""How long a requested move will take, checked at the door before anything is planned.

A move slower than :data:`~jaka_driver.motion.trajectory.MAX_MOTION_DURATION` (10 min) comes
from a units mistake (``mvvelo`` 1e-7, ``mvtime`` 3e38) and is refused; so is an ``mvtime``
shorter than the move needs. The planners refuse both too, but only the request knows which
field was at fault: these checks name it, with its value and the limit (docs/interface.md,
"Result codes": -2 and a message naming the field). Both backends get the same answer.

Units: joints rad, speeds rad/s or mm/s, accelerations rad/s² or mm/s², poses 4x4 in m,
durations s.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .motion.linear_path import line_duration
from .motion.profiles import SyncJointProfile
from .motion.trajectory import MAX_MOTION_DURATION
from .results import invalid

# A requested duration this little shorter than the minimum is float noise (profiles.py).
_DURATION_RTOL = 1e-9


def check_joint_move(q_start: np.ndarray, q_goal: np.ndarray, speed: np.ndarray,
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


def check_linear_move(T_start: np.ndarray, T_goal: np.ndarray, speed: float, accel: float,
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
