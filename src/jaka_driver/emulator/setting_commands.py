"""The controller's settings: identity and kinematic parameters, tool and user frames (a table
of 11 slots read back by id), payload, speed ratio, collision level, servo
filters (``set_servo_move_filter`` in the wire's units — Hz, deg/s…, mm/s…, buffer counts —
mapped to the twin's filter, :func:`wire_filter`, and applied to its servo stream). Every set is visible to the very next get, on any connection (JAKA's SDK polls the
get after the set; docs/protocol.md, "Settings read back").
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping

import math

from ..common.frames import TOOL, USER_FRAME
from ..common.models import RobotModel
from ..common.results import CommandRefused
from ..motion.servo_filters import ServoFilterSpec, checked_spec
from ..kinematics.controller_dh import dh_of_model
from ..protocol.fields import Cmd, Field
from .replies import ERROR_REQUEST, Answer, Rejected, done
from .status_packet import wire_pose
from .twin_controller import FRAME_IDS, MAX_CLSN_LEVEL, TwinController
from .wire_fields import integer, number, pose, vector

#: set_servo_move_filter: filter_type → its parameters (JAKA's SDK sends them unconverted: Hz,
#: deg/s, deg/s², deg/s³, mm/s, mm/s², mm/s³; buffer sizes are counts)
SERVO_FILTERS: Dict[int, tuple] = {
    0: (),                                                    # none
    1: (Field.LPF_CF,),                                       # joint low-pass
    2: (Field.NLF_MAX_VR, Field.NLF_MAX_AR, Field.NLF_MAX_JR),   # joint non-linear
    3: (Field.MMF_MAX_BUF, Field.MMF_KP, Field.MMF_KV, Field.MMF_KA),   # joint multi-order mean
    4: (Field.NLF_MAX_VP, Field.NLF_MAX_AP, Field.NLF_MAX_JP,            # Cartesian non-linear
        Field.NLF_MAX_VR, Field.NLF_MAX_AR, Field.NLF_MAX_JR),
    5: (Field.MMF_MAX_BUF, Field.MMF_KP),                     # speed foresight
}
#: parameters that must be > 0 (limits, a cut-off); the gains may be 0
_POSITIVE = {Field.LPF_CF, Field.NLF_MAX_VR, Field.NLF_MAX_AR, Field.NLF_MAX_JR,
             Field.NLF_MAX_VP, Field.NLF_MAX_AP, Field.NLF_MAX_JP}


class SettingCommands:
    def __init__(self, controller: TwinController):
        self.c = controller
        self.model = controller.model
        #: get_dh_param: the twin's own chain (its URDF) in the controller's convention
        self.dh_rows = dh_of_model(self.model).to_wire()

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        c = self.c
        return {
            Cmd.GET_VERSION: lambda r: Answer(c.identity_fields()),
            Cmd.GET_DH_PARAM: lambda r: Answer({Field.DH_PARAM: self.dh_rows}),
            Cmd.SET_TOOL_OFFSETS: self._set_tool_offsets,
            Cmd.SET_USER_OFFSETS: self._set_user_offsets,
            Cmd.GET_TOOL_OFFSETS: lambda r: Answer({Field.TOOL_OFFSETS: self._table(TOOL)}),
            Cmd.GET_USER_OFFSETS: lambda r: Answer(
                {Field.USER_OFFSETS: self._table(USER_FRAME)}),
            Cmd.SET_TOOL_ID: lambda r: done(c.activate_tool(self._slot(r, Field.TOOL_ID))),
            Cmd.SET_USER_ID: lambda r: done(c.activate_user(
                self._slot(r, Field.USER_FRAME_ID))),
            Cmd.GET_CURR_TOOL_ID: lambda r: Answer({Field.ID: int(c.state().tool_id)}),
            Cmd.GET_CURR_USER_ID: lambda r: Answer({Field.ID: int(c.state().user_id)}),
            Cmd.SET_PAYLOAD: self._set_payload,
            Cmd.GET_PAYLOAD: lambda r: Answer({Field.MASS: float(c.payload_mass),
                                               Field.CENTROID: c.payload_centroid_mm}),
            Cmd.RAPID_RATE: self._rapid_rate,
            Cmd.GET_RAPID_RATE: lambda r: Answer({Field.VALUE: float(c.rapid_rate)}),
            Cmd.SET_CLSN_SENSITIVITY: lambda r: done(c.set_collision_level(
                integer(r, Field.SENSITIVITY_VAL, 0, MAX_CLSN_LEVEL))),
            Cmd.GET_CLSN_SENSITIVITY: lambda r: Answer(
                {Field.SENSITIVITY_LEVEL: c.collision_level,
                 Field.SENSITIVITY_VAL: c.collision_level}),
            Cmd.SET_SERVO_MOVE_FILTER: self._set_servo_filter,
        }

    # ---- frames ---------------------------------------------------------------------------------
    def _table(self, kind: str) -> list:
        """Every slot, row = id: [x, y, z mm, rx, ry, rz deg RPY]; a slot never set is zeros."""
        return [wire_pose(self.c.frames.get(kind, i)) for i in FRAME_IDS]

    @staticmethod
    def _slot(req, key: str) -> int:
        return integer(req, key, FRAME_IDS.start, FRAME_IDS.stop - 1)

    @staticmethod
    def _settable(req) -> int:
        """The id of a frame to set: 1..10 (0 is the flange / the base itself)."""
        return integer(req, Field.ID, FRAME_IDS.start + 1, FRAME_IDS.stop - 1)

    def _set_tool_offsets(self, req) -> Answer:
        self.c.set_tool_offset(self._settable(req), pose(req, Field.TOOL_OFFSET))
        return Answer()

    def _set_user_offsets(self, req) -> Answer:
        # "userffset" (sic) is what JAKA's SDK sends; "useroffset" is read too, for old clients.
        key = Field.USER_OFFSET if Field.USER_OFFSET in req else "useroffset"
        self.c.set_user_offset(self._settable(req), pose(req, key))
        return Answer()

    # ---- payload, speed, servo filter -----------------------------------------------
    def _set_payload(self, req) -> Answer:
        mass = number(req, Field.MASS, lo=0.0, hi=self.model.max_payload_kg)
        self.c.set_payload(mass, vector(req, Field.CENTROID, 3))
        return Answer()

    def _rapid_rate(self, req) -> Answer:
        self.c.rapid_rate = number(req, Field.RATE_VALUE, lo=0.0, hi=1.0, positive=True)
        return Answer()

    def _set_servo_filter(self, req) -> Answer:
        filter_type = integer(req, Field.FILTER_TYPE, 0, max(SERVO_FILTERS))
        params = {}
        for key in SERVO_FILTERS[filter_type]:
            if key == Field.MMF_MAX_BUF:
                params[key] = integer(req, key, 1, 1_000_000)
            else:
                params[key] = number(req, key, lo=0.0, positive=key in _POSITIVE)
        self.c.set_servo_filter(filter_type, params, wire_filter(self.model, filter_type,
                                                                 params))
        return Answer()


#: the wire's key → (the driver's field, factor from the wire's unit to the driver's):
#: angles deg → rad, lengths stay mm (the driver's request speaks mm/s…), Hz and counts as sent
_WIRE_TO_REQUEST = {
    Field.LPF_CF: ("lpf_cutoff_hz", 1.0),
    Field.NLF_MAX_VR: ("nlf_max_vr", math.pi / 180.0),
    Field.NLF_MAX_AR: ("nlf_max_ar", math.pi / 180.0),
    Field.NLF_MAX_JR: ("nlf_max_jr", math.pi / 180.0),
    Field.NLF_MAX_VP: ("nlf_max_vp", 1.0), Field.NLF_MAX_AP: ("nlf_max_ap", 1.0),
    Field.NLF_MAX_JP: ("nlf_max_jp", 1.0),
    Field.MMF_MAX_BUF: ("mmf_buffer", 1.0), Field.MMF_KP: ("mmf_kp", 1.0),
    Field.MMF_KV: ("mmf_kv", 1.0), Field.MMF_KA: ("mmf_ka", 1.0),
}


def wire_filter(model: RobotModel, filter_type: int, params: Mapping[str, float]
                ) -> ServoFilterSpec:
    """The twin's filter for a ``set_servo_move_filter``'s ``filter_type`` and parameters in
    the wire's units (JAKA's SDK sends them unconverted: Hz, deg/s, deg/s², deg/s³, mm/s,
    mm/s², mm/s³, buffer counts): converted to the driver's units, and what lies above what
    the twin can run is clamped to it, not refused — JAKA documents no upper bound and no
    controller is known to refuse one (``servo_move_use_joint_LPF(125.0)`` among them): the
    emulator adds no range of its own (docs/twin.md, "Servo filters";
    :func:`~jaka_driver.motion.servo_filters.checked_spec` with ``clamp``). Left to refuse,
    with "1" naming the wire's field and value: the multi-order mean's three weights all 0
    (no mean to take)."""
    request = {}
    for key, value in params.items():
        name, factor = _WIRE_TO_REQUEST[key]
        request[name] = value * factor
    try:
        return checked_spec(model, filter_type, request, clamp=True)
    except CommandRefused as refusal:
        sent = ", ".join(f"{k} {v:g}" for k, v in params.items())
        raise Rejected(f"set_servo_move_filter: {refusal.message} (the request's {sent}; "
                       "angles converted from deg)", ERROR_REQUEST) from None
