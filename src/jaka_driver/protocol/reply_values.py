"""A reply's fields read as JAKA's SDK reads them: the toolkit every reply accessor of this
package uses (:mod:`.replies`, :mod:`.torque_sensor`, :mod:`.programs`), and :class:`Reply`
itself (:func:`.replies.parse_reply` makes one). A refusal raises
:class:`~.errors.CommandRejected`; a field missing or of the wrong type or shape raises
:class:`~.errors.ProtocolError` (where the SDK would abort its client)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from .errors import CommandRejected, ProtocolError
from .wire import float_vector


@dataclass(frozen=True)
class Reply:
    """One controller reply. ``ok`` is ``error_code == "0"``; ``error_msg`` is the controller's
    own text, kept verbatim; ``fields`` are the remaining keys, in wire units, read-only."""

    cmd_name: str
    ok: bool
    error_code: str
    error_msg: str
    fields: Mapping[str, Any]


def field(reply: Reply, *keys: str) -> Any:
    if not reply.ok:
        raise CommandRejected(reply)
    for key in keys:
        if key in reply.fields:
            return reply.fields[key]
    raise ProtocolError(f"reply to {reply.cmd_name!r} has no {' or '.join(map(repr, keys))}; "
                        f"its fields are {sorted(reply.fields)}")


def int_field(reply: Reply, *keys: str) -> int:
    raw = field(reply, *keys)
    try:
        return int(raw)
    except (TypeError, ValueError, OverflowError):
        raise ProtocolError(f"{keys[0]!r} in the reply to {reply.cmd_name!r} is not an "
                            f"integer: {raw!r}") from None


def number(reply: Reply, key: str) -> float:
    raw = field(reply, key)
    try:
        value = float(raw)
    except (TypeError, ValueError, OverflowError):
        value = math.nan
    if isinstance(raw, bool) or not math.isfinite(value):
        raise ProtocolError(f"{key!r} in the reply to {reply.cmd_name!r} is not a finite "
                            f"number: {raw!r}")
    return value


def wire_vector(reply: Reply, key: str, n: int) -> np.ndarray:
    raw = field(reply, key)
    v = float_vector(raw, n)
    if v is None:
        raise ProtocolError(f"{key!r} in the reply to {reply.cmd_name!r} should be {n} finite "
                            f"numbers; got {raw!r}")
    return v


def table(reply: Reply, key: str, rows: int, columns: int) -> np.ndarray:
    """A reply field that must be a JSON array of ``rows`` arrays of ``columns`` finite numbers
    (``rows`` 0: any number of rows, at least one) → float array (rows, columns)."""
    raw = field(reply, key)
    where = f"{key!r} in the reply to {reply.cmd_name!r}"
    if not isinstance(raw, list) or not raw or (rows and len(raw) != rows):
        shape = f"{rows} rows" if rows else "rows"
        raise ProtocolError(f"{where} should be an array of {shape} of {columns} numbers; got "
                            f"{str(raw)[:120]}")
    values = []
    for i, row in enumerate(raw):
        if not isinstance(row, list) or len(row) != columns or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in row):
            raise ProtocolError(f"{where}: row {i} should be {columns} numbers; got "
                                f"{str(row)[:120]}")
        values.append([float(v) for v in row])
    out = np.asarray(values)
    if not np.all(np.isfinite(out)):
        raise ProtocolError(f"{where} has a value that is not finite")
    return out
