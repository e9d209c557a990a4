"""The emulator's command port: one handler per ``cmdName``, wire request in, wire reply out.

Requests are read as a JAKA controller reads them (docs/protocol.md: joints deg, poses mm +
RPY deg, speeds deg/s or mm/s, IO index from 1, keys in any order, unknown extra keys ignored)
and converted once, here, to the SI values of :class:`~.twin_controller.TwinController`. Every
request gets exactly one reply object ``{"errorCode", "errorMsg", "cmdName", ...}``:
``errorCode`` ``"0"`` on success, ``"1"`` for a wrong request (unknown command, missing or
malformed field, malformed JSON), ``"2"`` for a command refused in the current state — never an
exception, never a silent close.

Where the twin has no such thing (user programs, extension IO, fieldbus arrays, user variables)
the answer is that of a controller with nothing configured: an empty list, zeros, errorCode
``"2"`` for a program that does not exist.

Emulator-only commands (a real controller answers them with an error) inject faults and help
tests; they all start with ``emulator_`` — see :data:`EMULATOR_COMMANDS`.
"""
from __future__ import annotations

import logging
import math
from collections import Counter
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Mapping, Optional, Tuple

import numpy as np

from ..protocol import units
from ..protocol.fields import Cmd, CoordMap, ERROR_CODE_OK, Field, JogMode, StatusField
from ..protocol.status_stream import encode_status
from ..protocol.wire import as_flag, float_vector
from ..protocol.errors import ProtocolError
from ..frames import TOOL, USER_FRAME
from ..transforms import pose_mm_rpy_to_matrix
from .status_packet import status_fields, wire_pose, zeros_of
from .twin_controller import (ERROR_REFUSED, ERROR_REQUEST, FRAME_IDS, MAX_CLSN_LEVEL, Rejected,
                              TwinController)

log = logging.getLogger(__name__)

#: Emulator-only commands and what they do.
EMULATOR_COMMANDS = {
    "emulator_emergency_stop": '{"pressed": 1} presses the e-stop (power cut, arm halts), '
                               '{"pressed": 0} releases it',
    "emulator_protective_stop": 'protective stop, as after a collision; optional "reason"',
    "emulator_set_input": 'drive an input: "signal" digital/analog, "type", "index" (from 1), "value"',
    "emulator_drop_connections": "reply, then close every client connection on both ports "
                                 "(the listening sockets stay open)",
    "emulator_stats": 'reply "commands": how many times each cmdName was received',
}

#: wire jog coord_map → the twin's coord (0 joint, 1 base, 2 tool)
_TWIN_COORD = {CoordMap.BASE: 1, CoordMap.JOINT: 0, CoordMap.TOOL: 2}


@dataclass
class Answer:
    """Reply fields of a successful command, and what the connection does next:
    ``then`` is None, ``"close"`` (this connection) or ``"drop_all"`` (every connection)."""

    fields: Dict[str, Any] = field(default_factory=dict)
    then: Optional[str] = None


class Malformed:
    """A request that could not be read as a JSON object (see :mod:`.framing`)."""

    def __init__(self, reason: str):
        self.reason = reason


# ---- reading wire fields (each raises Rejected with ERROR_REQUEST) -----------------------------

def _get(req: Mapping, key: str, default: Any = None) -> Any:
    if key in req:
        return req[key]
    if default is not None:
        return default
    raise Rejected(f"{req.get(Field.CMD_NAME)}: missing field {key!r}", ERROR_REQUEST)


def _vec(req: Mapping, key: str, n: int) -> np.ndarray:
    raw = _get(req, key)
    v = float_vector(raw, n)
    if v is None:
        raise Rejected(f"{req.get(Field.CMD_NAME)}: {key!r} must be {n} finite numbers; got "
                       f"{raw!r}", ERROR_REQUEST)
    return v


def _num(req: Mapping, key: str, default: Optional[float] = None, lo: float = -math.inf,
         hi: float = math.inf, positive: bool = False) -> float:
    raw = _get(req, key, default)
    try:
        x = float(raw)
    except (TypeError, ValueError):
        x = math.nan
    if not math.isfinite(x) or not lo <= x <= hi or (positive and x <= 0):
        bound = "> 0" if positive else f"in [{lo:g}, {hi:g}]"
        raise Rejected(f"{req.get(Field.CMD_NAME)}: {key!r} must be a number {bound}; got "
                       f"{raw!r}", ERROR_REQUEST)
    return x


def _int(req: Mapping, key: str, lo: int, hi: int, default: Optional[int] = None) -> int:
    raw = _get(req, key, default)
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or int(raw) != raw \
            or not lo <= int(raw) <= hi:
        raise Rejected(f"{req.get(Field.CMD_NAME)}: {key!r} must be an integer in [{lo}, {hi}]; "
                       f"got {raw!r}", ERROR_REQUEST)
    return int(raw)


def _flag(req: Mapping, key: str, default: Any = None) -> bool:
    raw = _get(req, key, default)
    try:
        return as_flag(raw, key)
    except ProtocolError as exc:
        raise Rejected(f"{req.get(Field.CMD_NAME)}: {exc}", ERROR_REQUEST) from None


def _joints(req: Mapping, key: str = Field.JOINT_POSITION) -> np.ndarray:
    return units.joints_from_wire(_vec(req, key, 6))


def _pose(req: Mapping, key: str) -> np.ndarray:
    """Wire pose (mm, RPY deg) → 4x4 (m)."""
    return pose_mm_rpy_to_matrix(units.pose_from_wire(_vec(req, key, 6)))


def _relative(base: np.ndarray, increment: np.ndarray) -> np.ndarray:
    """A relative Cartesian command: translation added in the user frame, rotation applied
    about the user frame's axes (the emulator's reading of relFlag 1; not verified)."""
    out = np.eye(4)
    out[:3, :3] = increment[:3, :3] @ base[:3, :3]
    out[:3, 3] = base[:3, 3] + increment[:3, 3]
    return out


def _signal(req: Mapping) -> str:
    signal = str(_get(req, "signal")).strip().lower()
    if signal not in ("digital", "analog"):
        raise Rejected(f"emulator_set_input: 'signal' must be 'digital' or 'analog'; got "
                       f"{signal!r}", ERROR_REQUEST)
    return signal


class CommandHandlers:
    """Dispatches requests to a :class:`TwinController`; ``counts`` records every ``cmdName``
    received (for ``emulator_stats``)."""

    def __init__(self, controller: TwinController):
        self.c = controller
        self.model = controller.model
        self.counts: Counter = Counter()
        self._table: Dict[str, Callable[[Mapping], Answer]] = {
            Cmd.POWER_ON: lambda r: self._done(self.c.set_power(True)),
            Cmd.POWER_OFF: lambda r: self._done(self.c.set_power(False)),
            Cmd.ENABLE_ROBOT: lambda r: self._done(self.c.set_enabled(True)),
            Cmd.DISABLE_ROBOT: lambda r: self._done(self.c.set_enabled(False)),
            Cmd.GET_ROBOT_STATE: self._get_robot_state,
            Cmd.EMERGENCY_STOP_STATUS: lambda r: Answer(
                {Field.EMERGENCY_STOP: int(self.c.twin.emergency_stop)}),
            Cmd.PROTECTIVE_STOP_STATUS: lambda r: Answer(
                {Field.PROTECTIVE_STOP: int(self.c.twin.protective_stop or self.c.twin.collision)}),
            Cmd.CLEAR_ERROR: lambda r: self._done(self.c.clear_error()),
            Cmd.JOINT_MOVE: self._joint_move,
            Cmd.MOVE_L: self._move_l,
            "move_l": self._move_l,   # the other spelling clients use
            Cmd.JOG: self._jog,
            Cmd.STOP_PROGRAM: lambda r: self._done(self.c.stop()),
            Cmd.SERVO_MOVE: lambda r: self._done(self.c.set_servo_mode(
                _int(r, Field.REL_FLAG, 0, 1) == 1)),
            Cmd.IS_IN_SERVOMOVE: lambda r: Answer(
                {Field.IN_SERVOMOVE: bool(self.c.twin.servo_mode)}),
            Cmd.SERVO_J: self._servo_j,
            Cmd.SERVO_P: self._servo_p,
            Cmd.SET_SERVO_MOVE_FILTER: lambda r: self._done(self.c.set_servo_filter(
                _int(r, Field.FILTER_TYPE, 0, 10))),
            Cmd.RAPID_RATE: self._rapid_rate,
            Cmd.GET_JOINT_POS: lambda r: Answer(
                {Field.JOINT_POS: units.joints_to_wire(self.c.twin.state().joint_position)}),
            Cmd.GET_TCP_POS: lambda r: Answer(
                {Field.TCP_POS: wire_pose(self.c.twin.state().tcp_pose)}),
            Cmd.GET_DATA: self._get_data,
            Cmd.KINE_FORWARD: self._kine_forward,
            Cmd.KINE_INVERSE: self._kine_inverse,
            Cmd.SET_TOOL_OFFSETS: self._set_tool_offsets,
            Cmd.SET_TOOL_ID: lambda r: self._done(self.c.activate_tool(
                _int(r, Field.TOOL_ID, FRAME_IDS.start, FRAME_IDS.stop - 1))),
            Cmd.GET_CURR_TOOL_ID: lambda r: Answer({Field.ID: int(self.c.twin.tool_id)}),
            Cmd.SET_USER_OFFSETS: self._set_user_offsets,
            Cmd.SET_USER_ID: lambda r: self._done(self.c.activate_user(
                _int(r, Field.USER_FRAME_ID, FRAME_IDS.start, FRAME_IDS.stop - 1))),
            Cmd.GET_CURR_USER_ID: lambda r: Answer({Field.ID: int(self.c.twin.user_id)}),
            Cmd.SET_PAYLOAD: self._set_payload,
            Cmd.GET_PAYLOAD: lambda r: Answer({Field.MASS: self.c.payload_mass,
                                               Field.CENTROID: self.c.payload_centroid_mm}),
            Cmd.SET_CLSN_SENSITIVITY: lambda r: self._done(self.c.set_collision_level(
                _int(r, Field.SENSITIVITY_VAL, 0, MAX_CLSN_LEVEL))),
            Cmd.GET_CLSN_SENSITIVITY: lambda r: Answer(
                {Field.SENSITIVITY_LEVEL: self.c.collision_level,
                 Field.SENSITIVITY_VAL: self.c.collision_level}),
            Cmd.SET_DIGITAL_OUTPUT: lambda r: self._set_output(r, "digital"),
            Cmd.SET_ANALOG_OUTPUT: lambda r: self._set_output(r, "analog"),
            Cmd.GET_DIGITAL_INPUT: lambda r: self._read_io(r, "digital", 0),
            Cmd.GET_ANALOG_OUTPUT: lambda r: self._read_io(r, "analog", 1),
            Cmd.GET_DIGITAL_INPUT_STATUS: lambda r: Answer(
                {Field.DIN_STATUS: status_fields(self.c)[StatusField.DIN]}),
            Cmd.DRAG_STATUS: lambda r: Answer({Field.DRAG_STATUS: int(self.c.twin.drag_mode)}),
            Cmd.GET_VERSION: lambda r: Answer({Field.VERSION: self.c.version,
                                               Field.ERROR_MSG: self.c.identity}),
            Cmd.GET_MOTION_STATE: self._get_motion_state,
            Cmd.WAIT_COMPLETE: self._wait_complete,
            Cmd.END_MOVE: self._end_move,
            Cmd.IS_ON_LIMIT: lambda r: Answer({Field.ON_LIMIT: int(self.c.on_limit())}),
            Cmd.GET_DIGITAL_OUTPUT: lambda r: self._read_io(r, "digital", 1),
            Cmd.GET_ANALOG_INPUT: lambda r: self._read_io(r, "analog", 0),
            Cmd.GET_RAPID_RATE: lambda r: Answer({Field.VALUE: float(self.c.rapid_rate)}),
            Cmd.GET_TOOL_OFFSETS: lambda r: Answer(
                {Field.TOOL_OFFSETS: wire_pose(self.c.frames.get(TOOL, self.c.twin.tool_id))}),
            Cmd.GET_USER_OFFSETS: lambda r: Answer(
                {Field.USER_OFFSETS: wire_pose(self.c.frames.get(USER_FRAME, self.c.twin.user_id))}),
            Cmd.GET_DRAG_STATUS: lambda r: Answer({Field.STATUS: bool(self.c.twin.drag_mode)}),
            Cmd.TORQUE_CONTROL_ENABLE: self._torque_control_enable,
            Cmd.SET_INSTALLATION_ANGLE: self._set_installation_angle,
            Cmd.GET_PROGRAM_STATE: lambda r: Answer({Field.PROGRAM_STATE: 0}),
            Cmd.GET_EXIST_PROGRAMS: lambda r: Answer({"programs": []}),
            Cmd.GET_LOADED_PROGRAM: lambda r: Answer({Field.PROGRAM_NAME: ""}),
            Cmd.LOAD_PROGRAM: lambda r: self._no_program(r),
            Cmd.PLAY_PROGRAM: lambda r: self._no_program(r),
            Cmd.PAUSE_PROGRAM: lambda r: self._no_program(r),
            Cmd.RESUME_PROGRAM: lambda r: self._no_program(r),
            Cmd.TORQUE_FEEDFORWARD: self._torque_feedforward,
            Cmd.GET_EXTIO_STATUS: lambda r: Answer({"extio_status": {"num": 0, "status": []}}),
            Cmd.GET_FUNCDI_STATUS: lambda r: Answer(
                {"funcdi_status": zeros_of("funcdi")}),
            Cmd.QUERY_USER_DEFINED_VARIABLE: lambda r: Answer({"var_list": []}),
            Cmd.MODIFY_USER_DEFINED_VARIABLE: lambda r: self._no_variable(r),
            Cmd.SET_TIO_VOUT_PARAM: self._set_tio_vout,
            Cmd.GET_TIO_VOUT_PARAM: lambda r: Answer(
                {"tio_vout_enable": self.c.tio_vout[0], "tio_vout_voltage": self.c.tio_vout[1]}),
            Cmd.QUIT: lambda r: Answer(then="close"),
            "emulator_emergency_stop": lambda r: self._note(self.c.emergency_stop(
                _flag(r, "pressed"))),
            "emulator_protective_stop": lambda r: self._note(self.c.protective_stop(
                str(r.get("reason") or "protective stop (emulator_protective_stop)"))),
            "emulator_set_input": self._set_input,
            "emulator_drop_connections": lambda r: Answer(then="drop_all"),
            "emulator_stats": lambda r: Answer({"commands": dict(self.counts)}),
        }

    @property
    def command_names(self) -> Tuple[str, ...]:
        return tuple(sorted(self._table))

    # ---- dispatch -------------------------------------------------------------------------------
    def handle(self, request: Any) -> Tuple[Dict[str, Any], Optional[str]]:
        """One request (a decoded JSON value or :class:`Malformed`) → (reply, then)."""
        if isinstance(request, Malformed):
            return _error("", ERROR_REQUEST, request.reason), None
        if not isinstance(request, dict):
            return _error("", ERROR_REQUEST, "a request must be a JSON object"), None
        name = request.get(Field.CMD_NAME)
        if not isinstance(name, str) or not name:
            return _error("", ERROR_REQUEST, f"the request has no string {Field.CMD_NAME!r}: "
                          f"{str(request)[:120]}"), None
        self.counts[name] += 1
        handler = self._table.get(name)
        if handler is None:
            return _error(name, ERROR_REQUEST, f"unknown command {name!r}"), None
        try:
            answer = handler(request)
        except Rejected as rejected:
            return _error(name, rejected.code, rejected.message), None
        except Exception as exc:  # noqa: BLE001 - a request must never take the server down
            log.exception("emulator: %s failed", name)
            return _error(name, ERROR_REFUSED, f"{name} failed inside the emulator: {exc!r}"), None
        reply = {Field.ERROR_CODE: ERROR_CODE_OK, Field.ERROR_MSG: "", Field.CMD_NAME: name}
        reply.update(answer.fields)
        return reply, answer.then

    @staticmethod
    def _done(_none=None) -> Answer:
        return Answer()

    @staticmethod
    def _note(message: str) -> Answer:
        return Answer({Field.ERROR_MSG: message})

    # ---- handlers -------------------------------------------------------------------------------
    def _get_robot_state(self, _req) -> Answer:
        t = self.c.twin
        return Answer({Field.ENABLE: "robot_enabled" if t.enabled else "robot_disabled",
                       Field.POWER: "powered_on" if t.powered else "powered_off"})

    def _get_data(self, _req) -> Answer:
        fields = status_fields(self.c)
        # ``len`` as in the status packet with the same fields
        return Answer({StatusField.LEN: len(encode_status(fields)), **fields})

    def wait_before(self, request: Any, limit: float) -> None:
        """Called by the server outside its command lock before :meth:`handle`: a
        ``wait_complete`` request waits here (at most ``limit`` s) until the queue is done, so
        other clients are served meanwhile."""
        if isinstance(request, dict) and request.get(Field.CMD_NAME) == Cmd.WAIT_COMPLETE:
            self.c.wait_idle(limit)

    def _joint_speed(self, req) -> Tuple[float, float]:
        """A joint-interpolated move's speed and accel (wire deg/s, deg/s² → rad/s, rad/s²).
        Without accel (a fw 1.4.11 client sends none) the joints' own limit is used."""
        speed = math.radians(_num(req, Field.SPEED, positive=True))
        default_accel = math.degrees(float(np.min(self.model.max_acceleration)))
        return speed, math.radians(_num(req, Field.ACCEL, default=default_accel, positive=True))

    def _joint_move(self, req) -> Answer:
        q = _joints(req)
        relative = _int(req, Field.REL_FLAG, 0, 1, default=0)
        speed, accel = self._joint_speed(req)
        # A relative move adds to where the move before it ends: resolved when its turn comes.
        self.c.joint_move((lambda: self.c.commanded_joints() + q) if relative else (lambda: q),
                          speed, accel)
        return Answer()

    def _move_l(self, req) -> Answer:
        target = _pose(req, Field.CART_POSITION)
        relative = _int(req, Field.REL_FLAG, 0, 1, default=0)
        speed = _num(req, Field.SPEED, positive=True) / 1000.0
        default_accel = self.model.max_tcp_accel_mm_s2 / 4
        accel = _num(req, Field.ACCEL, default=default_accel, positive=True) / 1000.0
        self.c.linear_move((lambda: _relative(self.c.commanded_tcp(), target)) if relative
                           else (lambda: target), speed, accel)
        return Answer()

    def _end_move(self, req) -> Answer:
        pose = _pose(req, Field.END_POSITION)
        self.c.end_move(pose, *self._joint_speed(req))
        return Answer()

    def _get_motion_state(self, _req) -> Answer:
        c = self.c
        return Answer({Field.MOTION_LINE: c.motion_line, Field.ERR_ADD_LINE: 0,
                       Field.QUEUE: c.queued, Field.ACTIVE_QUEUE: c.queued + int(c.moving),
                       Field.QUEUE_FULL: 0, Field.INPOS: bool(c.inpos)})

    def _wait_complete(self, _req) -> Answer:
        # The server waits for the queue outside its command lock (see server.py); this is
        # reached once the queue is done, or after the server's limit.
        if not self.c.inpos:
            raise Rejected("wait_complete: the motion did not complete")
        return Answer()

    def _torque_control_enable(self, req) -> Answer:
        on = _flag(req, Field.ENABLE_FLAG)
        result = self.c.twin.set_drag_mode(on)
        if not result.ok:
            raise Rejected(f"torque_control_enable: {result.message}")
        return Answer()

    def _set_installation_angle(self, req) -> Answer:
        angle_x = _num(req, Field.ANGLE_X, lo=0.0, hi=180.0)
        angle_z = _num(req, Field.ANGLE_Z, lo=0.0, hi=360.0)
        if angle_x or angle_z:
            raise Rejected("set_installation_angle: the twin is mounted upright; only angleX 0 "
                           "and angleZ 0 are possible")
        return Answer()         # upright, as it already is

    def _no_program(self, req) -> Answer:
        name = req.get(Field.PROGRAM_NAME) or req.get("programName") or ""
        raise Rejected(f"{req[Field.CMD_NAME]}: program {name!r} does not exist (the emulator "
                       "has no user programs)" if name else f"{req[Field.CMD_NAME]}: no "
                       "program loaded (the emulator has no user programs)")

    def _no_variable(self, req) -> Answer:
        raise Rejected(f"{req[Field.CMD_NAME]}: no such user variable (none is defined)")

    def _torque_feedforward(self, req) -> Answer:
        # Accepted and not applied: the twin's drives have no feed-forward input.
        return Answer()

    def _set_tio_vout(self, req) -> Answer:
        self.c.tio_vout = (_int(req, "tio_vout_enable", 0, 1, default=0),
                           _int(req, "tio_vout_voltage", 0, 1, default=0))
        return Answer()

    def _jog(self, req) -> Answer:
        mode = _int(req, Field.JOG_MODE, 0, 3)
        coord_map = CoordMap(_int(req, Field.COORD_MAP, 0, 2))
        axis = _int(req, Field.JNUM, 0, 5)
        if mode == JogMode.STOP:
            self.c.jog_stop()   # any jog: continuous, incremental, absolute
            return Answer()
        angular = coord_map == CoordMap.JOINT or axis >= 3
        velocity = _num(req, Field.JOGVEL)
        speed = math.radians(abs(velocity)) if angular else abs(velocity) / 1000.0
        if speed == 0:
            raise Rejected("jog: 'jogvel' must not be 0", ERROR_REQUEST)
        if mode == JogMode.CONTINUOUS:
            self.c.jog(_TWIN_COORD[coord_map], axis, 1 if velocity > 0 else -1, speed)
            return Answer()
        if coord_map != CoordMap.JOINT:
            raise Rejected("jog: the emulator does Cartesian jogs in continuous mode only "
                           "(jog_mode 1)", ERROR_REQUEST)
        # Increment (2) and absolute (3) joint jogs are queued joint moves of one axis.
        position = math.radians(_num(req, Field.POSCMD))

        def target() -> np.ndarray:
            q = self.c.commanded_joints()
            q[axis] = q[axis] + position if mode == JogMode.INCREMENT else position
            return q
        accel = float(self.model.max_acceleration[axis])
        self.c.joint_move(target, min(speed, float(self.model.max_velocity[axis])), accel,
                          what="jog")
        return Answer()

    def _steps(self, req) -> int:
        return _int(req, Field.STEP_NUM, 1, 1000, default=1)

    def _servo_j(self, req) -> Answer:
        q = _joints(req)
        if _int(req, Field.REL_FLAG, 0, 1, default=0):
            q = self.c.servo_reference("servo_j") + q
        self.c.servo_joints(q, self._steps(req))
        return Answer()

    def _servo_p(self, req) -> Answer:
        target = _pose(req, Field.SERVO_CART_POSITION)
        if _int(req, Field.REL_FLAG, 0, 1, default=0):
            here = self.c.twin.forward_kinematics(self.c.servo_reference("servo_p"))
            if not here.ok:
                raise Rejected(f"servo_p: {here.message}")
            target = _relative(here.value, target)
        self.c.servo_pose(target, self._steps(req))
        return Answer()

    def _rapid_rate(self, req) -> Answer:
        self.c.rapid_rate = _num(req, Field.RATE_VALUE, lo=0.0, hi=1.0, positive=True)
        return Answer()

    def _kine_forward(self, req) -> Answer:
        result = self.c.twin.forward_kinematics(_joints(req))
        if not result.ok:
            raise Rejected(f"kine_forward: {result.message}")
        return Answer({Field.CART_POSITION: wire_pose(result.value)})

    def _kine_inverse(self, req) -> Answer:
        ref = _joints(req)
        result = self.c.twin.inverse_kinematics(_pose(req, Field.CART_POSITION), ref)
        if not result.ok:
            raise Rejected(f"kine_inverse: {result.message}")
        return Answer({Field.JOINT_POSITION: units.joints_to_wire(result.value)})

    def _frame_id(self, req) -> int:
        return _int(req, Field.ID, 1, FRAME_IDS.stop - 1)

    def _set_tool_offsets(self, req) -> Answer:
        self.c.set_tool_offset(self._frame_id(req), _pose(req, Field.TOOL_OFFSET))
        return Answer()

    def _set_user_offsets(self, req) -> Answer:
        # "userffset" (sic) is what JAKA's SDK sends; "useroffset" is read too, for old clients.
        key = Field.USER_OFFSET if Field.USER_OFFSET in req else "useroffset"
        self.c.set_user_offset(self._frame_id(req), _pose(req, key))
        return Answer()

    def _set_payload(self, req) -> Answer:
        limit = 1.5 * self.model.rated_payload_kg
        mass = _num(req, Field.MASS, lo=0.0, hi=limit)
        self.c.set_payload(mass, _vec(req, Field.CENTROID, 3))
        return Answer()

    def _io_address(self, req, signal: str, path: int, what: str) -> Tuple[int, int]:
        """(type, 0-based index): the wire counts IO from 1, as JAKA's SDK sends it."""
        io_type = _int(req, Field.IO_TYPE, 0, 2)
        index = _int(req, Field.INDEX, 1, 10_000) - 1
        self.c.check_io(signal, io_type, path, index, what)
        return io_type, index

    def _set_output(self, req, signal: str) -> Answer:
        io_type, index = self._io_address(req, signal, 1, f"set_{signal}_output")
        if signal == "digital":
            value = 1.0 if _flag(req, Field.VALUE) else 0.0
        else:
            value = _num(req, Field.VALUE)
        self.c.twin.set_io(signal, io_type, index, value)
        return Answer()

    def _read_io(self, req, signal: str, path: int) -> Answer:
        io_type, index = self._io_address(req, signal, path, req[Field.CMD_NAME])
        value = self.c.twin.get_io(signal, path, io_type, index).value
        return Answer({Field.VALUE: int(value) if signal == "digital" else float(value)})

    def _set_input(self, req) -> Answer:
        signal = _signal(req)
        io_type = _int(req, Field.IO_TYPE, 0, 2)
        index = _int(req, Field.INDEX, 1, 10_000) - 1   # 1-based, like the IO commands
        value = _num(req, Field.VALUE)
        if signal == "digital":
            value = 1.0 if value else 0.0
        self.c.set_input(signal, io_type, index, value)
        return Answer()


def _error(name: str, code: str, message: str) -> Dict[str, Any]:
    return {Field.CMD_NAME: name, Field.ERROR_CODE: code, Field.ERROR_MSG: message}
