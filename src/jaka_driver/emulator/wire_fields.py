"""Reading a request's fields as a JAKA controller reads them: joints deg, poses mm + RPY deg,
keys in any order, unknown extra keys ignored. Each reader converts once, to SI, and raises
:class:`~.replies.Rejected` with ``errorCode`` "1" naming the field, the value and what
was expected when the field is missing or malformed.
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional

import numpy as np

from ..common.transforms import pose_mm_rpy_to_matrix
from ..protocol import units
from ..protocol.errors import ProtocolError
from ..protocol.fields import Field
from ..protocol.wire import as_flag, float_vector
from .replies import ERROR_REQUEST, Rejected

_SHOWN = 80   # characters of a bad value quoted in a refusal


def shown(value: Any) -> str:
    """``value`` quoted in a message, at most :data:`_SHOWN` characters of it."""
    text = repr(value)
    return text if len(text) <= _SHOWN else text[:_SHOWN] + "…"


def _refuse(req: Mapping, message: str) -> Rejected:
    return Rejected(f"{shown_name(req)}: {message}", ERROR_REQUEST)


def shown_name(req: Mapping) -> str:
    """The request's cmdName, as text of bounded length."""
    name = req.get(Field.CMD_NAME)
    return name[:_SHOWN] if isinstance(name, str) else shown(name)


def required(req: Mapping, key: str, default: Any = None) -> Any:
    """The raw value of ``key``; ``default`` when absent and a default is given."""
    if key in req:
        return req[key]
    if default is not None:
        return default
    raise _refuse(req, f"missing field {key!r}")


def vector(req: Mapping, key: str, n: int) -> np.ndarray:
    raw = required(req, key)
    v = float_vector(raw, n)
    if v is None:
        raise _refuse(req, f"{key!r} must be {n} finite numbers; got {shown(raw)}")
    return v


def number(req: Mapping, key: str, default: Optional[float] = None, lo: float = -math.inf,
           hi: float = math.inf, positive: bool = False) -> float:
    raw = required(req, key, default)
    try:   # a number, or a string holding one (some clients send "0.5")
        x = math.nan if isinstance(raw, bool) else float(raw)
    except (TypeError, ValueError, OverflowError):
        x = math.nan
    if not math.isfinite(x) or not lo <= x <= hi or (positive and x <= 0):
        bound = "> 0" if positive else f"in [{lo:g}, {hi:g}]"
        raise _refuse(req, f"{key!r} must be a number {bound}; got {shown(raw)}")
    return x


def integer(req: Mapping, key: str, lo: int, hi: int, default: Optional[int] = None) -> int:
    raw = required(req, key, default)
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw) \
            or int(raw) != raw or not lo <= int(raw) <= hi:
        raise _refuse(req, f"{key!r} must be an integer in [{lo}, {hi}]; got {shown(raw)}")
    return int(raw)


def flag(req: Mapping, key: str, default: Any = None) -> bool:
    raw = required(req, key, default)
    try:
        return as_flag(raw, key)
    except ProtocolError:
        raise _refuse(req, f"{key!r} should be a flag (0/1, true/false); got "
                           f"{shown(raw)}") from None


def text(req: Mapping, key: str, default: Optional[str] = None, longest: int = 255) -> str:
    raw = required(req, key, default)
    if not isinstance(raw, str) or len(raw) > longest:
        raise _refuse(req, f"{key!r} must be a string of at most {longest} characters; got "
                           f"{shown(raw)}")
    return raw


def joints(req: Mapping, key: str = Field.JOINT_POSITION) -> np.ndarray:
    """Wire joints (deg) → rad."""
    return units.joints_from_wire(vector(req, key, 6))


def pose(req: Mapping, key: str) -> np.ndarray:
    """Wire pose (mm, RPY deg) → 4x4 (m)."""
    return pose_mm_rpy_to_matrix(units.pose_from_wire(vector(req, key, 6)))
