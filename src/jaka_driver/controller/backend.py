"""The ``controller`` backend: a real JAKA controller (or ``jaka_emulator``) over the TCP
protocol, behind the same :class:`~jaka_driver.backend.Backend` contract as the twin.

Mapping (docs/protocol.md): joint_move → ``joint_move``, linear_move → ``moveL`` with
``ori_vel``/``ori_acc`` (the driver's orientation limits, :func:`~jaka_driver.motion.
linear_path.orientation_limits`), circular_move → ``movc``, jog → ``jog``, servo →
``servo_move`` confirmed by ``is_in_servomove`` + ``servo_j``/``servo_p`` (absolute), the servo
filter → ``set_servo_move_filter``, stop → ``stop_program``, frames →
``set_tool_offsets``/``set_user_offsets`` + ``set_tool_id``/``set_user_id`` confirmed by
``get_curr_tool_id``/``get_curr_user_id``, payload → ``set_tool_id`` + ``set_payload``, drag →
``torque_control_enable`` confirmed by ``get_drag_status``, collision →
``set_clsn_sensitivity``, IO → the set commands confirmed by the get commands, clear_error →
``clear_error``, FK/IK → ``kine_forward``/``kine_inverse``, trajectories → a ``servo_j`` stream
(:mod:`.servo_stream`), programs (the facet ``backend.programs``, :mod:`.programs`) → JAKA's
program commands. A setting is confirmed as JAKA's SDK confirms it: its get read back every
100 ms for up to 1 s (:meth:`.commander.Commander.settled`). Units are converted by the
protocol library; this module speaks SI (rad, m, 4x4 poses of the active tool in the active
user frame) like every backend.

The backend assembles its parts and serves the contract with them, each part handed what it
works with: state comes from the status packets of port 10000, 10004 or both
(``status_source``, :mod:`.connection`; :mod:`.status_view`); requests and their failure codes
are :mod:`.commander`; the link and its reconnect policy are :mod:`.connection`; frames by id
are :mod:`.frames_by_id`; the arm's identity and kinematic parameters, read at every
connection, are :mod:`.arm_identity`. What runs now — a move, a trajectory, a jog or a velocity
jog — and servo mode have one owner, the slot of :mod:`.running_motion` (busy, abort, what a
status packet tells it). Three parts serve the contract's requests by subject, and the
backend's methods of each subject pass the request on: motion — moves, trajectories, jogs,
stop — (:class:`~.moves.MoveCommands`: when a move has ended, :mod:`.move_watch`), servo mode,
servo targets and the velocity jog (:class:`~.servo_commands.ServoCommands`), and the arm's
settings — frames, payload, drag, collision, IO, errors, the speed ratio
(:class:`~.arm_settings.ArmSettings`); the controller's own programs are offered as the facet
``backend.programs`` (:class:`~.programs.ControllerPrograms`), whose state every sample carries,
and its trajectory recording as ``backend.recording`` (:class:`~.recording.ControllerRecording`).
When the arm carries a force/torque sensor (``force_sensor``), another part is ``backend.force``
(:class:`~.force.ControllerForce`: the sensor and force control, their readings from every
packet's ``torqsensor``).

``pause_motion`` / ``resume_motion`` stay -9: they serve a program step the driver's engine
runs, and on a controller the controller runs its programs itself (``pause_program``). Whether
``pause_program`` pauses a move sent over TCP outside a program is not on record.

Local kinematics: ``linear_move``'s (and ``circular_move``'s) whole path is checked before
``moveL`` (``movc``) goes out (IK every
8 ms from the joints the latest packet reports, joint limits, no joint jump), on
the arm's own chain when the controller states it (``get_dh_param``, a calibration of the
model's) — :attr:`ControllerBackend.kinematics`. ``get_fk`` and ``get_ik`` are the controller's
own (``kine_forward`` / ``kine_inverse``). While the parameters say the arm is another model's
(and ``kinematics`` is ``auto``), every motion is refused with -9 (:mod:`.arm_identity`).

The controller queues moves (docs/protocol.md, "Motion queue"); this backend never relies on
that (:mod:`.moves`).
"""
from __future__ import annotations

import logging
import threading

import numpy as np

from ..backend import Backend
from ..backend.force import HOW_TO_MOUNT, NoForceSensor
from ..backend.robot_state import RobotState
from ..common.models import RobotModel
from ..common.results import Code, CommandRefused, Result
from ..common.transforms import matrix_to_pose_mm_rpy, pose_mm_rpy_to_matrix
from ..kinematics import Kinematics
from ..protocol import commands
from .arm_identity import ArmIdentity
from .arm_settings import ArmSettings
from .commander import Commander, answers
from .connection import ControllerLink
from .force import ControllerForce
from .tool_io import ControllerToolIO
from .frames_by_id import ControllerFrames
from .mounting import ControllerMounting
from .moves import MoveCommands
from .network_loss import DEFAULT_ACTION, DEFAULT_TIME_LIMIT, NetworkLossHandling
from .programs import ControllerPrograms
from .recording import ControllerRecording
from .running_motion import RunningMotion
from .servo_commands import ServoCommands
from .status_view import StatusView

log = logging.getLogger(__name__)


class ControllerBackend(Backend):
    """A JAKA controller at ``host``: commands on ``command_port``, status on ``status_port``.

    Timeouts, s: ``connect_timeout`` per TCP connect attempt, ``call_timeout`` for a reply,
    ``stall_timeout`` of status silence that counts as a lost link, ``power_timeout`` for
    power-on and enable. ``trajectory_step_num`` decimates trajectory streams (set-points every
    ``trajectory_step_num`` × 8 ms). ``kinematics`` says which chain is right when the
    controller's parameters are another arm's (:data:`.arm_identity.KINEMATICS_CHOICES`).
    ``force_sensor``: the arm carries the flange force/torque sensor of the model's
    configuration (True), not (False), or as configured (None; off on every model).
    ``network_loss_action`` (``keep``, ``pause``, ``abort``) and ``network_loss_time`` (s): what
    the controller does with the motion under way once this driver's connection has been lost
    that long (:mod:`.network_loss`; default: abort after 0.1 s).
    """

    def __init__(self, model: RobotModel, host: str = "10.5.5.100", command_port: int = 10001,
                 status_port: int = 10000, *, status_source: str = "stream",
                 data_port: int = 10004, connect_timeout: float = 1.0,
                 call_timeout: float = 1.0, stall_timeout: float = 0.5,
                 power_timeout: float = 15.0, trajectory_step_num: int = 1,
                 kinematics: str = "auto", force_sensor: bool | None = None,
                 network_loss_action: str = DEFAULT_ACTION,
                 network_loss_time: float = DEFAULT_TIME_LIMIT):
        super().__init__(model)
        #: what the controller does with the motion when this connection is lost, sent at
        #: every connection (raises ValueError for a wrong action or time)
        self.network_loss = NetworkLossHandling(network_loss_action, network_loss_time)
        self.host = host
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
        #: what runs now (a move, a trajectory, a jog, a velocity jog) and servo mode
        self.motion = RunningMotion(self.view)
        kinematics_now = lambda: self.kinematics    # noqa: E731 - read when used
        self.settings = ArmSettings(self.send, self.view, self.frames_by_id, self.motion,
                                    self.state)
        self.servo = ServoCommands(model, self.send, self.link, self.view, self.motion,
                                   self.identity, kinematics_now, self.settings)
        self.moves = MoveCommands(model, self.send, self.link, self.view, self.motion,
                                  self.identity, kinematics_now, self.settings, self.servo,
                                  trajectory_step_num)
        self.mounting = ControllerMounting(self.send, self.view)
        #: the controller's own programs (``backend.programs``)
        self.programs = ControllerPrograms(self.send)
        #: the controller's trajectory recording (``backend.recording``)
        self.recording = ControllerRecording(self.send)
        #: the tool connector: JAKA's TIO commands, each setting read back (controller/tool_io.py)
        self.tool_io = ControllerToolIO(self.send)
        sensor = model.force_sensor.mounted_as(force_sensor)
        self._force_part = None
        if sensor.mounted:
            self._force_part = ControllerForce(sensor, model, self.send, self.link, self.view,
                                               self.motion, self.identity, kinematics_now)
            self.view.force_reading = self._force_part.reading
            self.force = self._force_part
        else:
            self.force = NoForceSensor("no force/torque sensor configured for this "
                                       f"controller's arm ({HOW_TO_MOUNT})")
        self._brought_up = threading.Event()

    # ---- life cycle -------------------------------------------------------------------
    def start(self) -> None:
        """Connect, then power on and enable if needed (like JAKA's driver). If the controller
        cannot be reached the backend still starts: it reports ``connected`` False, answers -1
        and keeps trying in the background."""
        link = self.link
        self.programs.start()
        self.tool_io.start()
        if link.start(wait=link.connect_timeout + link.first_packet_timeout + 0.5):
            self._brought_up.wait(2 * self.send.confirm_timeout + 3 * link.call_timeout)
        else:
            log.warning("starting without the controller at %s: %s", self.host,
                        link.down_message())

    def shutdown(self) -> None:
        self.motion.abort(Result.failure(Code.MOTION_STOPPED,
                                         "stopped: the driver is shutting down"))
        self.frames_by_id.stop()
        self.programs.stop_polling()
        self.tool_io.stop_polling()
        self.link.stop()

    @property
    def version(self) -> str:
        """The controller's version string (``get_version``), "" until read."""
        return self.identity.version

    def state(self) -> RobotState:
        return self.view.state(self.link.connected, self.motion.servo_mode,
                               int(self.programs.status().state))

    def states_since(self, after: float) -> list[RobotState]:
        return self.view.states_since(after, self.link.connected, self.motion.servo_mode,
                                      int(self.programs.status().state))

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
                     "reconnects": self.link.reconnects,
                     "servo_filter": self.servo.describe_filter()})
        if not self.link.connected:
            info["link"] = self.link.down_message()
        info.update(self.network_loss.describe())
        info["force sensor"] = "none configured" if self._force_part is None else "flange"
        info.update(self.identity.describe())
        info.update(self.frames_by_id.describe())
        latest = self.view.latest
        if latest is not None:
            info["homed"] = list(latest.homed)
            if latest.malformed:
                info["malformed status fields"] = list(latest.malformed)
        info.update(self.link.counters())
        return info

    def wait_for_sample(self, after: float, timeout: float) -> bool:
        """Until a status packet received later than ``after`` (s, ``time.time()``, as
        ``RobotState.stamp``) is here, at most ``timeout`` s: the packet wakes the wait (the
        node's publisher, the move follower)."""
        return self.view.wait_for_packet(after, timeout)

    # ---- link hooks -------------------------------------------------------------------------
    def _on_status(self, status, received: float) -> None:
        self.view.store(status, received)
        if status.emergency_stop or status.protective_stop or not status.enabled:
            self.motion.servo_mode = False   # the controller leaves servo mode on any of these
        self.frames_by_id.on_active(status.current_tool_id, status.current_user_id)
        self.tool_io.on_packet(status)
        self.motion.on_status(status, received)
        self.view.announce()       # last: the status thread blocks on its socket right after

    def _on_up(self, first: bool) -> None:
        """At every connection (supervisor thread): servo mode, identity, kinematic parameters
        and frames as the controller has them now; power and enable at the first only."""
        try:
            self.network_loss.send_to(self.send)    # first: a crash from now on is covered
            self.view.reset()
            self.motion.servo_mode = self.servo.read_mode()
            self.settings.read_rapid_rate()
            self.identity.read(self.send.read)
            self.mounting.read_at_connection()
            self.kinematics     # built now, not at the first linear move
            self.frames_by_id.read_all()
            self.programs.refresh()
            if self._force_part is not None:
                self._force_part.read_all()
            self.tool_io.read_all()
            if first:
                self._bring_up()
        finally:
            if first:
                self._brought_up.set()

    def _on_down(self, reason: str) -> None:
        self.motion.abort(Result.failure(
            Code.NOT_CONNECTED, f"connection to the controller lost ({reason}); the motion is "
            "not resumed after reconnecting"))
        self.motion.servo_mode = False   # unknown until is_in_servomove after the reconnect

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

    # ---- motion: MoveCommands (moves.py) -------------------------------------------------------
    def start_joint_move(self, q_target, speed, accel, duration=None) -> Result:
        return self.moves.start_joint_move(q_target, speed, accel, duration)

    def start_linear_move(self, target, speed, accel, ref_q=None, duration=None) -> Result:
        return self.moves.start_linear_move(target, speed, accel, ref_q, duration)

    def start_circular_move(self, mid, end, speed, accel, turns=0.0, mode=0,
                            duration=None) -> Result:
        return self.moves.start_circular_move(mid, end, speed, accel, turns, mode, duration)

    def start_trajectory(self, trajectory) -> Result:
        return self.moves.start_trajectory(trajectory)

    def jog(self, coord, axis, direction, speed) -> Result:
        return self.moves.jog(coord, axis, direction, speed)

    def jog_stop(self) -> Result:
        return self.moves.jog_stop()

    def stop_move(self) -> Result:
        return self.moves.stop_move()

    # ---- servo mode and what runs in it: ServoCommands (servo_commands.py) --------------------
    def servo_enable(self, on: bool) -> Result:
        return self.servo.enable(on)

    def servo_j(self, q_target, increment=None) -> Result:
        return self.servo.servo_j(q_target, increment)

    def servo_p(self, target, increment=None) -> Result:
        return self.servo.servo_p(target, increment)

    def velocity_jog(self, twist, in_tool) -> Result:
        return self.servo.velocity_jog(twist, in_tool)

    def set_servo_filter(self, spec) -> Result:
        return self.servo.set_filter(spec)

    # ---- the arm's settings: ArmSettings (arm_settings.py) -------------------------------------
    def set_speed_ratio(self, ratio: float) -> Result:
        return self.settings.set_speed_ratio(ratio)

    def speed_ratio(self) -> float:
        return self.settings.speed_ratio()

    def frames(self) -> tuple[np.ndarray, np.ndarray]:
        return self.settings.frames()

    def set_tool_frame(self, tool_id, pose) -> Result:
        return self.settings.set_tool_frame(tool_id, pose)

    def set_user_frame(self, user_id, pose) -> Result:
        return self.settings.set_user_frame(user_id, pose)

    def set_payload(self, tool_id, mass, centroid) -> Result:
        return self.settings.set_payload(tool_id, mass, centroid)

    def set_drag_mode(self, on: bool) -> Result:
        return self.settings.set_drag_mode(on)

    def set_collision_level(self, level) -> Result:
        return self.settings.set_collision_level(level)

    def collision_level(self) -> Result:
        return self.settings.collision_level()

    def set_installation_angle(self, mounting) -> Result:
        return self.mounting.set(mounting)

    def installation_angle(self) -> Result:
        return self.mounting.get()

    def set_io(self, signal, io_type, index, value) -> Result:
        return self.settings.set_io(signal, io_type, index, value)

    def get_io(self, signal, path, io_type, index) -> Result:
        return self.settings.get_io(signal, path, io_type, index)

    def clear_error(self) -> Result:
        return self.settings.clear_error()

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



