"""A request's values checked before it is sent, and a request put together: the toolkit every
request encoder of this package uses (:mod:`.commands`, :mod:`.torque_sensor`,
:mod:`.servo_filters`, :mod:`.programs`). A value that would not make a request JAKA's SDK
sends raises :class:`~.errors.InvalidArgument` naming it (nothing is sent)."""
from __future__ import annotations

import math
from typing import Any, Dict, Optional

import numpy as np

from .errors import InvalidArgument
from .fields import Field

Request = Dict[str, Any]


def vector(values, n: int, what: str) -> np.ndarray:
    """``n`` finite numbers."""
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InvalidArgument(f"{what} must be {n} numbers; got {values!r}") from None
    if v.shape != (n,):
        raise InvalidArgument(f"{what} has {v.size} values, expected {n}")
    if not np.all(np.isfinite(v)):
        raise InvalidArgument(f"{what} has a value that is not finite: {v.tolist()}")
    return v


def number(value, what: str, positive: bool = False, lo: float = -math.inf,
           hi: float = math.inf) -> float:
    """A finite number (not a bool), > 0 where ``positive``, within [``lo``, ``hi``]."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidArgument(f"{what} must be a number; got {value!r}") from None
    if isinstance(value, bool) or not math.isfinite(x):
        raise InvalidArgument(f"{what} must be a finite number; got {value!r}")
    if positive and x <= 0.0:
        raise InvalidArgument(f"{what} must be > 0; got {x}")
    if not lo <= x <= hi:
        raise InvalidArgument(f"{what} = {x} is outside [{lo}, {hi}]")
    return x


def integer(value, what: str, lo: Optional[int] = 0, hi: Optional[int] = None) -> int:
    """An int (not a bool) within [``lo``, ``hi``] (None: unbounded that side)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InvalidArgument(f"{what} must be an integer; got {value!r}")
    i = int(value)
    if (lo is not None and i < lo) or (hi is not None and i > hi):
        raise InvalidArgument(f"{what} = {i} is outside [{'-∞' if lo is None else lo}, "
                              f"{'∞' if hi is None else hi}]")
    return i


def flag(on) -> int:
    """A flag as the wire writes it: 1 or 0."""
    return 1 if on else 0


def command(cmd_name: str, /, **fields) -> Request:
    """A request: ``cmdName`` first, then ``fields``."""
    return {Field.CMD_NAME: cmd_name, **fields}


def sorted_request(cmd_name: str, /, **fields) -> Request:
    """A request with its keys in sorted order, as JAKA's SDK writes them (jsoncpp)."""
    items = command(cmd_name, **fields)
    return {key: items[key] for key in sorted(items)}
