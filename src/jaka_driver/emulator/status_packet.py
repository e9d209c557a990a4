"""The emulator's status packet: the twin's state as the fields of a port-10000 packet (and of
the port-10004 ``data_request`` reply and the ``get_data`` reply), in wire units — joints deg,
TCP mm + RPY deg — with the keys, types and array sizes of a real packet, in its key order
(docs/protocol.md, "Status packet"): the keys the profile's controller sends (the recorded fw
1.5.14 packet's 36 with ``len``, or every key JAKA's SDK reads), its array sizes.

Filled from the twin where the twin has the quantity:

* ``monitor_data`` = ``[scbMajor, scbMinor, cabinet temperature, average power, average
  current, [6 joint rows of 11]]``; per joint row ``[0]`` current = torque / 10 N·m/A (the order
  of a harmonic-drive joint; not a JAKA figure), ``[1]`` voltage = the 48 V DC bus while
  powered, ``[2]`` temperature 0 (no thermal model), ``[9]`` torque (N·m, the twin's drive
  torque), the rest 0; average power = Σ|torque · speed| (W, mechanical), average current =
  that power / bus voltage; SCB version 0.0 and cabinet temperature 0 (no such parts);
* top-level ``instVel`` = joint speeds (deg/s: the wire's joint unit; the unit of a real
  controller's ``instVel`` is not on record);
* ``curr_tcp_trans_vel`` = the TCP's speed (mm/s);
* ``timestamp`` (the recorded fw 1.5.14 packet only) = the sample's time, s (its unit on the
  real arm is not on record);
* ``torqsensor`` = the torque sensor's settings (:mod:`.torque_sensor`): with no sensor, none
  running (the recorded two-vector layout); on an arm with the sensor (``--force-sensor``), the
  twin's sensor payload and the sample's actual, general and real wrench;
* ``on_soft_limit``: 1 while a joint is within 0.1° of its limit (the twin's sample);
* the IO arrays of every type (cabinet, tool, ``extio`` for the extension module, ``relay_io``,
  ``mb_slave_*``, ``pn_dev_*``, ``eip_adpt_*``), as set.

Keys the twin has nothing behind are reported as an idle controller with nothing configured
would (``paused`` false, ``task_mode`` 2 = auto, ``funcdi`` unassigned).
``errcode`` is the emulator's own, written ``"0x…"`` as the SDK reads it: ``0xE001`` collision,
``0xE002`` protective stop, ``0x0`` none.

**Made again only when it changed.** A packet goes out every 8 ms, built in the interpreter
lock that the emulator's command threads wait for (a ``servo_j`` that arrives meanwhile is
answered after it). Each derived value (the wire's joints, poses, joint rows, speeds, the
torque sensor's lists) is kept with the inputs it was made from, and the same object goes out
again while they are the same (:class:`_Unchanged`): an arm at rest, which changes nothing
from packet to packet, costs the lookups, and the encoder (protocol.StatusEncoder) writes
such an object from the bytes it kept. The TCP's speed and the commanded TCP depend on the
active frames too; the measured TCP, made with them, is part of their inputs.
"""
from __future__ import annotations

import weakref
from typing import Any, Callable, Dict, List, Tuple

import numpy as np

from ..backend import ProgramState
from ..common.transforms import matrix_to_pose_mm_rpy
from ..protocol import units
from ..protocol.fields import InterpState, IOType, StatusField as S, TaskState
from .tool_io_commands import signal_rows
from .twin_controller import TwinController

ERRCODE_COLLISION = 0xE001
ERRCODE_PROTECTIVE_STOP = 0xE002
TASK_MODE_AUTO = 2
BUS_VOLTAGE = 48.0        # V, the arm's DC supply while powered
TORQUE_PER_AMP = 10.0     # N·m per A at a joint's output (an order of magnitude, see above)
JOINT_ROW = 11            # numbers per joint row of monitor_data, as a Zu 5s sends them
_TORQUE = 9               # index of the torque in a joint row

#: Keys the twin has nothing behind: what a controller with nothing configured sends.
_IDLE = {
    "drag_near_limit": lambda: [0] * 6, "funcdi": lambda: [[-1, -1] for _ in range(15)],
    "motion_mode": lambda: 0, "point_key": lambda: 0, "netState": lambda: 1,
    "tio_key": lambda: [0, 0, 0], "tio_rs_signals": lambda: [],
}

#: packet key → the IO it shows (signal, type, path: 0 inputs, 1 outputs)
IO_KEYS: Dict[str, Tuple[str, int, int]] = {
    S.DIN: ("digital", IOType.CABINET, 0), S.DOUT: ("digital", IOType.CABINET, 1),
    S.AIN: ("analog", IOType.CABINET, 0), S.AOUT: ("analog", IOType.CABINET, 1),
    S.TIO_DIN: ("digital", IOType.TOOL, 0), S.TIO_DOUT: ("digital", IOType.TOOL, 1),
    S.TIO_AIN: ("analog", IOType.TOOL, 0),
}
FIELDBUS_KEYS: Dict[str, Tuple[str, int, int]] = {S.RELAY_IO: ("digital", IOType.RELAY, 1)}
for _prefix, _type in (("mb_slave", IOType.MODBUS_SLAVE), ("pn_dev", IOType.PROFINET_SLAVE),
                       ("eip_adpt", IOType.EIP_SLAVE)):
    FIELDBUS_KEYS.update({f"{_prefix}_din": ("digital", _type, 0),
                          f"{_prefix}_dout": ("digital", _type, 1),
                          f"{_prefix}_ain": ("analog", _type, 0),
                          f"{_prefix}_aout": ("analog", _type, 1)})
_EXTENSION = [("digital", IOType.EXTEND, 0), ("digital", IOType.EXTEND, 1),
              ("analog", IOType.EXTEND, 0), ("analog", IOType.EXTEND, 1)]


#: a program's state → ``interp_state`` (its reading by third-party clients, medium
#: confidence: docs/protocol.md); ``paused`` is true while a program is paused
_INTERP = {ProgramState.RUNNING: InterpState.RUNNING, ProgramState.PAUSED: InterpState.PAUSED}


def zeros_of(key: str) -> Any:
    """The idle value of a packet key the twin has nothing behind (e.g. ``funcdi``)."""
    return _IDLE[key]()


#: the idle values as the status packets carry them: one object each, the same every packet
#: (a packet's values are only ever encoded, never changed), so an encoder that remembers
#: what it encoded last (protocol.StatusEncoder) encodes them once
_IDLE_VALUES = {key: make() for key, make in _IDLE.items()}


class _IoLists:
    """The IO arrays of a packet as lists, made again only when the board changed: a sample's
    IO is one read-only object until the next write (``RobotState.io``), so the same object
    means the same lists — the same list objects, which the encoder then encodes once."""

    def __init__(self):
        self._last: Tuple[Any, Dict[str, list]] = (None, {})

    def of(self, io, keys: Dict[str, Tuple[str, int, int]]) -> Dict[str, list]:
        last_io, lists = self._last
        if io is not last_io:
            lists = {name: _io_list(io.get(key), key) for name, key in keys.items()}
            self._last = (io, lists)
        return lists


_IO_LISTS = _IoLists()
_FIELDBUS_LISTS = _IoLists()


class _Unchanged:
    """One controller's packet values, each kept with the inputs it was made from (see the
    module). Threads may share it (the broadcaster, ``data_request``, ``get_data``): a value is
    only ever replaced whole, and what a thread gets was made from the inputs it asked with."""

    def __init__(self):
        self._kept: Dict[str, Tuple[Any, Any]] = {}

    def made(self, name: str, inputs: Any, make: Callable[[], Any]) -> Any:
        """``make()``, or the value made for ``name`` last if ``inputs`` (bytes, a tuple of them
        and other values, or an object that is not changed in place: the board's IO) are those
        it was made from."""
        kept = self._kept.get(name)
        if kept is not None and (kept[0] is inputs or kept[0] == inputs):
            return kept[1]
        value = make()
        self._kept[name] = (inputs, value)
        return value

    def same(self, name: str, value: Any) -> Any:
        """``value``, or the equal one given for ``name`` last (a list made afresh each time
        from settings: the torque sensor's, the tool connector's signals). Each of those keeps
        its JSON types for equal values, so equal means the same bytes."""
        kept = self._kept.get(name)
        if kept is not None and kept[1] == value:
            return kept[1]
        self._kept[name] = (None, value)
        return value


_UNCHANGED: "weakref.WeakKeyDictionary[TwinController, _Unchanged]" = \
    weakref.WeakKeyDictionary()


def _unchanged(controller: TwinController) -> _Unchanged:
    kept = _UNCHANGED.get(controller)
    if kept is None:
        kept = _UNCHANGED[controller] = _Unchanged()
    return kept


def wire_pose(pose: np.ndarray) -> list:
    """4x4 pose (m) → wire ``[x, y, z mm, rx, ry, rz deg]``."""
    return units.pose_to_wire(matrix_to_pose_mm_rpy(pose))


def _io_list(values, key: Tuple[str, int, int]) -> list:
    cast = int if key[0] == "digital" else float
    return [] if values is None else [cast(v) for v in values]


def io_values(controller: TwinController, key: Tuple[str, int, int]) -> list:
    """One IO array as the packet writes it (digital ints, analog floats), index 0 first."""
    return _io_list(controller.io_values().get(key), key)


def extio(controller: TwinController, io: Dict | None = None) -> Dict[str, Any]:
    """The extension module (IO type 2): ``{"num": 1, "status": [din, dout, ain, aout]}``, or
    ``{"num": 0, "status": []}`` when the profile has none. JAKA's SDK reads it only if
    ``num`` > 0, every value as an int."""
    io = controller.io_values() if io is None else io
    if not any(controller.io_count(*key) for key in _EXTENSION):
        return {"num": 0, "status": []}
    return {"num": 1, "status": [_io_list(io.get(key), key) for key in _EXTENSION]}


def _monitor_data(powered: bool, torque: np.ndarray, speed: np.ndarray) -> list:
    voltage = BUS_VOLTAGE if powered else 0.0
    power = float(np.sum(np.abs(torque * speed)))
    rows: List[list] = []
    for tau in torque:
        row = [0.0] * JOINT_ROW
        row[0], row[1], row[_TORQUE] = float(tau) / TORQUE_PER_AMP, voltage, float(tau)
        rows.append(row)
    return [0, 0, 0.0, power, power / voltage if voltage else 0.0, rows]


_HOMED: Dict[int, list] = {}


def _homed(count: int) -> list:
    """``homed`` of ``count`` joints: one list per count, the same every packet."""
    homed = _HOMED.get(count)
    if homed is None:
        homed = _HOMED[count] = [1] * count
    return homed


def status_fields(controller: TwinController) -> Dict[str, Any]:
    """One packet's fields, in a real packet's key order (without ``len``:
    :func:`~jaka_driver.protocol.encode_status` puts it first)."""
    st = controller.state()
    kept = _unchanged(controller)
    inpos = controller.inpos
    if st.collision:
        errcode = ERRCODE_COLLISION
    elif st.protective_stop:
        errcode = ERRCODE_PROTECTIVE_STOP
    else:
        errcode = 0
    if not st.powered:
        task_state = TaskState.POWER_OFF
    elif not st.enabled:
        task_state = TaskState.POWER_ON
    else:
        task_state = TaskState.ENABLED
    io = st.io          # the board as it stands (the same object until a write)
    q, qd, tcp = st.joint_position.tobytes(), st.joint_velocity.tobytes(), st.tcp_pose.tobytes()
    commanded = controller.commanded_joints()
    program = controller.programs.status()
    fields: Dict[str, Any] = {
        S.DRAG_STATUS: bool(st.drag_mode),
        S.EXTIO: kept.made(S.EXTIO, io, lambda: extio(controller, io)),
        S.ERRCODE: f"{errcode:#x}",
        S.ERRMSG: st.error_message if errcode else "",
        S.MONITOR_DATA: kept.made(
            S.MONITOR_DATA, (st.powered, st.joint_effort.tobytes(), qd),
            lambda: _monitor_data(st.powered, st.joint_effort, st.joint_velocity)),
        S.TORQSENSOR: kept.same(S.TORQSENSOR, controller.torqsensor(st)),
        S.RAPIDRATE: float(controller.rapid_rate),
        S.ENABLED: bool(st.enabled),
        S.POWERED_ON: int(st.powered),
        S.INPOS: bool(inpos),
        S.PAUSED: program.state == ProgramState.PAUSED,
        S.PROTECTIVE_STOP: int(st.protective_stop or st.collision),
        S.EMERGENCY_STOP: int(st.emergency_stop),
        S.ON_SOFT_LIMIT: int(st.on_limit),     # a joint within 0.1° of its limit
        S.TASK_STATE: int(task_state),
        S.TASK_MODE: TASK_MODE_AUTO,
        S.INTERP_STATE: int(_INTERP[program.state] if program.state != ProgramState.IDLE
                            else InterpState.IDLE if inpos else InterpState.RUNNING),
        "motion_mode": zeros_of("motion_mode"),
        S.CURRENT_TOOL_ID: int(st.tool_id),
        S.CURRENT_USER_ID: int(st.user_id),
        S.JOINT_ACTUAL_POSITION: kept.made(S.JOINT_ACTUAL_POSITION, q,
                                           lambda: units.joints_to_wire(st.joint_position)),
        S.JOINT_POSITION: kept.made(S.JOINT_POSITION, commanded.tobytes(),
                                    lambda: units.joints_to_wire(commanded)),
        S.ACTUAL_POSITION: kept.made(S.ACTUAL_POSITION, tcp, lambda: wire_pose(st.tcp_pose)),
        # the active frames are in the measured TCP: a frame changed changes it
        S.POSITION: kept.made(S.POSITION, (commanded.tobytes(), tcp),
                              lambda: wire_pose(controller.commanded_tcp())),
        "curr_tcp_trans_vel": kept.made("curr_tcp_trans_vel", (q, qd, tcp),
                                        lambda: float(controller.tcp_speed(st) * 1000.0)),
    }
    for name, values in _IO_LISTS.of(io, IO_KEYS).items():
        fields[name] = values
        if name == S.TIO_AIN:
            fields["tio_key"] = _IDLE_VALUES["tio_key"]
            fields["tio_rs_signals"] = kept.same("tio_rs_signals",
                                                 signal_rows(controller.backend.tool_io))
    fields[S.HOMED] = _homed(controller.profile.homed_count)
    for key in ("drag_near_limit", "funcdi", "point_key", "netState"):
        fields[key] = _IDLE_VALUES[key]
    fields.update(_FIELDBUS_LISTS.of(io, FIELDBUS_KEYS))
    fields[S.MOTION_LINE] = int(controller.motion_line)
    fields[S.ERR_ADD_LINE] = 0
    fields[S.EXECUTING_LINE] = int(controller.motion_line)
    fields[S.INST_VEL] = kept.made(S.INST_VEL, qd,
                                   lambda: np.degrees(st.joint_velocity).tolist())
    keys = controller.profile.packet_keys
    if keys is None:
        return fields
    fields["timestamp"] = float(st.stamp)
    return {key: fields[key] for key in keys}
