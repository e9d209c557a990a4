"""The emulator's controller rules as the executor of a program's steps: the twin's program
engine (:class:`~jaka_driver.programs.FolderPrograms`, docs/programs.md) runs the emulator's
programs, and each step is checked and carried out as this controller carries out the command
it stands for (:mod:`.twin_controller`): a move only when the arm may move (powered, enabled,
no stop, not in drag or servo mode) and stands still, a joint target within the limits, an
output that exists. A refused step answers 2 with the controller's message; the engine then
stops the program with the step's line.

Units are the engine's (:class:`~jaka_driver.programs.Executor`): joints rad, rad/s, rad/s²;
poses mm + rotation vector (rad) of the active tool in the active user frame, mm/s, mm/s².
A move's pause, resume and stop are the twin's own (``pause_motion``, ``resume_motion``,
``stop_move``), handed to the step's :class:`~jaka_driver.programs.MoveHold`.
"""
from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from ..common.models import io_level
from ..common.results import Code, Result
from ..common.transforms import pose_mm_to_matrix
from ..programs.executor import MoveHold
from .replies import Rejected
from .twin_controller import TwinController

#: s between two looks at a step's move (the move's completion wakes the wait sooner)
LOOK = 0.1


class ControllerSteps:
    """:class:`~jaka_driver.programs.Executor` on a :class:`TwinController` (see the module)."""

    def __init__(self, controller: TwinController):
        self.c = controller
        self.backend = controller.backend
        self.clock = controller.backend.clock

    # ---- moves ----------------------------------------------------------------------------
    def joint_move(self, joints: Sequence[float], speed: float, accel: float,
                   hold: MoveHold) -> Result:
        q = np.asarray(joints, float)

        def start() -> Result:
            self.c.check_limits(q, "joint_move")
            return self.backend.start_joint_move(
                q, _positive(speed, "joint_move", "speed", "rad/s"),
                accel or self.c.model.default_joint_accel)
        return self._move("joint_move", start, hold)

    def linear_move(self, pose: Sequence[float], speed: float, accel: float,
                    hold: MoveHold) -> Result:
        def start() -> Result:
            return self.backend.start_linear_move(
                pose_mm_to_matrix(pose), _positive(speed, "moveL", "speed", "mm/s") / 1e3,
                self._tcp_accel(accel))
        return self._move("moveL", start, hold)

    def circular_move(self, mid: Sequence[float], end: Sequence[float], speed: float,
                      accel: float, turns: float, mode: int, hold: MoveHold) -> Result:
        def start() -> Result:
            return self.backend.start_circular_move(
                pose_mm_to_matrix(mid), pose_mm_to_matrix(end),
                _positive(speed, "movc", "speed", "mm/s") / 1e3, self._tcp_accel(accel),
                float(turns), int(mode))
        return self._move("movc", start, hold)

    def _tcp_accel(self, accel_mm: float) -> float:
        """m/s²: the step's mm/s², or the model's default for 0."""
        return accel_mm / 1e3 if accel_mm else self.c.model.default_tcp_accel

    def _move(self, what: str, start: Callable[[], Result], hold: MoveHold) -> Result:
        """Start the move under the controller's rules, then follow it to its end with the
        step's pause and stop switch attached."""
        c = self.c
        try:
            with c.lock:
                c.require_can_move(what, program_step=True)
                c.require_still(what)
                started = start()
        except Rejected as refused:
            return Result.failure(Code.CONTROLLER_REJECTED, refused.message)
        if not started.ok:
            return started
        completion = started.value[0]
        backend = self.backend
        hold.attach(backend.pause_motion, backend.resume_motion, backend.stop_move)
        try:
            while True:
                result = completion.wait(LOOK, self.clock)
                if result is not None:
                    return result
        finally:
            hold.detach()

    # ---- IO ---------------------------------------------------------------------------------
    def set_output(self, signal: str, io_type: int, index: int, value: float) -> Result:
        try:
            self.c.check_io(signal, io_type, 1, index, "set_output")
            self.c.set_output(signal, io_type, index, io_level(signal, value))
        except Rejected as refused:
            return Result.failure(Code.CONTROLLER_REJECTED, refused.message)
        return Result.success(f"{signal} output {index} of type {io_type} = {value:g}")

    def read_io(self, signal: str, path: int, io_type: int, index: int) -> Result:
        try:
            self.c.check_io(signal, io_type, path, index, "wait_input")
        except Rejected as refused:
            return Result.failure(Code.CONTROLLER_REJECTED, refused.message)
        return Result.success("", self.c.read_io(signal, path, io_type, index))


def _positive(value: float, what: str, field: str, unit: str) -> float:
    if not value > 0:
        raise Rejected(f"{what}: {field} is {value:g} {unit}, expected > 0")
    return float(value)
