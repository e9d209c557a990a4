"""The twin's own controls for test suites, the driver's twin requests (RobotDriver's
``reset_twin``, ``pause_twin``, ``step_twin``):

- ``~sim/reset`` (``jaka_driver_msgs/ResetTwin``: joints rad, empty = home) — a fresh start
  there: errors and e-stop cleared, IO, frames, payload, collision level and speed ratio at their
  defaults, no motion (a waiting move answers -12);
- ``~sim/pause`` (``jaka_driver_msgs/PauseTwin``: pause true / false) — simulated time stops
  or runs (``~sim_time`` only);
- ``~sim/step`` (``jaka_driver_msgs/StepTwin``: cycles) — a paused twin runs that many 8 ms
  cycles (1–10000) and answers with the sim time after them.

Advertised on every backend, so that a suite run against a controller gets a clear refusal
(-9, "not a twin") instead of a missing service.
"""
from __future__ import annotations

import rospy

from jaka_driver_msgs.srv import (PauseTwin, PauseTwinResponse, ResetTwin, ResetTwinResponse,
                                  StepTwin, StepTwinResponse)

from ..driver import RobotDriver


def advertise_twin_control(driver: RobotDriver, after_reset=lambda: None) -> list:
    """``after_reset()``: what the node republishes after a reset (the latched speed ratio)."""
    def reset(req):
        result = driver.reset_twin(list(req.joints))
        rospy.loginfo("sim/reset: %s", result.message)
        if result.ok:
            after_reset()
        return ResetTwinResponse(ret=int(result.code), message=result.message)

    def pause(req):
        result = driver.pause_twin(req.pause)
        return PauseTwinResponse(ret=int(result.code), message=result.message)

    def step(req):
        result = driver.step_twin(req.cycles)
        sim_time = float(result.value) if result.ok else \
            (driver.clock.now() if driver.clock.simulated else 0.0)
        return StepTwinResponse(ret=int(result.code), message=result.message, sim_time=sim_time)

    return [rospy.Service("~sim/reset", ResetTwin, reset),
            rospy.Service("~sim/pause", PauseTwin, pause),
            rospy.Service("~sim/step", StepTwin, step)]
