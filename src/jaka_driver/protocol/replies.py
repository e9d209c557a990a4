"""Replies of the JAKA TCP protocol (port 10001): decoding and typed accessors.

:func:`parse_reply` turns a decoded JSON object into a :class:`Reply`. A reply with a non-zero
``errorCode`` is a normal reply (``ok`` False, the controller's ``errorMsg`` kept verbatim); the
``reply_*`` accessors raise :class:`~.errors.CommandRejected` for it, and otherwise read one
field and convert it back to the SDK's units (rad, mm + RPY rad).

Replies are read by key, whatever their layout: a real controller puts spaces after ``:`` and
``,``, an older one may not; extra keys are kept in ``fields`` and ignored by the accessors.

:mod:`.commands` re-exports everything here, so ``commands.get_joint_pos()`` and
``commands.reply_joint_pos(reply)`` sit side by side for callers.
"""
from __future__ import annotations

from types import MappingProxyType
from typing import Any, Dict, Mapping, NamedTuple, Tuple

import numpy as np

from . import units
from .errors import CommandRejected, ProtocolError
from .fields import ERROR_CODE_OK, IDENTITY_FIELDS, Field
from .reply_values import Reply
from .reply_values import field as _field, int_field as _int_field, number as _number
from .reply_values import table as _table, wire_vector as _wire_vector
from .wire import as_flag, clean_text


_META = (Field.CMD_NAME, Field.ERROR_CODE, Field.ERROR_MSG)


def parse_reply(obj: Any) -> Reply:
    """A decoded JSON reply → :class:`Reply`. Raises :class:`~.errors.ProtocolError` when it is
    not an object or has no ``errorCode``. A numeric ``errorCode`` is accepted as its string."""
    if not isinstance(obj, Mapping):
        raise ProtocolError(f"a reply must be a JSON object; got {type(obj).__name__}: "
                            f"{str(obj)[:200]}")
    if Field.ERROR_CODE not in obj:
        raise ProtocolError(f"reply has no {Field.ERROR_CODE!r}: {str(dict(obj))[:200]}")
    code = str(obj[Field.ERROR_CODE]).strip()
    return Reply(cmd_name=clean_text(obj.get(Field.CMD_NAME)), ok=code == ERROR_CODE_OK,
                 error_code=code, error_msg=clean_text(obj.get(Field.ERROR_MSG)),
                 fields=MappingProxyType({k: v for k, v in obj.items() if k not in _META}))


def command_names_match(sent: str, echoed: str) -> bool:
    """Whether a reply's ``cmdName`` echo answers the request ``sent``. Case and underscores
    are ignored: clients disagree on spellings like ``moveL``/``move_l``."""
    def norm(name: str) -> str:
        return name.replace("_", "").lower()
    return norm(sent) == norm(echoed)


def reply_joint_pos(reply: Reply) -> np.ndarray:
    """``get_joint_pos`` → joint position, rad (6,)."""
    return units.deg_to_rad(_wire_vector(reply, Field.JOINT_POS, 6))


def reply_tcp_pos(reply: Reply) -> np.ndarray:
    """``get_tcp_pos`` → TCP pose [x, y, z mm, rx, ry, rz rad]."""
    return units.pose_from_wire(_wire_vector(reply, Field.TCP_POS, 6))


def reply_kine_forward(reply: Reply) -> np.ndarray:
    """``kine_forward`` → TCP pose [x, y, z mm, rx, ry, rz rad]."""
    return units.pose_from_wire(_wire_vector(reply, Field.CART_POSITION, 6))


def reply_kine_inverse(reply: Reply) -> np.ndarray:
    """``kine_inverse`` → joint solution, rad (6,)."""
    return units.deg_to_rad(_wire_vector(reply, Field.JOINT_POSITION, 6))


def reply_flag(reply: Reply, key: str) -> bool:
    """A 0/1 reply field as bool, e.g. ``reply_flag(r, Field.EMERGENCY_STOP)``."""
    return as_flag(_field(reply, key), f"{key!r} in the reply to {reply.cmd_name!r}")


class PowerState(NamedTuple):
    powered: bool
    enabled: bool


def reply_robot_state(reply: Reply) -> PowerState:
    """``get_robot_state`` → (powered, enabled). Both reported formats are accepted
    (``"powered_on"``/``"robot_enabled"`` strings, or 0/1)."""
    return PowerState(powered=reply_flag(reply, Field.POWER),
                      enabled=reply_flag(reply, Field.ENABLE))


class MotionState(NamedTuple):
    """``get_motion_state``: the controller's motion queue."""
    inpos: bool
    """every queued move is done and the arm is at rest"""
    queue: int
    """moves waiting in the queue"""
    active_queue: int
    queue_full: bool
    err_add_line: int
    motion_line: int


def reply_motion_state(reply: Reply) -> MotionState:
    """``get_motion_state`` → :class:`MotionState`. ``inpos`` is required; the counters default
    to 0 when a controller leaves them out."""
    inpos = reply_flag(reply, Field.INPOS)

    def count(key: str) -> int:
        raw = reply.fields.get(key, 0)
        try:
            return int(raw)
        except (TypeError, ValueError):
            raise ProtocolError(f"{key!r} in the reply to {reply.cmd_name!r} is not an "
                                f"integer: {raw!r}") from None
    return MotionState(inpos, count(Field.QUEUE), count(Field.ACTIVE_QUEUE),
                       bool(count(Field.QUEUE_FULL)), count(Field.ERR_ADD_LINE),
                       count(Field.MOTION_LINE))


def reply_value(reply: Reply) -> float:
    """``get_digital_input`` / ``get_digital_output`` / ``get_analog_input`` /
    ``get_analog_output`` / ``get_rapid_rate`` → value."""
    return _number(reply, Field.VALUE)


def reply_din_status(reply: Reply) -> Tuple[int, ...]:
    """``get_digital_input_status`` → cabinet digital inputs as 0/1 ints."""
    raw = _field(reply, Field.DIN_STATUS)
    if not isinstance(raw, (list, tuple)):
        raise ProtocolError(f"'din_status' should be a list; got {raw!r}")
    return tuple(int(as_flag(v, "din_status entry")) for v in raw)


def reply_id(reply: Reply) -> int:
    """``get_curr_tool_id`` / ``get_curr_user_id`` → frame id."""
    return _int_field(reply, Field.ID)


def reply_clsn_sensitivity(reply: Reply) -> int:
    """``get_clsn_sensitivity`` → level 0–5 (clients disagree on the key; both are read)."""
    return _int_field(reply, Field.SENSITIVITY_LEVEL, Field.SENSITIVITY_VAL)


def reply_payload(reply: Reply) -> Tuple[float, np.ndarray]:
    """``get_payload`` / ``get_tool_payload`` → (mass kg, centroid mm (3,))."""
    return _number(reply, Field.MASS), _wire_vector(reply, Field.CENTROID, 3)


def reply_version(reply: Reply) -> str:
    """``get_version`` → the controller's version string."""
    return clean_text(_field(reply, Field.VERSION))


def reply_identity(reply: Reply) -> Dict[str, str]:
    """``get_version`` → the identity strings the controller sent, by key (``version``,
    ``controller_id``, ``controller_guarantee``, ``robot_id``, ``robot_name``, ``scb_version``,
    ``servo_version``; older controllers send only ``version``). A number is taken as its text
    (JAKA's SDK would abort on it); any other type is left out."""
    _field(reply, Field.VERSION)
    return {key: clean_text(value) for key, value in reply.fields.items()
            if key in IDENTITY_FIELDS and isinstance(value, (str, int, float))
            and not isinstance(value, bool)}


class DHParam(NamedTuple):
    """``get_dh_param``: the arm's own kinematic parameters, in the SDK's units."""
    alpha: np.ndarray
    """link twists, rad (6,)"""
    a: np.ndarray
    """link lengths, mm (6,)"""
    d: np.ndarray
    """link offsets, mm (6,)"""
    joint_homeoff: np.ndarray
    """joint zero offsets, rad (6,)"""


def reply_dh_param(reply: Reply) -> DHParam:
    """``get_dh_param`` → :class:`DHParam`. The wire sends ``dh_param`` as 4 rows of 6:
    alpha (deg), a (mm), d (mm), joint_homeoff (deg); any other shape or a non-number is a
    :class:`~.errors.ProtocolError` (JAKA's SDK crashes on an object or a flat list)."""
    rows = _table(reply, Field.DH_PARAM, 4, 6)
    return DHParam(alpha=units.deg_to_rad(rows[0]), a=rows[1], d=rows[2],
                   joint_homeoff=units.deg_to_rad(rows[3]))


def reply_tool_offsets(reply: Reply) -> Tuple[np.ndarray, ...]:
    """``get_tool_offsets`` → the stored tools by id (see :func:`_frames_by_id`)."""
    return _frames_by_id(reply, Field.TOOL_OFFSETS)


def reply_user_offsets(reply: Reply) -> Tuple[np.ndarray, ...]:
    """``get_user_offsets`` → the stored user frames by id (see :func:`_frames_by_id`)."""
    return _frames_by_id(reply, Field.USER_OFFSETS)


def _frames_by_id(reply: Reply, key: str) -> Tuple[np.ndarray, ...]:
    """Element ``i`` is frame ``i`` as [x, y, z mm, rx, ry, rz rad] (RPY). The wire sends a
    table, row = id, each [x, y, z mm, rx, ry, rz deg] (a real controller: 11 rows, ids
    0–10); a flat list or any other shape is a :class:`~.errors.ProtocolError` (JAKA's SDK
    crashes on it)."""
    return tuple(units.pose_from_wire(row) for row in _table(reply, key, 0, 6))
