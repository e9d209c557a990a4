"""What every layer shares: the arm models, poses, result codes, tool and user frames, joint
limits and the numbers defined once.

* :mod:`.models` — :func:`load_model`, :class:`RobotModel` (URDF + ``config/<model>.yaml``);
* :mod:`.transforms` — rotations and poses: rotation vector, RPY, quaternion, 4×4;
* :mod:`.results` — :class:`Result`, :class:`Code`, the one library exception
  :class:`CommandRefused`;
* :mod:`.frames` — :class:`FrameTable`, tool and user frames by id;
* :mod:`.joint_limits` — a joint target against the position and speed limits;
* :mod:`.values` — a request's values read as numbers (-2 naming field, value and limit);
* :mod:`.constants` — the controller cycle and the other numbers the layers share.
"""
from .constants import IN_POSITION, SERVO_CYCLE
from .frames import TOOL, USER_FRAME, FrameTable
from .joint_limits import fastest_step, outside_limits
from .models import MODEL_NAMES, RobotModel, load_model
from .results import Code, CommandRefused, Result

__all__ = ["SERVO_CYCLE", "IN_POSITION", "FrameTable", "TOOL", "USER_FRAME", "outside_limits",
           "fastest_step", "MODEL_NAMES", "RobotModel", "load_model", "Code", "CommandRefused",
           "Result", "constants", "frames", "joint_limits", "models", "results", "transforms", "values"]
