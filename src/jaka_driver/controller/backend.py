"""The ``controller`` backend: a real JAKA controller (or ``jaka_emulator``) over the TCP
protocol, behind the same :class:`~jaka_driver.backend.Backend` contract as the twin.

Mapping (docs/protocol.md): joint_move → ``joint_move``, linear_move → ``moveL`` with
``ori_vel``/``ori_acc`` (the driver's orientation limits, :func:`~jaka_driver.motion.
linear_path.orientation_limits`), jog → ``jog``, servo → ``servo_move`` confirmed by
``is_in_servomove`` + ``servo_j``/``servo_p`` (absolute), stop → ``stop_program``, frames →
``set_tool_offsets``/``set_user_offsets`` + ``set_tool_id``/``set_user_id`` confirmed by
``get_curr_tool_id``/``get_curr_user_id``, payload → ``set_tool_id`` + ``set_payload``, drag →
``torque_control_enable`` confirmed by ``get_drag_status``, collision →
``set_clsn_sensitivity``, IO → the set commands confirmed by the get commands, clear_error →
``clear_error``, FK/IK → ``kine_forward``/``kine_inverse``, trajectories → a ``servo_j`` stream
(:mod:`.servo_stream`). A setting is confirmed as JAKA's SDK confirms it: its get read back
every 100 ms for up to 1 s (:meth:`.commander.Commander.settled`). Units are converted by the
protocol library; this module speaks SI (rad, m, 4x4 poses of the active tool in the active
user frame) like every backend.

A move ends when the status packets say so or, between packets, when ``get_motion_state``
polled every :data:`MOTION_STATE_POLL` s says so (:mod:`.move_watch`); state comes from the status
packets of port 10000, 10004 or both (``status_source``, :mod:`.connection`;
:mod:`.status_view`); requests and their failure codes are :mod:`.commander`; the link and its
reconnect policy are :mod:`.connection`; frames by id are :mod:`.frames_by_id`; the arm's
identity and kinematic parameters, read at every connection, are :mod:`.arm_identity`. Two
parts of the class have modules of their own: servo mode, servo targets and the velocity jog
(:mod:`.servo_commands`), and the arm's settings — frames, payload, drag, collision, IO, errors,
the speed ratio (:mod:`.arm_settings`).

Local kinematics: ``linear_move``'s whole path is checked before ``moveL`` goes out (IK every
8 ms from the joints the latest packet reports, joint limits, no joint jump), on
the arm's own chain when the controller states it (``get_dh_param``, a calibration of the
model's) — :attr:`ControllerBackend.kinematics`. ``get_fk`` and ``get_ik`` are the controller's
own (``kine_forward`` / ``kine_inverse``). While the parameters say the arm is another model's
(and ``kinematics`` is ``auto``), every motion is refused with -9 (:mod:`.arm_identity`).

The controller queues moves: one sent while another runs is acknowledged and runs after it
(docs/protocol.md, "Motion queue"). This backend never relies on that: a move while its own
move or trajectory runs is refused with -10 (busy) before anything is sent, so the arm never
does a move its caller was told was refused, and ``stop_move`` always has one move to end.
"""
from __future__ import annotations

import logging
import threading
import time
from typing import Optional

import numpy as np

from ..backend import Backend
from ..backend.robot_state import RobotState
from ..common.constants import SERVO_CYCLE
from ..common.models import RobotModel
from ..common.results import Code, CommandRefused, Result
from ..common.transforms import matrix_to_pose_mm_rpy, pose_mm_rpy_to_matrix
from ..kinematics import Kinematics
from ..motion.linear_path import line_duration, orientation_limits, plan_linear_move
from ..motion.profiles import joint_move_profile
from ..protocol import commands, errors
from ..protocol.fields import CoordMap, JogMode
from .arm_identity import ArmIdentity
from .arm_settings import ArmSettings
from .commander import Commander, answers
from .connection import ControllerLink
from .frames_by_id import ControllerFrames
from .move_watch import MoveWatch, joint_error, joints_at, tcp_at
from .servo_commands import ServoCommands
from .servo_stream import TrajectoryStreamer
from .status_view import StatusView
from .twist_stream import TwistStreamer

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


class ControllerBackend(ServoCommands, ArmSettings, Backend):
    """A JAKA controller at ``host``: commands on ``command_port``, status on ``status_port``.

    Timeouts, s: ``connect_timeout`` per TCP connect attempt, ``call_timeout`` for a reply,
    ``stall_timeout`` of status silence that counts as a lost link, ``power_timeout`` for
    power-on and enable. ``trajectory_step_num`` decimates trajectory streams (set-points every
    ``trajectory_step_num`` × 8 ms). ``kinematics`` says which chain is right when the
    controller's parameters are another arm's (:data:`.arm_identity.KINEMATICS_CHOICES`).
    """

    def __init__(self, model: RobotModel, host: str = "10.5.5.100", command_port: int = 10001,
                 status_port: int = 10000, *, status_source: str = "stream",
                 data_port: int = 10004, connect_timeout: float = 1.0,
                 call_timeout: float = 1.0, stall_timeout: float = 0.5,
                 power_timeout: float = 15.0, trajectory_step_num: int = 1,
                 kinematics: str = "auto"):
        super().__init__(model)
        self.host = host
        self.trajectory_step_num = int(trajectory_step_num)
        self.view = StatusView()
        self.link = ControllerLink(host, command_port, status_port,
                                   status_source=status_source, data_port=data_port,
                                   connect_timeout=connect_timeout, call_timeout=call_timeout,
                                   stall_timeout=stall_timeout, on_status=self._on_status,
                                   on_up=self._on_up, on_down=self._on_down)
        self.send = Commander(self.link, self.view, power_timeout)
        self.frames_by_id = ControllerFrames(self.send.read)
        self.identity = ArmIdentity(model, kinematics)
        self._kinematics = (model, None)   # (the model it is of, Kinematics or None)
        self._lock = threading.RLock()
        self._send_lock = threading.Lock()   # orders sending a move against stop_move
        self._watch: Optional[MoveWatch] = None
        self._streamer: Optional[TrajectoryStreamer] = None
        self._servo_mode = False
        self._jog: Optional[tuple[int, int]] = None      # wire (coord_map, jnum) of the jog
        self._twist: Optional[TwistStreamer] = None        # a velocity jog's servo stream
        self._rapid_rate = 1.0                             # the last rate read back
        self._ids = (0, 0)                               # (tool, user) last set, until a packet
        self._brought_up = threading.Event()
        self._motion_state_known = True   # until the controller says it has no such command

    # ---- life cycle -------------------------------------------------------------------
    def start(self) -> None:
        """Connect, then power on and enable if needed (like JAKA's driver). If the controller
        cannot be reached the backend still starts: it reports ``connected`` False, answers -1
        and keeps trying in the background."""
        link = self.link
        if link.start(wait=link.connect_timeout + link.first_packet_timeout + 0.5):
            self._brought_up.wait(2 * self.send.confirm_timeout + 3 * link.call_timeout)
        else:
            log.warning("starting without the controller at %s: %s", self.host,
                        link.down_message())

    def shutdown(self) -> None:
        self._abort_motion(Result.failure(Code.MOTION_STOPPED,
                                          "stopped: the driver is shutting down"))
        self.frames_by_id.stop()
        self.link.stop()

    @property
    def version(self) -> str:
        """The controller's version string (``get_version``), "" until read."""
        return self.identity.version

    def state(self) -> RobotState:
        return self.view.state(self.link.connected, self._servo_mode)

    @property
    def kinematics(self) -> Kinematics:
        """The driver's local kinematics of the arm: on the controller's own parameters when
        they are in use (:attr:`.arm_identity.ArmIdentity.kinematic_model`), else the model's
        chain."""
        model = self.identity.kinematic_model
        of, kin = self._kinematics
        if kin is None or of is not model:
            kin = Kinematics(model)
            self._kinematics = (model, kin)
        return kin

    def describe(self) -> dict:
        info = {"backend": "controller", **super().describe()}
        info.update({"controller": self.host, "command port": self.link.command_port,
                     "status port": self.link.status_port,
                     "status source": self.link.status_source,
                     "connected": self.link.connected, "controller version": self.version,
                     "reconnects": self.link.reconnects})
        if not self.link.connected:
            info["link"] = self.link.down_message()
        info.update(self.identity.describe())
        info.update(self.frames_by_id.describe())
        latest = self.view.latest
        if latest is not None:
            info["homed"] = list(latest.homed)
            if latest.malformed:
                info["malformed status fields"] = list(latest.malformed)
        info.update(self.link.counters())
        return info

    # ---- link hooks -------------------------------------------------------------------------
    def _on_status(self, status, received: float) -> None:
        self.view.feed(status, received)
        if status.emergency_stop or status.protective_stop or not status.enabled:
            self._servo_mode = False   # the controller leaves servo mode on any of these
        self.frames_by_id.on_active(status.current_tool_id, status.current_user_id)
        watch = self._watch
        if watch is not None:
            watch.on_status(status, received)

    def _on_up(self, first: bool) -> None:
        """At every connection (supervisor thread): servo mode, identity, kinematic parameters
        and frames as the controller has them now; power and enable at the first only."""
        try:
            self.view.reset()
            self._servo_mode = self._read_servo_mode()
            self._read_rapid_rate()
            self.identity.read(self.send.read)
            self.kinematics     # built now, not at the first linear move
            self.frames_by_id.read_all()
            if first:
                self._bring_up()
        finally:
            if first:
                self._brought_up.set()

    def _on_down(self, reason: str) -> None:
        with self._lock:
            self._jog = None
        self._abort_motion(Result.failure(
            Code.NOT_CONNECTED, f"connection to the controller lost ({reason}); the motion is "
            "not resumed after reconnecting"))
        self._servo_mode = False   # unknown until is_in_servomove after the reconnect

    def _abort_motion(self, result: Result) -> None:
        with self._lock:
            watch, streamer, twist = self._watch, self._streamer, self._twist
        if twist is not None:
            twist.halt(result)
        if watch is not None:
            watch.abort(Result(result.code, f"{watch.label}: {result.message}"))
        if streamer is not None:
            streamer.stop(result)

    def _bring_up(self) -> None:
        """Power on and enable, each only if needed, each confirmed on the status stream. Done
        once, at the first connection (after a reconnect the operator decides)."""
        try:
            powered, enabled = self._power_state()
            if not powered:
                log.info("powering on the arm")
                self.send.confirmed(commands.power_on(), lambda s: s.powered, "power on")
            if not enabled:
                log.info("enabling the arm")
                self.send.confirmed(commands.enable_robot(), lambda s: s.enabled, "enable")
        except CommandRefused as refusal:
            log.warning("bring-up incomplete: %s; use the power and enable services",
                        refusal.message)
        else:
            log.info("controller ready (version %s)", self.version or "unknown")

    def _power_state(self) -> tuple[bool, bool]:
        """(powered, enabled) from ``get_robot_state``, or from the status stream on a
        controller that does not know that command (its reply format is not verified)."""
        try:
            return self.send.read(commands.get_robot_state(), commands.reply_robot_state)
        except CommandRefused as refusal:
            latest = self.view.latest
            if refusal.code == Code.NOT_CONNECTED or latest is None:
                raise
            log.info("get_robot_state failed (%s); reading power and enable from the status "
                     "stream", refusal.message)
            return latest.powered, latest.enabled

    # ---- power ----------------------------------------------------------------------------------
    @answers
    def set_power(self, on: bool) -> Result:
        request = commands.power_on() if on else commands.power_off()
        self.send.confirmed(request, lambda s: s.powered == on, "power")
        return Result.success("powered on" if on else "powered off")

    @answers
    def set_enabled(self, on: bool) -> Result:
        request = commands.enable_robot() if on else commands.disable_robot()
        self.send.confirmed(request, lambda s: s.enabled == on, "enable")
        return Result.success("enabled" if on else "disabled")

    # ---- moves --------------------------------------------------------------------------------
    def _start_move(self, request, watch: MoveWatch, estimate: float) -> Result:
        """Send a move; ``Result.value`` is ``(watch.completion, estimate)``. The watch ends the
        move from the status packets and get_motion_state (see move_watch); RobotDriver waits
        and stops an overrun."""
        self.send.require_link()
        with self._lock:
            if self._streamer is not None and self._streamer.running:
                raise CommandRefused(Code.BUSY, f"{watch.label} refused: a trajectory runs")
            if self._watch is not None and not self._watch.completion.done:
                # The controller would queue it; this driver does not (see the module doc).
                raise CommandRefused(Code.BUSY, f"{watch.label} refused: {self._watch.label} "
                                     "is still running (stop_move first)")
            self._watch = watch
        watch.arm()
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
                self.wait_for_sample(time.time(), 0.2)
            watch.on_motion_state(state.inpos, state.queue, self.view.latest_received)

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        """Until a status packet received later than ``after`` (s, ``time.time()``, as
        ``RobotState.stamp``) is here, at most ``timeout`` s: the packet wakes the wait (the
        node's publisher, the move follower)."""
        return self.view.wait_for_packet(after, timeout)

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
        ratio = self.speed_ratio()      # the controller scales what it is sent by its rate
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
                                         accel) / self.speed_ratio()
        note = None if ref_q is None else ("ref_joint is not sent: moveL chooses the "
                                           "configuration itself")
        watch = MoveWatch("linear_move", tcp_at(pose), note=note)
        request = commands.moveL(pose, speed * 1000.0, accel * 1000.0,
                                 ori_vel_rad_s=angular_speed, ori_acc_rad_s2=angular_accel)
        return self._start_move(request, watch, estimate)

    def _check_line(self, target, speed: float, accel: float) -> None:
        """The whole-path check of a line (IK at every cycle, joint limits, no joint faster
        than :data:`LINE_JUMP` × its limit) from the joints the latest packet reports, on
        :attr:`kinematics` and the active frames, seeded there as the controller's ``moveL``
        is (it is not sent ``ref_joint``); a
        :class:`~jaka_driver.motion.linear_path.PlanningError` (-4) says where it fails.
        Without a link the move is refused as any other (-1), unchecked."""
        self.send.require_link()
        latest = self.view.latest
        if latest is None or not np.all(np.isfinite(latest.joint_position)):
            return
        q0 = np.asarray(latest.joint_position, float)
        tool, user = self.frames()
        kin = self.kinematics

        def ik(pose, seed):
            solution = kin.ik(pose, seed=seed, tool=tool, user=user)
            return solution.q if solution.success else None

        plan_linear_move(kin.tcp_pose(q0, tool, user), target, speed, accel, q0, ik,
                         self.model.lower, self.model.upper,
                         LINE_JUMP * self.model.max_velocity, cycle=SERVO_CYCLE)

    # ---- trajectories ---------------------------------------------------------------------------
    @answers
    def start_trajectory(self, trajectory) -> Result:
        self.identity.require_motion("trajectory")
        self.send.require_link()
        with self._lock:
            if self._streamer is not None and self._streamer.running:
                raise CommandRefused(Code.BUSY, "a trajectory is already running")
        entered = False
        if not self._servo_mode:
            self._set_servo_mode(True)
            entered = True
        streamer = TrajectoryStreamer(trajectory, self.link.call,
                                      self._leave_servo if entered else None,
                                      step_num=self.trajectory_step_num)
        with self._lock:
            self._streamer = streamer
            self._watch = streamer.watch
        streamer.start()
        return Result.success(f"trajectory of {streamer.duration:.3f} s started",
                              (streamer.completion, streamer.duration))

    def _leave_servo(self) -> None:
        """End of a trajectory that entered servo mode itself (streamer thread)."""
        with self._lock:
            streamer = self._streamer
            if streamer is not None and self._watch is streamer.watch:
                self._watch = None
        self._leave_servo_mode("a trajectory")

    # ---- jog ------------------------------------------------------------------------------------
    @answers
    def jog(self, coord, axis, direction, speed) -> Result:
        self.identity.require_motion("jog")
        coord_map = int(JOG_COORD_MAP[int(coord)])
        angular = coord_map == CoordMap.JOINT or axis >= 3
        jogvel = direction * (speed if angular else speed * 1000.0)   # rad/s, or m/s → mm/s
        with self._lock:
            previous = self._jog
        if previous is not None and previous != (coord_map, axis):
            # Another axis: stop the old one first so that two axes never run at once.
            self.send.accepted(commands.jog(JogMode.STOP, *previous))
        self.send.accepted(commands.jog(JogMode.CONTINUOUS, coord_map, axis, jogvel))
        with self._lock:
            self._jog = (coord_map, axis)
        unit = "rad/s" if angular else "mm/s"
        return Result.success(f"jogging axis {axis} of coord_map {coord_map} at {jogvel:g} {unit}")

    @answers
    def jog_stop(self) -> Result:
        with self._lock:
            twist = self._twist if self._twist is not None and self._twist.running else None
        if twist is not None:
            twist.stop()
            return Result.success("velocity jog stopping")
        with self._lock:
            running, self._jog = self._jog, None
        if running is None:
            self.send.require_link()
            return Result.success("no jog was running")
        self.send.accepted(commands.jog(JogMode.STOP, *running))
        return Result.success("jog stopping")

    # ---- stop -----------------------------------------------------------------------------------
    @answers
    def stop_move(self) -> Result:
        self.send.require_link()
        with self._lock:
            self._jog = None
            twist = self._twist
        if twist is not None and twist.running:
            twist.stop()            # it ramps to rest on its own targets, then leaves servo mode
            return Result.success("velocity jog stopping")
        with self._send_lock:   # a move being sent goes out before stop_program, or not at all
            self._abort_motion(Result.failure(Code.MOTION_STOPPED, "stopped by stop_move"))
            self.send.accepted(commands.stop_program())
        return Result.success("stop_program sent: the arm decelerates to rest")

    def _moving(self) -> bool:
        """A move, trajectory or jog of this driver runs, or the status stream shows motion."""
        with self._lock:
            watch, jog, twist = self._watch, self._jog, self._twist
        latest = self.view.latest
        return ((watch is not None and not watch.completion.done) or jog is not None
                or (twist is not None and twist.running)
                or (latest is not None and not latest.inpos))

    # ---- kinematics -----------------------------------------------------------------------------
    @answers
    def forward_kinematics(self, q) -> Result:
        pose = self.send.read(commands.kine_forward(np.asarray(q, float)),
                              commands.reply_kine_forward)
        return Result.success("controller's forward kinematics (active tool, active user "
                              "frame)", pose_mm_rpy_to_matrix(pose))

    @answers
    def inverse_kinematics(self, target, ref_q) -> Result:
        request = commands.kine_inverse(np.asarray(ref_q, float), matrix_to_pose_mm_rpy(target))
        reply = self.send.call(request)
        if not reply.ok:
            # The controller's IK refusal means "unreachable": the contract's -4.
            raise CommandRefused(Code.IK_FAILED, "controller found no IK solution: "
                                 f"{reply.error_msg or reply.error_code}")
        q = self.send.parse(reply, commands.reply_kine_inverse)
        return Result.success("controller's inverse kinematics nearest ref_joint", q)



