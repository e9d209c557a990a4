"""RobotDriver is the one place a move is waited for: joint_move, linear_move and
follow_trajectory start the move on the backend, return what its completion says, stop a move
that overruns its plan (1.5 × planned + 2 s) or that the monitor objects to, and answer -12.
In-process, on a fake backend: no physics, no sockets, no rosmaster."""
from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from fake_backend import START, FakeBackend
from jaka_driver.common.constants import move_deadline
from jaka_driver.common.results import Code, Result
from jaka_driver.driver import RobotDriver
from support.ros_harness import wait_until

TARGET = START + np.array([0.3, 0, 0, 0, 0, 0])
MOVES = {
    "joint_move": lambda d: d.joint_move(TARGET, 1.0, 2.0),
    "linear_move": lambda d: d.linear_move([0, 0, 10.0, 0, 0, 0], 50.0, 200.0, coord_mode=2),
    "follow_trajectory": lambda d: d.follow_trajectory("a trajectory", lambda t, st: None),
}


def in_thread(fn):
    box = {}
    thread = threading.Thread(target=lambda: box.setdefault("result", fn()), daemon=True)
    thread.start()
    return thread, box


@pytest.mark.parametrize("move", MOVES)
def test_the_completion_s_result_is_the_answer(move):
    backend = FakeBackend(planned=5.0)
    driver = RobotDriver(backend)
    thread, box = in_thread(lambda: MOVES[move](driver))
    assert wait_until(lambda: backend.move is not None, 2.0)
    assert driver.moving
    backend.finish_move(Result.success("in position"))
    thread.join(2.0)
    assert box["result"].ok and "in position" in box["result"].message
    assert "stop_move" not in backend.names()
    assert not driver.moving


@pytest.mark.parametrize("move", MOVES)
def test_an_overrun_is_stopped_and_answered_minus_12(move):
    backend = FakeBackend(planned=0.1)   # deadline 1.5 × 0.1 + 2 = 2.15 s
    driver = RobotDriver(backend)
    t0 = time.monotonic()
    result = MOVES[move](driver)
    took = time.monotonic() - t0
    assert result.code == Code.MOTION_STOPPED
    assert "planned 0.10 s" in result.message and "allowed 2.15 s" in result.message
    assert backend.names()[-1] == "stop_move"
    # Wall clock: the fake backend has the wall clock (a unit test, no twin to own time).
    # Resolution µs; 0.05 s below for the deadline's own look period, 1.5 s above for the
    # stop's wait and a loaded machine — the bound checks the deadline is the one that acted.
    assert move_deadline(0.1) - 0.05 <= took < move_deadline(0.1) + 1.5


def test_the_monitor_s_objection_stops_the_trajectory_with_its_reason():
    backend = FakeBackend(planned=5.0)
    driver = RobotDriver(backend)
    seen = []

    def monitor(t, state):
        seen.append(t)      # objects on its 5th call: counted, not timed (wall clock)
        return "path tolerance of joint_1 exceeded" if len(seen) >= 5 else None

    result = driver.follow_trajectory("a trajectory", monitor, period=0.02)
    assert result.code == Code.MOTION_STOPPED
    assert result.message == "path tolerance of joint_1 exceeded"
    assert backend.names()[-1] == "stop_move"
    assert len(seen) == 5 and seen == sorted(seen)


def test_a_stop_move_ends_the_wait_with_minus_12():
    backend = FakeBackend(planned=5.0)
    driver = RobotDriver(backend)
    thread, box = in_thread(lambda: driver.joint_move(TARGET, 1.0, 2.0))
    assert wait_until(lambda: backend.move is not None, 2.0)
    assert driver.stop_move().ok
    thread.join(2.0)
    assert box["result"].code == Code.MOTION_STOPPED


def test_a_second_move_while_one_runs_is_refused_and_sent_nowhere():
    backend = FakeBackend(planned=5.0)
    driver = RobotDriver(backend)
    thread, box = in_thread(lambda: driver.joint_move(TARGET, 1.0, 2.0))
    assert wait_until(lambda: backend.move is not None, 2.0)
    for move in MOVES.values():
        refused = move(driver)
        assert refused.code == Code.BUSY and "another move is running" in refused.message
    assert backend.names() == ["start_joint_move"]
    backend.finish_move(Result.success("in position"))
    thread.join(2.0)


def test_a_backend_refusal_is_the_answer_without_waiting():
    backend = FakeBackend()
    backend.start_joint_move = lambda *a, **k: Result.failure(Code.IK_FAILED, "unreachable")
    driver = RobotDriver(backend)
    t0 = time.monotonic()
    result = driver.joint_move(TARGET, 1.0, 2.0)
    assert result.code == Code.IK_FAILED and time.monotonic() - t0 < 0.5
    assert not driver.moving

