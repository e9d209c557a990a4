"""JAKA's C++ SDK (libjakaAPI 2.1.14), restated for tests: what each of its functions sends and how
strictly it reads the reply (JAKA's ROS 1 node on it: :mod:`jaka_ros_node_model`).

We cannot run JAKA's binary SDK here. What it does on the wire was measured from the binary and
against a fake controller (docs/protocol.md gives the facts; the fixtures in test/data/ the
text); this module states exactly that, and nothing of the emulator's code: a request is
encoded as the SDK encodes it (compact JSON, sorted keys, its fixed decimals), and a reply is
read as strictly as the SDK's old jsoncpp reads it:

* ``asString`` on a number, ``asDouble``/``asInt`` on a string throw, and nothing catches them:
  the client process aborts (:class:`SdkCrash`); indexing a scalar or an object as an array
  is a segmentation fault (:class:`SdkCrash`);
* ``asBool`` of any non-empty string is true (``"false"`` reads true); ``asInt`` truncates a
  double and takes a bool;
* a missing key reads 0 / false / ""; a short array reads zeros for what is missing;
* ``errorCode``: a string read as an int, "0" success, anything else rc 2; a JSON int is the rc;
  missing or another type rc 2; a reply with errorCode ≠ 0 leaves the output untouched;
* a set the SDK waits on polls its get every 100 ms for 1 s and returns −61 if the value does
  not come back; an argument it checks itself returns −2 with nothing sent;
* ``get_robot_state``, ``is_in_estop``, ``joint_move``, ``linear_move``, ``jog`` and ``jog_stop``
  each send one ``emergency_stop_status`` (seen on the wire, one per call) and return 2 when its
  answer is not a success, though a move or jog sent in the same call was acknowledged and runs
  (:data:`ASKS_ESTOP`). The recorded fw 1.5.14 answers it with an exception, so these calls
  fail there; the SDK was written for a controller whose ``emergency_stop_status`` answers.

Where the SDK reads a value wrong but goes on (a garbled ``errcode``, a torque-sensor block of
the wrong shape), the model raises :class:`SdkGarbage`: a test should never see it.

Return values follow the SDK: an ``int`` rc (0 success), and for getters ``(rc, value)``.
Units at this API are the SDK's: rad, mm, RPY rad, rad/s, mm/s.
"""
from __future__ import annotations

import json
import math
import socket
import threading
import time
import zlib
from typing import Any, Dict, List, Optional, Sequence, Tuple

from .jaka_sdk_json import (FIXED_DECIMALS, SdkCrash, SdkGarbage, as_bool, as_double, as_int,
                             as_string, deg, doubles, element, member, pose_deg, pose_rad,
                             sdk_json)
from .jaka_sdk_status import RobotStatus, parse_robot_status

SDK_VERSION = "libadd jakaAPI_version: V2.1.14stable_linux"
DATA_BUFFER = 8200          # bytes the SDK reads a data_request reply into
RC_OK, RC_FAILED, RC_BAD_ARGUMENT, RC_TIMEOUT = 0, 2, -2, -61
WAIT_PERIOD, WAIT_LIMIT = 0.1, 1.0   # s: the SDK's poll after a set
ABS, INCR, CONTINUE = 0, 1, 2        # MoveMode
COORD_BASE, COORD_JOINT, COORD_TOOL = 0, 1, 2
IDENTITY = ("version", "controller_id", "controller_guarantee", "robot_id", "robot_name",
            "scb_version", "servo_version")
PROGRAM_STATES = {"idle": 0, "running": 1, "paused": 2}
FT_KEYS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")    # torqueSensorSoftLimit's keys
#: The SDK calls that ask ``emergency_stop_status`` inside them (one request per call) and
#: return 2 when it does not answer success. Where in the call it goes out is not on record;
#: the model sends it after the call's own command.
ASKS_ESTOP = ("get_robot_state", "is_in_estop", "joint_move", "linear_move", "jog", "jog_stop")

class JakaSdk:
    """One SDK handle: the command connection (10001) and the data_request connection (10004).
    ``sent`` keeps every request text, in order."""

    def __init__(self, host: str, command_port: int = 10001, data_port: int = 10004):
        self.host, self.command_port, self.data_port = host, command_port, data_port
        self.sent: List[str] = []
        self._movc_count = 0        # movc's executing_line_id: the SDK's counter
        self._lock = threading.Lock()
        self._cmd: Optional[socket.socket] = None
        self._data: Optional[socket.socket] = None

    # -- transport --
    def _request(self, request: dict) -> Tuple[int, dict]:
        text = sdk_json(request, FIXED_DECIMALS)
        with self._lock:
            if self._cmd is None:
                self._cmd = socket.create_connection((self.host, self.command_port), timeout=10)
            self.sent.append(text)
            self._cmd.sendall(text.encode())
            reply = _read_json(self._cmd)
        return _rc(reply), reply

    def call(self, command: str, **fields) -> Tuple[int, dict]:
        """Any command, its reply read only for errorCode (the reply is returned as is)."""
        return self._request({"cmdName": command, **fields})

    def _wait_until(self, read, expected) -> int:
        """The SDK's wait after a set: poll ``read()`` every 100 ms for 1 s."""
        deadline = time.monotonic() + WAIT_LIMIT
        while True:
            rc, value = read()
            if rc == RC_OK and expected(value):
                return RC_OK
            if time.monotonic() > deadline:
                return RC_TIMEOUT
            time.sleep(WAIT_PERIOD)

    def close(self) -> None:
        for sock in (self._cmd, self._data):
            if sock is not None:
                sock.close()
        self._cmd = self._data = None

    # -- login, power --
    def login_in(self) -> Tuple[int, Dict[str, str]]:
        rc, reply = self.call("get_version", sdk_version=SDK_VERSION)
        if rc != RC_OK:
            return rc, {}
        return rc, {key: as_string(member(reply, key)) for key in IDENTITY}

    def power_on(self) -> int:
        return self.call("power_on")[0]

    def power_off(self) -> int:
        return self.call("power_off")[0]

    def enable_robot(self) -> int:
        return self.call("enable_robot")[0]

    def disable_robot(self) -> int:
        return self.call("disable_robot")[0]

    # -- the e-stop, asked inside the calls of ASKS_ESTOP --
    def _estop_asked(self) -> Tuple[int, bool]:
        """The ``emergency_stop_status`` such a call sends: (RC_OK, pressed) when it answers
        success, else (RC_FAILED, False) — the call then returns 2."""
        rc, reply = self.call("emergency_stop_status")
        if rc != RC_OK:
            return RC_FAILED, False
        return RC_OK, bool(as_int(member(reply, "emergency_stop")))

    def _then_estop(self, rc: int) -> int:
        """A call's rc after the e-stop it asks: 2 if that answer is not a success."""
        estop_rc, _ = self._estop_asked()
        return RC_FAILED if estop_rc != RC_OK else rc

    def is_in_estop(self) -> Tuple[int, bool]:
        return self._estop_asked()

    def get_robot_state(self) -> Tuple[int, Optional[Dict[str, Any]]]:
        """RobotState: the e-stop from ``emergency_stop_status``, power and enable from
        ``get_robot_state`` (as the SDK's get_robot_status_simple reads them; how this call
        converts the words is not on record, so they are returned as they came)."""
        rc, reply = self.call("get_robot_state")
        estop_rc, pressed = self._estop_asked()
        if rc != RC_OK or estop_rc != RC_OK:
            return (rc if rc != RC_OK else RC_FAILED), None
        return RC_OK, {"estoped": pressed, "power": member(reply, "power"),
                       "enable": member(reply, "enable")}

    # -- status (port 10004) --
    def get_robot_status(self) -> Tuple[int, RobotStatus]:
        with self._lock:
            if self._data is None:
                self._data = socket.create_connection((self.host, self.data_port), timeout=10)
            self._data.sendall(b'{"cmdName":"data_request"}')
            inflater, size, text = zlib.decompressobj(), 0, b""
            while not inflater.eof:
                chunk = self._data.recv(65536)
                if not chunk:
                    raise ConnectionError("data port closed")
                size += len(chunk)
                text += inflater.decompress(chunk)
        if size > DATA_BUFFER:
            raise SdkGarbage(f"a {size}-byte reply in the SDK's {DATA_BUFFER}-byte buffer")
        text = text.decode()
        if not (text[0] == "{" and text[2:5] == "len" and text[-1] == "}"):
            raise SdkGarbage(f"not a status packet: {text[:40]!r}")
        return RC_OK, parse_robot_status(text)

    # -- programs --
    def get_program_state(self) -> Tuple[int, Optional[int]]:
        rc, reply = self.call("get_program_state")
        if rc != RC_OK:
            return rc, None
        raw = member(reply, "programState")
        if not isinstance(raw, str) and raw is not None:
            raise SdkCrash(f"programState {raw!r}: the SDK compares strings and aborts")
        return rc, PROGRAM_STATES.get(as_string(raw))   # an unknown string: left unchanged

    def get_loaded_program(self) -> Tuple[int, str]:
        rc, reply = self.call("get_loaded_program")
        return rc, as_string(member(reply, "programName")) if rc == RC_OK else ""

    def get_current_line(self) -> Tuple[int, int]:
        rc, reply = self.call("get_current_line")
        return rc, as_int(member(reply, "current_line")) if rc == RC_OK else 0

    def program_load(self, name: str) -> int:
        return self.call("load_program", programName=name + ".jks")[0]

    def program_run(self) -> int:
        return self.call("play_program")[0]

    def program_pause(self) -> int:
        return self.call("pause_program")[0]

    def program_resume(self) -> int:
        return self.call("resume_program")[0]

    def program_abort(self) -> int:
        rc = self.call("stop_program")[0]
        if rc != RC_OK:
            return rc
        return self._wait_until(lambda: self.call("get_motion_state"),
                                lambda r: as_int(member(r, "queue")) == 0
                                and not as_bool(member(r, "queue_full")))

    def get_user_var(self) -> Tuple[int, list]:
        """(id, value, alias) of each of the first 100 entries of ``var_list``; the output is
        left empty when errorCode is not 0."""
        rc, reply = self.call("query_user_defined_variable")
        if rc != RC_OK:
            return rc, []
        items = member(reply, "var_list")
        element(items, 0)           # an object or a scalar: the SDK's indexing crashes
        return rc, [(as_int(member(element(items, i), "id")),
                     as_double(member(element(items, i), "value")),
                     as_string(member(element(items, i), "alias")))
                    for i in range(min(len(items or []), 100))]

    def set_user_var(self, var_id: int, value: float, alias: str) -> int:
        """No wait and no read back: the reply's errorCode only."""
        return self.call("modify_user_defined_variable", alias_new=alias, id_new=int(var_id),
                          value_new=float(value))[0]

    def motion_abort(self) -> int:
        return self.call("stop_program")[0]

    # -- frames --
    def _frame(self, command: str, key: str, frame_id: int) -> Tuple[int, Optional[list]]:
        if not 0 <= frame_id <= 10:
            return RC_BAD_ARGUMENT, None
        rc, reply = self.call(command)
        if rc != RC_OK:
            return rc, None
        return rc, pose_rad(doubles(element(member(reply, key), frame_id), 6))

    def get_tool_data(self, tool_id: int) -> Tuple[int, Optional[list]]:
        return self._frame("get_tool_offsets", "tool_offsets", tool_id)

    def get_user_frame_data(self, user_id: int) -> Tuple[int, Optional[list]]:
        return self._frame("get_user_offsets", "user_offsets", user_id)

    def set_tool_data(self, tool_id: int, tcp: Sequence[float], name: str) -> int:
        if not 1 <= tool_id <= 10:
            return RC_BAD_ARGUMENT
        return self.call("set_tool_offsets", id=tool_id, name=name,
                          tooloffset=pose_deg(tcp))[0]

    def set_user_frame_data(self, user_id: int, frame: Sequence[float], name: str) -> int:
        if not 1 <= user_id <= 10:
            return RC_BAD_ARGUMENT
        return self.call("set_user_offsets", id=user_id, name=name,
                          userffset=pose_deg(frame))[0]

    def get_tool_id(self) -> Tuple[int, int]:
        rc, reply = self.call("get_curr_tool_id")
        return rc, as_int(member(reply, "id"))

    def get_user_frame_id(self) -> Tuple[int, int]:
        rc, reply = self.call("get_curr_user_id")
        return rc, as_int(member(reply, "id"))

    def set_tool_id(self, tool_id: int) -> int:
        if not 0 <= tool_id <= 10:
            return RC_BAD_ARGUMENT
        rc = self.call("set_tool_id", tool_id=tool_id)[0]
        return rc if rc != RC_OK else self._wait_until(self.get_tool_id,
                                                       lambda v: v == tool_id)

    def set_user_frame_id(self, user_id: int) -> int:
        if not 0 <= user_id <= 10:
            return RC_BAD_ARGUMENT
        rc = self.call("set_user_id", user_frame_id=user_id)[0]
        return rc if rc != RC_OK else self._wait_until(self.get_user_frame_id,
                                                       lambda v: v == user_id)

    # -- speed, drag, payloads --
    def set_rapidrate(self, rate: float) -> int:
        rc = self.call("rapid_rate", rate_value=float(rate))[0]
        return rc if rc != RC_OK else self._wait_until(self.get_rapidrate,
                                                       lambda v: abs(v - rate) < 0.01)

    def get_rapidrate(self) -> Tuple[int, float]:
        rc, reply = self.call("get_rapid_rate")
        return rc, as_double(member(reply, "value"))

    def drag_mode_enable(self, on: bool) -> int:
        rc = self.call("torque_control_enable", enable_flag=int(on))[0]
        return rc if rc != RC_OK else self._wait_until(self.is_in_drag_mode,
                                                       lambda v: v == on)

    def is_in_drag_mode(self) -> Tuple[int, bool]:
        rc, reply = self.call("get_drag_status")
        return rc, as_bool(member(reply, "status"))

    def set_payload(self, mass: float, centroid: Sequence[float]) -> int:
        return self.call("set_payload", mass=float(mass),
                          centroid=[float(c) for c in centroid])[0]

    def get_payload(self) -> Tuple[int, Tuple[float, List[float]]]:
        rc, reply = self.call("get_payload")
        return rc, (as_double(member(reply, "mass")), doubles(member(reply, "centroid"), 3))

    def set_torq_sensor_tool_payload(self, mass: float, centroid: Sequence[float]) -> int:
        rc = self.call("set_tool_payload", mass=float(mass),
                        centroid=[float(c) for c in centroid])[0]
        return rc if rc != RC_OK else self._wait_until(
            self.get_torq_sensor_tool_payload,
            lambda v: abs(v[0] - mass) < 1e-3 and all(abs(a - b) < 1e-3
                                                      for a, b in zip(v[1], centroid)))

    def get_torq_sensor_tool_payload(self) -> Tuple[int, Tuple[float, List[float]]]:
        rc, reply = self.call("get_tool_payload")
        return rc, (as_double(member(reply, "mass")), doubles(member(reply, "centroid"), 3))

    def set_torque_sensor_comm(self, comm_type: int, ip_addr: str, port: int) -> int:
        rc = self.call("set_torque_sensor_comm", type=comm_type, ip_addr=ip_addr,
                        port=port)[0]
        return rc if rc != RC_OK else self._wait_until(
            self.get_torque_sensor_comm, lambda v: v == (comm_type, ip_addr, port))

    def get_torque_sensor_comm(self) -> Tuple[int, Tuple[int, str, int]]:
        rc, reply = self.call("get_torque_sensor_comm")
        comm_type = as_int(member(reply, "type"))
        if comm_type == 1:             # the SDK skips the rest, errorCode included
            return RC_OK, (1, "", 0)
        return rc, (comm_type, as_string(member(reply, "ip_addr")),
                    as_int(member(reply, "port")))

    # -- the torque sensor and force control (sdk_wire_formats §5) --
    def set_torque_sensor_mode(self, mode: int) -> int:
        """No wait: the sensor's state is in the status packet (there is no get)."""
        return self.call("set_torque_sensor_mode", sensor_mode=int(mode))[0]

    def zero_end_sensor(self) -> int:
        return self.call("zero_end_sensor")[0]

    def set_torque_sensor_filter(self, cutoff: float) -> int:
        return self.call("set_torque_sensor_filter", torqueSensorFilter=float(cutoff))[0]

    def get_torque_sensor_filter(self) -> Tuple[int, float]:
        rc, reply = self.call("get_torque_sensor_filter")
        return rc, as_double(member(reply, "torqueSensorFilter")) if rc == RC_OK else 0.0

    def set_torque_sensor_soft_limit(self, limit: Sequence[float]) -> int:
        return self.call("set_torque_sensor_soft_limit", torqueSensorSoftLimit={
            key: float(v) for key, v in zip(FT_KEYS, limit)})[0]

    def get_torque_sensor_soft_limit(self) -> Tuple[int, List[float]]:
        rc, reply = self.call("get_torque_sensor_soft_limit")
        limit = member(reply, "torqueSensorSoftLimit")
        return rc, [as_double(member(limit, key)) for key in FT_KEYS] if rc == RC_OK else []

    def set_admit_ctrl_config(self, axis: int, opt: int, ft_user: float, ft_constant: float,
                              normal_track: int, rebound: float) -> int:
        """``ftReboundFK`` written with 3 decimals, as measured (``0.250``)."""
        return self.call("set_admit_ctrl_config", axis=int(axis), opt=int(opt),
                          ftUser=float(ft_user), ftConstant=float(ft_constant),
                          ftNnormalTrack=int(normal_track), ftReboundFK=float(rebound))[0]

    def get_admit_ctrl_config(self) -> Tuple[int, List[Tuple[int, float, float, float, int]]]:
        """Six rows [opt, ft_user, ft_rebound, ft_constant, ft_normal_track], row = axis."""
        rc, reply = self.call("get_admit_ctrl_config")
        if rc != RC_OK:
            return rc, []
        table = member(reply, "admitConfig")
        rows = []
        for axis in range(6):
            row = element(table, axis)
            rows.append((as_int(element(row, 0)), as_double(element(row, 1)),
                         as_double(element(row, 2)), as_double(element(row, 3)),
                         as_int(element(row, 4))))
        return rc, rows

    def set_compliant_type(self, compensation: int, compliance_type: int) -> int:
        return self.call("set_compliant_type", sensor_compensation=int(compensation),
                          compliance_type=int(compliance_type))[0]

    def get_compliant_type(self) -> Tuple[int, Tuple[int, int]]:
        rc, reply = self.call("get_compliant_type")
        return rc, (as_int(member(reply, "sensor_compensation")),
                    as_int(member(reply, "compliance_type")))

    def set_vel_compliant_ctrl(self, level: int, rates: Sequence[float]) -> int:
        return self.call("set_vel_compliant_ctrl",
                          compliant_ctrl=[int(level)] + [float(r) for r in rates])[0]

    def set_compliance_condition(self, wrench: Sequence[float]) -> int:
        return self.call("set_compliance_condition",
                          compliant_condition=[float(v) for v in wrench])[0]

    def set_ft_ctrl_frame(self, frame: int) -> int:
        return self.call("set_ft_ctrl_frame", ftFrame=int(frame))[0]

    def get_ft_ctrl_frame(self) -> Tuple[int, int]:
        rc, reply = self.call("get_ft_ctrl_frame")
        return rc, as_int(member(reply, "ftFrame"))

    def enable_admittance_ctrl(self, on: int) -> int:
        return self.call("enable_admittance_ctrl", enable_flag=int(on))[0]

    def enable_tool_drive(self, on: int) -> int:
        """The same command as enable_admittance_ctrl (measured)."""
        return self.enable_admittance_ctrl(on)

    def disable_force_control(self) -> int:
        return self.call("disable_force_control")[0]

    def set_tool_drive_config(self, axis: int, opt: int, rigidity: float,
                              rebound: float) -> int:
        return self.call("set_tool_drive_config", axis=int(axis), opt=int(opt),
                          rigidity=float(rigidity), rebound=float(rebound))[0]

    def get_tool_drive_config(self) -> Tuple[int, List[Tuple[int, int, float, float]]]:
        """Six rows as (axis, opt, rigidity, rebound): the SDK sets axis = row."""
        rc, reply = self.call("get_tool_drive_config")
        if rc != RC_OK:
            return rc, []
        table = member(reply, "force_ctrl_config")
        return rc, [(axis, as_int(element(element(table, axis), 0)),
                     as_double(element(element(table, axis), 1)),
                     as_double(element(element(table, axis), 2))) for axis in range(6)]

    def get_tool_drive_state(self) -> Tuple[int, Tuple[int, int]]:
        rc, reply = self.call("get_tool_drive_stat")
        return rc, (as_int(member(reply, "enable_flag")), as_int(member(reply, "drive_stat")))

    def set_tool_drive_frame(self, frame: int) -> int:
        return self.call("set_tool_drive_frame", toolDragFrame=int(frame))[0]

    def get_tool_drive_frame(self) -> Tuple[int, int]:
        rc, reply = self.call("get_tool_drive_frame")
        return rc, as_int(member(reply, "toolDragFrame"))

    def get_torque_sensor_data(self, kind: int) -> Tuple[int, Optional[Tuple[int, int, list]]]:
        """TorqSensorData: status, errorCode (the reply's ``errcode``), data [6]."""
        rc, reply = self.call("get_torque_sensor_data", type=int(kind))
        if rc != RC_OK:
            return rc, None
        return rc, (as_int(member(reply, "status")), as_int(member(reply, "errcode")),
                    doubles(member(reply, "data"), 6))

    def start_torq_sensor_payload_identify(self, joints: Sequence[float]) -> int:
        return self.call("start_torq_sensor_payload_identify", jointPosition=deg(joints))[0]

    def get_torq_sensor_identify_staus(self) -> Tuple[int, int]:
        """(sic) 0 done, 1 running, 2 error."""
        rc, reply = self.call("get_torq_sensor_identify_staus")
        return rc, as_int(member(reply, "identify_status"))

    def get_torq_sensor_payload_identify_result(self) -> Tuple[int, Tuple[float, List[float]]]:
        rc, reply = self.call("get_torq_sensor_payload_identify_result")
        return rc, (as_double(member(reply, "mass")), doubles(member(reply, "centroid"), 3))

    def set_collision_level(self, level: int) -> int:
        return self.call("set_clsn_sensitivity", sensitivityVal=level)[0]

    # -- servo mode --
    def servo_move_enable(self, on: bool) -> int:
        rc = self.call("servo_move", relFlag=int(on))[0]
        # the SDK waits for true also when it disables: disable returns -61 (its own bug)
        return rc if rc != RC_OK else self._wait_until(self.is_in_servomove, lambda v: v)

    def is_in_servomove(self) -> Tuple[int, bool]:
        rc, reply = self.call("is_in_servomove")
        return rc, as_bool(member(reply, "in_servomove"))

    def servo_j(self, joints: Sequence[float], mode: int, step_num: int = 1) -> int:
        if mode == CONTINUE or step_num < 1:
            return RC_BAD_ARGUMENT
        return self.call("servo_j", jointPosition=deg(joints), relFlag=int(mode == INCR),
                          stepNum=step_num)[0]

    def servo_p(self, pose: Sequence[float], mode: int, step_num: int = 1) -> int:
        if mode == CONTINUE or step_num < 1:
            return RC_BAD_ARGUMENT
        return self.call("servo_p", catPosition=pose_deg(pose), relFlag=int(mode == INCR),
                          stepNum=step_num)[0]

    def servo_move_use_none_filter(self) -> int:
        return self.call("set_servo_move_filter", filter_type=0)[0]

    def servo_move_use_joint_LPF(self, cutoff_hz: float) -> int:
        return self.call("set_servo_move_filter", filter_type=1, lpf_cf=float(cutoff_hz))[0]

    def servo_move_use_joint_NLF(self, max_vr: float, max_ar: float, max_jr: float) -> int:
        """deg/s, deg/s², deg/s³, sent unconverted."""
        return self.call("set_servo_move_filter", filter_type=2, nlf_max_vr=float(max_vr),
                          nlf_max_ar=float(max_ar), nlf_max_jr=float(max_jr))[0]

    def servo_move_use_joint_MMF(self, max_buf: int, kp: float, kv: float, ka: float) -> int:
        return self.call("set_servo_move_filter", filter_type=3, mmf_max_buf=int(max_buf),
                          mmf_kp=float(kp), mmf_kv=float(kv), mmf_ka=float(ka))[0]

    def servo_move_use_carte_NLF(self, max_vp: float, max_ap: float, max_jp: float,
                                 max_vr: float, max_ar: float, max_jr: float) -> int:
        """mm/s, mm/s², mm/s³ and deg/s, deg/s², deg/s³, sent unconverted."""
        return self.call("set_servo_move_filter", filter_type=4, nlf_max_vp=float(max_vp),
                          nlf_max_ap=float(max_ap), nlf_max_jp=float(max_jp),
                          nlf_max_vr=float(max_vr), nlf_max_ar=float(max_ar),
                          nlf_max_jr=float(max_jr))[0]

    def servo_speed_foresight(self, max_buf: int, kp: float) -> int:
        return self.call("set_servo_move_filter", filter_type=5, mmf_max_buf=max_buf,
                          mmf_kp=float(kp))[0]

    # -- motion --
    def joint_move(self, joints: Sequence[float], mode: int, speed: float, accel: float,
                   tol: float = 0.0) -> int:
        """Non-blocking; a blocking call is this plus :meth:`wait_inpos`."""
        return self._then_estop(self.call(
            "joint_move", jointPosition=deg(joints), relFlag=int(mode == INCR),
            speed=math.degrees(speed), accel=math.degrees(accel), executing_line_id=0,
            tol=float(tol))[0])

    def linear_move(self, pose: Sequence[float], mode: int, speed: float, accel: float,
                    tol: float = 0.0, ori_vel: float = 3.14, ori_acc: float = 12.56) -> int:
        return self._then_estop(self.call(
            "moveL", cartPosition=pose_deg(pose), relFlag=int(mode == INCR), speed=float(speed),
            accel=float(accel), ori_vel=math.degrees(ori_vel), ori_acc=math.degrees(ori_acc),
            executing_line_id=0, tol=float(tol))[0])

    def circular_move(self, end_pos: Sequence[float], mid_pos: Sequence[float], mode: int,
                      is_block: bool, speed: float, accel: float, tol: float = 0.0,
                      circle_cnt: float = 0.0, circle_mode: int = 0,
                      block_timeout: float = 30.0) -> int:
        """``movc`` with its keys sorted (sdk_wire_formats §9): poses mm + RPY rad (sent in
        deg), speed, accel and tol unconverted, ``circle_cnt`` a double, ``circle_mode`` an
        int, ``executing_line_id`` the SDK's own counter (1 for the first). It asks no
        e-stop. ``is_block``: then waits until the motion is done (:meth:`wait_inpos`)."""
        if mode == CONTINUE:
            return RC_BAD_ARGUMENT
        self._movc_count += 1
        rc = self.call("movc", pos_end=pose_deg(end_pos), pos_mid=pose_deg(mid_pos),
                       relFlag=int(mode == INCR), speed=float(speed), accel=float(accel),
                       tol=float(tol), circle_cnt=float(circle_cnt),
                       circle_mode=int(circle_mode), executing_line_id=self._movc_count)[0]
        if rc == RC_OK and is_block and not self.wait_inpos(block_timeout):
            return RC_TIMEOUT
        return rc

    def wait_inpos(self, timeout: float) -> bool:
        """Until the status says the motion is done (how the SDK's own blocking wait reads it
        is not in the evidence; the status's inpos is what its RobotStatus offers)."""
        deadline = time.monotonic() + timeout
        time.sleep(0.05)
        while time.monotonic() < deadline:
            if self.get_robot_status()[1].inpos:
                return True
            time.sleep(0.05)
        return False

    def jog(self, axis: int, mode: int, coord: int, velocity: float, position: float) -> int:
        """``velocity`` rad/s for joints (sent as deg/s), mm/s for x, y, z, and for rotation
        axes sent unconverted (the SDK's own); ``position`` rad or mm, sent deg or mm."""
        angular = coord == COORD_JOINT or axis >= 3
        jog_mode = {CONTINUE: 1, INCR: 2, ABS: 3}[mode]
        velocity = math.degrees(velocity) if coord == COORD_JOINT else float(velocity)
        return self._then_estop(self.call(
            "jog", jog_mode=jog_mode, coord_map=coord, jnum=axis, jogvel=velocity,
            poscmd=math.degrees(position) if angular else float(position))[0])

    def jog_stop(self, axis: int) -> int:
        """jog_mode 0 for ``axis`` (-1: all); the stop's other keys are not in the evidence."""
        return self._then_estop(self.call("jog", jog_mode=0, coord_map=COORD_BASE,
                                          jnum=axis)[0])

    def kine_forward(self, joints: Sequence[float]) -> Tuple[int, Optional[list]]:
        rc, reply = self.call("kine_forward", jointPosition=deg(joints))
        return rc, pose_rad(doubles(member(reply, "cartPosition"), 6)) if rc == RC_OK else None

    def kine_inverse(self, reference: Sequence[float],
                     pose: Sequence[float]) -> Tuple[int, Optional[list]]:
        rc, reply = self.call("kine_inverse", jointPosition=deg(reference),
                               cartPosition=pose_deg(pose))
        if rc != RC_OK:
            return rc, None
        return rc, [math.radians(v) for v in doubles(member(reply, "jointPosition"), 6)]

    # -- IO (the wire's index is the SDK's + 1, for every type) --
    def set_digital_output(self, io_type: int, index: int, value: bool) -> int:
        rc = self.call("set_digital_output", type=io_type, index=index + 1,
                        value=int(value))[0]
        return rc if rc != RC_OK else self._wait_until(
            lambda: self.get_digital_output(io_type, index), lambda v: v == bool(value))

    def set_analog_output(self, io_type: int, index: int, value: float) -> int:
        rc = self.call("set_analog_output", type=io_type, index=index + 1,
                        value=float(value))[0]
        return rc if rc != RC_OK else self._wait_until(
            lambda: self.get_analog_output(io_type, index), lambda v: abs(v - value) < 1e-3)

    def _io(self, command: str, io_type: int, index: int, convert) -> Tuple[int, Any]:
        rc, reply = self.call(command, type=io_type, index=index + 1)
        return rc, convert(member(reply, "value"))

    def get_digital_input(self, io_type: int, index: int) -> Tuple[int, bool]:
        return self._io("get_digital_input", io_type, index, as_bool)

    def get_digital_output(self, io_type: int, index: int) -> Tuple[int, bool]:
        return self._io("get_digital_output", io_type, index, as_bool)

    def get_analog_input(self, io_type: int, index: int) -> Tuple[int, float]:
        return self._io("get_analog_input", io_type, index, as_double)

    def get_analog_output(self, io_type: int, index: int) -> Tuple[int, float]:
        return self._io("get_analog_output", io_type, index, as_double)

    # -- kinematic parameters --
    def get_dh_param(self) -> Tuple[int, Optional[Dict[str, List[float]]]]:
        rc, reply = self.call("get_dh_param")
        if rc != RC_OK:
            return rc, None
        rows = member(reply, "dh_param")
        read = [[as_double(element(element(rows, k), j)) for j in range(6)] for k in range(4)]
        return rc, {"alpha": [math.radians(v) for v in read[0]], "a": read[1], "d": read[2],
                    "joint_homeoff": [math.radians(v) for v in read[3]]}


def _rc(reply: Any) -> int:
    code = member(reply, "errorCode")
    if isinstance(code, bool) or code is None:
        return RC_FAILED
    if isinstance(code, int):
        return code
    if isinstance(code, str):
        try:
            return RC_OK if int(code) == 0 else RC_FAILED
        except ValueError:
            return RC_FAILED
    return RC_FAILED


def _read_json(sock: socket.socket) -> Any:
    decoder, buf = json.JSONDecoder(), b""
    while True:
        chunk = sock.recv(65536)
        if not chunk:
            raise ConnectionError("the controller closed the connection")
        buf += chunk
        try:
            obj, _ = decoder.raw_decode(buf.decode().lstrip())
            return obj
        except ValueError:
            continue
