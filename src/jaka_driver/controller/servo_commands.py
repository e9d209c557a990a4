"""Servo mode on a controller, and what runs in it: ``servo_move`` confirmed by
``is_in_servomove``, ``servo_j`` / ``servo_p`` targets (absolute, or a client's increments sent
relatively as JAKA's SDK sends them) and the velocity jog, a ``servo_j`` stream the driver
computes from a twist (:mod:`.twist_stream`: why not the protocol's ``jog``) — and the servo
filter those targets pass through (``set_servo_move_filter``, sent as JAKA's SDK writes it:
:mod:`jaka_driver.protocol.servo_filters`). JAKA's SDK has no command that reads the filter back
(it neither waits after setting one nor asks for it), so the filter reported is the one last
accepted by the controller, not one read back.

:class:`ServoCommands` is a part :class:`~.backend.ControllerBackend` is composed of; what it
works with is handed to it (:class:`~.parts.RequestPart`): the link and its requests, the
status view, the one slot of what runs now and servo mode
(:class:`~.running_motion.RunningMotion`), the arm's identity, the local kinematics and the
arm's settings (frames, speed ratio). Units as the backend's: rad, m, 4x4
poses.
"""
from __future__ import annotations

import logging

import numpy as np

from ..common.constants import MAX_TOOL_ROTATION_ACCEL, SERVO_CYCLE
from ..common.results import Code, CommandRefused, Result
from ..common.transforms import matrix_to_pose_mm_rpy
from ..motion import velocity_jog
from ..motion.servo_filters import FilterType, ServoFilterSpec
from ..motion.velocity_jog import VelocityJog
from ..protocol import commands, servo_filters
from ..protocol.fields import Field
from .commander import answers
from .parts import RequestPart
from .running_motion import TwistRun
from .twist_stream import TwistStreamer

log = logging.getLogger(__name__)

#: errorCode of a recorded refusal: servo_j outside servo mode (fw 1.5.14 answers "-1").
SERVO_MODE_OFF_CODE = "-1"


class ServoCommands(RequestPart):
    """Servo mode, servo targets and the velocity jog on a controller (see the module; what it
    works with: :class:`~.parts.RequestPart`)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        #: the servo filter the controller last accepted (this driver's; none until set)
        self.filter = ServoFilterSpec()
        self._filter_set = False

    @answers
    def velocity_jog(self, twist, in_tool) -> Result:
        """A velocity jog as a ``servo_j`` stream (:mod:`.twist_stream`: why), entering servo
        mode for it; the twist at the rapid rate (× r, its ramp × r²), as the twin's."""
        self.identity.require_motion("velocity jog")
        ratio = self.settings.speed_ratio()
        twist = np.asarray(twist, float) * ratio
        running = self.motion.running(TwistRun)
        if running is not None:
            if running.streamer.jog.in_tool != bool(in_tool):
                raise CommandRefused(Code.BUSY, "velocity jog refused: one runs in the other "
                                     "frame; stop sending twists and start again")
            running.streamer.command(twist)
            return running.streamer.jog.progress()
        self.send.require_link()
        if self.motion.moving:
            raise CommandRefused(Code.BUSY, "velocity jog refused: the arm is moving")
        latest = self.view.latest
        if latest is None or not np.all(np.isfinite(latest.joint_position)):
            raise CommandRefused(Code.NOT_CONNECTED, "velocity jog refused: no joint "
                                 "positions from the controller yet")
        entered = not self.motion.servo_mode
        if entered:
            self.set_mode(True)
        jog = self._velocity_jog(bool(in_tool), ratio)
        jog.command(twist)
        streamer = TwistStreamer(jog, latest.joint_position, self.link.call,
                                 self._leave_twist if entered else None)
        self.motion.take(TwistRun(streamer),
                         lambda run: "velocity jog refused: the arm is moving")
        streamer.start()
        return streamer.jog.progress()

    def _velocity_jog(self, in_tool: bool, ratio: float) -> VelocityJog:
        tool, _ = self.settings.frames()     # on the arm's own chain, as the line check's
        return velocity_jog.on_arm(self.kinematics(), self.model, tool, in_tool=in_tool,
                                   ratio=ratio, cycle=SERVO_CYCLE,
                                   angular_accel=MAX_TOOL_ROTATION_ACCEL)

    def _leave_twist(self) -> None:
        """End of a velocity jog that entered servo mode itself (its thread)."""
        self.leave_mode("a velocity jog")

    def leave_mode(self, after: str) -> None:
        """Servo mode off at the end of a stream that entered it itself (``after`` says which,
        for the log); without a link it is off already (the controller ends it on its own)."""
        if not self.link.connected:
            self.motion.servo_mode = False
            return
        try:
            self.set_mode(False)
        except CommandRefused as refusal:
            log.warning("leaving servo mode after %s failed: %s", after, refusal.message)

    @answers
    def enable(self, on: bool) -> Result:
        """Enter or leave servo mode (the contract's ``servo_enable``)."""
        if on:
            self.identity.require_motion("servo mode")
        self.set_mode(bool(on))
        return Result.success(f"servo mode {'on' if on else 'off'}")

    def set_mode(self, on: bool) -> None:
        """``servo_move``, believed only once ``is_in_servomove`` says so: fw 1.5.14 acknowledges
        it while queued moves run and stays out of servo mode (refused with 2 then)."""
        try:
            self.send.settled(commands.servo_move(on), commands.is_in_servomove(),
                              _in_servomove, lambda now: now == on,
                              f"servo mode {'on' if on else 'off'}")
        except CommandRefused:
            self.motion.servo_mode = self.read_mode()
            raise
        self.motion.servo_mode = on

    def read_mode(self) -> bool:
        """What ``is_in_servomove`` says; off when it says nothing."""
        try:
            return self.send.read(commands.is_in_servomove(), _in_servomove)
        except CommandRefused as refusal:
            log.debug("is_in_servomove unavailable (%s); taking servo mode as off",
                      refusal.message)
            return False

    @answers
    def servo_j(self, q_target, increment=None) -> Result:
        """The absolute target, or the client's increment as a relative servo_j (relFlag 1),
        as JAKA's SDK sends it: the controller adds it to its own command position."""
        self.identity.require_motion("servo_j")
        if increment is None:
            self._servo_target(commands.servo_j(np.asarray(q_target, float)))
            return Result.success("servo_j target sent")
        self._servo_target(commands.servo_j(np.asarray(increment, float), relative=True))
        return Result.success("servo_j increment sent")

    @answers
    def servo_p(self, target, increment=None) -> Result:
        """The absolute target (mm + RPY deg on the wire), or the client's increment (m + RPY
        rad → mm + RPY) as a relative servo_p, as JAKA's SDK sends it; how the controller
        composes a relative rotation is its own."""
        self.identity.require_motion("servo_p")
        if increment is None:
            self._servo_target(commands.servo_p(matrix_to_pose_mm_rpy(target)))
            return Result.success("servo_p target sent")
        step = np.asarray(increment, float)
        self._servo_target(commands.servo_p(np.concatenate([step[:3] * 1e3, step[3:]]),
                                            relative=True))
        return Result.success("servo_p increment sent")

    @answers
    def set_filter(self, spec: ServoFilterSpec) -> Result:
        """``set_servo_move_filter`` with ``spec`` (checked already; refused by the driver in
        servo mode, as a controller refuses it). Not read back: no command reads it."""
        self.send.accepted(filter_request(spec))
        self.filter, self._filter_set = spec, True
        return Result.success(f"servo filter {spec.describe()} sent (set_servo_move_filter "
                              f"filter_type {int(spec.type)}); a controller has no command to "
                              "read it back")

    def describe_filter(self) -> str:
        """The filter for diagnostics: the one last sent, or what is known without one."""
        if not self._filter_set:
            return "not set by this driver (the controller keeps its own; it cannot be read)"
        return f"{self.filter.describe()} (sent; a controller cannot report it)"

    def _servo_target(self, request) -> None:
        reply = self.send.call(request)
        if reply.ok:
            return
        if reply.error_code == SERVO_MODE_OFF_CODE:
            # the recorded answer outside servo mode: the controller left it by itself
            self.motion.servo_mode = False
            raise CommandRefused(Code.SERVO_MODE_OFF, f"servo mode is off on the controller "
                                 f"({request[Field.CMD_NAME]}: {reply.error_msg})")
        raise CommandRefused(Code.CONTROLLER_REJECTED, f"controller rejected "
                             f"{request[Field.CMD_NAME]}: {reply.error_msg or reply.error_code}")


def filter_request(spec: ServoFilterSpec) -> dict:
    """``set_servo_move_filter`` for ``spec`` (SI: rad/s…, m/s…), in the wire's units (deg/s…,
    mm/s…) and keys, as JAKA's SDK sends each of its six filter functions."""
    t = spec.type
    if t == FilterType.JOINT_LPF:
        return servo_filters.servo_filter_joint_lpf(spec.cutoff)
    if t == FilterType.JOINT_NLF:
        return servo_filters.servo_filter_joint_nlf(spec.velocity, spec.accel, spec.jerk)
    if t == FilterType.JOINT_MMF:
        return servo_filters.servo_filter_joint_mmf(spec.buffer, spec.kp, spec.kv, spec.ka)
    if t == FilterType.CARTESIAN_NLF:
        return servo_filters.servo_filter_carte_nlf(
            spec.linear_velocity * 1e3, spec.linear_accel * 1e3, spec.linear_jerk * 1e3,
            spec.velocity, spec.accel, spec.jerk)
    if t == FilterType.SPEED_FORESIGHT:
        return servo_filters.servo_speed_foresight(spec.buffer, spec.kp)
    return servo_filters.servo_filter_none()


def _in_servomove(reply) -> bool:
    return commands.reply_flag(reply, Field.IN_SERVOMOVE)
