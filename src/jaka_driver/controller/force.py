"""The flange force/torque sensor and force control on a controller:
:class:`~jaka_driver.backend.force.Force` with JAKA's commands, sent as JAKA's SDK sends them
(docs/protocol.md, "Torque sensor"; the encoders are :mod:`jaka_driver.protocol.torque_sensor`)
— the transport of :class:`~jaka_driver.backend.force_rules.ForceRules`, where the modes, what
may start while what runs, the refusals and the answers are written once for both backends.

**Each setting is read back** as JAKA's SDK reads a setting back (its get every 100 ms for up to
1 s, :meth:`~.commander.Commander.settled`; else refused with 2: the controller did not do it)
where the controller has a get: the sensor's tool payload, filter, soft limit, an admittance or
tool-drive axis (its row of the table), the compliance type, both frames, and force control on
or off (``get_tool_drive_stat``'s ``enable_flag``: ``enable_admittance_ctrl`` is the one command
of admittance, constant force, velocity compliance and tool drive, so the flag is the state of
that command). Switching the sensor has no get: the status packets show it (``torqsensor``'s
status), and the request waits up to 1 s for one that does. The velocity-compliance levels and
the compliance condition have no get at all: accepted is all there is.

**The readings** come with every status packet (``torqsensor``, no request per sample):
:func:`.status_view.sensor_reading`. **What runs**: admittance, constant force and tool drive hold the arm,
so they take the backend's one slot (:class:`~.running_motion.ForceControlRun`: moves are
refused meanwhile, stop_move ends them, a halt in a packet ends them); velocity compliance
lets moves run and only slows them, so it is a flag here. **Identification**:
``start_torq_sensor_payload_identify`` with the end pose, then ``get_torq_sensor_identify_staus``
polled every :data:`IDENTIFY_POLL` s until it reads done or failed, then
``get_torq_sensor_payload_identify_result`` (:mod:`.payload_identification`) — behind the same
started-motion contract as the twin's (:class:`~.running_motion.IdentificationRun` in the
slot).

Refusals as on the twin: the sensor off (as the packets report it) -9, force control running
-10, the arm moving -10; a controller identifies on the way to one end pose only (-2 for more).
What the controller would refuse itself comes back as 2 with its message.

Wire units where JAKA's SDK passes a value unconverted and no controller's unit is on record
(one choice, docs/protocol.md): ``ftReboundFK`` and tool drive's ``rebound`` N/mm on x y z and
N·m/rad on rx ry rz (the request's and the facet's own: sent and read back unconverted),
``torqueSensorFilter`` Hz; forces N, moments N·m, mass kg, centroid mm, joints deg as on
record. The facet's units otherwise (jaka_driver.backend.force).
"""
from __future__ import annotations

import dataclasses
import logging
import threading
import time
from typing import Callable, Optional, Sequence, Tuple

import numpy as np

from ..backend.completion import Completion
from ..backend.force import (AXES, AdmittanceAxis, ComplianceType, ForceMode, ForceReading,
                             ForceSettings, IdentificationState, IdentificationStatus,
                             SensorPayload, ToolDriveAxis, VelocityCompliance)
from ..backend.force_rules import ForceRules
from ..common.models import RobotModel
from ..common.results import Code, CommandRefused, Result
from ..common.sensor_spec import ForceSensorSpec
from ..kinematics import Kinematics
from ..protocol import torque_sensor as wire
from ..protocol.fields import Field
from ..protocol.replies import reply_payload
from ..protocol.status_packet import StatusPacket
from .arm_identity import ArmIdentity
from .arm_settings import PACKET_CATCH_UP
from .commander import SETTLE_TIMEOUT, Commander
from .connection import ControllerLink
from .parts import hand_in
from .payload_identification import follow_identification, identification_plan
from .running_motion import ForceControlRun, IdentificationRun, RunningMotion, keeps_out
from .status_view import StatusView, sensor_reading

log = logging.getLogger(__name__)

#: A number read back matches what was sent within this (replies carry 6 decimals)
READBACK = 1e-3


class ControllerForce(ForceRules):
    """Force control on a controller whose arm, of ``model``, carries the sensor ``spec`` (see
    the module). What it works with is handed to it, as to the backend's other parts
    (:class:`~.parts.RequestPart`): requests through ``send`` over ``link``, the latest packet
    from ``view``, the one slot of what runs in ``motion``, motion allowed by ``identity``,
    ``kinematics()`` the local kinematics (the flange's orientation for a reading without
    ``real``). Not a RequestPart: its ``settings()`` is the facet's, not the arm's. The rules
    are :class:`~jaka_driver.backend.force_rules.ForceRules`'; this is their transport: what
    the controller was last read back or accepted as is kept (the sensor's own state and tool
    payload come from the packets)."""

    SENSOR_OFF_SOURCE = ", as the controller reports it"

    def __init__(self, spec: ForceSensorSpec, model: RobotModel, send: Commander,
                 link: ControllerLink, view: StatusView, motion: RunningMotion,
                 identity: ArmIdentity, kinematics: Callable[[], Kinematics]):
        super().__init__(spec)
        hand_in(self, model, send, link, view, motion, identity, kinematics)

    # ---- the packets -----------------------------------------------------------------------
    def reading(self, status: StatusPacket, q: np.ndarray) -> Optional[ForceReading]:
        """:func:`.status_view.sensor_reading` of ``status``, the flange turned as at joints
        ``q`` (rad)."""
        return sensor_reading(status, lambda: self.kinematics().flange_pose(q)[:3, :3],
                              self.view.gravity)

    def _sensor_status(self) -> Optional[int]:
        latest = self.view.latest
        ts = None if latest is None else latest.torque_sensor
        return None if ts is None else ts.status

    # ---- what it is and does ---------------------------------------------------------------
    def settings(self) -> ForceSettings:
        latest = self.view.latest
        ts = None if latest is None else latest.torque_sensor
        s = self._kept.value
        if ts is not None:
            s = dataclasses.replace(s, tool_payload=SensorPayload(
                ts.payload_mass, np.asarray(ts.payload_centroid) / 1000.0))
        return dataclasses.replace(s, sensor_on=bool(ts is not None and ts.status != 0),
                                   mode=self._mode())

    def sensor_on(self) -> bool:
        return bool(self._sensor_status())

    def running_mode(self) -> Optional[str]:
        if self.motion.running(IdentificationRun) is not None:
            return ForceMode.IDENTIFYING
        run = self.motion.running(ForceControlRun)
        return None if run is None else run.mode

    def read_all(self) -> None:
        """Every setting the controller can be asked for, as it has it now (at every
        connection: a pendant may have changed them); one that cannot be read keeps what was
        known, and is logged."""
        reads = (
            ("admittance", wire.get_admit_ctrl_config(), wire.reply_admit_ctrl_config,
             lambda rows: {"admittance": tuple(_admittance_axis(i, r)
                                               for i, r in enumerate(rows))}),
            ("tool drive", wire.get_tool_drive_config(), wire.reply_tool_drive_config,
             lambda rows: {"tool_drive": tuple(_tool_drive_axis(i, r)
                                               for i, r in enumerate(rows))}),
            ("compliance type", wire.get_compliant_type(), wire.reply_compliant_type,
             lambda v: {"compensation": bool(v[0]), "compliance_type": int(v[1])}),
            ("force-control frame", wire.get_ft_ctrl_frame(), _ft_frame,
             lambda v: {"frame": v}),
            ("tool drive frame", wire.get_tool_drive_frame(), _tool_drag_frame,
             lambda v: {"tool_drive_frame": v}),
            ("filter", wire.get_torque_sensor_filter(), wire.reply_torque_sensor_filter,
             lambda v: {"filter_hz": float(v)}),
            ("soft limit", wire.get_torque_sensor_soft_limit(),
             wire.reply_torque_sensor_soft_limit, lambda v: {"soft_limit": v}),
            ("tool payload", wire.get_tool_payload(), reply_payload,
             lambda v: {"tool_payload": SensorPayload(float(v[0]), np.asarray(v[1]) / 1000.0)}),
        )
        for what, request, accessor, changes in reads:
            try:
                self._kept.update(**changes(self.send.read(request, accessor)))
            except CommandRefused as refusal:
                log.info("the controller's torque-sensor %s is unknown: %s", what,
                         refusal.message)

    # ---- the transport's own refusals ----------------------------------------------------------
    def _require_arm_ready(self, what: str) -> None:
        self.identity.require_motion(what)

    def _check_tool_drive(self, s: ForceSettings) -> None:
        if s.compliance_type != ComplianceType.NONE or any(a.enabled for a in s.admittance):
            raise CommandRefused(Code.WRONG_MODE, "tool drive refused: a controller starts "
                                 "tool drive and admittance with one command "
                                 "(enable_admittance_ctrl), and with "
                                 + ("compliance type " + ComplianceType(s.compliance_type)
                                    .name.lower() if s.compliance_type else
                                    "an admittance axis on") + " it would start that instead: "
                                 "set the compliance type 0 and every admittance axis's opt 0 "
                                 "first")

    def _check_poses(self, poses: Sequence[np.ndarray]) -> None:
        if len(poses) != 1:
            raise CommandRefused(Code.INVALID_PARAMETER, "payload identification on a "
                                 "controller takes one end pose "
                                 "(start_torq_sensor_payload_identify identifies on the way "
                                 f"there); got {len(poses)} poses")

    # ---- the sensor --------------------------------------------------------------------------
    def _send_sensor_on(self, on: bool) -> str:
        """``set_torque_sensor_mode``; no get: confirmed by a packet showing it (1 s)."""
        self.send.accepted(wire.set_torque_sensor_mode(on))
        if not self.view.wait_until(lambda s: s.torque_sensor is not None
                                    and bool(s.torque_sensor.status) == on, SETTLE_TIMEOUT):
            raise CommandRefused(Code.CONTROLLER_REJECTED, f"sensor {'on' if on else 'off'}: "
                                 "the controller acknowledged set_torque_sensor_mode but its "
                                 f"status packets still show it {'off' if on else 'on'} after "
                                 f"{SETTLE_TIMEOUT:g} s")
        return " (the status packets show it)"

    def _send_zero(self) -> str:
        """``zero_end_sensor`` (no get); answered once a packet from after the reply is in,
        so the next sample is zeroed."""
        self.send.accepted(wire.zero_end_sensor())
        self.view.wait_for_packet(time.time(), 4 * self.link.call_timeout)
        return "sensor zeroed (zero_end_sensor accepted)"

    def _send_tool_payload(self, payload: SensorPayload) -> Tuple[SensorPayload, str]:
        c_mm = payload.centroid * 1000.0
        request = wire.set_tool_payload(payload.mass, c_mm)
        sent = float(request["mass"])       # the wire's 2 decimals
        read = self.send.settled(
            request, wire.get_tool_payload(), reply_payload,
            lambda v: abs(v[0] - sent) < READBACK and np.allclose(v[1], c_mm, atol=READBACK),
            "the sensor's tool payload")
        kept = SensorPayload(float(read[0]), np.asarray(read[1]) / 1000.0)
        self._kept.update(tool_payload=kept)
        # the packets carry it too (settings() reads it there): answer once one shows it
        self.view.wait_until(lambda status: status.torque_sensor is not None and abs(
            status.torque_sensor.payload_mass - read[0]) < READBACK, PACKET_CATCH_UP)
        return kept, " (read back)"

    def _send_filter(self, cutoff_hz: float) -> Tuple[float, str]:
        read = self.send.settled(wire.set_torque_sensor_filter(cutoff_hz),
                                 wire.get_torque_sensor_filter(), wire.reply_torque_sensor_filter,
                                 lambda v: abs(v - cutoff_hz) < READBACK, "the sensor filter")
        self._kept.update(filter_hz=float(read))
        return float(read), " (read back)"

    def _send_soft_limit(self, limit: np.ndarray) -> Tuple[np.ndarray, str]:
        read = self.send.settled(wire.set_torque_sensor_soft_limit(limit),
                                 wire.get_torque_sensor_soft_limit(),
                                 wire.reply_torque_sensor_soft_limit,
                                 lambda v: np.allclose(v, limit, atol=READBACK),
                                 "the sensor soft limit")
        self._kept.update(soft_limit=read)
        return read, " (read back)"

    # ---- settings of force control -----------------------------------------------------------
    def _send_admittance(self, axis: int, config: AdmittanceAxis) -> Tuple[AdmittanceAxis, str]:
        request = wire.set_admit_ctrl_config(axis, config.enabled, config.ft_user,
                                             config.constant, config.normal_track,
                                             config.rebound)
        sent = wire.AdmitRow(int(config.enabled), float(request["ftUser"]),
                             float(request["ftReboundFK"]), float(request["ftConstant"]),
                             int(config.normal_track))
        return self._set_axis("admittance", axis, request, sent, wire.get_admit_ctrl_config(),
                              wire.reply_admit_ctrl_config, _admittance_axis), " (read back)"

    def _set_axis(self, table: str, axis: int, request, sent, readback, reply, as_axis):
        """Send ``request`` (one axis of ``table``), read the table back until the axis's row
        is ``sent``; keep and return the row read, as the facet's axis (``as_axis``)."""
        rows = self.send.settled(request, readback, reply,
                                 lambda rows: _same_row(rows[axis], sent),
                                 f"{table.replace('_', ' ')} {AXES[axis]}")
        row = as_axis(axis, rows[axis])
        self._kept.update_row(table, axis, row)
        return row

    def _send_compliance_type(self, compensation: bool, kind: int) -> str:
        want = (int(compensation), kind)
        self.send.settled(wire.set_compliant_type(*want), wire.get_compliant_type(),
                          wire.reply_compliant_type, lambda v: tuple(v) == want,
                          "the compliance type")
        return " (read back)"

    def _send_velocity_compliance(self, config: VelocityCompliance) -> str:
        """``set_vel_compliant_ctrl``: the controller has no get of it."""
        self.send.accepted(wire.set_vel_compliant_ctrl(config.level, config.rates))
        return " (accepted; the controller has no get of it)"

    def _send_tool_drive(self, axis: int, config: ToolDriveAxis) -> Tuple[ToolDriveAxis, str]:
        request = wire.set_tool_drive_config(axis, config.enabled, config.rigidity,
                                             config.rebound)
        sent = wire.ToolDriveRow(int(config.enabled), float(request["rigidity"]),
                                 float(request["rebound"]))
        return self._set_axis("tool_drive", axis, request, sent, wire.get_tool_drive_config(),
                              wire.reply_tool_drive_config, _tool_drive_axis), " (read back)"

    def _send_frame(self, frame: int) -> str:
        self.send.settled(wire.set_ft_ctrl_frame(frame), wire.get_ft_ctrl_frame(), _ft_frame,
                          lambda v: v == frame, "the force-control frame")
        return " (read back)"

    def _send_tool_drive_frame(self, frame: int) -> str:
        self.send.settled(wire.set_tool_drive_frame(frame), wire.get_tool_drive_frame(),
                          _tool_drag_frame, lambda v: v == frame, "the tool drive frame")
        return " (read back)"

    def _send_condition(self, wrench: np.ndarray) -> str:
        """``set_compliance_condition``: the controller has no get of it."""
        self.send.accepted(wire.set_compliance_condition(wrench))
        return " (accepted; the controller has no get of it)"

    # ---- running force control ---------------------------------------------------------------
    def _switch(self, on: bool, what: str) -> None:
        """``enable_admittance_ctrl`` ``on``, read back as ``get_tool_drive_stat``'s
        ``enable_flag``."""
        self.send.settled(wire.enable_admittance_ctrl(on), wire.get_tool_drive_stat(),
                          wire.reply_tool_drive_stat, lambda v: bool(v[0]) == on, what)

    def _start_velocity_compliance(self) -> None:
        self._switch(True, "velocity compliance on")

    def _start_run(self, mode: str, label: str, frame: int, s: ForceSettings) -> None:
        run = ForceControlRun(mode, self._switch_off_quietly)
        self.motion.take(run, keeps_out(label))
        try:
            self._switch(True, f"{label} on")
        except CommandRefused:
            run.end()
            raise

    def _switch_off_quietly(self) -> None:
        """Force control off when its run is aborted (stop_move, shutdown), if the link is up;
        a failure is logged (the run has ended on this side either way)."""
        if not self.link.connected:
            return
        try:
            self.send.accepted(wire.disable_force_control())
        except CommandRefused as refusal:
            log.warning("disable_force_control after a stop failed: %s", refusal.message)

    def _stop(self, mode: str) -> None:
        self._switch(False, f"{mode.replace('_', ' ')} off")
        self._end_run()

    def _end_run(self) -> None:
        """Force control is off on the controller (it said so): off here too."""
        run = self.motion.running(ForceControlRun)
        if run is not None:
            run.end()

    def _send_disable(self, mode: str) -> None:
        """``disable_force_control``, read back as ``enable_flag`` 0; sent whatever runs
        (also when the driver knows of nothing running: a pendant may have started it)."""
        self.send.settled(wire.disable_force_control(), wire.get_tool_drive_stat(),
                          wire.reply_tool_drive_stat, lambda v: not v[0], "force control off")
        self._end_run()

    # ---- payload identification --------------------------------------------------------------
    def _identify(self, what: str, poses: Sequence[np.ndarray]) -> Result:
        q_end = np.asarray(poses[0], float)
        latest = self.view.latest
        planned = identification_plan(self.model, None if latest is None
                                      else latest.joint_position, q_end)
        completion = Completion()
        self.motion.take(IdentificationRun(completion), keeps_out(what))
        try:
            self.send.accepted(wire.start_torq_sensor_payload_identify(q_end))
        except CommandRefused as refusal:
            completion.finish(refusal.result())
            raise
        self._kept.report(IdentificationStatus(IdentificationState.RUNNING, 0.0,
                                                f"{what} started"))
        threading.Thread(target=follow_identification,
                         args=(self.send, completion, planned, self._kept.report),
                         name="jaka-identify", daemon=True).start()
        return Result.success(f"{what} started on the way to the end pose (planned "
                              f"{planned:.1f} s, the controller's pace)", (completion, planned))


def _same_row(read, sent) -> bool:
    """A table row read back equals the one sent (ints exactly, numbers within the reply's
    decimals)."""
    return all(abs(float(a) - float(b)) < READBACK for a, b in zip(read, sent))


def _admittance_axis(axis: int, row: wire.AdmitRow) -> AdmittanceAxis:
    return AdmittanceAxis(bool(row.opt), float(row.ft_user), float(row.ft_rebound),
                          float(row.ft_constant), bool(row.ft_normal_track))


def _tool_drive_axis(axis: int, row: wire.ToolDriveRow) -> ToolDriveAxis:
    return ToolDriveAxis(bool(row.opt), float(row.rigidity), float(row.rebound))


def _ft_frame(reply) -> int:
    return wire.reply_int(reply, Field.FT_FRAME)


def _tool_drag_frame(reply) -> int:
    return wire.reply_int(reply, Field.TOOL_DRAG_FRAME)
