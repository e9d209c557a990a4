"""The twin's own controls for test suites, on what only a twin can do (``backend.twin``):

- ``~sim/reset`` (``jaka_driver_msgs/ResetTwin``: joints rad, empty = home) — a fresh start
  there: errors and e-stop cleared, IO, frames, payload, collision level and speed ratio at their
  defaults, no motion (a waiting move answers -12);
- ``~sim/pause`` (``jaka_driver_msgs/PauseTwin``: pause true / false) — simulated time stops
  or runs (``~sim_time`` only);
- ``~sim/step`` (``jaka_driver_msgs/StepTwin``: cycles) — a paused twin runs that many 8 ms
  cycles and answers with the sim time after them.

Advertised on every backend, so that a suite run against a controller gets a clear refusal
(-9, "not a twin") instead of a missing service.
"""
from __future__ import annotations

import rospy

from jaka_driver_msgs.srv import (PauseTwin, PauseTwinResponse, ResetTwin, ResetTwinResponse,
                                  StepTwin, StepTwinResponse)

from ..common.results import Code, Result
from ..driver import RobotDriver

NOT_A_TWIN = Result.failure(Code.WRONG_MODE, "refused: this backend is a controller, not a "
                            "twin (reset, pause and step are the twin's own)")
#: the most cycles one step request runs (80 s of sim time)
MAX_STEP = 10000


def advertise_twin_control(driver: RobotDriver, after_reset=lambda: None) -> list:
    """``after_reset()``: what the node republishes after a reset (the latched speed ratio)."""
    twin = driver.backend.twin

    def reset(req):
        result = driver.reset_twin(list(req.joints))
        rospy.loginfo("sim/reset: %s", result.message)
        if result.ok:
            after_reset()
        return ResetTwinResponse(ret=int(result.code), message=result.message)

    def pause(req):
        if twin is None:
            result = NOT_A_TWIN
        else:
            result = twin.pause() if req.pause else twin.unpause()
        return PauseTwinResponse(ret=int(result.code), message=result.message)

    def step(req):
        if twin is None:
            result = NOT_A_TWIN
        elif not 1 <= req.cycles <= MAX_STEP:
            result = Result.failure(Code.INVALID_PARAMETER, f"cycles is {req.cycles}, expected "
                                    f"1–{MAX_STEP}")
        else:
            result = twin.step(req.cycles)
        sim_time = float(result.value) if result.ok else \
            (driver.clock.now() if driver.clock.simulated else 0.0)
        return StepTwinResponse(ret=int(result.code), message=result.message, sim_time=sim_time)

    return [rospy.Service("~sim/reset", ResetTwin, reset),
            rospy.Service("~sim/pause", PauseTwin, pause),
            rospy.Service("~sim/step", StepTwin, step)]
