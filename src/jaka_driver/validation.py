"""Checks at the door: each raises :class:`CommandRefused` (-2) with a message that names the
field, the value and the limit, and returns the value converted to numpy / Python types."""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from .models import RobotModel
from .results import invalid

#: A requested speed or acceleration above this many times the model's limit is taken for a
#: unit mistake (deg for rad, m for mm) and refused instead of silently clamped.
ABSURD_FACTOR = 10.0

IO_SIGNALS = ("digital", "analog")
IO_TYPES = {0: "cabinet", 1: "tool", 2: "extension"}
IO_PATHS = {0: "input", 1: "output"}


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
        raise invalid(f"{name} is {value}{_u(unit)}, expected a finite number")
    return value


def joint_targets(name: str, values: Sequence[float], model: RobotModel) -> np.ndarray:
    """Six joint angles (rad) inside the model's position limits."""
    q = vector(name, values)
    for i, (v, lo, hi) in enumerate(zip(q, model.lower, model.upper)):
        if not lo <= v <= hi:
            raise invalid(f"{model.joint_names[i]} target {v:.4f} rad is outside "
                          f"[{lo:.2f}, {hi:.2f}] rad")
    return q


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


def integer_in(name: str, value: int, lo: int, hi: int) -> int:
    if not lo <= int(value) <= hi:
        raise invalid(f"{name} is {value}, expected {lo}–{hi}")
    return int(value)


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
    where = f"{IO_TYPES[int(io_type)]} {signal} {IO_PATHS[int(path)]}s"
    if count == 0:
        raise invalid(f"the {where} do not exist on {model.name} (index {index})")
    if not 0 <= int(index) < count:
        raise invalid(f"index is {index}, {where} are 0–{count - 1}")


def _u(unit: str) -> str:
    return f" {unit}" if unit else ""
