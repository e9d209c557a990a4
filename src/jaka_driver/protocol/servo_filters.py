"""``set_servo_move_filter`` (JAKA's SDK's six servo filters, docs/protocol.md): one request,
``filter_type`` and the keys of that filter only.

The SDK sends the values unconverted, in its header's units — deg/s, deg/s², deg/s³ for joint
and rotation limits, mm/s… for the TCP, Hz, buffer counts. This library's API speaks rad for
angles, as everywhere: the encoders take rad/s… and send deg/s…. ``mmf_max_buf`` is an int.
"""
from __future__ import annotations

import math

from .request_values import Request, command as _cmd, integer as _integer
from .request_values import number as _number
from .fields import Cmd, Field, ServoFilter


def _filter(kind: ServoFilter, **fields) -> Request:
    """The request, keys in the sorted order JAKA's SDK writes them."""
    return dict(sorted(_cmd(Cmd.SET_SERVO_MOVE_FILTER,
                            **{Field.FILTER_TYPE: int(kind), **fields}).items()))


def _deg(value: float, what: str) -> float:
    return math.degrees(_number(value, what, positive=True))


def servo_filter_none() -> Request:
    """``servo_move_use_none_filter``."""
    return _filter(ServoFilter.NONE)


def servo_filter_joint_lpf(cutoff_hz: float) -> Request:
    """``servo_move_use_joint_LPF``: first-order low-pass of cut-off ``cutoff_hz`` Hz."""
    return _filter(ServoFilter.JOINT_LPF, **{
        Field.LPF_CF: _number(cutoff_hz, "low-pass cut-off (Hz)", positive=True)})


def servo_filter_joint_nlf(max_vr: float, max_ar: float, max_jr: float) -> Request:
    """``servo_move_use_joint_NLF``: joint limits rad/s, rad/s², rad/s³ (sent in deg)."""
    return _filter(ServoFilter.JOINT_NLF, **{
        Field.NLF_MAX_VR: _deg(max_vr, "joint speed limit (rad/s)"),
        Field.NLF_MAX_AR: _deg(max_ar, "joint acceleration limit (rad/s²)"),
        Field.NLF_MAX_JR: _deg(max_jr, "joint jerk limit (rad/s³)")})


def servo_filter_joint_mmf(max_buf: int, kp: float, kv: float, ka: float) -> Request:
    """``servo_move_use_joint_MMF``: buffer (cycles) and the three coefficients."""
    return _filter(ServoFilter.JOINT_MMF, **{
        Field.MMF_MAX_BUF: _integer(max_buf, "mean filter buffer", 1),
        Field.MMF_KP: _number(kp, "mmf kp", lo=0.0), Field.MMF_KV: _number(kv, "mmf kv", lo=0.0),
        Field.MMF_KA: _number(ka, "mmf ka", lo=0.0)})


def servo_filter_carte_nlf(max_vp: float, max_ap: float, max_jp: float, max_vr: float,
                           max_ar: float, max_jr: float) -> Request:
    """``servo_move_use_carte_NLF``: TCP limits mm/s, mm/s², mm/s³ and rotation limits rad/s,
    rad/s², rad/s³ (sent in deg)."""
    return _filter(ServoFilter.CARTE_NLF, **{
        Field.NLF_MAX_VP: _number(max_vp, "TCP speed limit (mm/s)", positive=True),
        Field.NLF_MAX_AP: _number(max_ap, "TCP acceleration limit (mm/s²)", positive=True),
        Field.NLF_MAX_JP: _number(max_jp, "TCP jerk limit (mm/s³)", positive=True),
        Field.NLF_MAX_VR: _deg(max_vr, "rotation speed limit (rad/s)"),
        Field.NLF_MAX_AR: _deg(max_ar, "rotation acceleration limit (rad/s²)"),
        Field.NLF_MAX_JR: _deg(max_jr, "rotation jerk limit (rad/s³)")})


def servo_speed_foresight(max_buf: int, kp: float) -> Request:
    """``servo_speed_foresight``: buffer (cycles) and the position coefficient."""
    return _filter(ServoFilter.SPEED_FORESIGHT, **{
        Field.MMF_MAX_BUF: _integer(max_buf, "foresight buffer", 1),
        Field.MMF_KP: _number(kp, "foresight kp", lo=0.0)})
