"""What a program's steps are carried out by: the :class:`Executor` interface, and
:class:`MoveHold`, the pause and stop switch of the move a step runs.

On the twin the executor is the driver's door (RobotDriver, through
:class:`jaka_driver.driver.program_steps.ProgramSteps`): every step passes the same checks as
the service call it stands for. In the emulator it will be the emulator's controller rules.
The runner (:mod:`.runner`) knows nothing else of the robot.

Units are the driver's interface's (docs/interface.md): joints rad, rad/s, rad/s²; Cartesian
poses mm + rotation vector (rad) of the active tool in the active user frame, mm/s, mm/s²;
IO as ``set_io`` / ``get_io`` take it; time s of the executor's :attr:`Executor.clock`.
"""
from __future__ import annotations

import threading
from typing import Callable, ContextManager, Optional, Protocol, Sequence

from ..common.results import Result


class MoveHold:
    """A pause and stop switch for the move one program step runs. The runner pauses, resumes
    and stops it; whoever runs the move attaches the move's own pause, resume and stop to it
    while the move runs (:meth:`attach` … :meth:`detach`). A pause or a stop that comes before
    the move has started is kept and applied the moment it is attached, so no move slips
    through either."""

    def __init__(self):
        self._lock = threading.Lock()
        self._paused = False
        self._stopped = False
        self._move: Optional[tuple[Callable[[], Result], ...]] = None

    @property
    def paused(self) -> bool:
        return self._paused

    def attach(self, pause: Callable[[], Result], resume: Callable[[], Result],
               stop: Callable[[], Result]) -> None:
        """The move now running: ``pause()`` brings it to rest on its path, ``resume()``
        continues it, ``stop()`` ends it (its waiter answered -12)."""
        with self._lock:
            self._move = (pause, resume, stop)
            if self._stopped:
                stop()
            elif self._paused:
                pause()

    def detach(self) -> None:
        with self._lock:
            self._move = None

    def pause(self) -> None:
        with self._lock:
            self._paused = True
            if self._move is not None:
                self._move[0]()

    def resume(self) -> None:
        with self._lock:
            self._paused = False
            if self._move is not None:
                self._move[1]()

    def stop(self) -> None:
        with self._lock:
            self._stopped = True
            if self._move is not None:
                self._move[2]()


class StepClock(Protocol):
    """The executor's time (a backend clock: wall or the twin's simulated time)."""

    def now(self) -> float: ...

    def wait(self, event: threading.Event, timeout: float) -> bool: ...

    def hold(self, react: bool = True) -> ContextManager:
        """Time stands still while the calling thread is inside and not waiting on the clock
        (a no-op on the wall clock)."""


class Executor(Protocol):
    """Carries out program steps; every method answers a :class:`Result` (a failure stops the
    program with its line and message). Moves block until the move has ended and accept a
    :class:`MoveHold` the runner pauses, resumes and stops them with."""

    clock: StepClock

    def joint_move(self, joints: Sequence[float], speed: float, accel: float,
                   hold: MoveHold) -> Result:
        """Joint move to ``joints`` (rad) at ``speed`` rad/s, ``accel`` rad/s² (0: default)."""

    def linear_move(self, pose: Sequence[float], speed: float, accel: float,
                    hold: MoveHold) -> Result:
        """Straight line to ``pose`` (mm + rotation vector) at ``speed`` mm/s, ``accel``
        mm/s² (0: default)."""

    def circular_move(self, mid: Sequence[float], end: Sequence[float], speed: float,
                      accel: float, turns: float, mode: int, hold: MoveHold) -> Result:
        """Arc through ``mid`` to ``end`` (mm + rotation vector), as the ``circular_move``
        service."""

    def set_output(self, signal: str, io_type: int, index: int, value: float) -> Result:
        """Set an output, as ``set_io``."""

    def read_io(self, signal: str, path: int, io_type: int, index: int) -> Result:
        """Read an input (``path`` 0) or output (1), as ``get_io``; the value in
        ``Result.value``."""
