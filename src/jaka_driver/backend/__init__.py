"""The backend contract: what the MuJoCo twin and the controller backend both implement, in SI
units (:mod:`.contract`), and what travels across it.

* :mod:`.contract` — :class:`Backend`: one robot, twin or controller connection;
* :mod:`.twin` — :class:`Twin`: what only a digital twin can do, a capability a backend
  may offer besides the contract (``backend.twin``);
* :mod:`.programs` — :class:`Programs`: robot programs, the other one (``backend.programs``),
  with :class:`ProgramState`, :class:`ProgramStatus` and :class:`UserVariable`
  (:class:`NoPrograms` refuses every request);
* :mod:`.force` — :class:`Force`: the flange force/torque sensor and force control, which every
  backend offers (``backend.force``; :class:`NoForceSensor` refuses every request), and
  :mod:`.force_checks`, the value checks of its settings (the driver's door and the emulator);
* :mod:`.recording` — :class:`Recording`: trajectory recording and its replay programs
  (``backend.recording``; :class:`NoRecording` refuses every request), :class:`TrajConfig`;
* :mod:`.tool_io` — :class:`ToolIO`: the tool connector (tool power, pins, RS485 channels,
  frames, signals; ``backend.tool_io``; :class:`NoToolIO` refuses every request);
* :mod:`.cameras` — :class:`Cameras`: the twin's cameras (``backend.cameras``; :class:`NoCameras`
  refuses every request), their frames (:class:`CameraFrame`);
* :mod:`.robot_state` — :class:`RobotState`, one sample of the arm, and :class:`MotionState`;
* :mod:`.completion` — :class:`Completion`, the end of a started motion;
* :mod:`.clock` — a backend's time: :class:`WallClock`, or the twin's :class:`SimClock`;
* :mod:`.timers` — :class:`Timer`, a callback scheduled on either (``call_at``).
"""
from .cameras import CameraFrame, Cameras, NoCameras
from .clock import SimClock, WallClock, make_clock
from .completion import Completion
from .contract import Backend
from .force import Force, ForceReading, ForceSettings, NoForceSensor
from .programs import NoPrograms, ProgramState, ProgramStatus, Programs, UserVariable
from .recording import NoRecording, Recording, TrajConfig
from .robot_state import MotionState, RobotState
from .timers import Timer
from .tool_io import ChannelComm, NoToolIO, Signal, ToolIO, ToolIOSettings
from .twin import Camera, Twin

__all__ = ["Backend", "Twin", "Camera", "Programs", "ProgramState", "ProgramStatus",
           "UserVariable", "NoPrograms", "Recording", "NoRecording", "TrajConfig", "Force",
           "ForceReading", "ForceSettings", "NoForceSensor", "ToolIO", "ToolIOSettings",
           "ChannelComm", "Signal", "NoToolIO", "Cameras", "CameraFrame", "NoCameras", "RobotState",
           "MotionState", "Completion", "WallClock", "SimClock", "Timer", "make_clock",
           "force_checks"]
