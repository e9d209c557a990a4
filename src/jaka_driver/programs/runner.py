"""Running a program: play, pause, resume, stop, its state and current line, its user variables.

One thread runs the loaded program, step by step, through an :class:`~.executor.Executor`.
A controller's rules, as JAKA's programs follow them:

- **pause** holds the program where it is: between steps (the next one waits), inside a move
  (the arm comes to rest on the move's path: :class:`~.executor.MoveHold`), inside a wait (the
  time left is kept). **resume** continues from there; a paused move goes on to its own end.
- **stop** ends the program: a move under way is brought to rest, nothing more runs.
- **a failing step** (the executor refuses it, or it cannot be evaluated) ends the program;
  the state then carries its line and the executor's message.
- the **current line** is the 1-based line, in the program's file, of the step under way
  (0 while idle).

All waiting happens on the executor's clock (the twin's simulated time, or the wall clock), in
steps of one controller cycle while an input or a variable is polled. The program's thread
holds the clock while it runs (:meth:`SimClock.hold`, let go only while it waits on the
clock), as a request does: in simulated time each step — a move's start, an output, the end
of a ``wait``, each look at a ``wait_input``'s input — acts between two definite cycles, the
ones the program and its requests decide, never at one its thread's wake-up picks.
"""
from __future__ import annotations

import logging
import threading
from collections import deque
from typing import Callable, Optional

from ..backend.programs import ProgramState, ProgramStatus
from ..common.constants import SERVO_CYCLE
from ..common.results import Code, Result
from .executor import Executor, MoveHold
from .language import (COMPARISONS, MOVES, CircularMove, JointMove, LinearMove, Program,
                       Repeat, SetOutput, SetVariable, Statement, StepError, Wait, WaitInput,
                       WaitUntil, vector)
from .variables import UserVariables

log = logging.getLogger(__name__)

#: a loop that runs this many times without waiting for anything is taken for a runaway
#: program (a ``repeat forever`` of variable arithmetic): it is stopped
MAX_IDLE_STEPS = 100_000
#: s (wall) ``play`` waits for the program's thread to hold the clock
HOLD_WAIT = 1.0
#: s: a wait's remaining time at most this is done. Its time is counted in cycles of
#: 0.008 s, whose float sums leave remainders like 5.6e-17 s (``wait 0.2`` begun at cycle 95),
#: which the clock's wait answers at once, before any cycle: the program looped on it holding
#: time, and the twin stood still until the hold ran out (10 s of wall time).
TIME_EPSILON = 1e-9


class _Stopped(Exception):
    """The program was stopped: unwind."""


class ProgramRunner:
    """Runs one loaded :class:`~.language.Program` at a time on an executor."""

    def __init__(self, variables: UserVariables, executor: Optional[Executor] = None,
                 on_change: Callable[[ProgramStatus], None] = lambda status: None):
        """``on_change(status)`` is called with the status of every change of state or line,
        in the order they were made (from the program's thread or the caller's; it must not
        block)."""
        self.variables = variables
        self.executor = executor
        self._on_change = on_change
        self._lock = threading.Lock()
        self._changes: deque = deque()        # statuses of changes not yet announced
        self._announcing = threading.RLock()  # one thread hands them on at a time
        self._wake = threading.Event()        # a pause, resume or stop to look at
        self._program: Optional[Program] = None
        self._state = ProgramState.IDLE
        self._line = 0
        self._error = ""
        self._stop = False
        self._hold: Optional[MoveHold] = None  # the running move step's
        self._paused_at = 0.0                  # executor clock s of the last pause
        self._paused_total = 0.0               # executor clock s spent paused, all pauses
        self._thread: Optional[threading.Thread] = None
        self._holding = threading.Event()     # the program's thread holds the clock

    # ---- what callers see ------------------------------------------------------------------
    def status(self) -> ProgramStatus:
        with self._lock:
            return self._status()

    def _status(self) -> ProgramStatus:
        name = self._program.name if self._program is not None else ""
        return ProgramStatus(self._state, name, self._line, self._error)

    def _changed(self) -> None:
        """Keep the status of the change just made (the lock held): :meth:`_announce` hands it
        on. A status read when ``on_change`` runs instead could already be a later one: a play
        whose caller lost its core meanwhile was announced at line 1, after line 1's own."""
        self._changes.append(self._status())

    def _announce(self) -> None:
        """Hand every kept change to ``on_change``, in the order they were made, whichever
        thread made them (the lock not held: ``on_change`` may read the status)."""
        with self._announcing:
            while True:
                with self._lock:
                    if not self._changes:
                        return
                    status = self._changes.popleft()
                self._on_change(status)

    @property
    def state_now(self) -> ProgramState:
        """The state, without the lock (one attribute read): for a thread that must not wait."""
        return self._state

    def load(self, program: Program) -> Result:
        with self._lock:
            if self._state != ProgramState.IDLE:
                return Result.failure(Code.BUSY, f"load refused: program "
                                      f"{self._program.name!r} is {self._state.word} "
                                      "(stop it first)")
            self._program, self._error = program, ""
            self._changed()
        self.variables.declare(program.variables)
        self._announce()
        return Result.success(f"program {program.name!r} loaded ({_count(program)} steps, "
                              f"{len(program.variables)} variables)")

    def unload(self) -> None:
        """Forget the loaded program (only while none runs)."""
        with self._lock:
            if self._state == ProgramState.IDLE:
                self._program, self._error = None, ""
                self._changed()
        self._announce()

    def play(self) -> Result:
        with self._lock:
            if self.executor is None:
                return Result.failure(Code.WRONG_MODE, "play refused: no executor is bound "
                                      "to run program steps")
            if self._program is None:
                return Result.failure(Code.WRONG_MODE, "play refused: no program loaded "
                                      "(load one first)")
            if self._state != ProgramState.IDLE:
                return Result.failure(Code.BUSY, f"play refused: program "
                                      f"{self._program.name!r} is already {self._state.word}")
            if self._thread is not None and self._thread.is_alive():
                return Result.failure(Code.BUSY, "play refused: the last run is still "
                                      "ending")
            program = self._program
            self._state, self._error, self._stop, self._line = ProgramState.RUNNING, "", \
                False, 0
            self._holding.clear()
            self._changed()
            self._thread = threading.Thread(target=self._run, args=(program,),
                                            name="program-runner", daemon=True)
            self._thread.start()
        # Until the thread holds the clock, time must not run on without it (the play request
        # holds it meanwhile); bounded, a thread that never starts cannot freeze the caller.
        self._holding.wait(HOLD_WAIT)
        self._announce()
        return Result.success(f"program {program.name!r} running")

    def pause(self) -> Result:
        with self._lock:
            if self._state != ProgramState.RUNNING:
                return Result.failure(Code.WRONG_MODE, f"pause refused: no program running "
                                      f"(state {self._state.word})")
            self._state = ProgramState.PAUSED
            self._paused_at = self.executor.clock.now()
            hold, line = self._hold, self._line
            if hold is not None:
                hold.pause()              # the move under way comes to rest on its path
            self._wake.set()
            self._changed()
        self._announce()
        return Result.success(f"program paused at line {line}")

    def resume(self) -> Result:
        with self._lock:
            if self._state != ProgramState.PAUSED:
                return Result.failure(Code.WRONG_MODE, f"resume refused: no program paused "
                                      f"(state {self._state.word})")
            self._state = ProgramState.RUNNING
            self._paused_total += self.executor.clock.now() - self._paused_at
            hold, line = self._hold, self._line
            if hold is not None:
                hold.resume()
            self._wake.set()
            self._changed()
        self._announce()
        return Result.success(f"program resumed at line {line}")

    def stop(self) -> Result:
        with self._lock:
            if self._state == ProgramState.IDLE:
                return Result.success("no program running")
            self._stop = True
            hold = self._hold
            self._wake.set()
        if hold is not None:
            hold.stop()                   # the move under way ends (-12) and the run unwinds
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(5.0)
        return Result.success("program stopped")

    # ---- the program's thread ----------------------------------------------------------------
    def _run(self, program: Program) -> None:
        with self.executor.clock.hold(react=False):
            self._holding.set()
            self._run_holding(program)

    def _run_holding(self, program: Program) -> None:
        self._idle_steps = 0
        error = ""
        try:
            self._block(program.statements)
        except _Stopped:
            pass
        except _Failed as failed:
            error = str(failed)
            log.warning("program %r stopped: %s", program.name, error)
        except Exception as exc:  # noqa: BLE001 — a program must not take the driver down
            log.exception("program %r failed", program.name)
            error = f"line {self._line}: failed inside the driver: {exc!r}"
        with self._lock:
            self._state, self._line, self._error, self._hold = ProgramState.IDLE, 0, error, \
                None
            self._changed()
        self._announce()

    def _block(self, statements) -> None:
        for statement in statements:
            self._step(statement)

    def _step(self, statement: Statement) -> None:
        self._wait_while_paused()
        with self._lock:
            self._line = statement.line
            self._changed()
        self._announce()
        try:
            if isinstance(statement, Repeat):
                self._repeat(statement)
            elif isinstance(statement, MOVES):
                self._idle_steps = 0
                self._move(statement)
            else:
                self._other(statement)
        except StepError as exc:
            raise _Failed(statement.line, str(exc)) from None

    def _repeat(self, loop: Repeat) -> None:
        if loop.count is None:
            while True:
                self._block(loop.body)
                self._check_runaway(loop)
        count = loop.count.evaluate(self.variables.values())
        if count < 0 or count != int(count):
            raise StepError(f"repeat count is {count:g}, expected a whole number ≥ 0")
        for _ in range(int(count)):
            self._block(loop.body)
            self._check_runaway(loop)

    def _check_runaway(self, loop: Repeat) -> None:
        self._idle_steps += 1
        if self._idle_steps > MAX_IDLE_STEPS:
            raise _Failed(loop.line, f"the loop ran {MAX_IDLE_STEPS} times without moving or "
                          "waiting: stopped as a runaway")

    def _move(self, step) -> None:
        values = self.variables.values()
        hold = MoveHold()
        with self._lock:
            if self._stop:
                raise _Stopped()
            self._hold = hold
            if self._state == ProgramState.PAUSED:
                hold.pause()
        try:
            result = self._execute_move(step, values, hold)
        finally:
            with self._lock:
                self._hold = None
        if self._stop:
            raise _Stopped()
        if not result.ok:
            raise _Failed(step.line, f"{_word(step)} refused ({result.code}): "
                          f"{result.message}")

    def _execute_move(self, step, values, hold: MoveHold) -> Result:
        x = self.executor
        speed, accel = step.speed.evaluate(values), step.accel.evaluate(values)
        if isinstance(step, JointMove):
            return x.joint_move(vector(step.joints, values), speed, accel, hold)
        if isinstance(step, LinearMove):
            return x.linear_move(vector(step.pose, values), speed, accel, hold)
        mode = step.mode.evaluate(values)
        if mode != int(mode):
            raise StepError(f"mode is {mode:g}, expected a whole number 0–3")
        return x.circular_move(vector(step.mid, values), vector(step.end, values), speed,
                               accel, step.turns.evaluate(values), int(mode), hold)

    def _other(self, step) -> None:
        values = self.variables.values()
        if isinstance(step, SetOutput):
            self._idle_steps = 0
            result = self.executor.set_output(step.signal, step.io_type, step.index,
                                              step.value.evaluate(values))
            if not result.ok:
                raise _Failed(step.line, f"set_output refused ({result.code}): "
                              f"{result.message}")
        elif isinstance(step, SetVariable):
            self.variables.assign(step.variable.id, step.value.evaluate(values))
        elif isinstance(step, Wait):
            self._idle_steps = 0
            seconds = step.seconds.evaluate(values)
            if seconds < 0:
                raise StepError(f"wait is {seconds:g} s, expected ≥ 0")
            self._sleep(seconds)
        elif isinstance(step, (WaitInput, WaitUntil)):
            self._idle_steps = 0
            self._wait_for(step)

    # ---- waiting: on the executor's clock, paused time not counted ----------------------------
    def _wait_while_paused(self) -> None:
        while True:
            with self._lock:
                if self._stop:
                    raise _Stopped()
                if self._state != ProgramState.PAUSED:
                    return
                self._wake.clear()
            self.executor.clock.wait(self._wake, 1.0)

    def _sleep(self, seconds: float, until: Optional[Callable[[], bool]] = None) -> bool:
        """Wait ``seconds`` of running time (pauses not counted), looking at ``until()`` every
        cycle when given; True once it holds, False when the time ran out."""
        clock = self.executor.clock
        remaining = seconds
        while True:
            self._wait_while_paused()
            if until is not None and until():
                return True
            if remaining <= TIME_EPSILON:
                return False
            with self._lock:
                self._wake.clear()
            if self._stop:
                raise _Stopped()
            t0 = self._running_time()
            clock.wait(self._wake, min(remaining, SERVO_CYCLE) if until else remaining)
            remaining -= self._running_time() - t0

    def _running_time(self) -> float:
        """The executor's clock less every pause (s): what a wait counts."""
        now = self.executor.clock.now()
        with self._lock:
            paused = now - self._paused_at if self._state == ProgramState.PAUSED else 0.0
            return now - self._paused_total - paused

    def _wait_for(self, step) -> None:
        values = self.variables.values()
        target = step.value.evaluate(values)
        compare = COMPARISONS[step.op]
        timeout = None if step.timeout is None else step.timeout.evaluate(values)
        if timeout is not None and timeout < 0:
            raise StepError(f"timeout is {timeout:g} s, expected ≥ 0")
        if isinstance(step, WaitInput):
            what = (f"{step.signal} input {step.index} of "
                    f"{('cabinet', 'tool', 'extension')[step.io_type]} {step.op} {target:g}")

            def holds() -> bool:
                read = self.executor.read_io(step.signal, 0, step.io_type, step.index)
                if not read.ok:
                    raise _Failed(step.line, f"wait_input cannot read the input "
                                  f"({read.code}): {read.message}")
                return compare(float(read.value), target)
        else:
            what = f"{step.variable.alias} {step.op} {target:g}"

            def holds() -> bool:
                return compare(self.variables.values()[step.variable.id], target)
        if not self._sleep(float("inf") if timeout is None else timeout, holds):
            raise _Failed(step.line, f"timed out after {timeout:g} s waiting for {what}")


class _Failed(Exception):
    """A step failed: the program ends with this line and message."""

    def __init__(self, line: int, message: str):
        super().__init__(f"line {line}: {message}")


def _word(step) -> str:
    return {JointMove: "joint_move", LinearMove: "linear_move",
            CircularMove: "circular_move"}[type(step)]


def _count(program: Program) -> int:
    def steps(statements) -> int:
        return sum(1 + (steps(s.body) if isinstance(s, Repeat) else 0) for s in statements)
    return steps(program.statements)

