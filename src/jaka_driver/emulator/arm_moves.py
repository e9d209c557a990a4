"""The moves a JAKA controller queues, its jogs, ``stop_program`` and the programs it plays (a
part of :class:`~.twin_controller.TwinController`): each motion command is refused in the
wrong state (:class:`~.arm_rules.ArmRules`), then queued on the motion queue
(:mod:`.motion_queue`: acknowledged at once, run after the moves before it). SI units.
"""
from __future__ import annotations

import threading
from typing import Callable, Tuple

import numpy as np

from ..backend import Backend, Twin
from ..common.constants import MAX_TOOL_ROTATION_SPEED
from ..common.models import RobotModel
from ..common.results import CommandRefused, Result
from ..motion.circular_path import arc_through
from .motion_queue import MotionQueue
from .replies import ERROR_REFUSED, Rejected


class ArmMoves:
    """Queued moves, jogs, stop and the programs' play / resume / pause."""

    # set by TwinController.__init__
    backend: Backend
    twin: Twin
    model: RobotModel
    lock: threading.RLock
    queue: MotionQueue

    def joint_move(self, target: Callable[[], np.ndarray], speed: float, accel: float,
                   what: str = "joint_move") -> None:
        """Queue a joint move; ``target()`` gives its goal (rad) when its turn comes (so a
        relative move adds to where the move before it ended)."""
        with self.lock:
            self.require_can_move(what)
            if not self.moving:
                self.check_limits(target(), what)   # refuse at once what is known to be wrong
            self.queue.enqueue(what, lambda: self._start_joint_move(target(), speed, accel,
                                                                    what))

    def _start_joint_move(self, q: np.ndarray, speed: float, accel: float,
                          what: str) -> Result:
        self.check_limits(q, what)
        return self.backend.start_joint_move(q, speed, accel)

    def end_move(self, pose: np.ndarray, speed: float, accel: float) -> None:
        """Queue a joint-interpolated move to the Cartesian ``pose`` (4x4, m); the joints are
        solved when its turn comes, near where the move before it ended."""
        def target() -> np.ndarray:
            solution = self.backend.inverse_kinematics(pose, self.commanded_joints())
            if not solution.ok:
                raise Rejected(f"end_move: {solution.message}")
            return solution.value
        # Queued as a joint move: an unreachable pose is refused at once when idle, as a joint
        # target outside the limits is.
        self.joint_move(target, speed, accel, what="end_move")

    def linear_move(self, target: Callable[[], np.ndarray], speed: float, accel: float) -> None:
        """Queue a straight-line move; ``target()`` gives its pose (4x4, m) when its turn
        comes."""
        with self.lock:
            self.require_can_move("moveL")
            self.queue.enqueue("moveL", lambda: self.backend.start_linear_move(target(), speed,
                                                                               accel))

    def circular_move(self, poses: Callable[[], Tuple[np.ndarray, np.ndarray]], speed: float,
                      accel: float, turns: float, mode: int) -> None:
        """Queue a circular move (``movc``); ``poses()`` gives its (middle, end) poses (4x4, m)
        when its turn comes. The twin plans the exact arc and checks its whole path then; when
        the arm is idle, three points on one line or too many turns are refused at once, as a
        joint target outside the limits is."""
        with self.lock:
            self.require_can_move("movc")
            if not self.moving:
                mid, end = poses()
                try:
                    arc_through(self.commanded_tcp()[:3, 3], mid[:3, 3], end[:3, 3], turns)
                except CommandRefused as refusal:
                    raise Rejected(f"movc: {refusal.message}", ERROR_REFUSED) from None
            self.queue.enqueue("movc", lambda: self.backend.start_circular_move(
                *poses(), speed, accel, turns, mode))

    def jog(self, coord: int, axis: int, direction: int, speed: float) -> None:
        """Continuous jog; ``coord`` as the twin numbers it (0 joint, 1 base, 2 tool)."""
        with self.lock:
            self.require_can_move("jog")
            if coord == 0:
                speed = min(speed, float(self.model.max_velocity[axis]))
            elif axis < 3:
                speed = min(speed, self.model.max_tcp_speed)
            else:
                speed = min(speed, MAX_TOOL_ROTATION_SPEED)
            result = self.backend.jog(coord, axis, direction, speed)
            if not result.ok:
                raise Rejected(f"jog: {result.message}")

    def jog_stop(self) -> None:
        """``jog_mode`` 0 ends any jog: continuous ones brake, incremental and absolute ones
        (queued moves labelled ``jog``) are stopped with the queue."""
        with self.lock:
            self.backend.jog_stop()
            if self.queue.running_label == "jog" and self.moving:
                self.stop()

    def stop(self) -> None:
        """``stop_program``: the program (if one runs or is paused) ends, the queue is
        emptied, the arm decelerates to rest."""
        if self.program_running():
            # outside the lock: the program's step may be waiting for it to start its move
            self.programs.stop()
        with self.lock:
            self.queue.clear()
            self.backend.stop_move()

    def play_program(self) -> None:
        """Run the loaded program: the arm must be free to move and still."""
        with self.lock:
            self.require_can_move("play_program")
            self.require_still("play_program")
            self._program_answer("play_program", self.programs.play())

    def resume_program(self) -> None:
        with self.lock:
            self.require_can_move("resume_program", program_step=True)
            self._program_answer("resume_program", self.programs.resume())

    def pause_program(self) -> None:
        self._program_answer("pause_program", self.programs.pause())

    @staticmethod
    def _program_answer(what: str, result) -> None:
        if not result.ok:
            raise Rejected(f"{what}: {result.message}")
