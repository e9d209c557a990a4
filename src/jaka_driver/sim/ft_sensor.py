"""The twin's flange force/torque sensor: how it is built into the MuJoCo model, and what it
reads every 8 ms cycle.

**Built** (:func:`add_sensor`): a body ``ft_tool`` welded to the flange body (``link_6``, whose
frame is the flange's) at its origin — the tool side of the sensor. It carries the payload
(``set_payload``'s mass folds into it, :class:`~.twin_model.Payload`) and the probe, a capsule
along flange z that touches the scene. MuJoCo's ``force`` and ``torque`` sensors on a site at
its origin measure the interaction between ``ft_tool`` and its parent (all forces on the
system: the tool's weight and inertia, contacts, an applied push), as the force and torque the
parent exerts on the child, in the site's frame; the reading here is its opposite, the load
the tool puts on the sensor (jaka_driver.backend.force says why).

**Read** (:class:`SensorReadings`, once per cycle in the physics thread, the numpy work of a
few 6-vectors): MuJoCo's values of the cycle's last step, plus the configured bias and a
seeded noise (the same after a reset), give ``general``; less the zero offset and through the
low-pass filter, ``actual``; less the sensor tool payload's weight at the sensor's orientation,
``real``. Zeroing averages the next :data:`ZERO_SAMPLES` raw readings (a zero right after the
payload changed must not average the old one), and answers once it has them.

Units: N, N·m, m, kg, Hz; rotations as 3x3 matrices sensor → world (world z up, the base's).
"""
from __future__ import annotations

import math
import threading
from typing import Optional

import mujoco
import numpy as np

from ..backend.force import ForceReading, SensorPayload, gravity_wrench
from ..common.sensor_spec import ForceSensorSpec

TOOL_BODY = "ft_tool"
SITE = "ft_sensor"
PROBE = "ft_probe"
#: the wrist bodies the probe may overlap where it leaves the flange
_NEIGHBOURS = ("link_4", "link_5", "link_6")
FLANGE_BODY = "link_6"
#: raw readings a zeroing averages (0.128 s)
ZERO_SAMPLES = 16
NOISE_SEED = 31


def add_sensor(spec: mujoco.MjSpec, sensor: ForceSensorSpec, probe: bool = True) -> None:
    """Add the tool side of the sensor, its probe (``probe``: none when a tool is mounted on
    it), its site and MuJoCo's force and torque sensors to ``spec`` (before the drives:
    ``ft_tool`` is an arm body for gravity compensation)."""
    tool = spec.body(FLANGE_BODY).add_body()
    tool.name = TOOL_BODY
    # mass and inertia as a payload sets them (twin_model.Payload); none yet: a weightless tool
    tool.mass = 0.0
    tool.inertia = [0.0, 0.0, 0.0]
    tool.explicitinertial = True
    if probe:
        geom = tool.add_geom()
        geom.name = PROBE
        geom.type = mujoco.mjtGeom.mjGEOM_CAPSULE
        length, radius = sensor.probe_length_mm / 1000.0, sensor.probe_radius_mm / 1000.0
        geom.fromto = [0.0, 0.0, radius, 0.0, 0.0, length]
        geom.size = [radius, 0.0, 0.0]
        geom.mass = 0.0
        geom.rgba = [0.3, 0.3, 0.35, 1.0]
    site = tool.add_site()
    site.name = SITE
    for kind, suffix in ((mujoco.mjtSensor.mjSENS_FORCE, "force"),
                         (mujoco.mjtSensor.mjSENS_TORQUE, "torque")):
        s = spec.add_sensor()
        s.name = f"{SITE}_{suffix}"
        s.type = kind
        s.objtype = mujoco.mjtObj.mjOBJ_SITE
        s.objname = SITE
    for other in _NEIGHBOURS:
        exclude = spec.add_exclude()
        exclude.bodyname1, exclude.bodyname2 = other, TOOL_BODY


class SensorReadings:
    """What the sensor of ``m`` reads each cycle (see the module). Its settings (on, filter,
    zero offset, tool payload) are changed between cycles, under the physics lock."""

    def __init__(self, m: mujoco.MjModel, spec: ForceSensorSpec, cycle: float):
        self._site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, SITE)
        if self._site < 0:
            raise ValueError(f"the twin has no force/torque sensor site {SITE!r}")
        force = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SENSOR, f"{SITE}_force")
        torque = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SENSOR, f"{SITE}_torque")
        self._force_adr = int(m.sensor_adr[force])
        self._torque_adr = int(m.sensor_adr[torque])
        self.spec = spec
        self.cycle = cycle
        #: the twin's gravity in the base frame, live (MuJoCo's own array: the mounting turns it)
        self.gravity = m.opt.gravity
        self.reset()

    def reset(self) -> None:
        """As a fresh sensor: off, no offset, no filter, no tool payload, the noise from its
        seed."""
        self.on = False
        self.offset = np.zeros(6)
        self.payload = SensorPayload()
        self.filter_hz = 0.0
        self._rng = np.random.default_rng(NOISE_SEED)
        self._zeroing: Optional[list] = None        # raw readings of a zeroing under way
        self._zeroed = threading.Event()
        self._filtered: Optional[np.ndarray] = None
        #: the latest reading (None while off) and the sensor's orientation then (sensor →
        #: world)
        self.latest: Optional[ForceReading] = None
        self.rotation = np.eye(3)

    def set_filter(self, cutoff_hz: float) -> None:
        self.filter_hz = float(cutoff_hz)

    def start_zero(self) -> threading.Event:
        """Zero from the next :data:`ZERO_SAMPLES` raw readings (their mean less the sensor
        tool payload's weight becomes the offset: ``actual`` then reads that weight, ``real``
        zero); the event is set once it is done."""
        self._zeroing = []
        self._zeroed = threading.Event()
        return self._zeroed

    def read(self, d: mujoco.MjData) -> Optional[ForceReading]:
        """This cycle's reading from ``d`` (None while off); kept as :attr:`latest`."""
        self.rotation = d.site_xmat[self._site].reshape(3, 3).copy()
        if not self.on:
            self.latest = None
            return None
        data = d.sensordata
        load = -np.concatenate([data[self._force_adr:self._force_adr + 3],
                                data[self._torque_adr:self._torque_adr + 3]])
        general = load + self.spec.bias + self._rng.normal(0.0, 1.0, 6) * self.spec.noise
        if self._zeroing is not None:
            self._zeroing.append(general)
            if len(self._zeroing) >= ZERO_SAMPLES:
                self.offset = np.mean(self._zeroing, axis=0) - gravity_wrench(
                    self.payload, self.rotation, self.gravity)
                self._zeroing, self._filtered = None, None
                self._zeroed.set()
        zeroed = general - self.offset
        if self.filter_hz > 0.0 and self._filtered is not None:
            alpha = 1.0 - math.exp(-2.0 * math.pi * self.filter_hz * self.cycle)
            self._filtered = self._filtered + alpha * (zeroed - self._filtered)
        else:
            self._filtered = zeroed
        actual = self._filtered
        real = actual - gravity_wrench(self.payload, self.rotation, self.gravity)
        self.latest = ForceReading(actual, general, real)
        return self.latest
