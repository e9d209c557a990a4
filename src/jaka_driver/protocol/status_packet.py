"""A status packet read: :class:`StatusPacket`, the packet's fields in the SDK's units, and
:func:`parse_status`, which reads them from a decoded packet (port 10000's stream, port 10004's
reply or ``get_data``'s fields) and never raises for a field it cannot read.

:func:`decode_read_keys` decodes a whole packet for it in one pass of msgspec's compiled parser,
only the keys it reads and the IO arrays left as their bytes: ~1100 of a packet's ~1300
numbers are IO arrays that come again unchanged packet after packet, and an array whose bytes
are the last packet's reads as the same floats without being parsed at all.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Dict, List, Mapping, Optional, Tuple

import msgspec
import numpy as np

from .errors import ProtocolError
from .fields import FIELDBUS_SLAVES, IO_ARRAYS, StatusField as S
from .tool_io import SignalRow, signal_rows
from .torque_sensor import TorqueSensorStatus, parse_torqsensor
from .wire import as_flag, clean_text


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
        if type(raw) is msgspec.Raw:   # from decode_read_keys: the array's bytes
            if raw == last_raw:        # the very bytes the last values were read from
                return last_values
            values = _numbers(_raw_value(raw))
        elif raw == last_raw and _NUMBER_TYPES.issuperset(map(type, raw)):
            return last_values
        else:
            values = _numbers(raw)
        self.last = (raw, values)
        return values


_ANY = msgspec.json.Decoder()


def _raw_value(raw: msgspec.Raw) -> Any:
    """The JSON value a key's bytes hold; ValueError when they cannot be read (invalid UTF-8
    in a string, nesting past the parser's limit: the compiled parser only skipped them)."""
    try:
        return _ANY.decode(raw)
    except (ValueError, RecursionError) as exc:   # msgspec.DecodeError is a ValueError
        raise ValueError(f"unreadable JSON ({exc})") from None


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
)


class _RepeatedSensor:
    """``torqsensor`` → (its error code ``torqsensor[1][1]``, the whole
    :class:`TorqueSensorStatus`), each None when unreadable, remembered for the bytes it was
    read from: its settings and (without a sensor running) its zeros come again unchanged
    packet after packet, and reading them was ~11 of parse_status's ~25 µs a packet."""

    __slots__ = ("last",)

    def __init__(self):
        self.last: Tuple[Any, Tuple[Optional[int], Optional[TorqueSensorStatus]]] = \
            (None, (None, None))

    def __call__(self, raw) -> Tuple[Optional[int], Optional[TorqueSensorStatus]]:
        raw_bytes = type(raw) is msgspec.Raw       # from decode_read_keys: the field's bytes
        if raw_bytes:
            if raw == self.last[0]:
                return self.last[1]
            try:
                value = _raw_value(raw)
            except ValueError:
                return None, None
        else:
            value = raw
        try:
            read: Tuple[Optional[int], Optional[TorqueSensorStatus]] = \
                (_sensor_errcode(value), None)
        except _UNREADABLE:
            read = (None, None)
        else:
            try:
                read = (read[0], parse_torqsensor(value))
            except _UNREADABLE:
                pass
        if raw_bytes:
            self.last = (raw, read)
        return read


_TORQSENSOR = _RepeatedSensor()


def _read_keys_struct():
    """A msgspec Struct of the keys parse_status reads: the arrays its
    :class:`_RepeatedNumbers` read and ``torqsensor`` (:class:`_RepeatedSensor`) as
    :class:`msgspec.Raw` (their bytes), the rest any JSON value; a key the packet lacks is
    UNSET."""
    arrays = [key for _, key, convert, _ in _FIELDS if isinstance(convert, _RepeatedNumbers)]
    arrays += [key for key, _ in _FIELDBUS] + [S.TORQSENSOR]
    others = [key for _, key, convert, _ in _FIELDS + _LAST_FIELDS
              if not isinstance(convert, _RepeatedNumbers)]
    return msgspec.defstruct(
        "ReadKeys", [(key, msgspec.Raw, msgspec.UNSET) for key in arrays]
        + [(key, Any, msgspec.UNSET) for key in others])


_READ_KEYS = _read_keys_struct()
_READ_KEYS_DECODER = msgspec.json.Decoder(_READ_KEYS)
_KEY_NAMES = _READ_KEYS.__struct_fields__
_UNSET = msgspec.UNSET
_OPEN_BRACE, _CLOSE_BRACE = ord("{"), ord("}")


def decode_read_keys(data) -> Optional[Dict[str, Any]]:
    """A whole status packet's bytes → the keys :func:`parse_status` reads, for it alone: one
    pass of the compiled parser, the IO and fieldbus arrays and ``torqsensor`` left undecoded
    (:class:`msgspec.Raw`, read by :func:`parse_status` only when their bytes changed), the keys
    it does not read skipped. None when ``data`` is not exactly one JSON object (two, an
    unfinished one, not JSON, NaN, invalid UTF-8 in a value it reads, nested past the parser's
    limit): then the careful reader (:class:`~.wire.HeadDecoder`) reads it. For the stream
    decoder of a reader that only parses (``StatusStreamDecoder(decode=decode_read_keys)``).

    The parser only skims what it leaves undecoded or skips: invalid UTF-8 inside an IO array
    makes that array malformed when it is read (the careful reader would have repaired the
    string and then refused it as not a number), and inside a key nobody reads it is not seen,
    so such a packet is not counted in ``text_repaired``."""
    if not data or data[0] != _OPEN_BRACE or data[-1] != _CLOSE_BRACE:
        return None
    try:
        packet = _READ_KEYS_DECODER.decode(data)
    except (ValueError, RecursionError):   # msgspec.DecodeError and ValidationError included
        return None
    return {key: value for key, value in zip(_KEY_NAMES, msgspec.structs.astuple(packet))
            if value is not _UNSET}


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
    if S.TORQSENSOR in packet:
        errcode, sensor = _TORQSENSOR(packet[S.TORQSENSOR])
        if errcode is not None:
            values["sensor_errcode"] = errcode
        if sensor is not None:
            values["torque_sensor"] = sensor
        else:
            missing.append(S.TORQSENSOR)
            malformed.append(S.TORQSENSOR)
    return StatusPacket(**values, missing=tuple(missing), malformed=tuple(malformed))
