"""A joint target against the model's limits: position, and speed over a step. The driver's
checks (:mod:`jaka_driver.driver.checks`), the twin, the emulator and the controller backend ask
the same two questions, each answering in its own terms.

Units: joints rad, speeds rad/s, time s.

The questions are asked in plain Python over six floats, not with numpy: they run on every
servo target and every sample, each time on a thread that has just woken, with the caches the
other threads left. There a numpy reduction (``any``, ``argmax``) over six numbers cost 21–40 µs
and an element-wise operation 8–14 µs, against 9 µs for a plain loop (this 2-core machine,
medians of 200 calls 8 ms apart beside a thread streaming 32 MB; hot, all are 1–4 µs). The
answers are the same: the same IEEE operations in the same order, the first joint on ties, and
a NaN is never outside a limit (as numpy's comparisons say).
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np

from .constants import SERVO_CYCLE
from .models import RobotModel


def _floats(values: Sequence[float] | np.ndarray) -> list[float]:
    return values.tolist() if isinstance(values, np.ndarray) else [float(v) for v in values]


def outside_limits(model: RobotModel, q: np.ndarray, tolerance: float = 0.0) -> Optional[int]:
    """The first joint of ``q`` (rad) outside the model's position limits widened by
    ``tolerance`` (rad; a wire in degrees needs ~1e-9 for its round trip), or None."""
    for i, (v, lo, hi) in enumerate(zip(_floats(q), model.lower.tolist(),
                                        model.upper.tolist())):
        if v < lo - tolerance or v > hi + tolerance:
            return i
    return None


#: rad: a joint this near a position limit is "on its limit" (what a controller's status packet
#: reports as ``on_soft_limit``, and ``is_on_limit`` answers)
ON_LIMIT_MARGIN = float(np.radians(0.1))


def on_limit(model: RobotModel, q: np.ndarray) -> bool:
    """A joint of ``q`` (rad) within :data:`ON_LIMIT_MARGIN` of its position limit, or past it."""
    return any(v <= lo + ON_LIMIT_MARGIN or v >= hi - ON_LIMIT_MARGIN
               for v, lo, hi in zip(_floats(q), model.lower.tolist(), model.upper.tolist()))


def fastest_step(model: RobotModel, q_from: np.ndarray, q_to: np.ndarray,
                 seconds: float = SERVO_CYCLE) -> Optional[tuple[int, float]]:
    """(joint, speed rad/s) of the joint that most exceeds its speed limit when going from
    ``q_from`` to ``q_to`` (rad) in ``seconds``, or None when every joint is within its limit."""
    worst, worst_ratio, worst_step = 0, -math.inf, 0.0
    limits = model.max_velocity.tolist()
    for i, (a, b, limit) in enumerate(zip(_floats(q_from), _floats(q_to), limits)):
        step = abs(b - a) / seconds
        ratio = step / limit
        if ratio != ratio:              # NaN: numpy's argmax picks the first, never too fast
            return None
        if ratio > worst_ratio:
            worst, worst_ratio, worst_step = i, ratio, step
    return (worst, worst_step) if worst_step > limits[worst] else None
