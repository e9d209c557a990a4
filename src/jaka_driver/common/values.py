"""A request's values read as numbers, in one place for every layer that checks one — the
driver's door and the emulator's commands alike (a controller's value ranges are the arm's, not
the driver's): each raises :class:`~.results.CommandRefused` (-2) naming the field, the value
and what was expected, and returns the value as numpy / Python types."""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from .joint_limits import outside_limits
from .models import RobotModel
from .results import invalid


def all_finite(values: np.ndarray) -> bool:
    """No NaN or infinity in ``values`` (an array of any shape). A plain loop, not
    ``np.all(np.isfinite(...))``: it runs on every status packet, on a thread that has just
    woken, where numpy's reduction over a few numbers costs 20-40 µs (jaka_driver.common.
    joint_limits says how it was measured)."""
    return all(map(math.isfinite, np.asarray(values, float).ravel().tolist()))


def unit_text(unit: str) -> str:
    """`` unit`` after a value in a message, or nothing."""
    return f" {unit}" if unit else ""


def vector(name: str, values: Sequence[float], n: int = 6) -> np.ndarray:
    """``values`` as a float array of exactly ``n`` finite numbers."""
    try:
        length = len(values)
    except TypeError:
        raise invalid(f"{name} must be a list of {n} numbers") from None
    if length != n:
        raise invalid(f"{name} has {length} values, expected {n}")
    out = np.asarray(values, dtype=float)
    for i, v in enumerate(out):
        if not math.isfinite(v):
            raise invalid(f"{name}[{i}] is {v}, expected a finite number")
    return out


def finite(name: str, value: float, unit: str = "") -> float:
    value = float(value)
    if not math.isfinite(value):
        raise invalid(f"{name} is {value}{unit_text(unit)}, expected a finite number")
    return value


def joint_targets(name: str, values: Sequence[float], model: RobotModel) -> np.ndarray:
    """Six joint angles (rad) inside the model's position limits."""
    q = vector(name, values)         # finite: the limits comparison below sees no NaN
    i = outside_limits(model, q)
    if i is not None:
        raise invalid(f"{model.joint_names[i]} target {q[i]:.4f} rad is outside "
                      f"[{model.lower[i]:.2f}, {model.upper[i]:.2f}] rad")
    return q


def integer_in(name: str, value: int, lo: int, hi: int) -> int:
    if not lo <= int(value) <= hi:
        raise invalid(f"{name} is {value}, expected {lo}–{hi}")
    return int(value)
