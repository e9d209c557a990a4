"""Motion on a controller: moves (``joint_move``, ``moveL``, ``movc``), trajectories (a ``servo_j``
stream, :mod:`.servo_stream`), the continuous jog and ``stop_move`` — what goes out on the wire
for each, and how each is followed to its end.

A move ends when the status packets say so or, between packets, when ``get_motion_state``
polled every :data:`MOTION_STATE_POLL` s says so (:mod:`.move_watch`). What runs now is the one
slot of :class:`~.running_motion.RunningMotion`: a move while this driver's own move,
trajectory or velocity jog runs is refused with -10 before anything is sent (the controller
would queue it: docs/protocol.md, "Motion queue"), so the arm never does a move its caller was
told was refused, and ``stop_move`` always has one motion to end.

:class:`MoveCommands` is a part :class:`~.backend.ControllerBackend` is composed of; what it
works with is handed to it: the link and its requests, the status view, the slot, the arm's
identity (motion refused while the arm is another model's), the local kinematics (a line's or
an arc's whole path is checked before ``moveL`` or ``movc``), the arm's settings (speed ratio, frames) and servo
mode (a trajectory enters it). Units as the backend's: rad, m, 4x4 poses.
"""
from __future__ import annotations

import logging
import threading
import time
from typing import Callable

import numpy as np

from ..common.constants import SERVO_CYCLE
from ..common.models import RobotModel
from ..common.results import Code, CommandRefused, Result
from ..common.transforms import matrix_to_pose_mm_rpy, pose_mm_rpy_to_matrix
from ..kinematics import Kinematics
from ..motion.circular_path import circle_duration, plan_circular_move, stop_pose
from ..motion.linear_path import line_duration, orientation_limits, plan_linear_move
from ..motion.profiles import joint_move_profile
from ..protocol import commands, errors
from ..protocol.fields import CoordMap, JogMode
from .arm_identity import ArmIdentity
from .arm_settings import ArmSettings
from .commander import Commander, answers
from .connection import ControllerLink
from .move_watch import MoveWatch, joint_error, joints_at, tcp_at
from .parts import RequestPart
from .running_motion import (JogRun, MoveRun, RunningMotion, TrajectoryRun, TwistRun,
                             keeps_out)
from .servo_commands import ServoCommands
from .servo_stream import TrajectoryStreamer
from .status_view import StatusView

log = logging.getLogger(__name__)

#: ROS jog coord (0 joint, 1 base, 2 tool) → the wire's coord_map (0 base, 1 joint, 2 tool).
JOG_COORD_MAP = {0: CoordMap.JOINT, 1: CoordMap.BASE, 2: CoordMap.TOOL}
UNKNOWN_MOVE_TIME = 30.0      # s, the estimate when the current position is unknown
MOTION_STATE_POLL = 0.05      # s between two get_motion_state requests while a move runs
MIN_WIRE_SPEED = 1e-6         # rad/s; a stretched move of nothing still needs a speed > 0
#: A plan this much (relative) longer than the fastest is stretched; shorter is float noise
#: between the driver's start and the latest packet's, and the move goes at the speed asked.
STRETCHED = 1e-6
#: A line whose IK needs a joint faster than this many times its speed limit between two 8 ms
#: samples jumps there (a configuration flip, a singularity passed through): refused before
#: moveL. Slower steps are the controller's business: it times moveL itself, and a tool turning
#: at the driver's cap (π rad/s) already asks J6 for its whole 3.14 rad/s.
LINE_JUMP = 2.0


class MoveCommands(RequestPart):
    """Moves, trajectories, jogs and stop on a controller (see the module; what it works with:
    :class:`~.parts.RequestPart`, and servo mode through ``servo``). ``trajectory_step_num``
    decimates trajectory streams (set-points every ``trajectory_step_num`` × 8 ms)."""

    def __init__(self, model: RobotModel, send: Commander, link: ControllerLink,
                 view: StatusView, motion: RunningMotion, identity: ArmIdentity,
                 kinematics: Callable[[], Kinematics], settings: ArmSettings,
                 servo: ServoCommands, trajectory_step_num: int = 1):
        super().__init__(model, send, link, view, motion, identity, kinematics, settings)
        self.servo = servo
        self.trajectory_step_num = int(trajectory_step_num)
        self._send_lock = threading.Lock()   # orders sending a move against stop_move
        self._motion_state_known = True   # until the controller says it has no such command
        #: ``movc``'s ``executing_line_id``: JAKA's SDK counts its circular moves from 1
        self._circles = 0

    # ---- moves ------------------------------------------------------------------------------
    def _start_move(self, request, watch: MoveWatch, estimate: float) -> Result:
        """Send a move; ``Result.value`` is ``(watch.completion, estimate)``. The watch ends the
        move from the status packets and get_motion_state (see move_watch); RobotDriver waits
        and stops an overrun."""
        self.send.require_link()
        # The controller would queue it; this driver does not (see the module doc).
        self.motion.take(MoveRun(watch), keeps_out(watch.label))
        watch.arm(packets_show_arrival=not self._motion_state_known)
        with self._send_lock:
            # stop_move or a lost link may end the watch before the move goes out: then it
            # is not sent, and the completion already says why
            if not watch.completion.done:
                try:
                    self.send.accepted(request)
                except CommandRefused as refusal:
                    watch.abort(refusal.result())
                    raise
        if self._motion_state_known and not watch.completion.done:
            threading.Thread(target=self._follow_motion_state, args=(watch,), daemon=True,
                             name="jaka-motion-state").start()
        return Result.success(f"{watch.label} started", (watch.completion, estimate))

    def _follow_motion_state(self, watch: MoveWatch) -> None:
        """While ``watch`` runs, ask ``get_motion_state`` every :data:`MOTION_STATE_POLL` s."""
        while not watch.completion.wait(MOTION_STATE_POLL):
            if not (self._motion_state_known and self.link.connected):
                return
            try:
                reply = self.link.call(commands.get_motion_state())
            except errors.JakaProtocolError as exc:
                log.debug("get_motion_state failed: %s", exc)   # the link handles a lost link
                continue
            try:
                state = commands.reply_motion_state(reply)
            except errors.JakaProtocolError as exc:
                log.info("the controller does not answer get_motion_state (%s); waiting on the "
                         "status packets only", exc)
                self._motion_state_known = False
                return
            if state.inpos and state.queue == 0:
                # the move ended: let a packet from after now arrive, so state() shows it ended
                self.view.wait_for_packet(time.time(), 0.2)
            watch.on_motion_state(state.inpos, state.queue, self.view.latest_received)

    @answers
    def start_joint_move(self, q_target, speed, accel, duration=None) -> Result:
        """``joint_move`` taking ``duration`` s (the driver's plan). The wire has no duration:
        a plan stretched longer than the fastest goes out at its lower peak speed (a stretched
        trapezoid is the fastest one at its own peak speed), computed by the driver's law
        (:func:`~jaka_driver.motion.profiles.joint_move_profile`) from the joints the latest
        packet reports."""
        self.identity.require_motion("joint_move")
        q_target = np.asarray(q_target, float)
        latest = self.view.latest
        estimate = duration or UNKNOWN_MOVE_TIME
        ratio = self.settings.speed_ratio()      # the controller scales what it is sent by its rate
        if latest is not None and np.all(np.isfinite(latest.joint_position)):
            plan = joint_move_profile(latest.joint_position, q_target,
                                      np.minimum(speed, self.model.max_velocity),
                                      np.minimum(accel, self.model.max_acceleration),
                                      duration * ratio if duration else None)
            estimate = plan.duration / ratio
            if plan.duration > plan.predicted_duration * (1.0 + STRETCHED):
                speed = max(float(np.max(plan.peak_velocity)), MIN_WIRE_SPEED)
        watch = MoveWatch("joint_move", joints_at(q_target), final_error=joint_error(q_target))
        return self._start_move(commands.joint_move(q_target, speed, accel), watch, estimate)

    @answers
    def start_linear_move(self, target, speed, accel, ref_q=None, duration=None) -> Result:
        """``moveL`` at ``speed`` m/s and ``accel`` m/s², its orientation at the driver's own
        limits for that speed (``ori_vel``/``ori_acc``, the twin's, so a controller never turns
        the tool at its own defaults), taking ``duration`` s (the driver's plan; without one,
        the same law from the TCP the latest packet reports). The whole line is checked first
        on the local kinematics (:meth:`_check_line`)."""
        self.identity.require_motion("linear_move")
        self._check_line(target, speed, accel)
        pose = matrix_to_pose_mm_rpy(target)
        angular_speed, angular_accel = orientation_limits(speed, accel)
        estimate = duration
        latest = self.view.latest
        if estimate is None:
            estimate = UNKNOWN_MOVE_TIME
            if latest is not None and np.all(np.isfinite(latest.tcp_pose)):
                estimate = line_duration(pose_mm_rpy_to_matrix(latest.tcp_pose), target, speed,
                                         accel) / self.settings.speed_ratio()
        note = None if ref_q is None else ("ref_joint is not sent: moveL chooses the "
                                           "configuration itself")
        watch = MoveWatch("linear_move", tcp_at(pose), note=note)
        request = commands.moveL(pose, speed * 1000.0, accel * 1000.0,
                                 ori_vel_rad_s=angular_speed, ori_acc_rad_s2=angular_accel)
        return self._start_move(request, watch, estimate)

    @answers
    def start_circular_move(self, mid, end, speed, accel, turns=0.0, mode=0,
                            duration=None) -> Result:
        """``movc`` through ``mid`` to ``end`` (4x4, m) at ``speed`` m/s and ``accel`` m/s²
        (sent as mm/s and mm/s², as ``moveL``'s), ``turns`` more times round (``circle_cnt``)
        with attitude rule ``mode`` (``circle_mode``), exactly as JAKA's SDK writes it
        (docs/protocol.md, "Circular moves"), taking ``duration`` s (the driver's plan;
        without one, the same law from the TCP the latest packet reports). The whole arc is
        checked first on the local kinematics (:meth:`_check_arc`); waited for like
        ``moveL``."""
        self.identity.require_motion("circular_move")
        self._check_arc(mid, end, speed, accel, turns, mode)
        start = self._reported_tcp()
        estimate = duration
        if estimate is None:
            estimate = UNKNOWN_MOVE_TIME if start is None else circle_duration(
                start, mid, end, speed, accel, turns, mode) / self.settings.speed_ratio()
        rests = end if start is None else stop_pose(start, mid, end, turns, mode)
        self._circles += 1
        request = commands.movc(matrix_to_pose_mm_rpy(end), matrix_to_pose_mm_rpy(mid),
                                speed * 1000.0, accel * 1000.0, circle_cnt=float(turns),
                                circle_mode=int(mode), executing_line_id=self._circles)
        watch = MoveWatch("circular_move", tcp_at(matrix_to_pose_mm_rpy(rests)))
        return self._start_move(request, watch, estimate)

    def _reported_tcp(self):
        """The TCP (4x4, m) the latest packet reports, or None."""
        latest = self.view.latest
        if latest is None or not np.all(np.isfinite(latest.tcp_pose)):
            return None
        return pose_mm_rpy_to_matrix(latest.tcp_pose)

    def _check_arc(self, mid, end, speed: float, accel: float, turns: float,
                   mode: int) -> None:
        """The whole-path check of an arc, as :meth:`_check_line`'s of a line: every cycle
        of the arc through ``mid`` to ``end`` (-2 collinear points, -4 where it leaves the
        workspace or the limits, or a joint would jump)."""
        m = self.model
        self._check_path(lambda start, q0, ik: plan_circular_move(
            start, mid, end, speed, accel, q0, ik, m.lower, m.upper,
            LINE_JUMP * m.max_velocity, turns, mode, cycle=SERVO_CYCLE))

    def _check_line(self, target, speed: float, accel: float) -> None:
        """The whole-path check of a line (IK at every cycle, joint limits, no joint faster
        than :data:`LINE_JUMP` × its limit); a
        :class:`~jaka_driver.motion.cartesian_path.PlanningError` (-4) says where it fails."""
        m = self.model
        self._check_path(lambda start, q0, ik: plan_linear_move(
            start, target, speed, accel, q0, ik, m.lower, m.upper,
            LINE_JUMP * m.max_velocity, cycle=SERVO_CYCLE))

    def _check_path(self, plan) -> None:
        """Run ``plan(start pose, start joints, ik)`` — a Cartesian path's whole-path check —
        from the joints the latest packet reports, on :attr:`kinematics` and the active
        frames, seeded there as the controller's ``moveL`` / ``movc`` is (it is not sent
        ``ref_joint``). Without a link the move is refused as any other (-1), unchecked."""
        self.send.require_link()
        latest = self.view.latest
        if latest is None or not np.all(np.isfinite(latest.joint_position)):
            return
        q0 = np.asarray(latest.joint_position, float)
        tool, user = self.settings.frames()
        kin = self.kinematics()

        def ik(pose, seed):
            solution = kin.ik(pose, seed=seed, tool=tool, user=user)
            return solution.q if solution.success else None
        plan(kin.tcp_pose(q0, tool, user), q0, ik)

    # ---- trajectories ---------------------------------------------------------------------------
    @answers
    def start_trajectory(self, trajectory) -> Result:
        self.identity.require_motion("trajectory")
        self.send.require_link()
        if self.motion.running(TrajectoryRun) is not None:
            raise CommandRefused(Code.BUSY, "a trajectory is already running")
        entered = False
        if not self.motion.servo_mode:
            self.servo.set_mode(True)
            entered = True
        streamer = TrajectoryStreamer(trajectory, self.link.call,
                                      self._leave_servo if entered else None,
                                      step_num=self.trajectory_step_num)
        self.motion.take(TrajectoryRun(streamer), keeps_out("trajectory"))
        streamer.start()
        return Result.success(f"trajectory of {streamer.duration:.3f} s started",
                              (streamer.completion, streamer.duration))

    def _leave_servo(self) -> None:
        """End of a trajectory that entered servo mode itself (streamer thread)."""
        self.servo.leave_mode("a trajectory")

    # ---- jog ------------------------------------------------------------------------------------
    @answers
    def jog(self, coord, axis, direction, speed) -> Result:
        self.identity.require_motion("jog")
        coord_map = int(JOG_COORD_MAP[int(coord)])
        angular = coord_map == CoordMap.JOINT or axis >= 3
        jogvel = direction * (speed if angular else speed * 1000.0)   # rad/s, or m/s → mm/s
        run = JogRun(coord_map, axis)
        self.motion.check(keeps_out("jog"))
        previous = self.motion.running(JogRun)
        if previous is not None and previous.axis != run.axis:
            # Another axis: stop the old one first so that two axes never run at once.
            self.send.accepted(commands.jog(JogMode.STOP, *previous.axis))
        self.send.accepted(commands.jog(JogMode.CONTINUOUS, coord_map, axis, jogvel))
        self.motion.take(run, keeps_out("jog"))
        unit = "rad/s" if angular else "mm/s"
        return Result.success(f"jogging axis {axis} of coord_map {coord_map} at {jogvel:g} {unit}")

    @answers
    def jog_stop(self) -> Result:
        twist = self.motion.running(TwistRun)
        if twist is not None:
            twist.streamer.stop()
            return Result.success("velocity jog stopping")
        running = self.motion.end_jog()
        if running is None:
            self.send.require_link()
            return Result.success("no jog was running")
        self.send.accepted(commands.jog(JogMode.STOP, *running.axis))
        return Result.success("jog stopping")

    # ---- stop -----------------------------------------------------------------------------------
    @answers
    def stop_move(self) -> Result:
        self.send.require_link()
        twist = self.motion.running(TwistRun)
        if twist is not None:
            twist.streamer.stop()   # it ramps to rest on its own targets, then leaves servo mode
            return Result.success("velocity jog stopping")
        with self._send_lock:   # a move being sent goes out before stop_program, or not at all
            self.motion.abort(Result.failure(Code.MOTION_STOPPED, "stopped by stop_move"))
            self.send.accepted(commands.stop_program())
        return Result.success("stop_program sent: the arm decelerates to rest")
