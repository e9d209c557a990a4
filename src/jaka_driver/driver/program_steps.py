"""The driver as the executor of a program's steps (:class:`jaka_driver.programs.executor.Executor`)
on a backend that runs the driver's program engine (the twin: ``backend.programs``).

Every step is the service call it stands for, through RobotDriver's door — the same field,
state and whole-path checks, the same planned duration and overrun rule — with the program's
pause and stop switch (:class:`~jaka_driver.programs.executor.MoveHold`) handed to the move. A program's
poses are mm + rotation vector whatever ``~conventions`` says (docs/programs.md): they are
turned into the reading the driver was built with before they go in.

:class:`PausedTime`: how long a move has stood paused, so that the overrun rule does not count
it (:meth:`.moves.MoveRequests.run_move`).
"""
from __future__ import annotations

from typing import Optional, Sequence

from ..common.results import Result
from ..common.transforms import pose_mm_to_matrix
from ..conventions import cartesian
from ..programs.executor import MoveHold


class ProgramSteps:
    """:class:`~jaka_driver.programs.executor.Executor` on a RobotDriver (handed in: the
    driver builds this, so it is not imported here)."""

    def __init__(self, driver):
        self._driver = driver
        self.clock = driver.clock

    def _pose(self, pose_mm_rotvec: Sequence[float]):
        """A program's pose (mm + rotation vector) in the driver's reading of poses."""
        return cartesian.matrix_to_pose_mm(self._driver.conventions,
                                           pose_mm_to_matrix(pose_mm_rotvec))

    def joint_move(self, joints, speed, accel, hold: MoveHold) -> Result:
        return self._driver.joint_move(joints, speed, accel, hold=hold)

    def linear_move(self, pose, speed, accel, hold: MoveHold) -> Result:
        return self._driver.linear_move(self._pose(pose), speed, accel, hold=hold)

    def circular_move(self, mid, end, speed, accel, turns, mode, hold: MoveHold) -> Result:
        return self._driver.circular_move(self._pose(mid), self._pose(end), speed, accel,
                                          turns, mode, hold=hold)

    def set_output(self, signal, io_type, index, value) -> Result:
        return self._driver.set_io(signal, io_type, index, value)

    def read_io(self, signal, path, io_type, index) -> Result:
        return self._driver.get_io(signal, path, io_type, index)


class PausedTime:
    """Time (s of ``clock``) a move has stood paused: from each pause its backend accepted to
    the resume after it."""

    def __init__(self, clock):
        self._clock = clock
        self._total = 0.0
        self._since: Optional[float] = None

    def began(self, result: Result) -> Result:
        if result.ok and self._since is None:
            self._since = self._clock.now()
        return result

    def ended(self, result: Result) -> Result:
        if self._since is not None:
            self._total += self._clock.now() - self._since
            self._since = None
        return result

    def total(self) -> float:
        since = self._since
        return self._total + (self._clock.now() - since if since is not None else 0.0)

    def describe(self) -> str:
        total = self.total()
        return f", {total:.2f} s of it paused" if total > 0.0 else ""
