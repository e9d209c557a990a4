"""Robot programs from ROS, through RobotDriver's program methods whatever the backend
(docs/interface.md, "Programs"; the twin's format: docs/programs.md):

- services ``~program/load`` (``LoadProgram``: name), ``~program/loaded``
  (``GetLoadedProgram``), ``~program/play``, ``~program/pause``, ``~program/resume``,
  ``~program/stop`` (``ProgramCommand``), ``~program/get_variables``
  (``GetProgramVariables``), ``~program/set_variable`` (``SetProgramVariable``: id, value,
  alias) — every one answers ``ret`` and ``message``;
- the latched topic ``~program/state`` (``jaka_driver_msgs/ProgramState``: state, its name,
  the loaded program, the current line, the last run's error), published on every change
  (looked at every 20 ms of wall time: also while a twin's simulated time is paused).
"""
from __future__ import annotations

import threading
import time

import rospy

from jaka_driver_msgs.msg import ProgramState
from jaka_driver_msgs.srv import (GetLoadedProgram, GetLoadedProgramResponse,
                                  GetProgramVariables, GetProgramVariablesResponse, LoadProgram,
                                  LoadProgramResponse, ProgramCommand, ProgramCommandResponse,
                                  SetProgramVariable, SetProgramVariableResponse)

from ..backend import ProgramStatus
from ..driver import RobotDriver
from ..host import realtime
from .service_answers import answer_with as _ret, logged as _logged

#: s (wall) between two looks at the program's state
POLL = 0.02


def state_message(status: ProgramStatus) -> ProgramState:
    return ProgramState(state=int(status.state), state_name=status.state.word,
                        name=status.name, line=status.line, error=status.error)


def advertise_programs(driver: RobotDriver) -> list:
    """The program services and the state topic (the topic's thread starts here)."""
    command = _ret(ProgramCommandResponse)

    def loaded(_req):
        result = driver.programs.loaded()
        return GetLoadedProgramResponse(name=(result.value or "") if result.ok else "",
                                        ret=int(result.code), message=result.message)

    def variables(_req):
        result = driver.programs.variables()
        listed = result.value if result.ok else []
        return GetProgramVariablesResponse(id=[v.id for v in listed],
                                           value=[v.value for v in listed],
                                           alias=[v.alias for v in listed],
                                           ret=int(result.code), message=result.message)

    table = [
        ("program/load", LoadProgram, lambda r: _ret(LoadProgramResponse)(
            driver.programs.load(r.name))),
        ("program/play", ProgramCommand, lambda r: command(driver.programs.play())),
        ("program/pause", ProgramCommand, lambda r: command(driver.programs.pause())),
        ("program/resume", ProgramCommand, lambda r: command(driver.programs.resume())),
        ("program/stop", ProgramCommand, lambda r: command(driver.programs.stop())),
        ("program/set_variable", SetProgramVariable, lambda r: _ret(SetProgramVariableResponse)(
            driver.programs.set_variable(r.id, r.value, r.alias))),
    ]
    services = [rospy.Service(f"~{name}", srv, _logged(name, handler))
                for name, srv, handler in table]
    services += [rospy.Service("~program/loaded", GetLoadedProgram, loaded),
                 rospy.Service("~program/get_variables", GetProgramVariables, variables)]
    ProgramStatePublisher(driver)
    return services


class ProgramStatePublisher:
    """``~program/state``, latched: the state as it is now, and again at every change."""

    def __init__(self, driver: RobotDriver):
        self._driver = driver
        self._pub = rospy.Publisher("~program/state", ProgramState, queue_size=10, latch=True)
        threading.Thread(target=self._run, name="program-state", daemon=True).start()

    @realtime.runs_periodically
    def _run(self) -> None:
        last = None
        while not rospy.is_shutdown():
            try:
                status = self._driver.programs.status()
                if status != last:
                    self._pub.publish(state_message(status))
                    last = status
            except Exception as exc:  # noqa: BLE001 — the topic must outlive a bad read
                rospy.logerr_throttle(10.0, f"program state failed: {exc!r}")
            time.sleep(POLL)
