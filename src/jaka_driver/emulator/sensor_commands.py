"""The torque-sensor commands of JAKA's SDK (docs/protocol.md, "Torque sensor"), answered as a
controller without a sensor can answer them coherently:

* a **setting** is stored and read back at once by its get command (JAKA's SDK polls the get
  after the set and returns −61 if the value does not come back within 1 s): the sensor's tool
  payload, brand, communication settings, filter, soft limits, admittance and tool-drive
  tables, compliance type off, the force-control and drag frames, sensitivity and warning
  levels, compliant speed limits, reference point, sensitivity thresholds;
* what **needs a sensor** is refused with errorCode "2" and says so: switching the sensor or a
  force control on, payload identification, zeroing, reading forces, the compliance
  conditions;
* switching force control **off** is accepted (nothing is on), and the tool-drive state reads
  "off".

Types are checked as the SDK writes them (ints where it sends ints); ranges only where their
meaning is on record (axis 0–5, frames 0 tool / 1 world, flags 0/1, a port, percentages).
The twin's dynamics do not use any of it: the arm's own payload is ``set_payload``.
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping

from ..protocol.fields import SOFT_LIMIT_KEYS, Field
from ..protocol.torque_sensor import AXIS_COUNT
from .replies import ERROR_REFUSED, ERROR_REQUEST, Answer, Rejected
from .torque_sensor import TorqueSensorSettings
from .wire_fields import integer, number, required, shown, shown_name, text, vector

NO_SENSOR = "no torque sensor is connected (the emulated arm has none)"
_INT = (-(1 << 31), (1 << 31) - 1)      # an int whose range is not on record
_FRAME = (0, 1)                         # 0 tool, 1 world


#: get command → its reply fields, made from the settings
_GETTERS: Dict[str, Callable[[TorqueSensorSettings], dict]] = {
    "get_tool_payload": lambda s: {Field.MASS: float(s.payload_mass),
                                   Field.CENTROID: list(s.payload_centroid)},
    "get_torsenosr_brand": lambda s: {"sensor_brand": s.brand},
    "get_torque_sensor_comm": lambda s: {"type": s.comm_type, "ip_addr": s.ip_addr,
                                         "port": s.port},
    "get_torque_sensor_filter": lambda s: {"torqueSensorFilter": float(s.filter)},
    "get_torque_sensor_soft_limit": lambda s: {"torqueSensorSoftLimit": dict(s.soft_limit)},
    "get_admit_ctrl_config": lambda s: {"admitConfig": [list(row) for row in s.admittance]},
    "get_tool_drive_config": lambda s: {"force_ctrl_config": [list(r) for r in s.tool_drive]},
    "get_compliant_type": lambda s: {"sensor_compensation": s.sensor_compensation,
                                     "compliance_type": s.compliance_type},
    "get_ft_ctrl_frame": lambda s: {"ftFrame": s.ft_frame},
    "get_tool_drive_frame": lambda s: {"toolDragFrame": s.tool_drag_frame},
    "get_fusion_drive_sensitivity_level": lambda s: {"sensitivity_level": s.sensitivity_level},
    "get_motion_limit_warning_range": lambda s: {"range_level": s.range_level},
    "get_compliant_speed_limit": lambda s: {"speed_limit": float(s.speed_limit),
                                            "angular_speed_limit": float(s.angular_speed_limit)},
    "get_torque_ref_point": lambda s: {"ref_point": s.ref_point},
    "get_end_sensor_sensitivity_threshold": lambda s: {
        "threshold_percent": list(s.threshold_percent)},
}


def _needs_sensor(req: Mapping) -> Answer:
    raise Rejected(f"{shown_name(req)}: {NO_SENSOR}", ERROR_REFUSED)


class SensorCommands:
    """Handlers of the torque-sensor commands on ``settings``; ``max_mass`` (kg) bounds the tool
    payload."""

    def __init__(self, settings: TorqueSensorSettings, max_mass: float):
        self.s = settings
        self.max_mass = max_mass

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        table: Dict[str, Callable[[Mapping], Answer]] = {
            "set_tool_payload": self._set_tool_payload,
            "set_torsenosr_brand": lambda r: self._store(brand=integer(r, "sensor_brand", *_INT)),
            "set_torque_sensor_mode": lambda r: self._off_only(r, "sensor_mode", "mode"),
            "set_torque_sensor_comm": self._set_comm,
            "set_torque_sensor_filter": lambda r: self._store(
                filter=number(r, "torqueSensorFilter", lo=0.0)),
            "set_torque_sensor_soft_limit": self._set_soft_limit,
            "set_admit_ctrl_config": self._set_admittance,
            "set_tool_drive_config": self._set_tool_drive,
            "set_compliant_type": self._set_compliant_type,
            "set_ft_ctrl_frame": lambda r: self._store(ft_frame=integer(r, "ftFrame", *_FRAME)),
            "set_tool_drive_frame": lambda r: self._store(
                tool_drag_frame=integer(r, "toolDragFrame", *_FRAME)),
            "set_fusion_drive_sensitivity_level": lambda r: self._store(
                sensitivity_level=integer(r, "sensitivity_level", *_INT)),
            "set_motion_limit_warning_range": lambda r: self._store(
                range_level=integer(r, "range_level", *_INT)),
            "set_compliant_speed_limit": lambda r: self._store(
                speed_limit=number(r, "speed_limit", lo=0.0),
                angular_speed_limit=number(r, "angular_speed_limit", lo=0.0)),
            "set_torque_ref_point": lambda r: self._store(
                ref_point=integer(r, "ref_point", *_INT)),
            "set_end_sensor_sensitivity_threshold": self._set_threshold,
            # switching force control off: nothing is on
            "enable_admittance_ctrl": lambda r: self._off_only(r, "enable_flag"),
            "disable_force_control": lambda r: Answer(),
            "get_tool_drive_stat": lambda r: Answer({"enable_flag": 0, "drive_stat": 0}),
            # what needs a sensor
            "start_torq_sensor_payload_identify": _needs_sensor,
            "get_torq_sensor_identify_staus": _needs_sensor,
            "get_torq_sensor_payload_identify_result": _needs_sensor,
            "zero_end_sensor": _needs_sensor,
            "get_torque_sensor_data": _needs_sensor,
            "set_vel_compliant_ctrl": _needs_sensor,
            "set_compliance_condition": _needs_sensor,
        }
        for name, fields in _GETTERS.items():
            table[name] = lambda r, fields=fields: self._read(fields)
        return table

    # ---- helpers ----------------------------------------------------------------------------
    def _store(self, **values) -> Answer:
        """Store every value (all were read and checked before: a refusal changes nothing)."""
        with self.s.lock:
            for name, value in values.items():
                setattr(self.s, name, value)
        return Answer()

    def _read(self, fields: Callable[[TorqueSensorSettings], dict]) -> Answer:
        """The reply fields ``fields(settings)`` makes, under the settings' lock (a set of
        several values is never seen half done)."""
        with self.s.lock:
            return Answer(fields(self.s))

    def _off_only(self, req: Mapping, key: str, attr: str = "") -> Answer:
        value = integer(req, key, 0, 1)
        if value:
            raise Rejected(f"{shown_name(req)}: {key} 1 needs a torque sensor; {NO_SENSOR}",
                           ERROR_REFUSED)
        return self._store(**{attr: 0}) if attr else Answer()

    # ---- settings with more than one field --------------------------------------------------
    def _set_tool_payload(self, req: Mapping) -> Answer:
        mass = number(req, Field.MASS, lo=0.0, hi=self.max_mass)
        centroid = [float(c) for c in vector(req, Field.CENTROID, 3)]
        return self._store(payload_mass=mass, payload_centroid=centroid)

    def _set_comm(self, req: Mapping) -> Answer:
        comm_type = integer(req, "type", 0, 255)
        # JAKA's SDK keeps the address in 20 characters
        ip_addr = text(req, "ip_addr", default="" if comm_type == 1 else None, longest=19)
        port = integer(req, "port", 0, 65535, default=0 if comm_type == 1 else None)
        return self._store(comm_type=comm_type, ip_addr=ip_addr, port=port)

    def _set_soft_limit(self, req: Mapping) -> Answer:
        raw = required(req, "torqueSensorSoftLimit")
        if not isinstance(raw, Mapping):
            raise Rejected(f"{shown_name(req)}: 'torqueSensorSoftLimit' must be an object with "
                           f"{', '.join(SOFT_LIMIT_KEYS)}; got {shown(raw)}", ERROR_REQUEST)
        limits = {key: number({**raw, Field.CMD_NAME: shown_name(req)}, key, lo=0.0)
                  for key in SOFT_LIMIT_KEYS}
        return self._store(soft_limit=limits)

    def _set_admittance(self, req: Mapping) -> Answer:
        axis = integer(req, "axis", 0, AXIS_COUNT - 1)
        row = [integer(req, "opt", *_INT), number(req, "ftUser"), number(req, "ftReboundFK"),
               number(req, "ftConstant"), integer(req, "ftNnormalTrack", *_INT)]
        with self.s.lock:
            self.s.admittance[axis] = row
        return Answer()

    def _set_tool_drive(self, req: Mapping) -> Answer:
        axis = integer(req, "axis", 0, AXIS_COUNT - 1)
        row = [integer(req, "opt", *_INT), number(req, "rigidity"), number(req, "rebound")]
        with self.s.lock:
            self.s.tool_drive[axis] = row
        return Answer()

    def _set_compliant_type(self, req: Mapping) -> Answer:
        compensation = integer(req, "sensor_compensation", *_INT)
        compliance = integer(req, "compliance_type", *_INT)
        if compensation or compliance:
            raise Rejected(f"{shown_name(req)}: sensor compensation and compliance control "
                           f"need a torque sensor (only 0/0, off, is possible); {NO_SENSOR}",
                           ERROR_REFUSED)
        return self._store(sensor_compensation=0, compliance_type=0)

    def _set_threshold(self, req: Mapping) -> Answer:
        values = vector(req, "threshold_percent", AXIS_COUNT)
        if not all(0.0 <= v <= 100.0 for v in values):
            raise Rejected(f"{shown_name(req)}: 'threshold_percent' must be 6 percentages in "
                           f"[0, 100]; got {shown(values.tolist())}", ERROR_REQUEST)
        return self._store(threshold_percent=[float(v) for v in values])
