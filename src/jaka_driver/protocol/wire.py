"""JSON on the wire: the two layouts (compact requests, spaced controller output), and decoding
one object from the head of a byte buffer.

Clients send compact JSON; a controller answers and streams in the layout of Python's
``json.dumps`` default, a space after every ``:`` and ``,`` — and public clients search the text
for ``"errorCode": "``, so a server must keep that layout (docs/protocol.md, "Framing and
layout"). A reader must accept either layout.

Both JAKA ports carry bare JSON objects with no delimiter between them, so
a reader cannot split on newlines: it parses one value and learns where it ended. That is
``json.JSONDecoder.raw_decode``, which works on ``str``; the helpers here translate its character
offset back to a byte offset, which differs from it as soon as a non-ASCII character (a Chinese
``errmsg``) precedes the end.

It also reads the loosely typed values the controller sends (flags as bools, numbers or words).
"""
from __future__ import annotations

import json
from typing import Any, Tuple

import numpy as np

from .errors import ProtocolError

_DECODER = json.JSONDecoder()
# surrogateescape maps an invalid byte to one lone surrogate and back, so the byte length of a
# decoded prefix can be recovered exactly even from damaged input.
_ERRORS = "surrogateescape"


def _plain(value: Any) -> Any:
    """``json`` default hook: numpy arrays and scalars become plain Python values."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def encode_json(obj: Any) -> bytes:
    """Compact JSON, the layout of requests (``{"cmdName":"power_on"}``), UTF-8, non-ASCII kept
    as is. NaN and infinity are refused: they are not JSON."""
    return json.dumps(obj, separators=(",", ":"), ensure_ascii=False, allow_nan=False,
                      default=_plain).encode("utf-8")


def encode_json_spaced(obj: Any) -> bytes:
    """The controller's layout of replies and status packets: ``", "`` and ``": "`` between
    items (``{"errorCode": "0", "errorMsg": ""}``), UTF-8, NaN and infinity refused."""
    return json.dumps(obj, separators=(", ", ": "), ensure_ascii=False, allow_nan=False,
                      default=_plain).encode("utf-8")


def decode_first_object(buf: bytes) -> Tuple[Any, int]:
    """Parse the JSON value that starts at ``buf[0]``; return it and the number of bytes it
    used. Raises ``json.JSONDecodeError`` when the head of ``buf`` is not (yet) a whole value."""
    text = bytes(buf).decode("utf-8", _ERRORS)
    obj, end = _DECODER.raw_decode(text)
    if text.isascii():
        return obj, end
    return obj, len(text[:end].encode("utf-8", _ERRORS))


def clean_text(value: Any) -> str:
    """A wire string as text that can always be re-encoded: bytes that were not UTF-8 (kept as
    lone surrogates by the decoder) become U+FFFD. ``None`` becomes ``""``."""
    if value is None:
        return ""
    text = str(value)
    try:
        return text.encode("utf-8", _ERRORS).decode("utf-8", "replace")
    except UnicodeEncodeError:   # a surrogate that came from a JSON escape, not from a byte
        return text.encode("utf-8", "replace").decode("utf-8")


_TRUE = {"1", "true", "on", "yes", "powered_on", "robot_enabled", "enabled"}
_FALSE = {"0", "false", "off", "no", "powered_off", "robot_disabled", "disabled"}


def as_flag(value: Any, what: str) -> bool:
    """A wire flag → bool. Accepts bools, numbers and the strings clients report
    (``"1"``, ``"powered_on"``, ``"robot_enabled"``, and their opposites)."""
    if isinstance(value, (bool, int, float)):
        return bool(value)
    if isinstance(value, str):
        text = value.strip().lower()
        if text in _TRUE:
            return True
        if text in _FALSE:
            return False
    raise ProtocolError(f"{what} should be a flag; got {value!r}")
