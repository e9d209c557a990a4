"""The ``sim`` backend: the MuJoCo twin of the arm.

Its face is :class:`SimBackend` — the backend contract, ``backend.twin`` (:class:`SimTwin`:
what only a twin can do), ``backend.force`` and ``backend.cameras``. The rest is how it works
inside:

* :mod:`.twin_model` — the MuJoCo model from the URDF, with floor, workcell and payload;
* :mod:`.physics` — :class:`~.physics.PhysicsLoop`, the real-time loop and its samples, and
  its one motion slot (what runs now);
* :mod:`.arm_flags` — :class:`~.arm_flags.ArmFlags`, the arm's flags, written only there;
* :mod:`.servo` — the joint drives (their cycle compiled in ``joint_drives.c``, loaded by
  :mod:`.native_drives`);
* :mod:`.motions` — what the twin's controller does each 8 ms cycle (hold, a trajectory, a jog,
  servo targets, a stop); :mod:`.jog_steps` — a jog's step on a joint or in Cartesian space;
* :mod:`.collisions` — contact force → protective stop; :mod:`.overload` — torque limits and
  following error → brakes; :mod:`.io_board` — the twin's IO;
* :mod:`.snapshot` — offscreen pictures (also ``scripts/snapshot``);
* the cameras (``backend.cameras``): :mod:`.cameras` (:class:`~.cameras.SimCameras`, the facet:
  a copy of each due cycle's state), :mod:`.camera_process` (the renderer in a process of its
  own, at the lowest priority), :mod:`.camera_render` (colour and depth offscreen, depth
  linearised), :mod:`.camera_mounts` (MuJoCo cameras in the cell or on
  the flange);
* the flange force/torque sensor and force control (``backend.force``): :mod:`.ft_sensor` (the
  sensor in the model and its readings), :mod:`.force` (:class:`~.force.SimForce`, the facet),
  :mod:`.force_control` (admittance, constant force, tool drive), :mod:`.payload_identification`,
  :mod:`.tool_push` (a hand on the tool);
* the tool connector (``backend.tool_io``): :mod:`.tool_connector` (:class:`SimToolIO`: settings,
  frames and signals, a device attached to it), :mod:`.tool_device` (:class:`ToolDevice`, what
  a gripper or suction cup on it answers).
"""
from .backend import SimBackend
from .tool_connector import SimToolIO
from .tool_device import ToolDevice
from .twin import SimTwin

__all__ = ["SimBackend", "SimTwin", "SimToolIO", "ToolDevice"]
