"""What a JAKA controller keeps set (a part of :class:`~.twin_controller.TwinController`):
tool and user frames, stored by id and activated separately from being set, the payload, drag
mode, the collision level and the servo filter applied to the twin's servo stream. SI units
(the payload's centroid mm, as the wire and the status packet report it).
"""
from __future__ import annotations

import threading
from typing import Tuple

import numpy as np

from ..backend import Backend, Twin
from ..common.frames import TOOL, USER_FRAME, FrameTable
from ..common.models import RobotModel
from ..motion.servo_filters import ServoFilterSpec
from .replies import Rejected

#: Tool and user frame slots: the rows of get_tool_offsets / get_user_offsets (ids 0..10, as
#: JAKA's SDK reads them; 0 is the flange / the base itself and cannot be set).
FRAME_IDS = range(0, 11)
MAX_CLSN_LEVEL = 5


class ArmSettings:
    """Frames, payload, drag mode, collision level, servo filter."""

    # set by TwinController.__init__
    backend: Backend
    twin: Twin
    model: RobotModel
    lock: threading.RLock
    frames: FrameTable
    payload_mass: float
    payload_centroid_mm: np.ndarray
    collision_level: int
    servo_filter: Tuple[int, dict]

    def set_tool_offset(self, tool_id: int, pose: np.ndarray) -> None:
        with self.lock:
            self.frames.store(TOOL, tool_id, pose)
            if self.state().tool_id == tool_id:
                self.backend.set_tool_frame(tool_id, pose)   # re-apply the active tool

    def activate_tool(self, tool_id: int) -> None:
        with self.lock:
            self.backend.set_tool_frame(tool_id, self.frames.get(TOOL, tool_id))

    def set_user_offset(self, user_id: int, pose: np.ndarray) -> None:
        with self.lock:
            self.frames.store(USER_FRAME, user_id, pose)
            if self.state().user_id == user_id:
                self.backend.set_user_frame(user_id, pose)

    def activate_user(self, user_id: int) -> None:
        with self.lock:
            self.backend.set_user_frame(user_id, self.frames.get(USER_FRAME, user_id))

    def set_payload(self, mass: float, centroid_mm: np.ndarray) -> None:
        with self.lock:
            self.backend.set_payload(self.state().tool_id, mass, centroid_mm / 1000.0)
            self.payload_mass, self.payload_centroid_mm = mass, centroid_mm.copy()

    def set_drag_mode(self, on: bool) -> None:
        with self.lock:
            if on and self.program_running():
                raise Rejected("torque_control_enable: a program is running (stop_program "
                               "first)")
            result = self.backend.set_drag_mode(on)
            if not result.ok:
                raise Rejected(f"torque_control_enable: {result.message}")

    def set_collision_level(self, level: int) -> None:
        with self.lock:
            self.backend.set_collision_level(level)
            self.collision_level = level

    def set_servo_filter(self, filter_type: int, params: dict, spec: ServoFilterSpec) -> None:
        """The servo filter ``spec`` on the twin's servo stream from the next servo mode on
        (JAKA's manual: set outside servo mode); ``filter_type`` and ``params`` as the wire
        sent them, kept to report."""
        with self.lock:
            if self.state().servo_mode:
                raise Rejected("set_servo_move_filter: not allowed in servo mode")
            result = self.backend.set_servo_filter(spec)
            if not result.ok:
                raise Rejected(f"set_servo_move_filter: {result.message}")
            self.servo_filter = (filter_type, dict(params))
