"""Knowing when a move the controller accepted has ended.

A JAKA controller acknowledges ``joint_move``/``moveL`` as soon as it has queued the move
(docs/protocol.md, "Motion queue"); the end of the move shows as ``inpos`` turning true again,
in the status packets and in the reply to ``get_motion_state``, which the backend polls while it
waits (a controller whose status port stalls, or a status source polled slowly, must not make a
finished move look unfinished). A packet read before the command went out, or produced before
the controller started the move, still says ``inpos`` — so a watch counts a move as done only
when

* ``inpos`` is true after it has been seen false since the command, or
* ``inpos`` is true and the arm is already at the target (a move too short to show up in a
  packet, or no move at all).

A fault in the stream (e-stop, protective stop, controller error, power or enable lost) ends
the watch with -12; :meth:`MoveWatch.abort` ends it from outside (stop_move: -12; link lost:
-1). RobotDriver waits on ``completion``, at most ``constants.move_deadline`` of the move's
estimated duration (the controller does not say how long a move will take).
"""
from __future__ import annotations

import time
from typing import Callable, Optional

import numpy as np

from ..backend.completion import Completion
from ..common.constants import IN_POSITION
from ..common.results import Code, Result
from ..common.transforms import rotation_angle_between, rpy_to_matrix
from ..common.values import all_finite
from ..protocol.status_packet import StatusPacket

TCP_IN_POSITION_MM = 0.5  # mm, for recognising a linear move that had nothing to do
TCP_IN_POSITION_RAD = 2e-3

def fault_of(status: StatusPacket) -> Optional[str]:
    """Why the controller cannot be moving a commanded motion any more, or None."""
    if status.emergency_stop:
        return "emergency stop"
    if status.protective_stop:
        return f"protective stop ({status.errmsg})" if status.errmsg else "protective stop"
    if status.errcode != 0:
        return f"controller error {status.errcode:#x} {status.errmsg}".strip()
    if not status.powered:
        return "robot powered off"
    if not status.enabled:
        return "robot disabled"
    return None


def joints_at(target: np.ndarray, tolerance: float = IN_POSITION) -> Callable[[StatusPacket], bool]:
    """Predicate: every measured joint within ``tolerance`` rad of ``target`` (rad)."""
    goal_list = np.asarray(target, float).tolist()

    def at(status: StatusPacket) -> bool:
        q = status.joint_position
        return all_finite(q) and max(abs(a - b) for a, b in
                                     zip(np.asarray(q, float).tolist(), goal_list)) <= tolerance
    return at


def joint_error(target: np.ndarray) -> Callable[[StatusPacket], str]:
    """Describes how far the measured joints ended from ``target`` (rad)."""
    goal = np.asarray(target, float)

    def error(status: StatusPacket) -> str:
        return f"final error {float(np.max(np.abs(status.joint_position - goal))):.1e} rad"
    return error


def tcp_at(target_mm_rpy: np.ndarray) -> Callable[[StatusPacket], bool]:
    """Predicate: the reported TCP within 0.5 mm and 2 mrad of ``target`` (mm + RPY rad)."""
    goal = np.asarray(target_mm_rpy, float)
    goal_rotation = rpy_to_matrix(*goal[3:])


    def at(status: StatusPacket) -> bool:
        p = status.tcp_pose
        if not all_finite(p):
            return False
        return bool(np.linalg.norm(p[:3] - goal[:3]) <= TCP_IN_POSITION_MM
                    # Compare rotations, not angles: near ±π and at gimbal lock one rotation has many RPYs.
                and rotation_angle_between(rpy_to_matrix(*p[3:]), goal_rotation)
                <= TCP_IN_POSITION_RAD)
    return at


class MoveWatch:
    """Watches one accepted move. ``at_target(status)`` recognises the goal; with
    ``need_inpos`` False (servo streams, where ``inpos`` is not documented) arriving at the
    target is enough. Feed it every packet with :meth:`on_status`."""

    def __init__(self, label: str, at_target: Callable[[StatusPacket], bool],
                 need_inpos: bool = True,
                 final_error: Optional[Callable[[StatusPacket], str]] = None,
                 note: Optional[str] = None):
        self.label = label
        self._final_error = final_error
        self._note = note
        self.completion = Completion()
        self._at_target = at_target
        self._need_inpos = need_inpos
        self._seen_moving = False
        self._armed_at = time.time()
        self._packets_show_arrival = True
        self.started = time.monotonic()

    def arm(self, packets_show_arrival: bool = True) -> None:
        """Judge only packets read from now on (call just before sending the command).

        ``packets_show_arrival`` False: a packet at the target with ``inpos`` does not end a
        move in which no motion was seen; :meth:`on_motion_state` does. A packet read after
        the command went out can have been written before the controller took it, and an arm
        already at the target shows ``inpos`` there (on a busy machine the move was then
        judged done before the controller had started it, and the next command was refused
        as "moving"); a ``get_motion_state`` reply is written after the move was taken, on
        the same connection. Where the controller has no such command, packets must do."""
        self._armed_at = time.time()
        self._seen_moving = False
        self._packets_show_arrival = packets_show_arrival

    def on_status(self, status: StatusPacket, received: float) -> None:
        if self.completion.done or received < self._armed_at:
            return
        fault = fault_of(status)
        if fault is not None:
            self.completion.finish(Result.failure(Code.MOTION_STOPPED,
                                                  f"{self.label} stopped: {fault}"))
            return
        if self._need_inpos and not status.inpos:
            self._seen_moving = True
            return
        if self._seen_moving or (self._packets_show_arrival and self._at_target(status)):
            message = f"{self.label} done in {time.monotonic() - self.started:.3f} s"
            if self._final_error is not None:
                message += f", {self._final_error(status)}"
            if self._note is not None:
                message += f" ({self._note})"
            self.completion.finish(Result.success(message))

    def on_motion_state(self, inpos: bool, queued: int, latest=None) -> None:
        """A ``get_motion_state`` reply read after :meth:`arm`: ``inpos`` and the number of
        moves ``queued`` (waiting or running); ``latest`` is the newest (packet, received) pair,
        used to recognise a move that had nothing to do."""
        if self.completion.done:
            return
        if not inpos or queued > 0:
            self._seen_moving = True
            return
        fresh = latest is not None and latest[1] >= self._armed_at
        if self._seen_moving or (fresh and self._at_target(latest[0])):
            self.completion.finish(Result.success(
                f"{self.label} done in {time.monotonic() - self.started:.3f} s"))

    def abort(self, result: Result) -> None:
        self.completion.finish(result)
