"""Splitting the command port's byte stream into requests.

Clients send bare JSON objects with no delimiter (docs/protocol.md, "Framing and layout"), possibly split across
reads or several in one read. A request ends where its outer braces balance (strings and escapes
respected), so a malformed object is recognised as soon as it is complete — it does not have to
wait for the next request — and it costs only itself:

* bytes that do not start an object (``[1, 2]``, ``hello``) are dropped up to the next ``{``;
* a balanced ``{...}`` that is not valid JSON is dropped whole;
* an object that stays incomplete for ``idle_timeout`` s is dropped (:meth:`expire`), so a
  truncated request gets its error reply instead of silence.

Each of those yields one :class:`~.handlers.Malformed` item, answered with an error reply.
"""
from __future__ import annotations

import json
from typing import Any, List, Optional

from .handlers import Malformed

MAX_REQUEST = 1 << 20   # bytes; a longer "request" is not one
_WHITESPACE = b" \t\r\n"
_OPEN, _CLOSE, _QUOTE, _BACKSLASH = ord("{"), ord("}"), ord('"'), ord("\\")


class RequestSplitter:
    """Bytes in, requests out: decoded JSON values, or :class:`Malformed` items."""

    def __init__(self, max_request: int = MAX_REQUEST):
        self.max_request = max_request
        self._buf = bytearray()

    @property
    def pending(self) -> int:
        """Bytes of an incomplete request."""
        return len(self._buf)

    def feed(self, data: bytes) -> List[Any]:
        self._buf += data
        out: List[Any] = []
        while True:
            self._strip()
            if not self._buf:
                break
            if self._buf[0] != _OPEN:
                out.append(self._drop_garbage())
                continue
            end = self._object_end()
            if end is None:
                if len(self._buf) > self.max_request:
                    self._buf.clear()
                    out.append(Malformed(f"request longer than {self.max_request} bytes "
                                         "without a complete JSON object; discarded"))
                break
            chunk = bytes(self._buf[:end])
            del self._buf[:end]
            try:
                out.append(json.loads(chunk))
            except ValueError as exc:   # JSONDecodeError and UnicodeDecodeError
                out.append(Malformed(f"malformed JSON request ({exc}): {chunk[:80]!r}"))
        return out

    def expire(self) -> Optional[Malformed]:
        """Drop an incomplete request (the client went quiet in the middle of it)."""
        self._strip()
        if not self._buf:
            return None
        head = bytes(self._buf[:80])
        self._buf.clear()
        return Malformed(f"incomplete JSON request discarded: {head!r}")

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

    def _object_end(self) -> Optional[int]:
        """Index just after the ``}`` that closes the object at the head, or None."""
        depth = 0
        in_string = escaped = False
        for i, byte in enumerate(self._buf):
            if in_string:
                if escaped:
                    escaped = False
                elif byte == _BACKSLASH:
                    escaped = True
                elif byte == _QUOTE:
                    in_string = False
            elif byte == _QUOTE:
                in_string = True
            elif byte == _OPEN:
                depth += 1
            elif byte == _CLOSE:
                depth -= 1
                if depth == 0:
                    return i + 1
        return None
