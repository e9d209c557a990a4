"""How one cycle of a jog moves the setpoint, for each coordinate system
(docs/interface.md, "jog").

A step function takes the current setpoint (rad) and the distance to travel this cycle along
the jog axis (rad, or m for X/Y/Z) and returns the next setpoint, or None when the jog must
end (limit reached, no IK, over-speed near a singularity).
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from ..common.models import RobotModel
from ..kinematics import Kinematics
from ..motion.velocity_jog import displaced_pose

Step = Callable[[np.ndarray, float], Optional[np.ndarray]]


def joint_step(model: RobotModel, axis: int, direction: int, brake: Callable[[], None],
               accel: float, cycle: float) -> Step:
    """Move one joint; start braking when the remaining distance to the limit is the braking
    distance, so the jog comes to rest at the limit instead of hitting it."""
    limit = model.upper[axis] if direction > 0 else model.lower[axis]

    def step(q_sp: np.ndarray, distance: float) -> Optional[np.ndarray]:
        remaining = (limit - q_sp[axis]) * direction
        speed = distance / cycle
        if remaining <= speed * speed / (2 * accel) + distance:
            brake()
        if remaining <= 1e-9:
            return None
        q = q_sp.copy()
        q[axis] += direction * min(distance, remaining)
        return q

    return step


def cartesian_step(kin: Kinematics, model: RobotModel, axis: int, direction: int,
                   in_tool: bool, tool: np.ndarray, cycle: float) -> Step:
    """Translate along / rotate about a base (``in_tool`` False) or tool axis, at the TCP."""
    unit = np.zeros(6)
    unit[axis] = direction

    def step(q_sp: np.ndarray, distance: float) -> Optional[np.ndarray]:
        target = displaced_pose(kin.tcp_pose(q_sp, tool), unit * distance, in_tool)
        solution = kin.ik(target, seed=q_sp, tool=tool)
        if not solution.success:
            return None
        q = solution.q
        if np.any(q < model.lower) or np.any(q > model.upper):
            return None
        if np.any(np.abs(q - q_sp) > model.max_velocity * cycle):
            return None
        return q

    return step
