"""The state snapshot every backend publishes, and the motion states of ``robot_states``."""
from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from types import MappingProxyType
from typing import Mapping, Optional, Tuple

import numpy as np

from .force import ForceReading


class MotionState(IntEnum):
    """``robot_states.motion_state`` (docs/interface.md, "Topics")."""

    STOP = 0
    PAUSE = 1
    EMERGENCY_STOP = 2
    RUNNING = 3
    ERROR = 4


# ProgramState's numbers (JAKA's SDK's), without importing the facet into every sample
_PROGRAM_RUNNING, _PROGRAM_PAUSED = 1, 2


#: Every IO point of a sample: (signal, type, path) → the values, index 0 first — signal
#: "digital" (0 / 1) or "analog" (V), type as set_io numbers it (0 cabinet, 1 tool, 2 extension,
#: 3 relay, 4–6 fieldbus slaves), path 0 inputs, 1 outputs; a kind the arm has no points of is
#: absent. Read-only.
IoValues = Mapping[Tuple[str, int, int], Tuple[float, ...]]
NO_IO: IoValues = MappingProxyType({})


def _zeros6() -> np.ndarray:
    return np.zeros(6)


@dataclass(frozen=True)
class RobotState:
    """One sample of the arm, taken at ``stamp``.

    Units: joints rad, rad/s, N·m. ``tcp_pose`` is the 4x4 pose (metres) of the active tool
    expressed in the active user frame. ``stamp`` is wall-clock time (``time.time()``, s) of
    the sample (sim time, s since the twin started, when the twin owns time) — the node stamps its messages with it, so it is when the physics (or the
    controller's status packet) produced the data, not when it was published. ``force``: the
    flange force/torque sensor's readings of the same instant (:mod:`.force`), None without a
    sensor or while it is off.
    """

    stamp: float
    joint_position: np.ndarray = field(default_factory=_zeros6)
    joint_velocity: np.ndarray = field(default_factory=_zeros6)
    joint_effort: np.ndarray = field(default_factory=_zeros6)
    tcp_pose: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool_id: int = 0
    user_id: int = 0
    connected: bool = True
    powered: bool = False
    enabled: bool = False
    servo_mode: bool = False
    drag_mode: bool = False
    emergency_stop: bool = False
    protective_stop: bool = False
    collision: bool = False
    moving: bool = False
    error_code: int = 0
    error_message: str = ""
    #: the program's state as JAKA's SDK numbers it: 0 idle, 1 running, 2 paused
    #: (:class:`~.programs.ProgramState`)
    program_state: int = 0
    #: every IO point as it came in this sample (:data:`IoValues`)
    io: IoValues = field(default_factory=lambda: NO_IO)
    force: Optional[ForceReading] = None
    #: a joint is on (or past) its soft position limit: a controller's ``on_soft_limit``, on
    #: the twin within 0.1° of a limit (:func:`jaka_driver.common.joint_limits.on_limit`)
    on_limit: bool = False

    @property
    def in_error(self) -> bool:
        """A stop that needs ``clear_err`` before the arm moves again."""
        return self.collision or self.protective_stop or self.error_code != 0

    @property
    def motion_state(self) -> MotionState:
        """Derived like JAKA's driver: e-stop beats error beats a paused program (1) beats
        running (moving, drag mode, or a program running: 3)."""
        if self.emergency_stop:
            return MotionState.EMERGENCY_STOP
        if self.in_error or not self.connected:
            return MotionState.ERROR
        if self.program_state == _PROGRAM_PAUSED:
            return MotionState.PAUSE
        if self.moving or self.drag_mode or self.program_state == _PROGRAM_RUNNING:
            return MotionState.RUNNING
        return MotionState.STOP
