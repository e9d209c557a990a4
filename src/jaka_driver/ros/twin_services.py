"""The twin's own services, all under ``~sim/``, in one place (docs/design.md, "Where a new
capability lives"): each calls ``driver.twin`` (:mod:`jaka_driver.driver.twin_requests`), the
door of what only a twin can do.

Advertised on every backend, so that a suite run against a controller gets a clear refusal
(-9, "not a twin") instead of a missing service:

- ``~sim/reset`` (``jaka_driver_msgs/ResetTwin``: joints rad, empty = home) — a fresh start
  there: errors and e-stop cleared, IO, frames, payload, collision level and speed ratio at their
  defaults, no motion (a waiting move answers -12);
- ``~sim/pause`` (``jaka_driver_msgs/PauseTwin``: pause true / false) — simulated time stops
  or runs (``~sim_time`` only);
- ``~sim/step`` (``jaka_driver_msgs/StepTwin``: cycles) — a paused twin runs that many 8 ms
  cycles (1–10000) and answers with the sim time after them.

Advertised only when the backend is a twin (``driver.twin.present``), the world acting on it:

- ``~sim/emergency_stop`` (SetBool: true presses, false releases), ``~sim/protective_stop``
  (Trigger), ``~sim/set_input`` (jaka_msgs/SetIO on the model's inputs: signal, type, index,
  value) — fault injection;
- ``~sim/push_tool`` (``jaka_driver_msgs/PushTool``) — an operator's hand on the tool: a wrench
  along the base's axes for a duration (what a force/torque sensor, tool drive and constant
  force react to);
- ``~sim/snapshot`` (std_srvs/Trigger) — a PNG of the twin as it stands now, written to the
  file named by the private parameter ``~snapshot_path``, read at every call (``rosparam set
  /jaka_driver/snapshot_path /tmp/arm.png`` redirects the next one); by default
  ``$ROS_HOME/<node name>_snapshot.png``. The answer's ``message`` is the path written, or why
  nothing was (:mod:`.twin_snapshot`).
"""
from __future__ import annotations

import os
from pathlib import Path

import rospy
from std_srvs.srv import SetBool, SetBoolResponse, Trigger, TriggerResponse

from jaka_driver_msgs import srv as msgs
from jaka_msgs import srv as jaka

from ..driver import RobotDriver
from .force_topics import wrench_values
from .service_answers import answer_with, logged
from .twin_snapshot import SnapshotWorker, default_path


def advertise_twin(driver: RobotDriver, after_reset=lambda: None) -> list:
    """Every ``~sim/`` service the backend can serve (see the module); ``after_reset()``: what
    the node republishes after a reset (the latched speed ratio)."""
    twin = driver.twin

    def reset(req):
        result = twin.reset(list(req.joints))
        rospy.loginfo("sim/reset: %s", result.message)
        if result.ok:
            after_reset()
        return msgs.ResetTwinResponse(ret=int(result.code), message=result.message)

    def pause(req):
        result = twin.pause(req.pause)
        return msgs.PauseTwinResponse(ret=int(result.code), message=result.message)

    def step(req):
        result = twin.step(req.cycles)
        sim_time = float(result.value) if result.ok else \
            (driver.clock.now() if driver.clock.simulated else 0.0)
        return msgs.StepTwinResponse(ret=int(result.code), message=result.message,
                                     sim_time=sim_time)

    services = [rospy.Service("~sim/reset", msgs.ResetTwin, reset),
                rospy.Service("~sim/pause", msgs.PauseTwin, pause),
                rospy.Service("~sim/step", msgs.StepTwin, step)]
    if twin.present:
        services += _world_on_the_twin(driver)
    return services


def _world_on_the_twin(driver: RobotDriver) -> list:
    """The faults, inputs, hand and camera of a twin."""
    twin = driver.twin

    def emergency_stop(req):
        result = twin.emergency_stop(req.data)
        rospy.logwarn("sim: %s", result.message)
        return SetBoolResponse(success=result.ok, message=result.message)

    def protective_stop(_req):
        result = twin.protective_stop()
        rospy.logwarn("sim: %s", result.message)
        return TriggerResponse(success=result.ok, message=result.message)

    def set_input(req):
        result = twin.set_input(req.signal, req.type, req.index, req.value)
        return jaka.SetIOResponse(ret=int(result.code), message=result.message)

    pushed = answer_with(msgs.PushToolResponse)

    def push_tool(req):
        return pushed(twin.push_tool(wrench_values(req.wrench), req.duration))

    worker = SnapshotWorker(driver)

    def snapshot(_req):
        # Absolute in the answer: roslaunch runs nodes in $ROS_HOME, not the caller's folder.
        path = os.path.abspath(Path(str(rospy.get_param("~snapshot_path", "")
                                        or default_path())).expanduser())
        ok, message = worker.take(path)
        if not ok:
            rospy.logwarn("sim/snapshot: %s", message)
        return TriggerResponse(success=ok, message=message)

    return [rospy.Service("~sim/emergency_stop", SetBool, emergency_stop),
            rospy.Service("~sim/protective_stop", Trigger, protective_stop),
            rospy.Service("~sim/set_input", jaka.SetIO, set_input),
            rospy.Service("~sim/push_tool", msgs.PushTool, logged("sim/push_tool", push_tool)),
            rospy.Service("~sim/snapshot", Trigger, snapshot)]
