"""Status packets: the port-10000 stream (decoding client side, encoding server side), the
port-10004 ``data_request`` reply (zlib), and :class:`StatusPacket`, a packet in the SDK's units.

The controller pushes JSON objects back to back with no delimiter, each starting with
``{"len": N`` (docs/protocol.md, "Status packet"); a packet can be several kB and arrives in any
number of TCP reads. The decoder resynchronises on the token ``{"len":``, so a lost or damaged
byte costs at most one packet, and it never holds more than ``max_buffer`` bytes.
"""
from __future__ import annotations

import math
import re
import zlib
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Dict, List, Mapping, Optional, Tuple

import numpy as np

from .errors import MalformedInput, ProtocolError
from .fields import FIELDBUS_SLAVES, IO_ARRAYS, StatusField as S
from .tool_io import SignalRow, signal_rows
from .torque_sensor import TorqueSensorStatus, parse_torqsensor
from .wire import HeadDecoder, as_flag, clean_text, encode_json_spaced

#: Every packet starts with these bytes (``len`` first; a space may follow the colon).
PACKET_START = b'{"len":'
_LEN_VALUE = re.compile(rb'\{"len":\s*(\d{1,9})')
#: Default cap of the decoder's buffer: ~100 packets of the largest size observed (8979 B).
MAX_BUFFER = 1 << 20
#: A declared ``len`` above this is not believed (7× the largest packet observed).
MAX_PACKET = 1 << 16


class StatusStreamDecoder:
    """Incremental decoder: bytes in, whole packets (dicts) out.

    Not thread-safe: one reader feeds it. Counters (cumulative):

    * ``packets`` — packets decoded;
    * ``bytes_dropped`` — bytes thrown away (garbage between packets, broken packets, overflow);
    * ``packets_dropped`` — packets lost: a malformed object (not JSON, nested too deep: see
      :class:`~.wire.HeadDecoder`), an unfinished one skipped at the next token, or the buffer
      discarded because it grew past ``max_buffer`` without a decodable packet;
    * ``fields_dropped`` — fields of decoded packets that were malformed and read as their
      default (:func:`parse_status`'s ``malformed``; the readers of :mod:`.client` count them);
    * ``text_repaired`` — packets with invalid UTF-8 inside a string (kept as U+FFFD).

    A packet is declared unfinished when it cannot be decoded although the next token has
    arrived and the buffer holds at least the packet's declared ``len``; the ``len`` check keeps
    a nested ``{"len":`` from being mistaken for the next packet. The decoder does not otherwise
    rely on ``len``, whose exact meaning on real controllers is not verified.
    """

    def __init__(self, max_buffer: int = MAX_BUFFER):
        if max_buffer < 2 * len(PACKET_START):
            raise ValueError(f"max_buffer must be at least {2 * len(PACKET_START)} bytes")
        self.max_buffer = int(max_buffer)
        self.packets = 0
        self.bytes_dropped = 0
        self.packets_dropped = 0
        self.fields_dropped = 0
        self.text_repaired = 0
        self._buf = bytearray()
        self._head = HeadDecoder()
        # Where to look for a '}' in the buffer before trying to decode again: a packet can only
        # have completed if a '}' arrived since the last failed attempt.
        self._scan_from = 0

    @property
    def buffered(self) -> int:
        """Bytes held, waiting for the rest of a packet."""
        return len(self._buf)

    def reset(self) -> None:
        """Forget buffered bytes (e.g. on a new connection); the counters are kept."""
        self._buf.clear()
        self._scan_from = 0
        self._head.reset()

    def feed(self, data: bytes) -> List[Dict[str, Any]]:
        """Add received bytes; return the packets they completed, in order."""
        self._buf += data
        packets: List[Dict[str, Any]] = []
        while self._buf:
            start = self._buf.find(PACKET_START)
            if start < 0:
                self._drop_all_but_token_prefix()
                break
            if start > 0:
                self._drop(start)
            try:
                packet = self._try_decode()
            except MalformedInput:
                self._drop_broken()
                continue
            if packet is not None:
                packets.append(packet)
                continue
            following = self._buf.find(PACKET_START, 1)
            if following < 0:
                break   # incomplete: wait for more bytes
            declared = self._declared_length()
            if declared is not None and len(self._buf) < declared:
                # The token may belong to a nested object ({"len": ...} inside the packet):
                # only a packet that stays undecodable past its own length is broken.
                break
            # A new packet starts where this one cannot be decoded: this one is broken.
            self._drop(following)
            self.packets_dropped += 1
        if len(self._buf) > self.max_buffer:
            self._drop(len(self._buf))
            self.packets_dropped += 1
        self.packets += len(packets)
        return packets

    def _try_decode(self):
        """The packet at the head, or None while it is unfinished; raises MalformedInput."""
        if self._buf.find(b"}", self._scan_from) < 0:
            self._scan_from = len(self._buf)
            return None
        decoded = self._head.decode(self._buf)
        if decoded is None:
            self._scan_from = len(self._buf)
            return None
        del self._buf[:decoded.used]
        self._scan_from = 0
        if decoded.repaired:
            self.text_repaired += 1
        return decoded.value

    def _drop_broken(self) -> None:
        """Drop the malformed packet at the head: up to the next token, or all of it."""
        following = self._buf.find(PACKET_START, 1)
        if following < 0:
            self._drop_all_but_token_prefix()
        else:
            self._drop(following)
        self.packets_dropped += 1

    def _declared_length(self):
        match = _LEN_VALUE.match(self._buf)
        if match is None:
            return None
        n = int(match.group(1))
        # A corrupt or oddly defined length must not hold the stream back for long.
        return n if n <= MAX_PACKET else None

    def _drop(self, n: int) -> None:
        del self._buf[:n]
        self.bytes_dropped += n
        self._scan_from = 0
        self._head.reset()

    def _drop_all_but_token_prefix(self) -> None:
        # Keep a tail that may be the beginning of a token split across reads.
        keep = 0
        for k in range(min(len(PACKET_START) - 1, len(self._buf)), 0, -1):
            if self._buf.endswith(PACKET_START[:k]):
                keep = k
                break
        self._drop(len(self._buf) - keep)


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
            part = name + encode_json_spaced(value)
            if isinstance(value, (list, dict)):
                kept[key] = (value, part)
            parts.append(part)
        return _with_len(b"{" + b", ".join(parts) + b"}")


def encode_data_reply(fields: Mapping[str, Any]) -> bytes:
    """Server side of port 10004: the reply to ``data_request``, one status packet
    (:func:`encode_status`) compressed with zlib."""
    return zlib.compress(encode_status(fields), 6)


def decode_data_reply(data: bytes) -> Dict[str, Any]:
    """Client side of port 10004: a whole zlib reply → the packet's fields. Raises
    :class:`~.errors.ProtocolError` when it does not decompress to one JSON object."""
    try:
        text = zlib.decompress(data)
    except zlib.error as exc:
        raise ProtocolError(f"the data_request reply ({len(data)} bytes) is not a "
                            f"zlib-compressed JSON status packet: {exc}") from None
    return data_reply_fields(text, len(data))


def data_reply_fields(text: bytes, compressed_size: int) -> Dict[str, Any]:
    """The fields of a data_request reply already decompressed (``text``; it arrived as
    ``compressed_size`` bytes). Raises :class:`~.errors.ProtocolError` when it is not one JSON
    object."""
    try:
        decoded = HeadDecoder().decode(text)
    except MalformedInput as exc:
        raise MalformedInput(f"the data_request reply ({compressed_size} bytes) is not a "
                             f"zlib-compressed JSON status packet: {exc}") from None
    if decoded is None:
        raise MalformedInput(f"the data_request reply ({compressed_size} bytes) ends before "
                             "its JSON object does")
    if not isinstance(decoded.value, dict):
        raise MalformedInput("the data_request reply is not a JSON object")
    return decoded.value


# ---- the status record -----------------------------------------------------------------------

def _frozen_array(values) -> np.ndarray:
    a = np.array(values, dtype=float)
    a.flags.writeable = False
    return a


_NAN6 = (np.nan,) * 6


@dataclass(frozen=True, eq=False)
class StatusPacket:
    """One status packet in the SDK's units (rad, mm, RPY rad).

    Positions whose field was missing are NaN, never zero: a made-up pose must not look real.
    ``missing`` names the fields that were absent or malformed and got their default (an
    absent ``errcode`` reads 0, an unreadable one -1); ``malformed`` those of them that were
    present but unreadable (wrong type, wrong length, not finite). Fields only some controllers
    send (``instVel``, ``monitor_data``, ``homed``, ``torqsensor``, ``motion_line``) are not
    noted when absent.
    IO lists are as on the wire: element ``i`` is the signal the SDK's API calls ``i``
    (docs/protocol.md, "IO").
    """

    joint_position: np.ndarray = field(default_factory=lambda: _frozen_array(_NAN6))
    """measured joints, rad (6,) — from ``joint_actual_position`` (deg)"""
    joint_command: np.ndarray = field(default_factory=lambda: _frozen_array(_NAN6))
    """commanded joints, rad (6,) — from ``joint_position`` (deg)"""
    tcp_pose: np.ndarray = field(default_factory=lambda: _frozen_array(_NAN6))
    """TCP [x, y, z mm, rx, ry, rz rad] — from ``actual_position`` (mm, RPY deg)"""
    joint_velocity: np.ndarray = field(default_factory=lambda: _frozen_array(_NAN6))
    """joint speeds, rad/s (6,) — from the top-level ``instVel``, read in deg/s like every
    joint quantity of the wire (its unit is not documented); NaN when absent"""
    joint_torque: np.ndarray = field(default_factory=lambda: _frozen_array(_NAN6))
    """joint torques, N·m (6,) — element [9] of each joint row ``monitor_data[5][j]``; NaN when
    absent"""
    powered: bool = False
    enabled: bool = False
    emergency_stop: bool = False
    protective_stop: bool = False
    on_soft_limit: bool = False
    inpos: bool = False
    paused: bool = False
    drag_status: bool = False
    task_state: int = 0
    """fields.TaskState: 1 power off, 2 power on, 3 disabled, 4 enabled (0 unknown)"""
    task_mode: int = 0
    interp_state: int = 0
    """fields.InterpState: 0 idle, 1 loading, 2 paused, 3 running"""
    errcode: int = 0
    """controller error code, 0 = no error (wire: hex string "0x0")"""
    errmsg: str = ""
    sensor_errcode: int = 0
    """the torque sensor's error code, ``torqsensor[1][1]`` (0 = none or no sensor)"""
    torque_sensor: Optional[TorqueSensorStatus] = None
    """``torqsensor`` whole: its settings, status and the three wrenches (.torque_sensor);
    None when the packet has none"""
    rapidrate: float = 1.0
    current_tool_id: int = 0
    current_user_id: int = 0
    motion_line: int = 0
    homed: Tuple[int, ...] = ()
    """``homed`` as sent (9 entries on a real controller; the SDK and JAKA call it obsolete)"""
    din: Tuple[float, ...] = ()
    dout: Tuple[float, ...] = ()
    ain: Tuple[float, ...] = ()
    aout: Tuple[float, ...] = ()
    tio_din: Tuple[float, ...] = ()
    tio_dout: Tuple[float, ...] = ()
    tio_ain: Tuple[float, ...] = ()
    tio_rs_signals: Optional[Tuple[SignalRow, ...]] = None
    """the tool connector's signals with their latest values (``tio_rs_signals``, later
    firmware); None when the packet has none"""
    relay_io: Tuple[float, ...] = ()
    """the relay outputs (IO type 3), ``relay_io``; () when the packet has none"""
    extio: Tuple[Tuple[float, ...], ...] = ()
    """the extension module (IO type 2): its (din, dout, ain, aout) from ``extio.status`` when
    ``extio.num`` > 0 (as JAKA's SDK reads it), else ()"""
    fieldbus: Mapping[str, Tuple[float, ...]] = field(default_factory=dict)
    """the fieldbus slaves' arrays (IO types 4–6) the packet carries, by key
    (``mb_slave_din`` … ``eip_adpt_aout``: :data:`~.fields.FIELDBUS_SLAVES`)"""
    missing: Tuple[str, ...] = ()
    malformed: Tuple[str, ...] = ()

    @property
    def has_error(self) -> bool:
        return self.errcode != 0


def parse_errcode(value: Any) -> int:
    """``errcode`` → int. The wire sends a hex string (``"0x0"``, ``"0x0F0034"``); a bare
    number or decimal string is taken as is, a prefix-less hex string as hex."""
    if isinstance(value, bool):
        raise ValueError("errcode is a bool")
    if isinstance(value, (int, float)):
        return int(value)
    if not isinstance(value, str):
        raise ValueError(f"errcode is a {type(value).__name__}")
    text = value.strip()
    try:
        return int(text, 0)
    except ValueError:
        return int(text, 16)


#: What a field reader may raise on a value of the wrong type or size: the field is malformed.
_UNREADABLE = (TypeError, ValueError, ArithmeticError, IndexError, KeyError, ProtocolError)


def _finite(x: float) -> float:
    if not math.isfinite(x):
        raise ValueError(f"{x} is not finite")
    return x


def _number(raw) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (int, float)):
        raise TypeError(f"not a number: {type(raw).__name__}")
    return _finite(float(raw))


def _integer(raw) -> int:
    """An int, or a float or bool (as the SDK's ``asInt`` reads them, truncated)."""
    if not isinstance(raw, (int, float)):
        raise TypeError(f"not a number: {type(raw).__name__}")
    return int(raw)


#: the types a JSON number decodes to (bool is its own type, so it is not among them)
_NUMBER_TYPES = frozenset((int, float))


def _numbers(raw) -> Tuple[float, ...]:
    if not isinstance(raw, list):
        raise TypeError(f"not a list: {type(raw).__name__}")
    # A packet carries ~1200 numbers 125 times a second: checked and converted in C (map)
    # when they are all plain numbers, else one by one, which names what is wrong.
    if _NUMBER_TYPES.issuperset(map(type, raw)):
        values = tuple(map(float, raw))
        if all(map(math.isfinite, values)):
            return values
    return tuple(_number(v) for v in raw)


def _six(raw) -> Tuple[float, ...]:
    values = _numbers(raw)
    if len(values) != 6:
        raise ValueError(f"expected 6 numbers, got {len(values)}")
    return values


_RAD = math.pi / 180.0   # units.deg_to_rad's factor (numpy's radians): the same rad to the bit


def _wire_joints(raw) -> np.ndarray:
    """Six joint values in degrees (or deg/s) → a read-only array in rad (rad/s)."""
    a = np.array(_six(raw))
    a *= _RAD
    a.flags.writeable = False
    return a


def _wire_pose(raw) -> np.ndarray:
    """``[x, y, z mm, rx, ry, rz deg]`` → a read-only ``[x, y, z mm, rx, ry, rz rad]``."""
    x, y, z, rx, ry, rz = _six(raw)
    a = np.array((x, y, z, rx * _RAD, ry * _RAD, rz * _RAD))
    a.flags.writeable = False
    return a


def _joint_torques(raw) -> np.ndarray:
    """``monitor_data`` → the six joint torques: [9] of each row of ``monitor_data[5]``."""
    if not isinstance(raw, list) or len(raw) < 6 or not isinstance(raw[5], list):
        raise TypeError("monitor_data is not [5 numbers, [6 joint rows]]")
    rows = raw[5]
    if len(rows) != 6 or not all(isinstance(r, list) and len(r) >= 10 for r in rows):
        raise ValueError("monitor_data[5] is not 6 rows of at least 10 numbers")
    return np.asarray([_number(r[9]) for r in rows])


def _sensor_errcode(raw) -> int:
    """``torqsensor`` → ``torqsensor[1][1]``, the sensor's error code."""
    if not isinstance(raw, list) or len(raw) < 2 or not isinstance(raw[1], list):
        raise TypeError("torqsensor is not [[config], [status, errcode, ...]]")
    return _integer(raw[1][1])


def _extio(raw) -> Tuple[Tuple[float, ...], ...]:
    """``extio`` = {num, status: [[din], [dout], [ain], [aout]]} → the four arrays, or () when
    ``num`` is 0 (JAKA's SDK reads ``status`` only when ``num`` > 0)."""
    if not isinstance(raw, Mapping):
        raise TypeError("extio is not an object")
    if _integer(raw.get("num", 0)) <= 0:
        return ()
    status = raw.get("status")
    if not isinstance(status, list) or len(status) != len(IO_ARRAYS):
        raise ValueError("extio.status is not [[din], [dout], [ain], [aout]]")
    return tuple(_numbers(values) for values in status)


def _text(raw) -> str:
    if not isinstance(raw, str):
        raise TypeError(f"not a string: {type(raw).__name__}")
    return clean_text(raw)


class _RepeatedNumbers:
    """:func:`_numbers` of one packet key that remembers the last list it read: the IO arrays
    (~1100 of a packet's ~1300 numbers) come again unchanged packet after packet, and a list
    equal to the last one, of plain numbers again (no bool: ``True == 1``), reads as the same
    floats. A list read with a malformed value is not remembered."""

    __slots__ = ("last",)

    def __init__(self):
        self.last: Tuple[Any, Tuple[float, ...]] = (None, ())

    def __call__(self, raw) -> Tuple[float, ...]:
        last_raw, last_values = self.last
        if raw == last_raw and _NUMBER_TYPES.issuperset(map(type, raw)):
            return last_values
        values = _numbers(raw)
        self.last = (raw, values)
        return values


def _flag_of(key: str):
    return lambda raw: as_flag(raw, key)


def _homed(raw) -> Tuple[int, ...]:
    return tuple(_integer(v) for v in _numbers(raw))


def _torques(raw) -> np.ndarray:
    return _frozen_array(_joint_torques(raw))


#: (attribute, packet key, reader, optional) in the order parse_status reads them; the
#: readers are made once, not per packet (125 packets a second)
_FIELDS = (
    ("joint_position", S.JOINT_ACTUAL_POSITION, _wire_joints, False),
    ("joint_command", S.JOINT_POSITION, _wire_joints, False),
    ("tcp_pose", S.ACTUAL_POSITION, _wire_pose, False),
    ("joint_velocity", S.INST_VEL, _wire_joints, True),
    ("joint_torque", S.MONITOR_DATA, _torques, True),
    *((attr, key, _flag_of(key), False) for attr, key in (
        ("powered", S.POWERED_ON), ("enabled", S.ENABLED),
        ("emergency_stop", S.EMERGENCY_STOP), ("protective_stop", S.PROTECTIVE_STOP),
        ("on_soft_limit", S.ON_SOFT_LIMIT), ("inpos", S.INPOS), ("paused", S.PAUSED),
        ("drag_status", S.DRAG_STATUS))),
    *((attr, key, _integer, False) for attr, key in (
        ("task_state", S.TASK_STATE), ("task_mode", S.TASK_MODE),
        ("interp_state", S.INTERP_STATE), ("current_tool_id", S.CURRENT_TOOL_ID),
        ("current_user_id", S.CURRENT_USER_ID))),
    ("errcode", S.ERRCODE, parse_errcode, False),
    ("errmsg", S.ERRMSG, _text, False),
    ("rapidrate", S.RAPIDRATE, _number, False),
    *((key, key, _RepeatedNumbers(), False) for key in (
        S.DIN, S.DOUT, S.AIN, S.AOUT, S.TIO_DIN, S.TIO_DOUT, S.TIO_AIN)),
    ("relay_io", S.RELAY_IO, _RepeatedNumbers(), True),
    ("extio", S.EXTIO, _extio, True),
    ("tio_rs_signals", S.TIO_RS_SIGNALS, signal_rows, True),
)
#: the fieldbus slaves' keys, each with its reader
_FIELDBUS = tuple((f"{prefix}_{array}", _RepeatedNumbers())
                  for prefix, _ in FIELDBUS_SLAVES for array in IO_ARRAYS)
_LAST_FIELDS = (
    ("motion_line", S.MOTION_LINE, _integer, True),
    ("homed", S.HOMED, _homed, True),
    ("sensor_errcode", S.TORQSENSOR, _sensor_errcode, True),
)


def parse_status(packet: Mapping[str, Any]) -> StatusPacket:
    """A decoded status packet (or ``get_data`` reply fields) → :class:`StatusPacket`.

    Never raises for a missing or malformed field: it takes the default and lists the field in
    ``missing`` (and in ``malformed`` when it was there but unreadable). Raises
    :class:`~.errors.ProtocolError` only if ``packet`` is not a mapping."""
    if not isinstance(packet, Mapping):
        raise ProtocolError(f"a status packet must be a JSON object; got {type(packet).__name__}")
    missing: List[str] = []
    malformed: List[str] = []
    values: Dict[str, Any] = {}

    def take(fields) -> None:
        for attr, key, convert, optional in fields:
            if key not in packet:
                if not optional:
                    missing.append(key)
                continue
            try:
                values[attr] = convert(packet[key])
            except _UNREADABLE:
                missing.append(key)
                malformed.append(key)

    take(_FIELDS)
    if S.ERRCODE in malformed:
        values["errcode"] = -1   # unreadable is not "no error": keep the robot in error
    fieldbus = {}
    for key, convert in _FIELDBUS:
        if key in packet:
            try:
                fieldbus[key] = convert(packet[key])
            except _UNREADABLE:
                missing.append(key)
                malformed.append(key)
    values["fieldbus"] = MappingProxyType(fieldbus)
    take(_LAST_FIELDS)
    if S.TORQSENSOR in packet and S.TORQSENSOR not in malformed:
        try:
            values["torque_sensor"] = parse_torqsensor(packet[S.TORQSENSOR])
        except _UNREADABLE:
            missing.append(S.TORQSENSOR)
            malformed.append(S.TORQSENSOR)
    return StatusPacket(**values, missing=tuple(missing), malformed=tuple(malformed))
