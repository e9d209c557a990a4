"""The program engine (jaka_driver.programs) on a fake executor and a clock the test moves by hand:
steps run in order through the executor with the values the program computes; pause inside a
move pauses that move (its hold) and resume continues it; pause between steps and inside a wait
holds the program there (a wait's time left kept); stop ends it (the move under way stopped, the
rest not run); a failing step ends it with its line and the executor's message; variables set
from outside are seen by the program; loops run their count (a variable's too)."""
from __future__ import annotations

import contextlib
import threading
import time

import pytest

from support.ros_harness import wait_until

from jaka_driver.backend.clock import SimClock
from jaka_driver.backend.programs import ProgramState, ProgramStatus
from jaka_driver.common.results import Code, Result
from jaka_driver.programs import MoveHold, ProgramRunner, UserVariables, parse


class HandClock:
    """Time that moves only when the test says (``advance``); waiters wake on their event or
    when time passes their deadline."""

    def __init__(self):
        self.t = 0.0
        self.waiting = 0                 # threads inside wait()
        self._cond = threading.Condition()

    def now(self) -> float:
        return self.t

    def advance(self, dt: float) -> None:
        """Once the runner waits on this clock (so that it has read the time it waits
        from), move time on by ``dt``."""
        assert wait_until(lambda: self.waiting, 5.0)
        with self._cond:
            self.t += dt
            self._cond.notify_all()

    def hold(self, react: bool = True):
        """The program's thread holds time while it runs: this clock moves only by hand."""
        return contextlib.nullcontext()

    def wait(self, event: threading.Event, timeout: float) -> bool:
        with self._cond:
            deadline = self.t + timeout
            self.waiting += 1
            while not event.is_set() and self.t < deadline:
                self._cond.wait(0.005)
            self.waiting -= 1
        return event.is_set()


class Move:
    """One move the fake executor is running: the test ends it (``finish``)."""

    def __init__(self, kind, args):
        self.kind, self.args = kind, args
        self.log: list[str] = []
        self.done = threading.Event()
        self.result = Result.success(f"{kind} done")

    def finish(self, result: Result | None = None):
        if result is not None:
            self.result = result
        self.done.set()


class FakeExecutor:
    def __init__(self):
        self.clock = HandClock()
        self.moves: list[Move] = []
        self.outputs: list[tuple] = []
        self.inputs: dict = {}
        self.refuse: dict = {}              # kind → Result to answer instead
        self.stops = 0

    def _move(self, kind, args, hold) -> Result:
        if kind in self.refuse:
            return self.refuse[kind]
        move = Move(kind, args)
        self.moves.append(move)
        hold.attach(lambda: move.log.append("paused") or Result.success("p"),
                    lambda: move.log.append("resumed") or Result.success("r"),
                    lambda: self._stop(move))
        move.done.wait(10.0)
        return move.result

    def joint_move(self, joints, speed, accel, hold):
        return self._move("joint_move", (joints, speed, accel), hold)

    def linear_move(self, pose, speed, accel, hold):
        return self._move("linear_move", (pose, speed, accel), hold)

    def circular_move(self, mid, end, speed, accel, turns, mode, hold):
        return self._move("circular_move", (mid, end, speed, accel, turns, mode), hold)

    def set_output(self, signal, io_type, index, value):
        if "set_output" in self.refuse:
            return self.refuse["set_output"]
        self.outputs.append((signal, io_type, index, value))
        return Result.success("set")

    def read_io(self, signal, path, io_type, index):
        return Result.success("read", self.inputs.get((signal, io_type, index), 0.0))

    def _stop(self, move):
        self.stops += 1
        move.finish(Result.failure(Code.MOTION_STOPPED, "stopped by stop_move"))
        return Result.success("stopping")


THREE_MOVES = """\
# three moves and an output
var 1 speed = 0.5
joint_move [0, 1.5708, -1.5708, 1.5708, 1.5708, 0] speed speed * 2
linear_move [482, 114, 443, 2.2214, -2.2214, 0] speed 100 accel 500
set_output digital cabinet 3 = 1
circular_move mid [562, 194, 443, 2.2214, -2.2214, 0] end [642, 114, 443, 2.2214, -2.2214, 0] speed 50 turns 0.5 mode 3
"""


@pytest.fixture
def engine():
    executor = FakeExecutor()
    runner = ProgramRunner(UserVariables(), executor)
    yield runner, executor
    runner.stop()
    for move in executor.moves:
        move.finish()


def running_move(executor: FakeExecutor, n: int) -> Move:
    assert wait_until(lambda: len(executor.moves) >= n, 5.0), len(executor.moves)
    return executor.moves[n - 1]


def ended(runner: ProgramRunner) -> bool:
    return wait_until(lambda: runner.status().state == ProgramState.IDLE, 5.0)


def test_a_three_move_program_runs_its_steps_in_order_with_its_values(engine):
    runner, executor = engine
    assert runner.load(parse(THREE_MOVES, "three")).ok
    assert runner.play().ok
    first = running_move(executor, 1)
    assert runner.status() == ProgramStatus(ProgramState.RUNNING, "three", 3, "")
    assert first.kind == "joint_move" and first.args[1] == 1.0       # speed * 2
    first.finish()
    running_move(executor, 2).finish()
    third = running_move(executor, 3)
    assert executor.outputs == [("digital", 0, 3, 1.0)]
    assert third.kind == "circular_move" and third.args[4:] == (0.5, 3)
    assert runner.status().line == 6
    third.finish()
    assert ended(runner)
    assert runner.status() == ProgramStatus(ProgramState.IDLE, "three", 0, "")


def test_pause_inside_a_move_pauses_that_move_and_resume_continues_it(engine):
    runner, executor = engine
    runner.load(parse(THREE_MOVES, "three"))
    runner.play()
    move = running_move(executor, 1)
    assert runner.pause().ok
    assert runner.status().state == ProgramState.PAUSED and runner.status().line == 3
    assert move.log == ["paused"]
    assert runner.pause().code == Code.WRONG_MODE                     # not running
    assert runner.resume().ok
    assert move.log == ["paused", "resumed"]
    move.finish()
    assert running_move(executor, 2).kind == "linear_move"


def test_a_pause_or_stop_before_the_move_has_started_reaches_the_move_when_it_starts():
    hold, log = MoveHold(), []
    hold.pause()                                 # the step's move is not running yet
    hold.attach(lambda: log.append("paused"), lambda: log.append("resumed"),
                lambda: log.append("stopped"))
    assert log == ["paused"]
    hold.resume()
    hold.detach()
    hold.pause()                                 # after the move: nothing to pause
    assert log == ["paused", "resumed"]
    stopped, log = MoveHold(), []
    stopped.stop()
    stopped.attach(lambda: log.append("paused"), lambda: log.append("resumed"),
                   lambda: log.append("stopped"))
    assert log == ["stopped"]


def test_pause_between_steps_holds_the_next_step_until_resume(engine):
    runner, executor = engine
    runner.load(parse("wait 1\njoint_move [0, 0, 0, 0, 0, 0] speed 1\n", "p"))
    runner.play()
    assert wait_until(lambda: runner.status().line == 1, 5.0)
    runner.pause()
    executor.clock.advance(5.0)                # far beyond the wait: paused time not counted
    assert not wait_until(lambda: executor.moves, 0.2)
    runner.resume()
    assert not wait_until(lambda: executor.moves, 0.2)   # the second still to wait
    executor.clock.advance(1.0)
    running_move(executor, 1).finish()
    assert ended(runner)


def test_a_wait_keeps_its_time_left_across_a_pause(engine):
    runner, executor = engine
    runner.load(parse("wait 2\njoint_move [0, 0, 0, 0, 0, 0] speed 1\n", "w"))
    runner.play()
    assert wait_until(lambda: runner.status().line == 1, 5.0)
    executor.clock.advance(1.5)
    assert not wait_until(lambda: executor.moves, 0.2)
    runner.pause()
    executor.clock.advance(10.0)
    runner.resume()
    assert not wait_until(lambda: executor.moves, 0.2)    # 0.5 s of the wait left
    executor.clock.advance(0.6)
    running_move(executor, 1).finish()


def test_a_wait_on_the_twins_clock_ends_on_its_cycle_whatever_cycle_it_began_at():
    """``wait 0.2`` begun at cycle 95 of 8 ms: 25 cycles later (the float sums of the cycles
    leave 5.6e-17 s, which once kept the program looping, holding time, until the clock's
    hold limit let it run on 10 s later)."""
    clock, quit_ = SimClock(0.008, real_time_factor=0), threading.Event()
    clock.pause()

    def physics():
        while clock.wait_for_cycle(quit_):
            clock.tick()

    thread = threading.Thread(target=physics, daemon=True)
    thread.start()
    executor = FakeExecutor()
    executor.clock = clock
    runner = ProgramRunner(UserVariables(), executor)
    try:
        assert clock.step(95, 5.0)
        runner.load(parse("wait 0.2\nset_output digital cabinet 3 = 1\n", "w"))
        assert runner.play().ok
        assert clock.step(24, 5.0) and executor.outputs == []
        assert clock.step(1, 5.0), "the program's wait kept holding time"
        assert ended(runner) and executor.outputs == [("digital", 0, 3, 1.0)]
        assert clock.cycles == 95 + 25
    finally:
        runner.stop()
        quit_.set()
        clock.unpause()
        thread.join(2.0)


def test_stop_ends_the_program_and_its_move_and_runs_nothing_more(engine):
    runner, executor = engine
    runner.load(parse(THREE_MOVES, "three"))
    runner.play()
    running_move(executor, 1)
    runner.pause()
    assert runner.stop().ok
    assert ended(runner)
    assert executor.stops == 1 and len(executor.moves) == 1 and not executor.outputs
    assert runner.status() == ProgramStatus(ProgramState.IDLE, "three", 0, "")   # stopped: no error
    assert runner.stop().ok                                         # nothing to stop


def test_a_failing_step_ends_the_program_with_its_line_and_message(engine):
    runner, executor = engine
    executor.refuse["linear_move"] = Result.failure(Code.IK_FAILED, "no IK solution at 40 %")
    runner.load(parse(THREE_MOVES, "three"))
    runner.play()
    running_move(executor, 1).finish()
    assert ended(runner)
    status = runner.status()
    assert status.error == "line 4: linear_move refused (-4): no IK solution at 40 %"
    assert not executor.outputs                 # nothing after the failing step


def test_a_step_that_cannot_be_evaluated_ends_the_program_there(engine):
    runner, executor = engine
    runner.load(parse("var 1 n = 0\nset n = 1 / n\n", "div"))
    runner.play()
    assert ended(runner)
    assert runner.status().error == "line 2: division by zero (1 / 0)"


def test_a_variable_set_from_outside_is_seen_by_the_program(engine):
    runner, executor = engine
    runner.load(parse("var 7 go = 0\nwait_until go == 1\nset_output digital tool 0 = go + 1\n",
                      "go"))
    assert [v.value for v in runner.variables.listed()] == [0.0]
    runner.play()
    assert wait_until(lambda: runner.status().line == 2, 5.0)
    executor.clock.advance(1.0)
    assert not executor.outputs
    assert runner.variables.set(7, 1.0, "").ok
    executor.clock.advance(0.01)
    assert wait_until(lambda: executor.outputs, 5.0)
    assert executor.outputs == [("digital", 1, 0, 2.0)]


def test_a_wait_with_a_timeout_that_runs_out_fails_with_what_it_waited_for(engine):
    runner, executor = engine
    runner.load(parse("wait_input digital cabinet 2 == 1 timeout 0.5\n", "t"))
    runner.play()
    assert wait_until(lambda: runner.status().line == 1, 5.0)
    executor.clock.advance(0.6)
    assert ended(runner)
    assert runner.status().error == ("line 1: timed out after 0.5 s waiting for digital input "
                                     "2 of cabinet == 1")


def test_a_loop_runs_its_count_and_reads_a_variable_count(engine):
    runner, executor = engine
    runner.load(parse("var 1 n = 3\nvar 2 k = 0\nrepeat n\n  set k = k + 1\n"
                      "  set_output analog cabinet 0 = k\nend\n", "loop"))
    runner.play()
    assert ended(runner)
    assert [o[3] for o in executor.outputs] == [1.0, 2.0, 3.0]
    assert runner.variables.values()[2] == 3.0
    assert runner.variables.set(1, 2, "").ok                  # the count from outside
    runner.play()
    assert ended(runner)
    assert [o[3] for o in executor.outputs] == [1.0, 2.0, 3.0, 4.0, 5.0]


def test_a_loop_without_moves_or_waits_is_stopped_as_a_runaway(engine):
    runner, executor = engine
    runner.load(parse("var 1 k = 0\nrepeat forever\n  set k = k + 1\nend\n", "spin"))
    runner.play()
    assert ended(runner)
    assert "line 2: the loop ran 100000 times without moving or waiting" in \
        runner.status().error


def test_play_load_pause_resume_are_refused_in_the_wrong_state(engine):
    runner, executor = engine
    assert runner.play().code == Code.WRONG_MODE                # nothing loaded
    runner.load(parse(THREE_MOVES, "three"))
    assert runner.resume().code == Code.WRONG_MODE
    runner.play()
    running_move(executor, 1)
    assert runner.play().code == Code.BUSY
    assert runner.load(parse(THREE_MOVES, "other")).code == Code.BUSY


class _LateCaller:
    """The play request's wait for the program's thread, 0.2 s late: its caller lost its core
    right after the program started (a loaded machine), while the program ran on."""

    def __init__(self, event: threading.Event):
        self._event = event

    def __getattr__(self, name):
        return getattr(self._event, name)

    def wait(self, timeout=None):
        time.sleep(0.2)
        return self._event.wait(timeout)


@pytest.mark.parametrize("caller", ["prompt", "late"])
def test_every_status_change_reaches_a_watcher_in_order(tmp_path, caller):
    """~program/state publishes from this feed: each line a program passes is seen, however
    fast the lines go by (a poll every 20 ms of wall time skipped some at real_time_factor 0),
    and however late the play request's own thread runs (its status was once read after the
    program had gone on: line 0 missing, found in a loaded clean-clone run)."""
    from jaka_driver.programs import FolderPrograms
    (tmp_path / "outputs.jdp").write_text("set_output digital cabinet 1 = 1\n"
                                          "set_output digital cabinet 2 = 1\n"
                                          "wait 0\n"
                                          "set_output digital cabinet 3 = 1\n")
    programs = FolderPrograms(str(tmp_path))
    executor = FakeExecutor()
    programs.bind(executor)
    if caller == "late":
        runner = programs._runner
        runner._holding = _LateCaller(runner._holding)
    seen: list[ProgramStatus] = []
    assert programs.watch(seen.append)
    assert programs.load("outputs").ok
    assert programs.play().ok
    assert wait_until(lambda: seen and seen[-1].state == ProgramState.IDLE
                      and len(executor.outputs) == 3, 5.0)
    running = [s.line for s in seen if s.state == ProgramState.RUNNING]
    assert running == [0, 1, 2, 3, 4], running            # play, then each line in order
    assert seen[0] == ProgramStatus(ProgramState.IDLE, "outputs")       # loaded
