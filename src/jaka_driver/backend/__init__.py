"""The backend contract: what the MuJoCo twin and the controller backend both implement, in SI
units (:mod:`.contract`), and what travels across it.

* :mod:`.contract` — :class:`Backend`: one robot, twin or controller connection;
* :mod:`.twin` — :class:`Twin`: what only a digital twin can do, a capability a backend
  may offer besides the contract (``backend.twin``);
* :mod:`.programs` — :class:`Programs`: robot programs, the other one (``backend.programs``),
  with :class:`ProgramState`, :class:`ProgramStatus` and :class:`UserVariable`;
* :mod:`.force` — :class:`Force`: the flange force/torque sensor and force control, which every
  backend offers (``backend.force``; :class:`NoForceSensor` refuses every request);
* :mod:`.robot_state` — :class:`RobotState`, one sample of the arm, and :class:`MotionState`;
* :mod:`.completion` — :class:`Completion`, the end of a started motion;
* :mod:`.clock` — a backend's time: :class:`WallClock`, or the twin's :class:`SimClock`;
* :mod:`.timers` — :class:`Timer`, a callback scheduled on either (``call_at``).
"""
from .clock import SimClock, WallClock, make_clock
from .completion import Completion
from .contract import Backend
from .force import Force, ForceReading, ForceSettings, NoForceSensor
from .programs import ProgramState, ProgramStatus, Programs, UserVariable
from .robot_state import MotionState, RobotState
from .timers import Timer
from .twin import Camera, Twin

__all__ = ["Backend", "Twin", "Camera", "Programs", "ProgramState", "ProgramStatus",
           "UserVariable", "Force", "ForceReading", "ForceSettings", "NoForceSensor",
           "RobotState", "MotionState", "Completion", "WallClock", "SimClock", "Timer",
           "make_clock"]
