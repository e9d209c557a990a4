"""A joint target against the model's limits: position, and speed over a step. The driver's
checks (:mod:`jaka_driver.driver.checks`), the twin, the emulator and the controller backend ask
the same two questions, each answering in its own terms.

Units: joints rad, speeds rad/s, time s.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .constants import SERVO_CYCLE
from .models import RobotModel


def outside_limits(model: RobotModel, q: np.ndarray, tolerance: float = 0.0) -> Optional[int]:
    """The first joint of ``q`` (rad) outside the model's position limits widened by
    ``tolerance`` (rad; a wire in degrees needs ~1e-9 for its round trip), or None."""
    outside = (q < model.lower - tolerance) | (q > model.upper + tolerance)
    return int(np.argmax(outside)) if outside.any() else None


#: rad: a joint this near a position limit is "on its limit" (what a controller's status packet
#: reports as ``on_soft_limit``, and ``is_on_limit`` answers)
ON_LIMIT_MARGIN = float(np.radians(0.1))


def on_limit(model: RobotModel, q: np.ndarray) -> bool:
    """A joint of ``q`` (rad) within :data:`ON_LIMIT_MARGIN` of its position limit, or past it."""
    q = np.asarray(q, float)
    return bool(np.any((q <= model.lower + ON_LIMIT_MARGIN) | (q >= model.upper - ON_LIMIT_MARGIN)))


def fastest_step(model: RobotModel, q_from: np.ndarray, q_to: np.ndarray,
                 seconds: float = SERVO_CYCLE) -> Optional[tuple[int, float]]:
    """(joint, speed rad/s) of the joint that most exceeds its speed limit when going from
    ``q_from`` to ``q_to`` (rad) in ``seconds``, or None when every joint is within its limit."""
    step = np.abs(np.asarray(q_to) - np.asarray(q_from)) / seconds
    worst = int(np.argmax(step / model.max_velocity))
    return (worst, float(step[worst])) if step[worst] > model.max_velocity[worst] else None
