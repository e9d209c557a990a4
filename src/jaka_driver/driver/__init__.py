"""The door of the driver: every request of the node passes :class:`RobotDriver`.

* :mod:`.robot_driver` — :class:`RobotDriver`, assembled from the parts below;
* :mod:`.door` — the core every part shares: the state checks in their order, the motion lock,
  the watchdogs, the wrapper that turns any failure into an answer;
* the parts by subject: :mod:`.moves` (moves, trajectories, stop, the one wait loop),
  :mod:`.jogs`, :mod:`.servo_requests` (servo mode, targets, the servo filter),
  :mod:`.program_requests`, :mod:`.arm_settings` (settings, kinematics),
  :mod:`.twin_requests` (what only a twin can do);
* :mod:`.program_steps` — the driver as the executor of a program's steps;
* :mod:`.checks` — field checks (-2 naming field, value and limit) and a move's planned
  duration;
* :mod:`.force_requests` — the force/torque sensor and force control, offered as
  ``driver.force`` (:class:`~.force_requests.ForceRequests`); their field checks
  :mod:`jaka_driver.backend.force_checks`, which the emulator applies too;
* :mod:`.tool_io_requests` — the tool connector (supply, pins, RS485 channels, frames,
  signals), offered as ``driver.tool_io`` (:class:`~.tool_io_requests.ToolIORequests`);
* :mod:`.camera_requests` — the cameras, offered as ``driver.cameras``;
* :mod:`.watchdogs` — the jog keep-alive and the servo stream's gap.

How requests are read where JAKA's document and JAKA's driver code differ (servo increments,
RPY poses, the jog's speed field) is jaka_driver.conventions, which RobotDriver applies.
"""
from .robot_driver import RobotDriver

__all__ = ["RobotDriver"]
