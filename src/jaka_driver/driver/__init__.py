"""The door of the driver: every request of the node passes :class:`RobotDriver`.

* :mod:`.robot_driver` — :class:`RobotDriver`: order of checks, motion lock, the one wait loop;
* :mod:`.checks` — field checks (-2 naming field, value and limit) and a move's planned
  duration;
* :mod:`.watchdogs` — the jog keep-alive and the servo stream's gap;
* :mod:`.servo_increment` — servo_j / servo_p read as increments (``servo_increment``), as
  JAKA's driver code sends them: a convention of the driver's servo path.
"""
from .robot_driver import RobotDriver

__all__ = ["RobotDriver"]
