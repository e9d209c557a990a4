"""Commands of the JAKA TCP protocol (port 10001): request encoders and reply decoders.

Every encoder takes **the SDK's units** — joints in rad (rad/s, rad/s²), Cartesian poses as
``[x, y, z mm, rx, ry, rz rad]`` (RPY, ``R = Rz·Ry·Rx``), speeds mm/s and mm/s², IO indices
0-based as the SDK's API counts them — validates them at the door
(:class:`~.errors.InvalidArgument`, nothing is sent), and returns the request as a plain dict in
**wire units** (deg, deg/s, deg/s², mm, RPY deg, IO index + 1). :func:`encode` turns a dict
into compact JSON bytes, the layout clients send.

Replies are decoded by :func:`parse_reply` into a :class:`Reply`; the ``reply_*`` accessors
check success, read one field and convert it back to the SDK's units (module :mod:`.replies`,
re-exported here).

Key names and how sure we are of each command come from :mod:`.fields` (see ``COMMANDS`` there
for the medium- and low-confidence entries).
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional

from . import units
from .errors import InvalidArgument
from .fields import Cmd, CoordMap, Field, JogMode
# Replies live in their own module; re-exported so requests and their accessors read together.
from .replies import (DHParam, PowerState, Reply, command_names_match,  # noqa: F401
                      parse_reply, MotionState, reply_clsn_sensitivity, reply_dh_param,
                      reply_din_status, reply_flag, reply_id, reply_identity, reply_joint_pos,
                      reply_kine_forward, reply_kine_inverse, reply_motion_state, reply_payload,
                      reply_robot_state, reply_tcp_pos, reply_tool_offsets, reply_user_offsets,
                      reply_value, reply_version)
from .request_values import Request, command as _cmd, flag, integer as _integer
from .request_values import number as _number, vector as _vector
from .wire import encode_json


def encode(request: Mapping[str, Any]) -> bytes:
    """A request dict → compact UTF-8 JSON bytes, ready for ``sendall``."""
    name = request.get(Field.CMD_NAME) if isinstance(request, Mapping) else None
    if not isinstance(name, str) or not name:
        raise InvalidArgument(f"a request needs a non-empty string {Field.CMD_NAME!r}; "
                              f"got {request!r}")
    try:
        return encode_json(dict(request))
    except (TypeError, ValueError) as exc:
        raise InvalidArgument(f"request {name!r} cannot be encoded as JSON: {exc}") from None


def _rel_flag(relative: bool) -> int:
    return flag(relative)


# ---- power, enable, state ------------------------------------------------------------------

def power_on() -> Request:
    return _cmd(Cmd.POWER_ON)


def power_off() -> Request:
    return _cmd(Cmd.POWER_OFF)


def enable_robot() -> Request:
    return _cmd(Cmd.ENABLE_ROBOT)


def disable_robot() -> Request:
    return _cmd(Cmd.DISABLE_ROBOT)


def get_robot_state() -> Request:
    """Reply: see :func:`reply_robot_state`."""
    return _cmd(Cmd.GET_ROBOT_STATE)


def emergency_stop_status() -> Request:
    """Reply: ``reply_flag(reply, Field.EMERGENCY_STOP)``."""
    return _cmd(Cmd.EMERGENCY_STOP_STATUS)


def protective_stop_status() -> Request:
    """Reply: ``reply_flag(reply, Field.PROTECTIVE_STOP)``."""
    return _cmd(Cmd.PROTECTIVE_STOP_STATUS)


def clear_error() -> Request:
    """Recover from a collision or protective stop."""
    return _cmd(Cmd.CLEAR_ERROR)


def get_data() -> Request:
    """Full status in one reply; its fields are those of a status packet, so decode them with
    ``status_packet.parse_status(reply.fields)``."""
    return _cmd(Cmd.GET_DATA)


def get_version() -> Request:
    return _cmd(Cmd.GET_VERSION)


def quit() -> Request:  # noqa: A001 - the protocol's name
    """Ask the controller to close this command connection."""
    return _cmd(Cmd.QUIT)


# ---- motion ----------------------------------------------------------------------------------

def joint_move(q_rad, speed_rad_s: float, accel_rad_s2: float, relative: bool = False) -> Request:
    """Joint move to ``q_rad`` (6 joints, rad; an increment if ``relative``) with joint speed
    ``speed_rad_s`` (rad/s) and acceleration ``accel_rad_s2`` (rad/s²).

    The controller answers when the move is accepted, not when it ends."""
    q = _vector(q_rad, 6, "joint target (rad)")
    speed = _number(speed_rad_s, "joint speed (rad/s)", positive=True)
    accel = _number(accel_rad_s2, "joint acceleration (rad/s²)", positive=True)
    return _cmd(Cmd.JOINT_MOVE, **{
        Field.JOINT_POSITION: units.joints_to_wire(q),
        Field.SPEED: math.degrees(speed),
        Field.ACCEL: math.degrees(accel),
        Field.REL_FLAG: _rel_flag(relative)})


def moveL(pose_mm_rpy, speed_mm_s: float, accel_mm_s2: float, relative: bool = False,
          tol_mm: Optional[float] = None, ori_vel_rad_s: Optional[float] = None,
          ori_acc_rad_s2: Optional[float] = None) -> Request:  # noqa: N802 - the protocol's name
    """Straight-line move of the TCP to ``pose_mm_rpy`` (mm + RPY rad) at
    ``speed_mm_s`` (mm/s) and ``accel_mm_s2`` (mm/s²); ``tol_mm`` is the optional blending
    tolerance. ``ori_vel_rad_s`` (rad/s) and ``ori_acc_rad_s2`` (rad/s²) bound the
    orientation's speed and acceleration, sent as ``ori_vel`` deg/s and ``ori_acc`` deg/s² as
    JAKA's SDK sends them with every moveL; without them the controller turns the tool at its
    own defaults (the SDK's are 3.14 rad/s and 12.56 rad/s²).

    With ``relative`` the pose is an increment (how the controller composes a relative
    orientation is not documented)."""
    pose = _vector(pose_mm_rpy, 6, "TCP pose (mm, RPY rad)")
    request = _cmd(Cmd.MOVE_L, **{
        Field.CART_POSITION: units.pose_to_wire(pose),
        Field.SPEED: _number(speed_mm_s, "TCP speed (mm/s)", positive=True),
        Field.ACCEL: _number(accel_mm_s2, "TCP acceleration (mm/s²)", positive=True),
        Field.REL_FLAG: _rel_flag(relative)})
    if tol_mm is not None:
        request[Field.TOL] = _number(tol_mm, "tolerance (mm)", lo=0.0)
    if ori_vel_rad_s is not None:
        request[Field.ORI_VEL] = math.degrees(_number(ori_vel_rad_s, "orientation speed "
                                                      "(rad/s)", positive=True))
    if ori_acc_rad_s2 is not None:
        request[Field.ORI_ACC] = math.degrees(_number(ori_acc_rad_s2, "orientation "
                                                      "acceleration (rad/s²)", positive=True))
    return request


def movc(pos_end_mm_rpy, pos_mid_mm_rpy, speed_mm_s: float, accel_mm_s2: float,
         tol_mm: float = 0.0, circle_cnt: float = 0.0, circle_mode: int = 0,
         relative: bool = False, executing_line_id: int = 0) -> Request:
    """Circular move through ``pos_mid_mm_rpy`` to ``pos_end_mm_rpy`` (mm + RPY rad, sent as
    mm + RPY deg) at ``speed_mm_s`` and ``accel_mm_s2`` (sent unconverted, as JAKA's SDK
    does), ``circle_cnt`` extra turns (a double: 1.5 is sent as 1.5), attitude rule
    ``circle_mode`` 0–3 (an int), blending ``tol_mm``; ``executing_line_id`` is the SDK's own
    move counter. Keys in the sorted order JAKA's SDK writes them."""
    request = {
        Field.ACCEL: _number(accel_mm_s2, "circle acceleration (mm/s²)", positive=True),
        Field.CIRCLE_CNT: _number(circle_cnt, "circle_cnt (turns)", lo=0.0),
        Field.CIRCLE_MODE: _integer(circle_mode, "circle_mode", 0, 3),
        Field.CMD_NAME: Cmd.MOVC,
        Field.EXECUTING_LINE_ID: _integer(executing_line_id, "executing_line_id"),
        Field.POS_END: units.pose_to_wire(_vector(pos_end_mm_rpy, 6, "end pose (mm, RPY rad)")),
        Field.POS_MID: units.pose_to_wire(_vector(pos_mid_mm_rpy, 6,
                                                  "middle pose (mm, RPY rad)")),
        Field.REL_FLAG: _rel_flag(relative),
        Field.SPEED: _number(speed_mm_s, "circle speed (mm/s)", positive=True),
        Field.TOL: _number(tol_mm, "tolerance (mm)", lo=0.0)}
    return dict(sorted(request.items()))


def _angular_axis(coord_map: int, jnum: int) -> bool:
    # Joints are all angular; in Cartesian jogs axes 3..5 are rx, ry, rz.
    return coord_map == CoordMap.JOINT or jnum >= 3


def jog(mode: int, coord_map: int, jnum: int, jogvel: float = 0.0,
        poscmd: float = 0.0) -> Request:
    """Jog one axis. ``mode``: :class:`~.fields.JogMode` (0 stop, 1 continuous, 2 increment,
    3 absolute); ``coord_map``: :class:`~.fields.CoordMap` (0 base, 1 joint, 2 tool);
    ``jnum`` 0–5 (joint 1–6, or x, y, z, rx, ry, rz).

    ``jogvel`` in rad/s for angular axes (every joint; rx, ry, rz) and mm/s for x, y, z; its
    sign is the direction. ``poscmd`` (rad or mm) is the increment or absolute target for modes
    2 and 3. Sent as deg/s, deg, mm/s, mm (medium confidence, see ``fields.COMMANDS``). A stop
    (mode 0) carries only ``coord_map`` and ``jnum``."""
    mode = JogMode(_integer(mode, "jog mode", 0, 3))
    coord = CoordMap(_integer(coord_map, "jog coord_map", 0, 2))
    axis = _integer(jnum, "jog axis number", 0, 5)
    fields: Request = {Field.JOG_MODE: int(mode), Field.COORD_MAP: int(coord), Field.JNUM: axis}
    if mode != JogMode.STOP:
        vel = _number(jogvel, "jog speed")
        pos = _number(poscmd, "jog position")
        if _angular_axis(coord, axis):
            vel, pos = math.degrees(vel), math.degrees(pos)
        fields[Field.JOGVEL] = vel
        fields[Field.POSCMD] = pos
    return _cmd(Cmd.JOG, **fields)


def stop_program() -> Request:
    """Stop any motion or program (the SDK's ``motion_abort``)."""
    return _cmd(Cmd.STOP_PROGRAM)


def rapid_rate(rate: float) -> Request:
    """Global speed override, 0 < rate ≤ 1 (1 = 100 %)."""
    return _cmd(Cmd.RAPID_RATE, **{Field.RATE_VALUE: _number(rate, "rapid rate", positive=True,
                                                             hi=1.0)})


# ---- servo mode ------------------------------------------------------------------------------

def servo_move(enable: bool) -> Request:
    """Enter (``True``) or leave servo mode."""
    return _cmd(Cmd.SERVO_MOVE, **{Field.REL_FLAG: 1 if enable else 0})


def is_in_servomove() -> Request:
    """Reply: ``reply_flag(reply, Field.IN_SERVOMOVE)``."""
    return _cmd(Cmd.IS_IN_SERVOMOVE)


def _step_fields(step_num: int) -> Request:
    # stepNum is optional on the wire; leaving it out for 1 keeps the common message as old
    # controllers know it.
    n = _integer(step_num, "servo step_num", 1)
    return {} if n == 1 else {Field.STEP_NUM: n}


def servo_j(q_rad, relative: bool = False, step_num: int = 1) -> Request:
    """One servo set-point: joints ``q_rad`` (rad; an increment if ``relative``), to be reached
    in ``step_num`` × 8 ms. The controller refuses more than 180°/s implied joint speed."""
    q = _vector(q_rad, 6, "servo joint target (rad)")
    return _cmd(Cmd.SERVO_J, **{Field.JOINT_POSITION: units.joints_to_wire(q),
                                Field.REL_FLAG: _rel_flag(relative), **_step_fields(step_num)})


def servo_p(pose_mm_rpy, relative: bool = False, step_num: int = 1) -> Request:
    """One Cartesian servo set-point: TCP pose (mm + RPY rad; an increment if
    ``relative``) in ``step_num`` × 8 ms. Sent under the key ``catPosition`` (sic)."""
    pose = _vector(pose_mm_rpy, 6, "servo TCP pose (mm, RPY rad)")
    return _cmd(Cmd.SERVO_P, **{Field.SERVO_CART_POSITION: units.pose_to_wire(pose),
                                Field.REL_FLAG: _rel_flag(relative), **_step_fields(step_num)})


# ---- positions and kinematics ---------------------------------------------------------------

def get_joint_pos() -> Request:
    """Reply: :func:`reply_joint_pos`."""
    return _cmd(Cmd.GET_JOINT_POS)


def get_tcp_pos() -> Request:
    """Reply: :func:`reply_tcp_pos`."""
    return _cmd(Cmd.GET_TCP_POS)


def kine_forward(q_rad) -> Request:
    """Forward kinematics of the controller (active tool, active user frame). Reply:
    :func:`reply_kine_forward`."""
    q = _vector(q_rad, 6, "joint position (rad)")
    return _cmd(Cmd.KINE_FORWARD, **{Field.JOINT_POSITION: units.joints_to_wire(q)})


def kine_inverse(ref_q_rad, pose_mm_rpy) -> Request:
    """Inverse kinematics near the reference configuration ``ref_q_rad`` (rad) for the TCP
    pose (mm + RPY rad). Reply: :func:`reply_kine_inverse`."""
    ref = _vector(ref_q_rad, 6, "reference joint position (rad)")
    pose = _vector(pose_mm_rpy, 6, "TCP pose (mm, RPY rad)")
    return _cmd(Cmd.KINE_INVERSE, **{Field.JOINT_POSITION: units.joints_to_wire(ref),
                                     Field.CART_POSITION: units.pose_to_wire(pose)})


# ---- frames, payload, safety ----------------------------------------------------------------

def set_tool_offsets(tool_id: int, pose_mm_rpy, name: str = "") -> Request:
    """Store tool frame ``tool_id``: its pose relative to the flange (mm + RPY rad)."""
    pose = _vector(pose_mm_rpy, 6, "tool offset (mm, RPY rad)")
    return _cmd(Cmd.SET_TOOL_OFFSETS, **{Field.TOOL_OFFSET: units.pose_to_wire(pose),
                                         Field.ID: _integer(tool_id, "tool id"),
                                         Field.NAME: str(name)})


def set_tool_id(tool_id: int) -> Request:
    """Activate tool frame ``tool_id`` (0 = flange)."""
    return _cmd(Cmd.SET_TOOL_ID, **{Field.TOOL_ID: _integer(tool_id, "tool id")})


def get_curr_tool_id() -> Request:
    """Reply: :func:`reply_id`."""
    return _cmd(Cmd.GET_CURR_TOOL_ID)


def set_user_offsets(user_id: int, pose_mm_rpy, name: str = "") -> Request:
    """Store user frame ``user_id``: its pose relative to the base (mm + RPY rad)."""
    pose = _vector(pose_mm_rpy, 6, "user frame (mm, RPY rad)")
    return _cmd(Cmd.SET_USER_OFFSETS, **{Field.USER_OFFSET: units.pose_to_wire(pose),
                                         Field.ID: _integer(user_id, "user frame id"),
                                         Field.NAME: str(name)})


def set_user_id(user_id: int) -> Request:
    """Activate user frame ``user_id`` (0 = base)."""
    return _cmd(Cmd.SET_USER_ID, **{Field.USER_FRAME_ID: _integer(user_id, "user frame id")})


def get_curr_user_id() -> Request:
    """Reply: :func:`reply_id`."""
    return _cmd(Cmd.GET_CURR_USER_ID)


def set_payload(mass_kg: float, centroid_mm) -> Request:
    """Payload ``mass_kg`` (kg) with its centre of mass ``centroid_mm`` (mm, flange frame)."""
    centroid = _vector(centroid_mm, 3, "payload centroid (mm)")
    return _cmd(Cmd.SET_PAYLOAD, **{Field.MASS: _number(mass_kg, "payload mass (kg)", lo=0.0),
                                    Field.CENTROID: [float(v) for v in centroid]})


def get_payload() -> Request:
    """Reply: :func:`reply_payload`."""
    return _cmd(Cmd.GET_PAYLOAD)


def set_clsn_sensitivity(level: int) -> Request:
    """Collision sensitivity level: 0 off, 1–5 (25–125 N)."""
    return _cmd(Cmd.SET_CLSN_SENSITIVITY,
                **{Field.SENSITIVITY_VAL: _integer(level, "collision level", 0, 5)})


def get_clsn_sensitivity() -> Request:
    """Reply: :func:`reply_clsn_sensitivity`."""
    return _cmd(Cmd.GET_CLSN_SENSITIVITY)


def drag_status() -> Request:
    """Reply: ``reply_flag(reply, Field.DRAG_STATUS)``."""
    return _cmd(Cmd.DRAG_STATUS)


def torque_control_enable(on: bool) -> Request:
    """Enter (``True``) or leave drag mode (hand guiding), as JAKA's SDK's
    ``drag_mode_enable`` does; confirm with :func:`get_drag_status`."""
    return _cmd(Cmd.TORQUE_CONTROL_ENABLE, **{Field.ENABLE_FLAG: 1 if on else 0})


def get_dh_param() -> Request:
    """The arm's own kinematic parameters. Reply: :func:`reply_dh_param`."""
    return _cmd(Cmd.GET_DH_PARAM)


# ---- IO -------------------------------------------------------------------------------------
# io_type: fields.IOType (0 cabinet, 1 tool, 2 extension; controllers know more). ``index`` is
# 0-based, as the SDK's API counts; the wire is 1-based, and JAKA's SDK sends index + 1 for every
# IO type (docs/protocol.md, "IO"): sending the API index unchanged would switch the next output.

def _io(io_type: int, index: int) -> Request:
    return {Field.IO_TYPE: _integer(io_type, "IO type"),
            Field.INDEX: _integer(index, "IO index") + 1}


def set_digital_output(io_type: int, index: int, value) -> Request:
    """Set a digital output; any truthy ``value`` is 1."""
    return _cmd(Cmd.SET_DIGITAL_OUTPUT, **_io(io_type, index), **{Field.VALUE: 1 if value else 0})


def set_analog_output(io_type: int, index: int, value: float) -> Request:
    """Set an analog output (controller units, usually V or mA)."""
    return _cmd(Cmd.SET_ANALOG_OUTPUT, **_io(io_type, index),
                **{Field.VALUE: _number(value, "analog output value")})


def get_digital_input(io_type: int, index: int) -> Request:
    """Reply: :func:`reply_value` (0/1)."""
    return _cmd(Cmd.GET_DIGITAL_INPUT, **_io(io_type, index))


def get_digital_input_status() -> Request:
    """Reply: :func:`reply_din_status` (all cabinet digital inputs)."""
    return _cmd(Cmd.GET_DIGITAL_INPUT_STATUS)


def get_analog_output(io_type: int, index: int) -> Request:
    """Reply: :func:`reply_value`."""
    return _cmd(Cmd.GET_ANALOG_OUTPUT, **_io(io_type, index))


def get_digital_output(io_type: int, index: int) -> Request:
    """Reply: :func:`reply_value` (0/1)."""
    return _cmd(Cmd.GET_DIGITAL_OUTPUT, **_io(io_type, index))


def get_analog_input(io_type: int, index: int) -> Request:
    """Reply: :func:`reply_value`."""
    return _cmd(Cmd.GET_ANALOG_INPUT, **_io(io_type, index))


# ---- the motion queue -------------------------------------------------------------------------

def get_motion_state() -> Request:
    """The controller's motion queue. Reply: :func:`reply_motion_state`."""
    return _cmd(Cmd.GET_MOTION_STATE)


def wait_complete() -> Request:
    """Answered once every queued move is done (the reply may take as long as the moves)."""
    return _cmd(Cmd.WAIT_COMPLETE)


def is_on_limit() -> Request:
    """Reply: ``reply_flag(reply, Field.ON_LIMIT)``."""
    return _cmd(Cmd.IS_ON_LIMIT)


def end_move(pose_mm_rpy, speed_rad_s: float, accel_rad_s2: float) -> Request:
    """Joint-interpolated move to a Cartesian pose (mm + RPY rad) with joint speed (rad/s) and
    acceleration (rad/s²); queued like every move."""
    pose = _vector(pose_mm_rpy, 6, "end_move pose (mm, RPY rad)")
    speed = _number(speed_rad_s, "joint speed (rad/s)", positive=True)
    accel = _number(accel_rad_s2, "joint acceleration (rad/s²)", positive=True)
    return _cmd(Cmd.END_MOVE, **{Field.END_POSITION: units.pose_to_wire(pose),
                                 Field.SPEED: math.degrees(speed),
                                 Field.ACCEL: math.degrees(accel)})


def data_request() -> Request:
    """Port 10004 only: one status packet, zlib-compressed (see :class:`.status_client.StatusPoller`)."""
    return _cmd(Cmd.DATA_REQUEST)


# ---- reading settings back ------------------------------------------------------------------

def get_drag_status() -> Request:
    """Reply: ``reply_flag(reply, Field.STATUS)`` (a JSON bool)."""
    return _cmd(Cmd.GET_DRAG_STATUS)


def get_rapid_rate() -> Request:
    """Reply: :func:`reply_value` (1.0 = 100 %)."""
    return _cmd(Cmd.GET_RAPID_RATE)


def get_tool_offsets() -> Request:
    """Every stored tool, by id. Reply: :func:`reply_tool_offsets`."""
    return _cmd(Cmd.GET_TOOL_OFFSETS)


def get_user_offsets() -> Request:
    """Every stored user frame, by id. Reply: :func:`reply_user_offsets`."""
    return _cmd(Cmd.GET_USER_OFFSETS)
