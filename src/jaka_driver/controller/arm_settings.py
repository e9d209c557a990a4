"""The arm's settings on a controller: frames by id, payload, drag mode, collision
sensitivity, IO, errors and the speed ratio (``rapid_rate``). Each is confirmed as JAKA's SDK
confirms it — its get command read back every 100 ms for up to 1 s
(:meth:`.commander.Commander.settled`) — and then awaited in the status packets, so that
``state()`` agrees with the answer the moment it is given.

:class:`ArmSettings` is a part :class:`~.backend.ControllerBackend` is composed of; what it
works with is handed to it: the link's requests, the status view, the controller's frame
tables (:class:`~.frames_by_id.ControllerFrames`), what runs now and servo mode
(:class:`~.running_motion.RunningMotion`) and the backend's ``state()``. It keeps the rapid
rate last read back and the frame ids last set. Units as the backend's: m, kg, 4x4 poses; the
wire's mm where the commands take them.
"""
from __future__ import annotations

import logging
from typing import Callable

import numpy as np

from ..backend.robot_state import RobotState
from ..common.frames import TOOL, USER_FRAME
from ..common.results import Code, CommandRefused, Result
from ..common.transforms import matrix_to_pose_mm_rpy
from ..protocol import commands
from ..protocol.fields import Field
from ..protocol.status_packet import StatusPacket
from .commander import SETTLE_TIMEOUT, Commander, answers
from .frames_by_id import TABLE_SIZE, ControllerFrames
from .running_motion import RunningMotion
from .status_view import StatusView

log = logging.getLogger(__name__)

#: The highest frame id a controller stores (its tables hold ids 0-10; JAKA's SDK refuses 11).
MAX_FRAME_ID = TABLE_SIZE - 1
#: An analog output reads back as set within this (the wire carries 6 decimals).
ANALOG_READBACK_TOLERANCE = 1e-3
#: The get command of each (signal, path): path 0 input, 1 output.
IO_READS = {("digital", 0): commands.get_digital_input, ("digital", 1): commands.get_digital_output,
            ("analog", 0): commands.get_analog_input, ("analog", 1): commands.get_analog_output}
#: The rapid rate reads back as set within this (JAKA's SDK's tolerance)
RAPID_RATE_READBACK = 0.01
#: s a confirmed setting waits for a status packet that shows it: the controller has read it
#: back, so the stream shows it one packet later (8 or 30 ms) unless the host is slow to deliver
#: it — as long as JAKA's SDK allows the read-back itself, so that a loaded machine does not
#: leave ``state()`` disagreeing with the answer (a joint_move right after drag mode off was
#: refused "in drag mode" with 0.2 s, on a busy 2-core machine at 30 ms packets)
PACKET_CATCH_UP = SETTLE_TIMEOUT


class ArmSettings:
    """Frames, payload, drag mode, collision, IO, errors and the speed ratio of a controller
    (see the module): requests through ``send``, the latest packet from ``view``, the frame
    tables ``frames_by_id``, what runs and servo mode in ``motion``, the arm's ``state()``."""

    def __init__(self, send: Commander, view: StatusView, frames_by_id: ControllerFrames,
                 motion: RunningMotion, state: Callable[[], RobotState]):
        self.send = send
        self.view = view
        self.frames_by_id = frames_by_id
        self.motion = motion
        self.state = state
        self._rapid_rate = 1.0                  # the last rate read back
        self._ids = (0, 0)                      # (tool, user) last set, until a packet

    @answers
    def set_speed_ratio(self, ratio: float) -> Result:
        """``rapid_rate``, read back with ``get_rapid_rate`` until within 0.01, as JAKA's SDK
        confirms it."""
        ratio = float(ratio)
        self._rapid_rate = self.send.settled(
            commands.rapid_rate(ratio), commands.get_rapid_rate(), commands.reply_value,
            lambda now: abs(now - ratio) < RAPID_RATE_READBACK, f"rapid rate {ratio:g}")
        self._await_packet(lambda status: abs(status.rapidrate - ratio) < RAPID_RATE_READBACK)
        return Result.success(f"rapid rate {self._rapid_rate:g} (read back): moves and jogs at "
                              f"{self._rapid_rate * 100:g} % speed")

    def speed_ratio(self) -> float:
        """The rate the latest status packet reports (a pendant may change it), else the one
        last read back."""
        latest = self.view.latest
        if latest is not None and 0.0 < latest.rapidrate <= 1.0:
            return float(latest.rapidrate)
        return self._rapid_rate

    def read_rapid_rate(self) -> None:
        """The rate as the controller has it now (at every connection)."""
        try:
            self._rapid_rate = float(self.send.read(commands.get_rapid_rate(),
                                                    commands.reply_value))
        except CommandRefused as refusal:
            log.info("get_rapid_rate unavailable (%s); taking the rate from the status packets",
                     refusal.message)

    def frames(self) -> tuple[np.ndarray, np.ndarray]:
        latest = self.view.latest
        ids = (latest.current_tool_id, latest.current_user_id) if latest is not None \
            else self._ids
        return self.frames_by_id.table.active(*ids)

    @answers
    def set_tool_frame(self, tool_id, pose) -> Result:
        tool_id = _frame_id("tool_num", tool_id)
        self._set_frame(TOOL, tool_id, pose, commands.set_tool_offsets, commands.set_tool_id,
                        commands.get_curr_tool_id())
        self._ids = (tool_id, self._ids[1])
        return Result.success(f"tool {tool_id} set and active")

    @answers
    def set_user_frame(self, user_id, pose) -> Result:
        user_id = _frame_id("user_num", user_id)
        self._set_frame(USER_FRAME, user_id, pose, commands.set_user_offsets,
                        commands.set_user_id, commands.get_curr_user_id())
        self._ids = (self._ids[0], user_id)
        return Result.success(f"user frame {user_id} set and active")

    def _set_frame(self, kind: str, frame_id: int, pose, store, activate, current) -> None:
        """Store the offset (not for id 0, the flange / base itself), then activate the id and
        read the active id back as JAKA's SDK does."""
        if frame_id:
            name = f"jaka_driver_{kind.replace(' ', '_')}_{frame_id}"
            self.send.accepted(store(frame_id, matrix_to_pose_mm_rpy(pose), name))
            self.frames_by_id.keep(kind, frame_id, pose)
        else:
            self.frames_by_id.activating(kind, 0)
        self.send.settled(activate(frame_id), current, commands.reply_id,
                          lambda active: active == frame_id, f"{kind} {frame_id} active")
        self._await_packet(lambda status: (status.current_tool_id if kind == TOOL
                                           else status.current_user_id) == frame_id)

    @answers
    def set_payload(self, tool_id, mass, centroid) -> Result:
        tool_id = _frame_id("tool_num", tool_id)
        c_mm = np.asarray(centroid, float) * 1000.0
        self.frames_by_id.activating(TOOL, tool_id)
        self.send.settled(commands.set_tool_id(tool_id), commands.get_curr_tool_id(),
                          commands.reply_id, lambda active: active == tool_id,
                          f"tool {tool_id} active")
        self._await_packet(lambda status: status.current_tool_id == tool_id)
        self._ids = (tool_id, self._ids[1])
        self.send.accepted(commands.set_payload(float(mass), c_mm))
        return Result.success(f"payload {mass:g} kg at ({c_mm[0]:.1f}, {c_mm[1]:.1f}, "
                              f"{c_mm[2]:.1f}) mm; tool {tool_id} active")

    @answers
    def set_drag_mode(self, on: bool) -> Result:
        """``torque_control_enable``, confirmed by ``get_drag_status`` as JAKA's SDK confirms
        it; refused in servo mode (-9) and while the arm moves (-10), as on the twin."""
        on = bool(on)
        self.send.require_link()
        if on == self.state().drag_mode:
            return Result.success(f"drag mode already {'on' if on else 'off'}")
        if on:
            if self.motion.servo_mode:
                return Result.failure(Code.WRONG_MODE, "drag mode refused in servo mode")
            if self.motion.moving:
                return Result.failure(Code.BUSY, "drag mode refused while the arm moves")
        self.send.settled(commands.torque_control_enable(on), commands.get_drag_status(),
                          _drag_status, lambda now: now == on,
                          f"drag mode {'on' if on else 'off'}")
        self._await_packet(lambda status: status.drag_status == on)
        return Result.success(f"drag mode {'on' if on else 'off'}")

    def _await_packet(self, shows: Callable[[StatusPacket], bool]) -> None:
        """After a confirmed setting the status packets carry: wait (at most
        :data:`PACKET_CATCH_UP` s) for one that shows it, so that ``state()`` agrees with the
        answer the moment it is given (the next request's state checks read it)."""
        if not self.view.wait_until(shows, PACKET_CATCH_UP):
            log.debug("the status stream did not show the setting within %.2f s", PACKET_CATCH_UP)

    @answers
    def set_collision_level(self, level) -> Result:
        self.send.accepted(commands.set_clsn_sensitivity(int(level)))
        if level == 0:
            return Result.success("collision detection off")
        return Result.success(f"collision sensitivity level {level}")

    @answers
    def collision_level(self) -> Result:
        """``get_clsn_sensitivity`` → ``sensitivityLevel``, as JAKA's SDK reads it."""
        level = self.send.read(commands.get_clsn_sensitivity(), commands.reply_clsn_sensitivity)
        return Result.success("collision detection off" if level == 0 else
                              f"collision sensitivity level {level}", int(level))

    @answers
    def set_io(self, signal, io_type, index, value) -> Result:
        """Set an output and read it back as JAKA's SDK does (every 100 ms, up to 1 s)."""
        if signal == "digital":
            want = 1.0 if value else 0.0
            request = commands.set_digital_output(io_type, index, value)
        else:
            want = float(value)
            request = commands.set_analog_output(io_type, index, value)
        self.send.settled(request, IO_READS[(signal, 1)](io_type, index), commands.reply_value,
                          lambda now: abs(now - want) <= ANALOG_READBACK_TOLERANCE,
                          f"{signal} output {index} of type {io_type}")
        return Result.success(f"{signal} output {index} of type {io_type} = {value:g}")

    @answers
    def get_io(self, signal, path, io_type, index) -> Result:
        what = f"{signal} {'output' if path else 'input'} {index} of type {io_type}"
        value = self.send.read(IO_READS[(signal, path)](io_type, index), commands.reply_value)
        return Result.success(f"{what} = {value:g}", value)

    @answers
    def clear_error(self) -> Result:
        self.send.accepted(commands.clear_error())
        return Result.success("clear_error sent")


def _drag_status(reply) -> bool:
    return commands.reply_flag(reply, Field.STATUS)


def _frame_id(field: str, frame_id) -> int:
    """A tool or user frame id a controller stores: 0 (the flange / base) to
    :data:`MAX_FRAME_ID`. The driver's contract numbers tools up to 11 (JAKA's document);
    a controller's tables hold ids 0-10 and JAKA's SDK refuses 11, so 11 is refused here."""
    frame_id = int(frame_id)
    if not 0 <= frame_id <= MAX_FRAME_ID:
        raise CommandRefused(Code.INVALID_PARAMETER, f"{field} is {frame_id}: a JAKA controller "
                             f"stores frames 1-{MAX_FRAME_ID} (its tables hold ids "
                             f"0-{MAX_FRAME_ID}); choose one of those")
    return frame_id
