"""The torque sensor and force control on the wire (docs/protocol.md, "Torque sensor"): the
requests JAKA's SDK 2.1.14 sends, with its keys and spellings ("torsenosr", "staus",
"ftNnormalTrack"), keys in sorted order as it writes them; the replies as it reads them; and
the status packet's ``torqsensor``.

Units are the SDK's: forces N, moments N·m, mass kg, centroid mm, joints rad (degrees only on
the wire); everything else (ftUser, ftReboundFK, rigidity, the compliant speed limit, levels)
goes out as given — the SDK passes it unconverted, and its unit is the controller's.
Encoders check types and finiteness (:class:`~.errors.InvalidArgument`, nothing is sent);
ranges are the caller's (a controller's are not on record beyond axis 0–5, frames 0/1 and
flags). Decoders raise :class:`~.errors.CommandRejected` for a refusal and
:class:`~.errors.ProtocolError` for a field of the wrong type or shape — where the SDK would
abort its client (a string for a number, a scalar for an array).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from . import units
from .errors import InvalidArgument, ProtocolError
from .fields import SOFT_LIMIT_KEYS, Cmd, Field
from .replies import Reply, reply_payload
from .reply_values import field as _field, number as _number, table as _table
from .reply_values import wire_vector as _wire_vector
from .request_values import Request, flag as _flag, integer, number as _float
from .request_values import sorted_request as _request, vector
from .wire import Fixed

#: the axes of force control and the components of a wrench: one row each in the admittance
#: and tool-drive tables, one number each in a wrench
AXIS_COUNT = 6
#: decimals JAKA's SDK writes these fields with (measured: "mass":1.50, "ftReboundFK":0.250);
#: the value goes out rounded to them, and is read back as such
MASS_DECIMALS = 2
REBOUND_DECIMALS = 3


def _int(value, what: str, lo: Optional[int] = None, hi: Optional[int] = None) -> int:
    """An int; the ranges are the caller's (unbounded unless given)."""
    return integer(value, what, lo, hi)


def _floats(values, n: int, what: str) -> list:
    return vector(values, n, what).tolist()


# ---- the sensor ----------------------------------------------------------------------------

def set_torsenosr_brand(brand: int) -> Request:
    """The sensor's type/brand (JAKA's numbering)."""
    return _request(Cmd.SET_TORSENOSR_BRAND, **{Field.SENSOR_BRAND: _int(brand, "brand")})


def get_torsenosr_brand() -> Request:
    """Reply: :func:`reply_torsenosr_brand`."""
    return _request(Cmd.GET_TORSENOSR_BRAND)


def set_torque_sensor_mode(on: bool) -> Request:
    """The sensor on (1) or off (0); read back in the status packet's ``torqsensor``."""
    return _request(Cmd.SET_TORQUE_SENSOR_MODE, **{Field.SENSOR_MODE: _flag(on)})


def zero_end_sensor() -> Request:
    return _request(Cmd.ZERO_END_SENSOR)


def set_tool_payload(mass_kg: float, centroid_mm: Sequence[float]) -> Request:
    """The sensor's tool payload: ``mass_kg`` at ``centroid_mm`` (mm, sensor frame); the mass
    goes out with the SDK's 2 decimals (``"mass":1.50``)."""
    return _request(Cmd.SET_TOOL_PAYLOAD, **{
        Field.CENTROID: _floats(centroid_mm, 3, "centroid (mm)"),
        Field.MASS: Fixed(_float(mass_kg, "mass (kg)"), MASS_DECIMALS)})


def get_tool_payload() -> Request:
    """Reply: :func:`~.replies.reply_payload` (mass kg, centroid mm)."""
    return _request(Cmd.GET_TOOL_PAYLOAD)


def set_torque_sensor_comm(comm_type: int, ip_addr: str, port: int) -> Request:
    """How the controller reaches the sensor: ``comm_type`` (0 TCP/IP, 1 RS485 on record)."""
    if not isinstance(ip_addr, str):
        raise InvalidArgument(f"ip_addr must be a string; got {ip_addr!r}")
    return _request(Cmd.SET_TORQUE_SENSOR_COMM, **{Field.COMM_TYPE: _int(comm_type, "type"),
                                                   Field.IP_ADDR: ip_addr,
                                                   Field.PORT: _int(port, "port", 0, 65535)})


def get_torque_sensor_comm() -> Request:
    """Reply: :func:`reply_torque_sensor_comm`."""
    return _request(Cmd.GET_TORQUE_SENSOR_COMM)


def set_torque_sensor_filter(cutoff_hz: float) -> Request:
    return _request(Cmd.SET_TORQUE_SENSOR_FILTER,
                    **{Field.SENSOR_FILTER: _float(cutoff_hz, "filter (Hz)")})


def get_torque_sensor_filter() -> Request:
    """Reply: :func:`reply_torque_sensor_filter`."""
    return _request(Cmd.GET_TORQUE_SENSOR_FILTER)


def set_torque_sensor_soft_limit(limit: Sequence[float]) -> Request:
    """``limit`` Fx Fy Fz (N), Mx My Mz (N·m), sent as an object keyed by those names."""
    values = _floats(limit, AXIS_COUNT, "soft limit")
    # Fx … Mz is already the sorted order jsoncpp writes an object's keys in
    return _request(Cmd.SET_TORQUE_SENSOR_SOFT_LIMIT, **{
        Field.SENSOR_SOFT_LIMIT: dict(zip(SOFT_LIMIT_KEYS, values))})


def get_torque_sensor_soft_limit() -> Request:
    """Reply: :func:`reply_torque_sensor_soft_limit`."""
    return _request(Cmd.GET_TORQUE_SENSOR_SOFT_LIMIT)


def get_torque_sensor_data(kind: int) -> Request:
    """One reading: ``kind`` 1 actual, 2 general, 3 real (JAKA's header numbers them so and its
    SDK sends the number unchanged). Reply: :func:`reply_torque_sensor_data`."""
    return _request(Cmd.GET_TORQUE_SENSOR_DATA, **{Field.COMM_TYPE: _int(kind, "type", 1, 3)})


# ---- identification ------------------------------------------------------------------------

def start_torq_sensor_payload_identify(end_joints_rad: Sequence[float]) -> Request:
    """Identify the sensor's payload on the way to ``end_joints_rad`` (rad; deg on the wire)."""
    q = _floats(end_joints_rad, 6, "end joint position (rad)")
    return _request(Cmd.START_TORQ_SENSOR_PAYLOAD_IDENTIFY,
                    **{Field.JOINT_POSITION: units.joints_to_wire(q)})


def get_torq_sensor_identify_staus() -> Request:
    """(sic) Reply: :func:`reply_identify_status`."""
    return _request(Cmd.GET_TORQ_SENSOR_IDENTIFY_STAUS)


def get_torq_sensor_payload_identify_result() -> Request:
    """Reply: :func:`~.replies.reply_payload` (mass kg, centroid mm)."""
    return _request(Cmd.GET_TORQ_SENSOR_PAYLOAD_IDENTIFY_RESULT)


# ---- force control ---------------------------------------------------------------------------

def set_admit_ctrl_config(axis: int, opt: bool, ft_user: float, ft_constant: float,
                          normal_track: bool, ft_rebound: float) -> Request:
    """Axis ``axis`` (0–5: x y z rx ry rz) of admittance: ``opt`` on, ``ft_user`` and
    ``ft_constant`` (N or N·m), normal tracking, ``ft_rebound`` (with the SDK's 3 decimals,
    ``"ftReboundFK":0.250``)."""
    return _request(Cmd.SET_ADMIT_CTRL_CONFIG, **{
        Field.AXIS: _int(axis, "axis", 0, 5), Field.OPT: _flag(opt),
        Field.FT_USER: _float(ft_user, "ftUser"), Field.FT_CONSTANT: _float(ft_constant,
                                                                            "ftConstant"),
        Field.FT_NORMAL_TRACK: _flag(normal_track),
        Field.FT_REBOUND: Fixed(_float(ft_rebound, "ftReboundFK"), REBOUND_DECIMALS)})


def get_admit_ctrl_config() -> Request:
    """Reply: :func:`reply_admit_ctrl_config`."""
    return _request(Cmd.GET_ADMIT_CTRL_CONFIG)


def set_tool_drive_config(axis: int, opt: bool, rigidity: float, rebound: float) -> Request:
    return _request(Cmd.SET_TOOL_DRIVE_CONFIG, **{
        Field.AXIS: _int(axis, "axis", 0, 5), Field.OPT: _flag(opt),
        Field.REBOUND: _float(rebound, "rebound"), Field.RIGIDITY: _float(rigidity,
                                                                          "rigidity")})


def get_tool_drive_config() -> Request:
    """Reply: :func:`reply_tool_drive_config`."""
    return _request(Cmd.GET_TOOL_DRIVE_CONFIG)


def enable_admittance_ctrl(on: bool) -> Request:
    """Force control on or off (JAKA's enable_tool_drive sends this same command)."""
    return _request(Cmd.ENABLE_ADMITTANCE_CTRL, **{Field.ENABLE_FLAG: _flag(on)})


def disable_force_control() -> Request:
    return _request(Cmd.DISABLE_FORCE_CONTROL)


def set_compliant_type(sensor_compensation: bool, compliance_type: int) -> Request:
    """``compliance_type`` 0 none, 1 constant force, 2 velocity compliance."""
    return _request(Cmd.SET_COMPLIANT_TYPE, **{
        Field.COMPLIANCE_TYPE: _int(compliance_type, "compliance_type", 0, 2),
        Field.SENSOR_COMPENSATION: _flag(sensor_compensation)})


def get_compliant_type() -> Request:
    """Reply: :func:`reply_compliant_type`."""
    return _request(Cmd.GET_COMPLIANT_TYPE)


def set_vel_compliant_ctrl(level: int, rates: Sequence[float]) -> Request:
    """Velocity compliance: ``level`` 1–3 and its four ``rates``."""
    return _request(Cmd.SET_VEL_COMPLIANT_CTRL, **{
        Field.COMPLIANT_CTRL: [_int(level, "vc_level", 1, 3)] + _floats(rates, 4, "rates")})


def set_compliance_condition(wrench: Sequence[float]) -> Request:
    """The wrench (N, N·m) above which motion stops."""
    return _request(Cmd.SET_COMPLIANCE_CONDITION, **{
        Field.COMPLIANT_CONDITION: _floats(wrench, AXIS_COUNT, "compliance condition")})


def set_ft_ctrl_frame(frame: int) -> Request:
    """0 tool, 1 world."""
    return _request(Cmd.SET_FT_CTRL_FRAME, **{Field.FT_FRAME: _int(frame, "ftFrame", 0, 1)})


def get_ft_ctrl_frame() -> Request:
    """Reply: :func:`reply_int` with ``Field.FT_FRAME``."""
    return _request(Cmd.GET_FT_CTRL_FRAME)


def get_tool_drive_stat() -> Request:
    """(sic) Reply: :func:`reply_tool_drive_stat`."""
    return _request(Cmd.GET_TOOL_DRIVE_STAT)


def set_tool_drive_frame(frame: int) -> Request:
    """0 tool, 1 world."""
    return _request(Cmd.SET_TOOL_DRIVE_FRAME,
                    **{Field.TOOL_DRAG_FRAME: _int(frame, "toolDragFrame", 0, 1)})


def get_tool_drive_frame() -> Request:
    """Reply: :func:`reply_int` with ``Field.TOOL_DRAG_FRAME``."""
    return _request(Cmd.GET_TOOL_DRIVE_FRAME)


def set_fusion_drive_sensitivity_level(level: int) -> Request:
    """0 off, 1–5."""
    return _request(Cmd.SET_FUSION_DRIVE_SENSITIVITY_LEVEL,
                    **{Field.SENSITIVITY_LEVEL_FUSION: _int(level, "sensitivity_level", 0, 5)})


def get_fusion_drive_sensitivity_level() -> Request:
    return _request(Cmd.GET_FUSION_DRIVE_SENSITIVITY_LEVEL)


def set_motion_limit_warning_range(level: int) -> Request:
    """1–5."""
    return _request(Cmd.SET_MOTION_LIMIT_WARNING_RANGE,
                    **{Field.RANGE_LEVEL: _int(level, "range_level", 1, 5)})


def get_motion_limit_warning_range() -> Request:
    return _request(Cmd.GET_MOTION_LIMIT_WARNING_RANGE)


def set_compliant_speed_limit(speed: float, angular_speed: float) -> Request:
    """Force control's speed limit, linear and angular (unconverted, as the SDK sends it)."""
    return _request(Cmd.SET_COMPLIANT_SPEED_LIMIT, **{
        Field.ANGULAR_SPEED_LIMIT: _float(angular_speed, "angular_speed_limit"),
        Field.SPEED_LIMIT: _float(speed, "speed_limit")})


def get_compliant_speed_limit() -> Request:
    """Reply: :func:`reply_compliant_speed_limit`."""
    return _request(Cmd.GET_COMPLIANT_SPEED_LIMIT)


def set_torque_ref_point(point: int) -> Request:
    return _request(Cmd.SET_TORQUE_REF_POINT, **{Field.REF_POINT: _int(point, "ref_point")})


def get_torque_ref_point() -> Request:
    return _request(Cmd.GET_TORQUE_REF_POINT)


def set_end_sensor_sensitivity_threshold(percent: Sequence[float]) -> Request:
    return _request(Cmd.SET_END_SENSOR_SENSITIVITY_THRESHOLD, **{
        Field.THRESHOLD_PERCENT: _floats(percent, AXIS_COUNT, "threshold_percent")})


def get_end_sensor_sensitivity_threshold() -> Request:
    """Reply: :func:`reply_sensitivity_threshold`."""
    return _request(Cmd.GET_END_SENSOR_SENSITIVITY_THRESHOLD)


# ---- replies -----------------------------------------------------------------------------------

def reply_int(reply: Reply, key: str) -> int:
    """An int field as JAKA's SDK reads it (``asInt``: an int, a double truncated, a bool); a
    string or anything else is a :class:`~.errors.ProtocolError` (the SDK's client aborts)."""
    raw = _field(reply, key)
    if not isinstance(raw, (int, float)) or (isinstance(raw, float) and not math.isfinite(raw)):
        raise ProtocolError(f"{key!r} in the reply to {reply.cmd_name!r} should be a number; "
                            f"got {raw!r}")
    return int(raw)


def reply_torsenosr_brand(reply: Reply) -> int:
    return reply_int(reply, Field.SENSOR_BRAND)


def reply_identify_status(reply: Reply) -> int:
    """0 done, 1 running, 2 error."""
    return reply_int(reply, Field.IDENTIFY_STATUS)


def reply_identify_result(reply: Reply) -> Tuple[float, np.ndarray]:
    """(mass kg, centroid mm (3,))."""
    return reply_payload(reply)


class AdmitRow(NamedTuple):
    """One axis of ``get_admit_ctrl_config`` (row index = axis)."""
    opt: int
    ft_user: float
    ft_rebound: float
    ft_constant: float
    ft_normal_track: int


def reply_admit_ctrl_config(reply: Reply) -> Tuple[AdmitRow, ...]:
    """``admitConfig``: 6 rows [opt, ft_user, ft_rebound, ft_constant, ft_normal_track]."""
    rows = _table(reply, Field.ADMIT_CONFIG, AXIS_COUNT, 5)
    return tuple(AdmitRow(int(r[0]), r[1], r[2], r[3], int(r[4])) for r in rows)


class ToolDriveRow(NamedTuple):
    """One axis of ``get_tool_drive_config`` (row index = axis)."""
    opt: int
    rigidity: float
    rebound: float


def reply_tool_drive_config(reply: Reply) -> Tuple[ToolDriveRow, ...]:
    """``force_ctrl_config``: 6 rows [opt, rigidity, rebound]."""
    rows = _table(reply, Field.FORCE_CTRL_CONFIG, AXIS_COUNT, 3)
    return tuple(ToolDriveRow(int(r[0]), r[1], r[2]) for r in rows)


def reply_compliant_type(reply: Reply) -> Tuple[int, int]:
    """(sensor_compensation, compliance_type)."""
    return (reply_int(reply, Field.SENSOR_COMPENSATION),
            reply_int(reply, Field.COMPLIANCE_TYPE))


def reply_torque_sensor_comm(reply: Reply) -> Tuple[int, str, int]:
    """(type, ip_addr, port). As JAKA's SDK: type 1 reads neither address nor port ("", 0)."""
    kind = reply_int(reply, Field.COMM_TYPE)
    if kind == 1:
        return kind, "", 0
    ip = _field(reply, Field.IP_ADDR)
    if not isinstance(ip, str):
        raise ProtocolError(f"'ip_addr' in the reply to {reply.cmd_name!r} should be a string; "
                            f"got {ip!r}")
    return kind, ip, reply_int(reply, Field.PORT)


def reply_torque_sensor_filter(reply: Reply) -> float:
    return _number(reply, Field.SENSOR_FILTER)


def reply_torque_sensor_soft_limit(reply: Reply) -> np.ndarray:
    """The soft limit object → [Fx, Fy, Fz, Mx, My, Mz]."""
    raw = _field(reply, Field.SENSOR_SOFT_LIMIT)
    if not isinstance(raw, dict):
        raise ProtocolError(f"{Field.SENSOR_SOFT_LIMIT!r} in the reply to {reply.cmd_name!r} "
                            f"should be an object {{Fx … Mz}}; got {str(raw)[:120]}")
    values = []
    for key in SOFT_LIMIT_KEYS:
        v = raw.get(key, 0.0)          # a missing key reads 0, as in the SDK
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ProtocolError(f"{Field.SENSOR_SOFT_LIMIT}.{key} should be a number; got {v!r}")
        values.append(float(v))
    return np.asarray(values)


class SensorData(NamedTuple):
    """``get_torque_sensor_data``: the sensor's ``status``, its ``errcode`` and one reading
    (N, N·m)."""
    status: int
    errcode: int
    data: np.ndarray


def reply_torque_sensor_data(reply: Reply) -> SensorData:
    return SensorData(reply_int(reply, Field.SENSOR_DATA_STATUS),
                      reply_int(reply, Field.SENSOR_ERRCODE),
                      _wire_vector(reply, Field.SENSOR_DATA, AXIS_COUNT))


def reply_tool_drive_stat(reply: Reply) -> Tuple[int, int]:
    """(enable_flag, drive_stat)."""
    return reply_int(reply, Field.ENABLE_FLAG), reply_int(reply, Field.DRIVE_STAT)


def reply_compliant_speed_limit(reply: Reply) -> Tuple[float, float]:
    """(speed_limit, angular_speed_limit), unconverted."""
    return _number(reply, Field.SPEED_LIMIT), _number(reply, Field.ANGULAR_SPEED_LIMIT)


def reply_sensitivity_threshold(reply: Reply) -> np.ndarray:
    return _wire_vector(reply, Field.THRESHOLD_PERCENT, AXIS_COUNT)


# ---- the status packet's torqsensor ---------------------------------------------------------------

_NAN6 = (math.nan,) * AXIS_COUNT


@dataclass(frozen=True, eq=False)
class TorqueSensorStatus:
    """The status packet's ``torqsensor``: ``[[commType, [ip, port], [mass, [x, y, z]]],
    [status, errcode, actTorque[6], torque[6], realTorque[6]]]`` (JAKA's SDK reads the three
    vectors as ``get_torque_sensor_data``'s actual, general and real). A vector the packet does
    not carry is NaN (the recorded Zu 5s sends two); ``ip``/``port`` are "" and 0 when
    ``comm_type`` is 1, as the SDK skips them. N, N·m, kg, mm."""

    comm_type: int
    ip: str
    port: int
    payload_mass: float
    payload_centroid: np.ndarray
    status: int
    errcode: int
    actual: np.ndarray
    general: np.ndarray
    real: np.ndarray


def _number_of(raw, what: str) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw):
        raise ValueError(f"{what} should be a finite number; got {raw!r}")
    return float(raw)


def _vector_of(raw, n: int, what: str) -> np.ndarray:
    if not isinstance(raw, list) or len(raw) != n:
        raise ValueError(f"{what} should be {n} numbers; got {str(raw)[:80]}")
    v = np.asarray([_number_of(x, what) for x in raw])
    v.setflags(write=False)
    return v


def parse_torqsensor(raw: Any) -> TorqueSensorStatus:
    """``torqsensor`` → :class:`TorqueSensorStatus`; raises ``ValueError`` or ``TypeError``
    for any other shape (the status parser counts the field malformed)."""
    if not (isinstance(raw, list) and len(raw) >= 2 and isinstance(raw[0], list)
            and isinstance(raw[1], list) and len(raw[0]) >= 3 and len(raw[1]) >= 2):
        raise TypeError("torqsensor is not [[commType, [ip, port], [mass, [x, y, z]]], "
                        "[status, errcode, [6]...]]")
    config, monitor = raw[0], raw[1]
    comm_type = int(_number_of(config[0], "torqsensor commType"))
    ip, port = "", 0
    if comm_type != 1:
        address = config[1]
        if not (isinstance(address, list) and len(address) == 2 and isinstance(address[0], str)):
            raise TypeError("torqsensor's address is not [ip, port]")
        ip, port = address[0], int(_number_of(address[1], "torqsensor port"))
    payload = config[2]
    if not (isinstance(payload, list) and len(payload) == 2):
        raise TypeError("torqsensor's payload is not [mass, [x, y, z]]")
    vectors = [_vector_of(v, AXIS_COUNT, "a torqsensor wrench") for v in monitor[2:5]]
    vectors += [np.asarray(_NAN6)] * (3 - len(vectors))
    return TorqueSensorStatus(
        comm_type=comm_type, ip=ip, port=port,
        payload_mass=_number_of(payload[0], "torqsensor payload mass"),
        payload_centroid=_vector_of(payload[1], 3, "torqsensor payload centroid"),
        status=int(_number_of(monitor[0], "torqsensor status")),
        errcode=int(_number_of(monitor[1], "torqsensor errcode")),
        actual=vectors[0], general=vectors[1], real=vectors[2])
