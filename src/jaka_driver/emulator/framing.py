"""Splitting a request port's byte stream into requests (the command port 10001 and the
``data_request`` port 10004 alike).

Clients send bare JSON objects with no delimiter (docs/protocol.md, "Framing and layout"),
possibly split across reads or several in one read. A request ends where its outer braces
balance (strings and escapes respected), so a malformed object is recognised as soon as it is
complete — it does not have to wait for the next request — and it costs only itself. Each of
these yields one :class:`Malformed` item, which the server answers with an error reply:

* bytes that do not start an object (``[1, 2]``, ``hello``, a lone ``}``, binary garbage) are
  dropped up to the next ``{``;
* a balanced ``{...}`` that is not a request a controller could read is dropped whole: not
  UTF-8, not JSON, nested deeper than :data:`MAX_DEPTH`, ``NaN``/``Infinity`` (not JSON, though
  Python's parser takes them), a number beyond a double (``1e999``) or an integer of more than
  :data:`MAX_INT_DIGITS` digits;
* an object still open after :data:`MAX_REQUEST` bytes is discarded at once;
* an object that stays incomplete for the server's idle time is dropped (:meth:`expire`), so a
  truncated request gets its error reply instead of silence.

The scan is incremental (each byte is looked at once, however the request is split) and
iterative (no recursion, whatever the nesting), and decoding only starts on a complete object
whose depth is known to be small: no input reaches Python's recursive parser deep enough to
raise ``RecursionError``.
"""
from __future__ import annotations

import json
import math
import re
from typing import Any, List, Optional

MAX_REQUEST = 1 << 20   # bytes; a longer "request" is not one
#: Deepest nesting of objects and arrays a request may have. The deepest a JAKA client sends is
#: 3 (``torqueSensorSoftLimit`` inside the request object, a table of rows); 32 leaves room.
MAX_DEPTH = 32
#: Longest integer literal read. A controller's parser (jsoncpp) holds integers in 64 bits
#: (20 digits); a longer literal is not a number any command takes.
MAX_INT_DIGITS = 20
_WHITESPACE = b" \t\r\n"
_OPEN, _CLOSE, _QUOTE = ord("{"), ord("}"), ord('"')
_OPEN_LIST, _CLOSE_LIST = ord("["), ord("]")
_STRUCTURE = re.compile(rb'[{}\[\]"]')     # what matters outside a string
_IN_STRING = re.compile(rb'["\\]')          # what matters inside one


class Malformed:
    """A request that could not be read as a JSON object; ``reason`` says why (it becomes the
    error reply's ``errorMsg``)."""

    def __init__(self, reason: str):
        self.reason = reason

    def __repr__(self) -> str:
        return f"Malformed({self.reason!r})"


class RequestSplitter:
    """Bytes in, requests out: decoded JSON values, or :class:`Malformed` items."""

    def __init__(self, max_request: int = MAX_REQUEST, max_depth: int = MAX_DEPTH):
        self.max_request = max_request
        self.max_depth = max_depth
        self._buf = bytearray()
        self._reset_scan()

    def _reset_scan(self) -> None:
        # Where the scan of the object at the head of the buffer stands.
        self._pos = 0            # next byte to look at
        self._braces = 0         # open '{' (the object ends when this returns to 0)
        self._depth = 0          # open '{' and '['
        self._deepest = 0
        self._in_string = False

    @property
    def pending(self) -> int:
        """Bytes of an incomplete request."""
        return len(self._buf)

    def feed(self, data: bytes) -> List[Any]:
        self._buf += data
        out: List[Any] = []
        while True:
            if self._pos == 0:
                self._strip()
                if not self._buf:
                    break
                if self._buf[0] != _OPEN:
                    out.append(self._drop_garbage())
                    continue
            end = self._scan()
            if end is None:
                if len(self._buf) > self.max_request:
                    self._buf.clear()
                    self._reset_scan()
                    out.append(Malformed(f"request longer than {self.max_request} bytes "
                                         "without a complete JSON object; discarded"))
                break
            chunk = bytes(self._buf[:end])
            deepest = self._deepest
            del self._buf[:end]
            self._reset_scan()
            out.append(self._decode(chunk, deepest))
        return out

    def expire(self) -> Optional[Malformed]:
        """Drop an incomplete request (the client went quiet in the middle of it)."""
        self._strip()
        if not self._buf:
            return None
        head = bytes(self._buf[:80])
        self._buf.clear()
        self._reset_scan()
        return Malformed(f"incomplete JSON request discarded: {head!r}")

    def _decode(self, chunk: bytes, deepest: int) -> Any:
        head = chunk[:80]
        if deepest > self.max_depth:
            return Malformed(f"request nested {deepest} deep (at most {self.max_depth}); "
                             f"discarded: {head!r}")
        try:
            text = chunk.decode("utf-8")
        except UnicodeDecodeError as exc:
            return Malformed(f"request is not UTF-8 (byte {exc.start}); discarded: {head!r}")
        try:
            return json.loads(text, parse_constant=_not_json, parse_float=_finite,
                              parse_int=_bounded_int)
        except (ValueError, RecursionError) as exc:   # JSONDecodeError and the hooks' refusals
            return Malformed(f"malformed JSON request ({exc}): {head!r}")

    def _strip(self) -> None:
        i = 0
        while i < len(self._buf) and self._buf[i] in _WHITESPACE:
            i += 1
        del self._buf[:i]

    def _drop_garbage(self) -> Malformed:
        nxt = self._buf.find(b"{")
        cut = len(self._buf) if nxt < 0 else nxt
        head = bytes(self._buf[:min(cut, 80)])
        del self._buf[:cut]
        return Malformed(f"not a JSON object: {head!r}")

    def _scan(self) -> Optional[int]:
        """Continue the scan of the object at the head; the index just after its closing
        ``}``, or None while it is incomplete."""
        buf, pos = self._buf, self._pos
        while True:
            if self._in_string:
                match = _IN_STRING.search(buf, pos)
                if match is None:
                    self._pos = len(buf)
                    return None
                i = match.start()
                if buf[i] == _QUOTE:
                    self._in_string = False
                    pos = i + 1
                elif i + 1 < len(buf):
                    pos = i + 2                     # a backslash escapes the next byte
                else:
                    self._pos = i                   # look at the backslash again
                    return None
                continue
            match = _STRUCTURE.search(buf, pos)
            if match is None:
                self._pos = len(buf)
                return None
            i = match.start()
            byte = buf[i]
            pos = i + 1
            if byte == _QUOTE:
                self._in_string = True
            elif byte in (_OPEN, _OPEN_LIST):
                self._braces += byte == _OPEN
                self._depth += 1
                self._deepest = max(self._deepest, self._depth)
            else:
                self._depth -= 1
                if byte == _CLOSE:
                    self._braces -= 1
                    if self._braces == 0:
                        return pos


def _not_json(name: str) -> float:
    raise ValueError(f"{name} is not a JSON number")


def _finite(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"number {text[:40]} is beyond a double")
    return value


def _bounded_int(text: str) -> int:
    digits = len(text.lstrip("-"))
    if digits > MAX_INT_DIGITS:
        raise ValueError(f"an integer of {digits} digits (at most {MAX_INT_DIGITS})")
    return int(text)
