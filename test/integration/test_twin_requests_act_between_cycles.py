"""In simulated time a twin's own request — a fault, an input, a reset, a pause — arrives
between two cycles exactly as a move request does: one that comes while a cycle is being
stepped acts once that cycle has ended, never inside it.

The test plays the twin's physics loop itself (``wait_for_cycle``, one cycle, ``tick``; the
loop's thread is not started) and keeps a cycle "being stepped" for far longer than the
clock's wall-time slices, so the rule is checked without depending on how threads happen to
be scheduled (as test/unit/test_sim_clock_acts_between_cycles.py does for the clock alone).
Each request goes through RobotDriver, the node's only door to the twin.
"""
import threading
import time

import numpy as np
import pytest

from jaka_driver.common.models import load_model
from jaka_driver.driver import RobotDriver
from jaka_driver.sim import SimBackend

MODEL = load_model("zu5")
IN_CYCLE_S = 0.3    # wall s a cycle stays "being stepped": 6 of the clock's wall slices
TOOL = np.eye(4)
TOOL[2, 3] = 0.1


@pytest.fixture
def twin():
    """A driver on a twin in sim time whose cycles the test steps itself."""
    backend = SimBackend(MODEL, sim_time=True, real_time_factor=0)
    driver = RobotDriver(backend)
    yield driver
    driver.shutdown()


# request name → (what the request does, what shows it has acted); both on a RobotDriver
REQUESTS = {
    "joint_move": (lambda d: d.joint_move(MODEL.home + 0.2, 1.0, 2.0),
                   lambda d: d.backend.twin.motion_active),
    "emergency_stop": (lambda d: d.twin.emergency_stop(True), lambda d: d.state().emergency_stop),
    "protective_stop": (lambda d: d.twin.protective_stop(), lambda d: d.state().protective_stop),
    "set_input": (lambda d: d.twin.set_input("digital", 0, 2, 1),
                  lambda d: d.backend.get_io("digital", 0, 0, 2).value == 1.0),
    "reset_twin": (lambda d: d.twin.reset(), lambda d: d.state().tool_id == 0),
    "pause_twin": (lambda d: d.twin.pause(True), lambda d: d.clock.paused),
}


@pytest.mark.parametrize("name", list(REQUESTS))
def test_a_request_arriving_inside_a_cycle_acts_once_the_cycle_has_ended(twin, name):
    request, acted = REQUESTS[name]
    clock, physics = twin.clock, twin.backend._physics
    assert twin.backend.set_tool_frame(1, TOOL).ok        # something a reset undoes
    assert not acted(twin)
    quit_ = threading.Event()
    answers = []

    assert clock.wait_for_cycle(quit_)                    # cycle 0 starts being stepped...
    thread = threading.Thread(target=lambda: answers.append(request(twin)), daemon=True)
    thread.start()                                        # ...and the request arrives in it
    time.sleep(IN_CYCLE_S)
    assert thread.is_alive() and not acted(twin), f"{name} acted inside the cycle"
    physics.step_cycle()
    clock.tick()                                          # the cycle ends: time is 1 cycle

    if name == "joint_move":
        # a move is started, then waited for (time may run while it waits): stop it
        assert _until(lambda: acted(twin)), "the move did not start after the cycle"
        assert clock.cycles == 1
        assert twin.stop_move().ok
    thread.join(5.0)
    assert not thread.is_alive(), f"{name} still waits"
    assert acted(twin), f"{name} did not act after the cycle"
    assert clock.cycles == 1                              # no cycle ran meanwhile
    if name != "joint_move":
        assert answers[0].ok, answers[0].message


def _until(condition, timeout: float = 5.0) -> bool:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.005)
    return True

