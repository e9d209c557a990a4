"""jaka_driver: JAKA's documented ROS driver interface over a MuJoCo twin or a real JAKA
controller (docs/design.md has the picture). The package, by role:

* :mod:`.ros` — the node: the only layer that imports rospy;
* :mod:`.driver` — the door every request passes (:class:`~.driver.RobotDriver`): checks,
  state, the one wait loop, watchdogs, servo increments;
* :mod:`.backend` — the contract every backend implements (:class:`~.backend.Backend`, the
  twin's own capability :class:`~.backend.Twin`), its samples, completions and clocks;
* :mod:`.sim` — the MuJoCo twin; :mod:`.controller` — a JAKA controller over TCP, on
  :mod:`.protocol` (JAKA's TCP/JSON protocol, depending on nothing else here);
  :mod:`.emulator` — the twin behind that protocol;
* :mod:`.motion`, :mod:`.kinematics`, :mod:`.common` — what the layers share: time laws and
  paths, FK/IK, the arm models, poses, result codes, frames, shared numbers;
* :mod:`.host` — the machine: the threads' time slice, where compiled libraries are.

This file imports nothing: a program first asks for its threads' short time slice
(``from jaka_driver.host import latency_hint``), before any import that starts a thread.
"""

__all__ = ["ros", "driver", "backend", "sim", "controller", "protocol", "emulator", "motion",
           "kinematics", "common", "host"]
