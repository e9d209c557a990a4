"""The door of the driver: every request of the node passes :class:`RobotDriver`.

* :mod:`.robot_driver` — :class:`RobotDriver`: order of checks, motion lock, the one wait loop;
* :mod:`.checks` — field checks (-2 naming field, value and limit) and a move's planned
  duration;
* :mod:`.force_requests` — the force/torque sensor and force control, offered as
  ``driver.force`` (:class:`~.force_requests.ForceRequests`); their field checks
  :mod:`.force_checks`;
* :mod:`.watchdogs` — the jog keep-alive and the servo stream's gap.

How requests are read where JAKA's document and JAKA's driver code differ (servo increments,
RPY poses, the jog's speed field) is jaka_driver.conventions, which RobotDriver applies.
"""
from .robot_driver import RobotDriver

__all__ = ["RobotDriver"]
