"""Robot programs from ROS, through RobotDriver's program methods whatever the backend
(docs/interface.md, "Programs"; the twin's format: docs/programs.md):

- services ``~program/load`` (``LoadProgram``: name), ``~program/loaded``
  (``GetLoadedProgram``), ``~program/play``, ``~program/pause``, ``~program/resume``,
  ``~program/stop`` (``ProgramCommand``), ``~program/get_variables``
  (``GetProgramVariables``), ``~program/set_variable`` (``SetProgramVariable``: id, value,
  alias) — every one answers ``ret`` and ``message``;
- the latched topic ``~program/state`` (``jaka_driver_msgs/ProgramState``: state, its name,
  the loaded program, the current line, the last run's error), published on every change:
  each one as the twin's program engine makes it; a controller's looked at every 20 ms of
  wall time.
"""
from __future__ import annotations

import threading
import time
from collections import deque

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
    """``~program/state``, latched: the state as it is now, and again at every change.

    Where the backend reports each change as it happens (the twin's program engine,
    :meth:`ProgramRequests.watch <jaka_driver.driver.program_requests.ProgramRequests.watch>`) every one is published, in order: a program that runs
    several lines between two looks still shows each, so the topic is the same in every run
    of a sim-time scenario. Otherwise (a controller's programs) it looks every ``POLL`` s of
    wall time and publishes what changed."""

    def __init__(self, driver: RobotDriver):
        self._driver = driver
        # every change is queued here first: room for a burst of lines
        self._pub = rospy.Publisher("~program/state", ProgramState, queue_size=100, latch=True)
        self._pending: deque[ProgramStatus] = deque()
        self._wake = threading.Event()
        watched = driver.programs.watch(self._changed)
        threading.Thread(target=self._run, args=(watched,), name="program-state",
                         daemon=True).start()

    def _changed(self, status: ProgramStatus) -> None:
        """From the thread that changed it: queue, never block."""
        self._pending.append(status)
        self._wake.set()

    def _next(self, watched: bool) -> list[ProgramStatus]:
        if not watched:
            time.sleep(POLL)
            return [self._driver.programs.status()]
        self._wake.wait(1.0)
        self._wake.clear()
        changes = []
        while self._pending:
            changes.append(self._pending.popleft())
        return changes

    @realtime.runs_periodically
    def _run(self, watched: bool) -> None:
        last = None
        changes = [self._driver.programs.status()]
        while not rospy.is_shutdown():
            try:
                for status in changes:
                    if status != last:
                        self._pub.publish(state_message(status))
                        last = status
            except Exception as exc:  # noqa: BLE001 — the topic must outlive a bad read
                rospy.logerr_throttle(10.0, f"program state failed: {exc!r}")
            changes = self._next(watched)
