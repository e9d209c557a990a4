"""The torque-sensor and force-control commands of an emulated arm that carries the sensor
(``--force-sensor``; docs/controller.md, "The emulator"): answered from the twin's sensor and
force control (the backend's ``force`` facet, :class:`~jaka_driver.backend.force.Force`), so
what the twin refuses — the sensor off, force control running, the arm moving or in the wrong
mode — is refused here with "2" and the twin's reason, and what it does the arm does.

They take the place of :mod:`.sensor_commands`' answers where a sensor makes a difference; the
settings no sensor touches (brand, communication, sensitivity and warning levels, the
compliant speed limit, the reference point, the sensitivity thresholds) stay stored there.

Wire units (docs/protocol.md, "Torque sensor"; JAKA's SDK passes them unconverted, and no
controller's unit is on record for the first two): ``ftReboundFK`` and ``rebound`` N/mm on x
y z and N·m/rad on rx ry rz, ``torqueSensorFilter`` Hz; forces N, moments N·m, mass kg,
centroid mm, the identification's end pose deg, as on record. Values are checked with
the force settings' value checks the driver's door applies too (:mod:`jaka_driver.backend.
force_checks`, the sensor's range from the arm's configuration) and refused with "1" naming the
field.

``enable_admittance_ctrl`` is the one command of every force control (JAKA's SDK's
enable_tool_drive sends it too), so ``enable_flag`` 1 starts what the settings describe:
constant force or velocity compliance when the compliance type says so; with type 0,
admittance when an admittance axis is on, else tool drive when a tool-drive axis is on.
``get_tool_drive_stat``'s ``enable_flag`` is that command's state: 1 while any of them runs.
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping

from ..backend import force_checks as fcheck
from ..backend.force import (AdmittanceAxis, ComplianceType, ForceMode, ReadingType,
                             ToolDriveAxis)
from ..common.results import CommandRefused, Result
from ..protocol.fields import SOFT_LIMIT_KEYS, Field
from ..protocol.torque_sensor import AXIS_COUNT
from .replies import ERROR_REQUEST, Answer, Rejected
from .twin_controller import TwinController
from .wire_fields import integer, joints, number, required, shown, shown_name, vector

#: force control that holds ``get_tool_drive_stat``'s enable_flag at 1
_RUNNING = (ForceMode.ADMITTANCE, ForceMode.CONSTANT_FORCE, ForceMode.VELOCITY_COMPLIANCE,
            ForceMode.TOOL_DRIVE)


class ForceCommands:
    """Handlers of the commands a sensor answers, on ``controller``'s twin (see the module)."""

    def __init__(self, controller: TwinController):
        self.c = controller
        self.force = controller.backend.force
        self.range = self.force.settings().range

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        return {
            "set_torque_sensor_mode": self._set_mode,
            "zero_end_sensor": lambda r: self._done(r, self.force.zero()),
            "set_tool_payload": self._set_tool_payload,
            "get_tool_payload": lambda r: Answer(self._payload_fields(
                self.force.settings().tool_payload)),
            "set_torque_sensor_filter": lambda r: self._done(r, self.force.set_filter(
                self._checked(r, fcheck.filter_hz, number(r, "torqueSensorFilter")))),
            "get_torque_sensor_filter": lambda r: Answer(
                {"torqueSensorFilter": float(self.force.settings().filter_hz)}),
            "set_torque_sensor_soft_limit": self._set_soft_limit,
            "get_torque_sensor_soft_limit": lambda r: Answer({"torqueSensorSoftLimit": dict(
                zip(SOFT_LIMIT_KEYS, map(float, self.force.settings().soft_limit)))}),
            "set_admit_ctrl_config": self._set_admittance,
            "get_admit_ctrl_config": lambda r: Answer({"admitConfig": [
                [int(a.enabled), float(a.ft_user), float(a.rebound),
                 float(a.constant), int(a.normal_track)]
                for a in self.force.settings().admittance]}),
            "set_tool_drive_config": self._set_tool_drive,
            "get_tool_drive_config": lambda r: Answer({"force_ctrl_config": [
                [int(a.enabled), float(a.rigidity), float(a.rebound)]
                for a in self.force.settings().tool_drive]}),
            "set_compliant_type": self._set_compliant_type,
            "get_compliant_type": lambda r: Answer(self._compliant_type()),
            "set_vel_compliant_ctrl": self._set_velocity_compliance,
            "set_compliance_condition": lambda r: self._done(r, self.force.set_condition(
                self._checked(r, fcheck.wrench_limits, "compliant_condition",
                              vector(r, "compliant_condition", AXIS_COUNT), self.range,
                              zero_allowed=True))),
            "set_ft_ctrl_frame": lambda r: self._done(r, self.force.set_frame(
                integer(r, "ftFrame", 0, 1))),
            "get_ft_ctrl_frame": lambda r: Answer({"ftFrame": int(self.force.settings().frame)}),
            "set_tool_drive_frame": lambda r: self._done(r, self.force.set_tool_drive_frame(
                integer(r, "toolDragFrame", 0, 1))),
            "get_tool_drive_frame": lambda r: Answer(
                {"toolDragFrame": int(self.force.settings().tool_drive_frame)}),
            "enable_admittance_ctrl": self._enable,
            "disable_force_control": lambda r: self._done(r, self.force.disable()),
            "get_tool_drive_stat": lambda r: Answer({
                "enable_flag": int(self.force.settings().mode in _RUNNING), "drive_stat": 0}),
            "start_torq_sensor_payload_identify": self._start_identification,
            "get_torq_sensor_identify_staus": lambda r: Answer(
                {"identify_status": int(self.force.identification_status().state)}),
            "get_torq_sensor_payload_identify_result": self._identification_result,
            "get_torque_sensor_data": self._sensor_data,
        }

    # ---- helpers ----------------------------------------------------------------------------
    @staticmethod
    def _done(req: Mapping, result: Result) -> Answer:
        """The twin's answer: a refusal becomes "2" with its reason."""
        if not result.ok:
            raise Rejected(f"{shown_name(req)}: {result.message}")
        return Answer()

    @staticmethod
    def _checked(req: Mapping, check: Callable, *args, **kwargs):
        """A value through the door's check; its refusal becomes "1" naming the field."""
        try:
            return check(*args, **kwargs)
        except CommandRefused as refusal:
            raise Rejected(f"{shown_name(req)}: {refusal.message}", ERROR_REQUEST) from None

    @staticmethod
    def _payload_fields(payload) -> dict:
        return {Field.MASS: float(payload.mass),
                Field.CENTROID: [float(c) * 1000.0 for c in payload.centroid]}

    def _compliant_type(self) -> dict:
        s = self.force.settings()
        return {"sensor_compensation": int(s.compensation),
                "compliance_type": int(s.compliance_type)}

    # ---- the sensor -------------------------------------------------------------------------
    def _set_mode(self, req: Mapping) -> Answer:
        return self._done(req, self.force.set_sensor_on(bool(integer(req, "sensor_mode", 0,
                                                                      1))))

    def _set_tool_payload(self, req: Mapping) -> Answer:
        mass = number(req, Field.MASS, lo=0.0, hi=self.c.model.max_payload_kg)
        centroid = vector(req, Field.CENTROID, 3)
        return self._done(req, self.force.set_tool_payload(mass, centroid / 1000.0))

    def _set_soft_limit(self, req: Mapping) -> Answer:
        raw = required(req, "torqueSensorSoftLimit")
        if not isinstance(raw, Mapping):
            raise Rejected(f"{shown_name(req)}: 'torqueSensorSoftLimit' must be an object with "
                           f"{', '.join(SOFT_LIMIT_KEYS)}; got {shown(raw)}", ERROR_REQUEST)
        inner = {**raw, Field.CMD_NAME: shown_name(req)}
        values = [number(inner, key) for key in SOFT_LIMIT_KEYS]
        return self._done(req, self.force.set_soft_limit(self._checked(
            req, fcheck.wrench_limits, "torqueSensorSoftLimit", values, self.range,
            zero_allowed=False)))

    def _sensor_data(self, req: Mapping) -> Answer:
        """One reading of the latest sample: ``type`` 1 actual, 2 general, 3 real
        (JAKA's numbering, sent unchanged by its SDK); with the
        sensor off, status 0 and zeros (what the status packet says too)."""
        kind = integer(req, "type", *ReadingType.span())
        reading = self.c.state().force
        if reading is None:
            return Answer({"status": 0, "errcode": 0, "data": [0.0] * AXIS_COUNT})
        return Answer({"status": int(reading.status), "errcode": int(reading.errcode),
                       "data": [float(v) for v in reading.of(kind)]})

    # ---- settings of force control ----------------------------------------------------------
    def _set_admittance(self, req: Mapping) -> Answer:
        axis = integer(req, "axis", 0, AXIS_COUNT - 1)
        opt = integer(req, "opt", 0, 1)
        normal_track = integer(req, "ftNnormalTrack", 0, 1)
        # the door refuses normal tracking (JAKA deprecates it): a controller keeps the flag
        config = self._checked(req, fcheck.admittance, axis, opt, number(req, "ftUser"),
                               number(req, "ftReboundFK"), number(req, "ftConstant"), 0,
                               self.range)
        config = AdmittanceAxis(config.enabled, config.ft_user, config.rebound, config.constant,
                                bool(normal_track))
        return self._done(req, self.force.set_admittance(axis, config))

    def _set_tool_drive(self, req: Mapping) -> Answer:
        axis = integer(req, "axis", 0, AXIS_COUNT - 1)
        config: ToolDriveAxis = self._checked(req, fcheck.tool_drive, axis,
                                              integer(req, "opt", 0, 1),
                                              number(req, "rigidity"), number(req, "rebound"),
                                              self.range)
        return self._done(req, self.force.set_tool_drive(axis, config))

    def _set_compliant_type(self, req: Mapping) -> Answer:
        compensation = integer(req, "sensor_compensation", 0, 1)
        kind = integer(req, "compliance_type", 0, 2)
        return self._done(req, self.force.set_compliance_type(bool(compensation), kind))

    def _set_velocity_compliance(self, req: Mapping) -> Answer:
        raw = vector(req, "compliant_ctrl", 5)
        if raw[0] != int(raw[0]):
            raise Rejected(f"{shown_name(req)}: 'compliant_ctrl'[0] (vc_level) must be an "
                           f"integer; got {shown(raw[0])}", ERROR_REQUEST)
        config = self._checked(req, fcheck.velocity_compliance, int(raw[0]), raw[1:])
        return self._done(req, self.force.set_velocity_compliance(config))

    # ---- running force control ----------------------------------------------------------------
    def _enable(self, req: Mapping) -> Answer:
        """``enable_flag`` 1 starts what the settings describe (see the module); 0 ends it."""
        if not integer(req, "enable_flag", 0, 1):
            return self._done(req, self.force.disable())
        what = shown_name(req)
        s = self.force.settings()
        with self.c.lock:
            self.c.require_can_move(what)
            if s.compliance_type == ComplianceType.VELOCITY:
                return self._done(req, self.force.enable_admittance(True))
            self.c.require_still(what)
            if s.compliance_type == ComplianceType.CONSTANT_FORCE or any(
                    a.enabled for a in s.admittance):
                if not any(a.enabled for a in s.admittance):
                    raise Rejected(f"{what}: constant force needs an admittance axis on "
                                   "(set_admit_ctrl_config opt 1)")
                return self._done(req, self.force.enable_admittance(True))
            if any(a.enabled for a in s.tool_drive):
                return self._done(req, self.force.enable_tool_drive(True))
            raise Rejected(f"{what}: no admittance or tool drive axis is on "
                           "(set_admit_ctrl_config or set_tool_drive_config opt 1 first)")

    # ---- payload identification ----------------------------------------------------------------
    def _start_identification(self, req: Mapping) -> Answer:
        """On the way to the end pose ``jointPosition`` (deg), as the twin identifies with one
        pose; the arm moves at once (refused while anything moves, as a move in servo or drag
        mode is)."""
        q = joints(req)
        what = shown_name(req)
        with self.c.lock:
            self.c.require_can_move(what)
            self.c.require_still(what)
            self.c.check_limits(q, what)
            return self._done(req, self.force.start_identification([q]))

    def _identification_result(self, req: Mapping) -> Answer:
        status = self.force.identification_status()
        if status.result is None:
            raise Rejected(f"{shown_name(req)}: no identification result "
                           f"({status.message})")
        return Answer(self._payload_fields(status.result))

