"""The status JAKA's SDK parses from a port-10004 ``data_request`` reply into its RobotStatus,
exactly as strictly as the SDK (docs/protocol.md, "Status packet": count in element 0 of every
IO array, ``monitor_data`` an array indexed [5][j][9], top-level ``instVel``, ``torqsensor``,
the ``errcode`` rules and the SDK's overrides).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

from .jaka_sdk_json import (SdkCrash, SdkGarbage, as_bool, as_double, as_int, as_string, doubles,
                             element, member, pose_rad)


@dataclass
class JointMonitor:
    current: float = 0.0
    voltage: float = 0.0
    temperature: float = 0.0
    velocity: float = 0.0      # from the top-level instVel
    torque: float = 0.0


@dataclass
class TorqueSensorMonitor:
    ip: str = ""
    port: int = 0
    payload_mass: float = 0.0
    payload_centroid: List[float] = field(default_factory=lambda: [0.0] * 3)
    status: int = 0
    errcode: int = 0
    act_torque: List[float] = field(default_factory=lambda: [0.0] * 6)
    torque: List[float] = field(default_factory=lambda: [0.0] * 6)
    real_torque: List[float] = field(default_factory=lambda: [0.0] * 6)


@dataclass
class RobotStatus:
    """JAKA's RobotStatus as the SDK fills it from one packet. IO arrays as the SDK keeps them:
    element 0 is the JSON array's length, the values from element 1."""

    errcode: int = 0
    inpos: bool = False
    powered_on: int = 0
    enabled: bool = False
    rapidrate: float = 0.0
    protective_stop: int = 0
    emergency_stop: int = 0
    on_soft_limit: int = 0
    drag_status: bool = False
    current_tool_id: int = 0
    current_user_id: int = 0
    din: List[float] = field(default_factory=list)
    dout: List[float] = field(default_factory=list)
    ain: List[float] = field(default_factory=list)
    aout: List[float] = field(default_factory=list)
    tio_din: List[float] = field(default_factory=list)
    tio_dout: List[float] = field(default_factory=list)
    tio_ain: List[float] = field(default_factory=list)
    tio_key: Optional[List[int]] = None
    io_groups: Dict[str, Dict[str, List[float]]] = field(default_factory=dict)
    extio: Optional[Dict[str, List[int]]] = None
    joint_position: List[float] = field(default_factory=lambda: [0.0] * 6)   # rad, commanded
    cartesiantran_position: Optional[List[float]] = None                    # mm, RPY rad
    scb_major: float = 0.0
    scb_minor: float = 0.0
    cabinet_temperature: float = 0.0
    average_power: float = 0.0
    average_current: float = 0.0
    joints: List[JointMonitor] = field(default_factory=lambda: [JointMonitor()
                                                               for _ in range(6)])
    torq_sensor: Optional[TorqueSensorMonitor] = None


def _io_array(raw: Any, size: int, convert) -> List[float]:
    """[count, values…] in an array of ``size`` (the count is the JSON array's length)."""
    if raw is None:
        return [0]
    if not isinstance(raw, list):
        raise SdkCrash(f"an IO array that is a {type(raw).__name__}: SIGSEGV")
    return [len(raw)] + [convert(v) for v in raw[:size - 1]]


def _errcode(text: str, packet: dict) -> int:
    raw = packet.get("errcode")
    if '"errcode": "0x' in text:
        if "0x30" in raw:
            return 0           # the SDK's hex reading gives 0 for any "0x30…"
        return int(raw, 16)
    if isinstance(raw, str):
        raise SdkGarbage(f"errcode {raw!r}: neither an int nor '\"errcode\": \"0x…'")
    return as_int(raw)


def parse_robot_status(text: str) -> RobotStatus:
    """A decompressed data_request reply → RobotStatus, as the SDK reads it."""
    packet = json.loads(text)
    st = RobotStatus()
    get = lambda key: member(packet, key)            # noqa: E731
    st.inpos, st.enabled, st.drag_status = (as_bool(get(k)) for k in
                                            ("inpos", "enabled", "drag_status"))
    (st.powered_on, st.protective_stop, st.emergency_stop, st.on_soft_limit,
     st.current_tool_id, st.current_user_id) = (as_int(get(k)) for k in (
        "powered_on", "protective_stop", "emergency_stop", "on_soft_limit",
        "current_tool_id", "current_user_id"))
    st.rapidrate = as_double(get("rapidrate"))
    for key, size, convert in (("din", 256, as_int), ("dout", 256, as_int),
                               ("ain", 256, as_double), ("aout", 256, as_double),
                               ("tio_din", 16, as_int), ("tio_dout", 16, as_int),
                               ("tio_ain", 16, as_double)):
        setattr(st, key, _io_array(get(key), size, convert))
    if get("tio_key") is not None:
        st.tio_key = [as_int(element(get("tio_key"), i)) for i in range(3)]
    for group, prefix in (("modbus_slave", "mb_slave"), ("profinet_slave", "pn_dev"),
                          ("eip_slave", "eip_adpt")):
        st.io_groups[group] = {kind: _io_array(get(f"{prefix}_{kind}"), 256,
                                               as_int if kind[0] == "d" else as_double)
                               for kind in ("din", "dout", "ain", "aout")}
    ext = get("extio")
    if as_int(member(ext, "num")) > 0:
        status = member(ext, "status")
        st.extio = {kind: _io_array(element(status, i), 256, as_int)
                    for i, kind in enumerate(("din", "dout", "ain", "aout"))}
    st.joint_position = [math.radians(v) for v in doubles(get("joint_position"), 6)]
    if get("actual_position") is not None:
        st.cartesiantran_position = pose_rad(doubles(get("actual_position"), 6))
    monitor = get("monitor_data")
    if monitor is not None and not isinstance(monitor, list):
        raise SdkCrash("monitor_data is not an array: SIGSEGV")
    (st.scb_major, st.scb_minor, st.cabinet_temperature, st.average_power,
     st.average_current) = doubles(monitor, 5)
    rows = element(monitor, 5)
    velocities = doubles(get("instVel"), 6)
    for j in range(6):
        row = element(rows, j)
        st.joints[j] = JointMonitor(as_double(element(row, 0)), as_double(element(row, 1)),
                                    as_double(element(row, 2)), velocities[j],
                                    as_double(element(row, 9)))
    st.torq_sensor = _torq_sensor(get("torqsensor"))
    st.errcode = _errcode(text, packet)
    # the SDK's overrides, in its order
    if st.on_soft_limit:
        st.errcode = 0x0F0008
    if st.protective_stop:
        st.errcode = 0x0F0034
    if st.emergency_stop:
        st.errcode = 0x309082
    if st.errcode == 0 and st.torq_sensor is not None and st.torq_sensor.errcode:
        st.errcode = st.torq_sensor.errcode
    return st


def _torq_sensor(raw: Any) -> Optional[TorqueSensorMonitor]:
    if raw is None:
        return None
    try:
        setup, state = element(raw, 0), element(raw, 1)
        m = TorqueSensorMonitor()
        comm_type = as_int(element(setup, 0))
        if comm_type != 1:
            address = element(setup, 1)
            m.ip, m.port = as_string(element(address, 0))[:19], as_int(element(address, 1))
        payload = element(setup, 2)
        m.payload_mass = as_double(element(payload, 0))
        m.payload_centroid = doubles(element(payload, 1), 3)
        m.status, m.errcode = as_int(element(state, 0)), as_int(element(state, 1))
        m.act_torque, m.torque, m.real_torque = (doubles(element(state, i), 6)
                                                 for i in (2, 3, 4))
        return m
    except SdkCrash as exc:     # this block's throw is caught: garbage, rc 0
        raise SdkGarbage(f"torqsensor read wrong: {exc}") from None
