"""The end torque sensor's settings as the emulated controller keeps them, and the status
packet's ``torqsensor``. A controller keeps a sensor's configuration whether one is connected
or not, and JAKA's SDK reads a setting back after it sets it (:mod:`.sensor_commands` answers
the commands; docs/protocol.md, "Torque sensor"). An arm that carries the sensor
(``--force-sensor``) answers what the sensor makes a difference to from the twin's sensor
(:mod:`.force_commands`); the rest stays stored here.

Units as on the wire: mass kg, centroid mm, forces N, torques N·m; the rest as the client sends
them (their units are the SDK's, which it passes unconverted).
"""
from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..backend.force import ForceReading
from ..protocol.fields import SOFT_LIMIT_KEYS
from ..protocol.torque_sensor import AXIS_COUNT



@dataclass
class TorqueSensorSettings:
    """Every stored value, with the value a controller with nothing configured reports. The
    communication settings default to those of the recorded Zu 5s packet (commType 0,
    192.168.2.100:8080), taken to be the factory values."""

    lock: threading.Lock = field(default_factory=threading.Lock, repr=False, compare=False)
    brand: int = 0
    mode: int = 0                       # set_torque_sensor_mode: 0 off (1 needs a sensor)
    comm_type: int = 0
    ip_addr: str = "192.168.2.100"
    port: int = 8080
    payload_mass: float = 0.0           # kg, set_tool_payload: what hangs on the sensor
    payload_centroid: List[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])   # mm
    filter: float = 0.0                 # torqueSensorFilter
    soft_limit: Dict[str, float] = field(
        default_factory=lambda: {key: 0.0 for key in SOFT_LIMIT_KEYS})
    #: per axis: [opt, ft_user, ft_rebound, ft_constant, ft_normal_track]
    admittance: List[list] = field(
        default_factory=lambda: [[0, 0.0, 0.0, 0.0, 0] for _ in range(AXIS_COUNT)])
    #: per axis: [opt, rigidity, rebound]
    tool_drive: List[list] = field(
        default_factory=lambda: [[0, 0.0, 0.0] for _ in range(AXIS_COUNT)])
    sensor_compensation: int = 0
    compliance_type: int = 0
    ft_frame: int = 0                   # 0 tool, 1 world
    tool_drag_frame: int = 0            # 0 tool, 1 world
    sensitivity_level: int = 0          # fusion drive sensitivity
    range_level: int = 0                # motion limit warning range
    speed_limit: float = 0.0            # compliant speed limit, as sent
    angular_speed_limit: float = 0.0
    ref_point: int = 0                  # torque reference point
    threshold_percent: List[float] = field(default_factory=lambda: [0.0] * AXIS_COUNT)

    def monitor(self, sensor: Optional[tuple] = None) -> list:
        """The status packet's ``torqsensor``. Without a sensor, the recorded layout
        ``[[commType, [ip, port], [mass, [x, y, z]]], [status, errcode, [6], [6]]]``: status 0
        and errcode 0 (no sensor running), zero forces, the stored payload. With one,
        ``sensor`` = (payload mass kg, centroid mm, the sample's :class:`ForceReading` or None
        while it is off): its payload, and ``[status, errcode, actual, general, real]`` — all
        three vectors, as JAKA's SDK reads them (:func:`sensor_monitor`). Whole millimetres go
        out as integers, as the recorded packet writes the centroid."""
        with self.lock:
            mass, centroid = (self.payload_mass, self.payload_centroid) if sensor is None \
                else sensor[:2]
            config = [self.comm_type, [self.ip_addr, self.port],
                      [float(mass), [int(c) if float(c).is_integer() else float(c)
                                     for c in centroid]]]
        if sensor is None:
            return [config, [0, 0, [0.0] * AXIS_COUNT, [0.0] * AXIS_COUNT]]
        return [config, sensor_monitor(sensor[2])]


def sensor_monitor(reading: Optional[ForceReading]) -> list:
    """``torqsensor[1]`` of an arm with a sensor, ``[status, errcode, actual[6], general[6],
    real[6]]`` (N, N·m), from the sample's ``reading`` (None: the sensor is off, status 0 and
    zeros). Values are rounded to 0.1 mN and 0.1 mN·m, far below a sensor's noise, to keep the
    packet and get_data within a client's 8192-byte read."""
    if reading is None:
        return [0, 0, [0.0] * AXIS_COUNT, [0.0] * AXIS_COUNT, [0.0] * AXIS_COUNT]
    return [int(reading.status), int(reading.errcode)] + [
        _rounded(w) for w in (reading.actual, reading.general, reading.real)]


def _rounded(values: Sequence[float]) -> list:
    return [round(float(v), 4) for v in np.asarray(values, float)]
