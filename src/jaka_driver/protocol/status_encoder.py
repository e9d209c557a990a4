"""Status packets written as a controller writes them (server side: the emulator): ``len``
first and equal to the packet's own length in bytes, spaces after ``:`` and ``,``
(docs/protocol.md, "Status packet")."""
from __future__ import annotations

from json.encoder import encode_basestring
from typing import Any, Dict, Mapping, Tuple

from .fields import StatusField as S
from .wire import encode_json_spaced


def encode_status(fields: Mapping[str, Any]) -> bytes:
    """Server side: one status packet in the controller's layout (``{"len": N, ...}``, spaces
    after ``:`` and ``,``) with ``len`` first and equal to the packet's own length in bytes, the
    ``len`` field included. Any ``len`` in ``fields`` is replaced. Numpy arrays and scalars are
    accepted."""
    # Serialised once (the packet goes out 125 times a second): the length field is spliced
    # in front, its value the fixed point of len(packet) = rest + digits(len).
    return _with_len(encode_json_spaced({k: v for k, v in fields.items() if k != S.LEN}))


def _with_len(body: bytes) -> bytes:
    """A packet's JSON object ``body`` (no ``len``) with ``len`` spliced in first."""
    head = b'{"%s": ' % S.LEN.encode()
    tail = b"}" if body == b"{}" else b", " + body[1:]
    rest = len(head) + len(tail)
    digits = 1
    while len(str(rest + digits)) != digits:
        digits += 1
    return head + str(rest + digits).encode() + tail


def _value(value: Any) -> bytes:
    """``encode_json_spaced(value)``, the ~30 scalars a packet changes written without a call
    into the JSON encoder each: the same bytes (``json`` writes a float or an int as its
    ``repr``, a string through ``encode_basestring``)."""
    kind = type(value)
    if kind is float and value - value == 0.0:      # finite: NaN and ±inf go to json (refused)
        return float.__repr__(value).encode()
    if kind is int:
        return int.__repr__(value).encode()
    if kind is bool:
        return b"true" if value else b"false"
    if kind is str:
        return encode_basestring(value).encode("utf-8")
    if value is None:
        return b"null"
    return encode_json_spaced(value)


class StatusEncoder:
    """:func:`encode_status` for a stream of packets from one source: the same bytes, with
    the encoding of each list or object value kept and used again while the packet carries
    the very same object (``is``) under the same key — a source that builds its unchanged
    arrays once (the emulator's IO, ~1100 of a packet's numbers) has them encoded once.
    A value handed in again must not have been changed in place since. One thread only."""

    def __init__(self):
        self._kept: Dict[str, Tuple[Any, bytes]] = {}
        self._keys: Dict[str, bytes] = {}       # '"key": ' of each key seen

    def encode(self, fields: Mapping[str, Any]) -> bytes:
        if not all(isinstance(key, str) for key in fields):
            return encode_status(fields)        # JSON writes other keys its own way
        kept, parts = self._kept, []
        for key, value in fields.items():
            if key == S.LEN:
                continue
            last = kept.get(key)
            if last is not None and last[0] is value:
                parts.append(last[1])
                continue
            name = self._keys.get(key)
            if name is None:
                name = self._keys[key] = encode_json_spaced(key) + b": "
            part = name + _value(value)
            if isinstance(value, (list, dict)):
                kept[key] = (value, part)
            parts.append(part)
        return _with_len(b"{" + b", ".join(parts) + b"}")
