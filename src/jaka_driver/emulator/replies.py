"""A command reply: its content (what a handler answers, :class:`Answer`, or the refusal it
raises, :class:`Rejected`; the reply objects, :func:`success_reply` and :func:`error_reply`)
and its text (:func:`encode_reply`).

Every reply begins ``errorCode``, ``errorMsg``, ``cmdName`` in that order, a refusal too, as
recorded on a real controller; ``errorCode`` is a string: "0" success, "1" a wrong request
(unknown command, missing or malformed field, malformed JSON), "2" a command refused in the
current state, and what a real controller was recorded answering where it answered otherwise
(:class:`RecordedReply`).

The text is the controller's (docs/protocol.md, "Framing and layout"): a space after every ``:``
and ``,`` (public clients search the text for ``"errorCode": "``), keys in the order given,
every non-integer number with 6 decimals (``482.000000``, as recorded on a Zu 5s with firmware
1.5.14), integers and bools as they are.

Status packets keep Python's shortest float form (:func:`~jaka_driver.protocol.encode_status`):
the recorded packet and the fixture written from it carry plain numbers (``35.6``, ``1.0``), the
6-decimal form is recorded for replies only, and a packet goes out up to 125 times a second. The
one reply that is a packet, ``get_data``, is written as the packet is (:class:`PlainFloats`): no
real ``get_data`` reply is on record, and with 6 decimals its several hundred zeros no longer fit
the 8192-byte read of a client tested on a real controller.

Strings are UTF-8; a lone surrogate (a ``\\ud800`` escape in a request, echoed in an error
message) becomes ``?`` rather than making the reply unencodable.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional

import numpy as np

from ..protocol.fields import ERROR_CODE_EXCEPTION, ERROR_CODE_FAILED, ERROR_CODE_OK, Field

#: ``errorCode`` strings of the emulator. "1": the request itself is wrong (unknown command,
#: missing or malformed field); "2": a valid command refused in the current state.
ERROR_REQUEST = ERROR_CODE_EXCEPTION
ERROR_REFUSED = ERROR_CODE_FAILED


class Rejected(Exception):
    """A command the controller refuses: ``code`` (``errorCode``) and ``message``
    (``errorMsg``) of its error reply."""

    def __init__(self, message: str, code: str = ERROR_REFUSED):
        super().__init__(message)
        self.code = code
        self.message = message


@dataclass
class Answer:
    """What a handler answers on success: the reply's fields after the first three, and what
    the connection does next: ``then`` is None, ``"close"`` (this connection) or
    ``"drop_all"`` (every connection)."""

    fields: Dict[str, Any] = field(default_factory=dict)
    then: Optional[str] = None


def done(_result: Any = None) -> Answer:
    """The answer of a command whose success has no fields (its controller call's return value
    is not part of the reply)."""
    return Answer()


class RecordedReply(Exception):
    """Raised by a handler whose command a real controller was recorded answering with
    ``reply`` exactly (keys included or left out as recorded)."""

    def __init__(self, reply: Dict[str, Any]):
        super().__init__(reply.get(Field.ERROR_MSG, ""))
        self.reply = reply


class PlainFloats(dict):
    """Reply fields written as a status packet writes its numbers, floats in their shortest
    round-trip form (``35.6``, ``0.0``), not with a reply's 6 decimals: ``get_data``'s, which are
    the packet's. A reply made from them (:func:`success_reply`) is one too."""


def success_reply(name: str, fields: Mapping[str, Any]) -> Dict[str, Any]:
    reply: Dict[str, Any] = PlainFloats() if isinstance(fields, PlainFloats) else {}
    reply.update({Field.ERROR_CODE: ERROR_CODE_OK, Field.ERROR_MSG: "", Field.CMD_NAME: name})
    reply.update(fields)
    return reply


def error_reply(name: Any, message: str, code: str = ERROR_CODE_EXCEPTION) -> Dict[str, Any]:
    """A refusal in the recorded key order. ``name`` is echoed as ``cmdName`` when it is a
    string (at most 80 characters of it), else ``""``."""
    name = name[:80] if isinstance(name, str) else ""
    return {Field.ERROR_CODE: code, Field.ERROR_MSG: message, Field.CMD_NAME: name}


def encode_reply(reply: Mapping[str, Any]) -> bytes:
    """``reply`` in the controller's text layout, UTF-8; floats with 6 decimals, or as the
    status packet writes them when ``reply`` is :class:`PlainFloats`."""
    if all(type(key) is str and type(value) is str for key, value in reply.items()):
        # Most replies (every acknowledged motion and servo command) hold strings only, which
        # json's C encoder writes in this very layout (", " and ": ") in a fifth of the time.
        return json.dumps(dict(reply), ensure_ascii=False).encode("utf-8", "replace")
    parts: List[str] = []
    _write(reply, parts, _plain if isinstance(reply, PlainFloats) else _six_decimals)
    return "".join(parts).encode("utf-8", "replace")


def _six_decimals(value: float) -> str:
    text = f"{value:.6f}"
    return "0.000000" if text == "-0.000000" else text   # no sign on a zero


def _plain(value: float) -> str:
    return json.dumps(value)        # the shortest text that reads back as the same double


def _write(value: Any, out: List[str], real=_six_decimals) -> None:
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (bool, str)):
        out.append(json.dumps(value, ensure_ascii=False))
    elif isinstance(value, int):
        out.append(str(value))
    elif isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{value!r} is not a JSON number")
        out.append(real(value))
    elif isinstance(value, Mapping):
        out.append("{")
        for i, (key, item) in enumerate(value.items()):
            if i:
                out.append(", ")
            out.append(json.dumps(str(key), ensure_ascii=False))
            out.append(": ")
            _write(item, out, real)
        out.append("}")
    elif isinstance(value, (list, tuple)):
        out.append("[")
        for i, item in enumerate(value):
            if i:
                out.append(", ")
            _write(item, out, real)
        out.append("]")
    else:
        raise TypeError(f"{type(value).__name__} is not JSON serialisable")
