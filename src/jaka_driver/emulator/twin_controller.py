"""What a JAKA controller does, on the MuJoCo twin: the emulator's controller logic in SI units.

The twin (a backend that offers :class:`~jaka_driver.backend.Twin`: the MuJoCo twin) already
moves like the arm; this layer adds what a controller has and the twin does not, one concern a
module, assembled here into :class:`TwinController` (as the motion queue was taken out before):

* :mod:`.arm_rules` — refusing motion in the wrong state, power and enable, the joint limits,
  the commanded setpoint and the arm's kinematics;
* :mod:`.arm_moves` — a motion queue (a move is acknowledged at once and runs after the ones
  before it; ``inpos`` once the queue is done — docs/protocol.md, "Motion queue"; the queue and
  its thread are :mod:`.motion_queue`, what may be queued is decided here), jogs,
  ``stop_program``, and the programs the twin's engine runs on this controller's rules
  (:mod:`.program_steps`): while one runs or is paused, motion commands are refused and
  ``stop_program`` ends it;
* :mod:`.servo_mode` — servo mode and the ``stepNum`` interpolation of its set-points;
* :mod:`.arm_settings` — stored frames that are activated separately from being set, the
  payload and collision settings to report back, drag mode, the servo filter applied to the
  twin's servo stream;
* :mod:`.arm_io` — IO, the inputs and faults the world outside drives, the packet's readings;
* here — the speed override (the twin's speed ratio), the controller's identity and start
  state, the queue's state.

Every method takes SI values (rad, m, 4x4 poses of the active tool in the active user frame) and
raises :class:`~.replies.Rejected` with the controller's message when the command is refused;
wire parsing lives in :mod:`.handlers`.

It uses only the backend's face: the contract (commands, ``state()``), ``backend.twin`` (the
commanded setpoint, the servo ramp, IO, faults) and the facets (``backend.force``,
``backend.programs``), never the simulation's internals nor the driver.

Thread-safe: commands are serialised by one lock (a controller executes one at a time); the
status snapshot reads without it. The queue's thread starts each queued move, under that lock,
when the one before it has ended.
"""
from __future__ import annotations

import threading
import time
from typing import Optional, Tuple

import numpy as np

from ..backend import Backend
from ..common.frames import FrameTable
from ..protocol.fields import IDENTITY_FIELDS
from .arm_io import ArmIo
from .arm_moves import ArmMoves
from .arm_rules import ArmRules
from .arm_settings import FRAME_IDS, MAX_CLSN_LEVEL, ArmSettings
from .motion_queue import MotionQueue
from .profiles import DEFAULT_PROFILE, ControllerProfile, profile_named
from .servo_mode import ERROR_NOT_IN_SERVO_MODE, NOT_IN_SERVO_MODE, ServoMode
from .torque_sensor import TorqueSensorSettings

__all__ = ["TwinController", "FRAME_IDS", "MAX_CLSN_LEVEL", "ERROR_NOT_IN_SERVO_MODE",
           "NOT_IN_SERVO_MODE"]


class TwinController(ArmRules, ArmMoves, ServoMode, ArmSettings, ArmIo):
    """A JAKA controller whose arm is ``backend``, a twin (``backend.twin`` is not None)."""

    def __init__(self, backend: Backend, profile: Optional[ControllerProfile] = None):
        """``profile``: the controller generation (default :data:`~.profiles.DEFAULT_PROFILE`,
        fw 1.7.2: the controller JAKA's current software is written for)."""
        if backend.twin is None:
            raise ValueError("the emulator needs a backend that offers a twin (backend.twin)")
        self.backend = backend
        self.twin = backend.twin
        self.model = backend.model
        self.profile = profile = profile or profile_named(DEFAULT_PROFILE)
        #: what get_version answers: the profile's firmware in a real controller's form, so
        #: clients that parse it work
        self.version = profile.version
        #: where a person reads it (get_version's robot_name, the log): this is the emulator
        self.identity = f"jaka_driver emulator ({self.model.name} MuJoCo twin), not a controller"
        self.lock = threading.RLock()
        #: the queued moves, started one after another by its own thread
        self.queue = MotionQueue(self.lock)
        self.tio_vout = (0, 0)                        # (enable 0/1, voltage code 0 24 V, 1 12 V)
        self.sensor = TorqueSensorSettings()
        self.frames = FrameTable()
        self.payload_mass = 0.0
        self.payload_centroid_mm = np.zeros(3)
        self.collision_level = self.twin.collision_level
        self.servo_filter: Tuple[int, dict] = (0, {})   # (filter_type, its parameters)

    @property
    def rapid_rate(self) -> float:
        """The speed override (``rapid_rate``), 0 < r ≤ 1: the twin's speed ratio, so moves and
        jogs are scaled by the one law the driver plans with (time × 1/r: speeds × r,
        accelerations × r²); servo set-points are not scaled."""
        return self.backend.speed_ratio()

    @rapid_rate.setter
    def rapid_rate(self, rate: float) -> None:
        with self.lock:
            self.backend.set_speed_ratio(float(rate))

    def identity_fields(self) -> dict:
        """get_version's seven identity strings (JAKA's SDK logs them at login; a number there
        aborts its login). Version 0.0 stands for a part the twin does not have."""
        values = (self.version, "jaka_driver-emulator", "none", f"emulator-{self.model.name}",
                  self.identity, "0.0", "0.0")
        return dict(zip(IDENTITY_FIELDS, values))

    def apply_start(self, start: str) -> None:
        """Put the arm in a start state of :data:`~.profiles.START_STATES` (the twin itself
        starts powered on and enabled)."""
        with self.lock:
            self.backend.set_power(start != "off")
            self.backend.set_enabled(start == "enabled")

    def close(self) -> None:
        self.queue.close()

    @property
    def moving(self) -> bool:
        """Queued moves wait, or one is being started or runs."""
        return self.queue.moving

    @property
    def queued(self) -> int:
        """Moves waiting behind the running one."""
        return self.queue.queued

    @property
    def motion_line(self) -> int:
        """Moves started so far."""
        return self.queue.motion_line

    @property
    def inpos(self) -> bool:
        """The queue is done and the arm is not being driven."""
        return not self.moving and not self.twin.motion_active

    def wait_idle(self, timeout: float) -> bool:
        """Block until the queue is done (``wait_complete``); False on timeout."""
        deadline = time.monotonic() + timeout
        while not self.inpos and time.monotonic() < deadline:
            time.sleep(0.01)
        return self.inpos
