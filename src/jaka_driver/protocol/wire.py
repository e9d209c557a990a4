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

A value that fills its buffer exactly — one reply per read, a status packet cut at its declared
``len`` — is parsed in one pass by msgspec's compiled parser (:func:`decode_whole`): a 7 kB status
packet every 8 ms is the node's largest piece of work, and the compiled parser holds the
interpreter lock a third as long as ``json`` does. Whatever it refuses goes the careful way below.

Readers of the controller's output use :class:`HeadDecoder`, which is strict where it must be
and says which of three things the head of its buffer is: a whole value, the beginning of one
(wait for more bytes), or bytes that can never become one (:class:`~.errors.MalformedInput`:
drop them). No input makes it raise anything else — Python's own parser raises
``RecursionError`` on deep nesting and a plain ``ValueError`` on an over-long integer, neither of
which a reader catching ``JSONDecodeError`` survives.

It also reads the loosely typed values the controller sends (flags as bools, numbers or words).
"""
from __future__ import annotations

import json
import math
import re
from typing import Any, NamedTuple, Optional, Tuple

import msgspec
import numpy as np

from .errors import MalformedInput, ProtocolError

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


class Fixed(float):
    """A number JAKA's SDK writes with a fixed count of decimals — ``"mass":1.50``,
    ``"ftReboundFK":0.250`` (docs/protocol.md, "Framing and layout") —: the value rounded to
    ``places`` decimals, which :func:`encode_json` writes with exactly that many when it is a
    top-level field of a request. Anywhere else it is the plain float it equals."""

    places: int

    def __new__(cls, value: float, places: int) -> "Fixed":
        if not math.isfinite(value):
            raise ValueError(f"{value!r} is not a finite number")
        number = super().__new__(cls, f"{value:.{places}f}")
        number.places = places
        return number

    @property
    def text(self) -> str:
        return f"{float(self):.{self.places}f}"


# A Fixed field goes through json.dumps as this marked string, then loses its quotes.
_FIXED_MARK = "\x00"
_FIXED_TEXT = re.compile(r'"\\u0000(-?[0-9]+\.[0-9]+)"')


# What json.dumps builds on every call with these options, built once (a servo stream
# encodes a request or a reply every 8 ms, a status packet dozens of values).
_COMPACT = json.JSONEncoder(separators=(",", ":"), ensure_ascii=False, allow_nan=False,
                            default=_plain)
_SPACED = json.JSONEncoder(separators=(", ", ": "), ensure_ascii=False, allow_nan=False,
                           default=_plain)


def encode_json(obj: Any) -> bytes:
    """Compact JSON, the layout of requests (``{"cmdName":"power_on"}``), UTF-8, non-ASCII kept
    as is, a :class:`Fixed` field with its decimals. NaN and infinity are refused: they are not
    JSON."""
    fixed = isinstance(obj, dict) and any(type(v) is Fixed for v in obj.values())
    if fixed:
        obj = {k: _FIXED_MARK + v.text if type(v) is Fixed else v for k, v in obj.items()}
    text = _COMPACT.encode(obj)
    if fixed:
        text = _FIXED_TEXT.sub(r"\1", text)
    return text.encode("utf-8")


def encode_json_spaced(obj: Any) -> bytes:
    """The controller's layout of replies and status packets: ``", "`` and ``": "`` between
    items (``{"errorCode": "0", "errorMsg": ""}``), UTF-8, NaN and infinity refused."""
    return _SPACED.encode(obj).encode("utf-8")


def decode_first_object(buf: bytes) -> Tuple[Any, int]:
    """Parse the JSON value that starts at ``buf[0]``; return it and the number of bytes it
    used. Raises ``json.JSONDecodeError`` when the head of ``buf`` is not (yet) a whole value."""
    text = bytes(buf).decode("utf-8", _ERRORS)
    obj, end = _DECODER.raw_decode(text)
    if text.isascii():
        return obj, end
    return obj, len(text[:end].encode("utf-8", _ERRORS))


#: Deepest bracket nesting a reader accepts. A real reply or status packet nests 4 deep
#: (``torqsensor``); anything near this is not a controller talking.
MAX_NESTING = 64


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON")


# NaN and Infinity are Python's extension, not JSON: a controller cannot mean them.
_STRICT = json.JSONDecoder(parse_constant=_no_constant)
_STRUCTURE = re.compile(rb'[][{}"]')
_IN_STRING = re.compile(rb'["\\]')
_QUOTE, _BACKSLASH = ord('"'), ord("\\")
_OPENING = b"{["
_CLOSING_OF = {ord("{"): b"}", ord("["): b"]"}
_OPENING_OF = {ord("}"): ord("{"), ord("]"): ord("[")}


# msgspec's JSON parser, no schema: a whole buffer → one plain value (dict, list, str, int …)
_WHOLE = msgspec.json.Decoder()
# what it raises on a buffer that is not exactly one JSON value: not JSON or not all of it
# (DecodeError), invalid UTF-8 (UnicodeDecodeError, a ValueError), nesting past Python's
# recursion limit (RecursionError)
_NOT_WHOLE = (msgspec.DecodeError, ValueError, RecursionError)
_BRACKETS = (ord("{"), ord("["))
_CLOSERS = (ord("}"), ord("]"))


def decode_whole(data) -> Optional[Any]:
    """The JSON object or array that is exactly ``data`` (bytes or bytearray: it begins with
    ``{`` or ``[`` and ends with ``}`` or ``]``), parsed by the compiled parser; None when
    ``data`` is anything else — unfinished, two values, not JSON, NaN, invalid UTF-8, a lone
    surrogate escape, nested past the parser's limit —, which the caller then reads the careful
    way (:class:`HeadDecoder`). A value is never cut at a wrong place: a buffer that parses
    whole from a ``{`` is the object that ``{`` opens and nothing more.

    The compiled parser takes integers of any length and nesting up to Python's recursion
    limit: a whole value it accepts is read even where :class:`HeadDecoder` would have refused
    it for nesting deeper than its ``max_depth`` (no field a reader takes nests more than 4
    deep, and the parser reports deeper nesting as an error rather than crashing)."""
    if not data or data[0] not in _BRACKETS or data[-1] not in _CLOSERS:
        return None
    try:
        return _WHOLE.decode(data)
    except _NOT_WHOLE:
        return None


class Decoded(NamedTuple):
    """A value taken from the head of a buffer."""
    value: Any
    used: int
    """bytes it occupied"""
    repaired: bool
    """a string in it held invalid UTF-8, kept as U+FFFD by :func:`clean_text`"""


class HeadDecoder:
    """Decodes the JSON object or array at the head of a growing byte buffer.

    :meth:`decode` answers the value once all of it has arrived, None while it may still be
    completed, and raises :class:`~.errors.MalformedInput` once it cannot be: it is not JSON
    (``NaN``/``Infinity`` literals included, and integers longer than Python converts), or it
    nests deeper than ``max_depth``. Whether an unparsable head is unfinished or broken is told
    by counting brackets outside strings (no parsing), resumed where the last count stopped —
    so bytes arriving one at a time cost no more than all at once. Numbers too large for a
    float decode as ``inf``: JSON allows them, and the field readers refuse what is not finite.

    Invalid UTF-8 inside a string is kept (as lone surrogates that :func:`clean_text` turns
    into U+FFFD) and reported as ``repaired``: a controller writing its messages in another
    encoding must not lose its whole reply or status stream to one word.

    One per buffer; call :meth:`reset` whenever bytes leave the head of the buffer other than
    through a decoded value.
    """

    def __init__(self, max_depth: int = MAX_NESTING):
        self.max_depth = int(max_depth)
        self.reset()

    def reset(self) -> None:
        self._pos = 0          # where the bracket count stopped
        self._open = b""       # the brackets open there, innermost last
        self._in_string = False

    def decode(self, buf) -> Optional[Decoded]:
        data = bytes(buf)
        whole = decode_whole(data)   # the usual case: the buffer holds one value, all of it
        if whole is not None:
            self.reset()
            return Decoded(whole, len(data), False)
        try:
            text, checked = data.decode("utf-8"), True
        except UnicodeDecodeError:
            text, checked = data.decode("utf-8", _ERRORS), False
        try:
            value, end = _STRICT.raw_decode(text)
        except RecursionError:
            self.reset()
            raise MalformedInput("nested deeper than the JSON parser follows") from None
        except ValueError as exc:   # JSONDecodeError, or an integer too long to convert
            if self._head_end(data) is None:
                return None
            self.reset()
            raise MalformedInput(f"not valid JSON ({exc})") from None
        self.reset()
        if text.isascii():
            return Decoded(value, end, False)
        head = text[:end]
        if checked:
            return Decoded(value, len(head.encode("utf-8")), False)
        try:   # the invalid bytes may all lie beyond the head
            return Decoded(value, len(head.encode("utf-8")), False)
        except UnicodeEncodeError:
            return Decoded(value, len(head.encode("utf-8", _ERRORS)), True)

    def _head_end(self, data: bytes) -> Optional[int]:
        """Where the bracketed value at ``data[0]`` ends, or None while it is open. Raises
        :class:`MalformedInput` when the head is not a bracket, a bracket closes another kind,
        or the brackets nest too deep."""
        if not data or data[0] not in _OPENING:
            raise MalformedInput(f"does not begin with '{{' or '[': {data[:40]!r}")
        pos, opened, in_string = self._pos, self._open, self._in_string
        try:
            while True:
                if in_string:
                    m = _IN_STRING.search(data, pos)
                    if m is None:
                        return None
                    if data[m.start()] == _BACKSLASH:
                        if m.start() + 1 >= len(data):
                            pos = m.start()    # the escaped byte has not arrived
                            return None
                        pos = m.start() + 2
                        continue
                    pos, in_string = m.end(), False
                    continue
                m = _STRUCTURE.search(data, pos)
                if m is None:
                    pos = len(data)
                    return None
                pos, c = m.end(), data[m.start()]
                if c == _QUOTE:
                    in_string = True
                elif c in _OPENING:
                    opened += _CLOSING_OF[c]
                    if len(opened) > self.max_depth:
                        raise MalformedInput(f"nested more than {self.max_depth} deep")
                elif opened[-1] != c:
                    raise MalformedInput(f"{chr(c)!r} at byte {pos - 1} closes "
                                         f"{chr(_OPENING_OF[opened[-1]])!r}")
                else:
                    opened = opened[:-1]
                    if not opened:
                        return pos
        finally:
            self._pos, self._open, self._in_string = pos, opened, in_string


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


def float_vector(value: Any, n: int) -> Optional[np.ndarray]:
    """``value`` (a JSON array) as ``n`` finite floats, or None when it is anything else."""
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return None
    # a plain loop: numpy's reduction over n numbers costs 20-40 µs on a thread just woken,
    # and every status packet passes here several times
    return v if v.shape == (n,) and all(map(math.isfinite, v.tolist())) else None


def as_flag(value: Any, what: str) -> bool:
    """A wire flag → bool. Accepts bools, numbers and the strings clients report
    (``"1"``, ``"powered_on"``, ``"robot_enabled"``, and their opposites); not NaN or
    infinity."""
    if isinstance(value, (bool, int)) or (isinstance(value, float) and np.isfinite(value)):
        return bool(value)
    if isinstance(value, str):
        text = value.strip().lower()
        if text in _TRUE:
            return True
        if text in _FALSE:
            return False
    raise ProtocolError(f"{what} should be a flag; got {value!r}")
