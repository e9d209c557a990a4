"""The real-robot backend: a JAKA controller over its TCP protocol (no ROS in here).

* :mod:`.backend` — :class:`ControllerBackend`, the :class:`~jaka_driver.backend.Backend`
  contract on the protocol library.
* :mod:`.connection` — :class:`ControllerLink`, both connections and the reconnect supervisor.
* :mod:`.status_view` — status packets → :class:`~jaka_driver.backend.robot_state.RobotState`.
* :mod:`.running_motion` — what runs now (one slot: a move, a trajectory, a jog, a velocity
  jog, force control that holds the arm, a payload identification) and servo mode.
* the parts that serve the contract, each handed what it works with: :mod:`.moves` (moves,
  trajectories, jogs, stop), :mod:`.servo_commands` (servo mode, servo targets, the velocity
  jog), :mod:`.arm_settings` (frames, payload, drag, collision, IO, errors, the speed ratio),
  :mod:`.force` (``backend.force`` when the arm carries a force/torque sensor: the sensor,
  force control, identification — polled by :mod:`.payload_identification` —; the readings
  of every packet are :mod:`.status_view`'s), :mod:`.tool_io` (``backend.tool_io``: JAKA's
  TIO commands, each setting read back, signals from the packets too).
* :mod:`.move_watch` — when an accepted move has ended, from the status stream.
* :mod:`.servo_stream` — trajectories as a ``servo_j`` stream; :mod:`.twist_stream` — a
  velocity jog as one.
"""
from .backend import ControllerBackend
from .connection import ControllerLink, NotConnected

__all__ = ["ControllerBackend", "ControllerLink", "NotConnected"]
