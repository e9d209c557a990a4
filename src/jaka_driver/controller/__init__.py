"""The real-robot backend: a JAKA controller over its TCP protocol (no ROS in here).

* :mod:`.backend` — :class:`ControllerBackend`, the :class:`~jaka_driver.backend.Backend`
  contract on the protocol library.
* :mod:`.connection` — :class:`ControllerLink`, both connections and the reconnect supervisor.
* :mod:`.status_view` — status packets → :class:`~jaka_driver.backend.robot_state.RobotState`.
* :mod:`.move_watch` — when an accepted move has ended, from the status stream.
* :mod:`.servo_stream` — trajectories as a ``servo_j`` stream.
"""
from .backend import ControllerBackend
from .connection import ControllerLink, NotConnected

__all__ = ["ControllerBackend", "ControllerLink", "NotConnected"]
