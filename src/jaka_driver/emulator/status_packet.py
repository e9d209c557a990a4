"""The emulator's status packet: the twin's state as the fields of a port-10000 packet (and of
the port-10004 ``data_request`` reply and the ``get_data`` reply), in wire units — joints deg,
TCP mm + RPY deg — with every key, type and array size of a real Zu 5s packet
(docs/protocol.md, "Status packet").

Field values the twin has no notion of are reported as an idle controller with nothing
configured would (``paused`` false, ``on_soft_limit`` 0, ``task_mode`` 2 = auto, fieldbus arrays
zeros). ``errcode`` is the emulator's own, written ``"0x…"`` as the SDK reads it: ``0xE001``
collision, ``0xE002`` protective stop, ``0x0`` none.
"""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from ..protocol import units
from ..protocol.fields import InterpState, StatusField as S, TaskState
from ..transforms import matrix_to_pose_mm_rpy
from .twin_controller import TwinController

ERRCODE_COLLISION = 0xE001
ERRCODE_PROTECTIVE_STOP = 0xE002
TASK_MODE_AUTO = 2

#: The IO of a real controller cabinet as the packet shows it (sizes of a Zu 5s packet: cabinet
#: analog 64 each way, tool digital 8 each way; digital cabinet IO over 100 — 136 here).
CONTROLLER_IO_SIZES = {("digital", 0, 0): 136, ("digital", 0, 1): 136, ("analog", 0, 0): 64,
                       ("analog", 0, 1): 64, ("digital", 1, 0): 8, ("digital", 1, 1): 8,
                       ("analog", 1, 0): 2, ("analog", 1, 1): 0, ("digital", 2, 0): 8,
                       ("digital", 2, 1): 8, ("analog", 2, 0): 4, ("analog", 2, 1): 4}

#: Keys the twin has nothing behind: what a controller with nothing configured sends.
_IDLE = {
    "monitor_data": lambda: {"instVel": [0.0] * 6},
    "torqsensor": lambda: [[0, [0.0] * 6, 0], [0, [0.0] * 6]],
    "drag_near_limit": lambda: [0] * 6, "funcdi": lambda: [[-1, -1] for _ in range(15)],
    "motion_mode": lambda: 0, "point_key": lambda: 0, "netState": lambda: 1,
    "relay_io": lambda: [0] * 4, "tio_key": lambda: [0, 0, 0], "tio_rs_signals": lambda: [],
    "extio": lambda: {"num": 0, "status": []},
    **{f"{bus}_{kind}": (lambda kind=kind: [0.0 if kind[0] == "a" else 0] * 64)
       for bus in ("mb_slave", "pn_dev", "eip_adpt") for kind in ("din", "dout", "ain", "aout")},
}


def zeros_of(key: str) -> Any:
    """The idle value of a packet key the twin has nothing behind (e.g. ``funcdi``)."""
    return _IDLE[key]()


#: status field → the twin's IO key (signal, type, path)
IO_FIELDS = {S.DIN: ("digital", 0, 0), S.DOUT: ("digital", 0, 1), S.AIN: ("analog", 0, 0),
             S.AOUT: ("analog", 0, 1), S.TIO_DIN: ("digital", 1, 0),
             S.TIO_DOUT: ("digital", 1, 1), S.TIO_AIN: ("analog", 1, 0)}


def wire_pose(pose: np.ndarray) -> list:
    """4x4 pose (m) → wire ``[x, y, z mm, rx, ry, rz deg]``."""
    return units.pose_to_wire(matrix_to_pose_mm_rpy(pose))


def status_fields(controller: TwinController) -> Dict[str, Any]:
    """One packet's fields (without ``len``; :func:`~jaka_driver.protocol.encode_status`
    adds it)."""
    twin = controller.twin
    st = twin.state()
    inpos = controller.inpos
    if twin.collision:
        errcode = ERRCODE_COLLISION
    elif twin.protective_stop:
        errcode = ERRCODE_PROTECTIVE_STOP
    else:
        errcode = 0
    if not st.powered:
        task_state = TaskState.POWER_OFF
    elif not st.enabled:
        task_state = TaskState.POWER_ON
    else:
        task_state = TaskState.ENABLED
    io = twin.io.snapshot()
    fields: Dict[str, Any] = {
        S.JOINT_ACTUAL_POSITION: units.joints_to_wire(st.joint_position),
        S.JOINT_POSITION: units.joints_to_wire(controller.commanded_joints()),
        S.ACTUAL_POSITION: wire_pose(st.tcp_pose),
        S.POSITION: wire_pose(controller.commanded_tcp()),
        S.TASK_STATE: int(task_state),
        S.TASK_MODE: TASK_MODE_AUTO,
        S.INTERP_STATE: int(InterpState.IDLE if inpos else InterpState.RUNNING),
        S.POWERED_ON: int(st.powered),
        S.ENABLED: bool(st.enabled),
        S.PAUSED: False,
        "homed": [1] * 6,
        "curr_tcp_trans_vel": 0.0,
        S.MOTION_LINE: int(controller.motion_line),
        "err_add_line": 0,
        "executing_line": int(controller.motion_line),
        S.INPOS: bool(inpos),
        S.DRAG_STATUS: bool(st.drag_mode),
        S.EMERGENCY_STOP: int(st.emergency_stop),
        S.PROTECTIVE_STOP: int(st.protective_stop or st.collision),
        S.ON_SOFT_LIMIT: 0,
        S.ERRCODE: f"{errcode:#x}",
        S.ERRMSG: st.error_message if errcode else "",
        S.RAPIDRATE: float(controller.rapid_rate),
        S.CURRENT_TOOL_ID: int(st.tool_id),
        S.CURRENT_USER_ID: int(st.user_id),
    }
    for name, key in IO_FIELDS.items():
        values = io.get(key)
        cast = int if key[0] == "digital" else float
        fields[name] = [] if values is None else [cast(v) for v in values]
    for key, idle in _IDLE.items():
        fields[key] = idle()
    return fields
