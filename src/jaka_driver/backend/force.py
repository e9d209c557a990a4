"""The force capability every backend offers as ``backend.force`` (:class:`Force`): a flange
force/torque sensor and JAKA's force control on it — never None. An arm without a sensor
offers :class:`NoForceSensor`, which refuses every request with -9 and says how to configure
one; so the layers above ask the facet, never which backend they have or whether it exists.

**The sensor frame** is the flange frame (URDF link ``flange``): origin at the flange centre,
z out of the flange. Every wrench here is ``[Fx, Fy, Fz N, Mx, My, Mz N·m]`` in that frame,
moments about its origin, and it is the load the tool side puts on the sensor: the sum of the
external forces on the tool (its weight, its inertia, a contact, a hand) — with the tool
pointing down, a 2 kg tool reads Fz = +19.6 N and pressing it on a table reads Fz < 0.

**The three readings** of JAKA's ``get_torque_sensor_data`` (SDK header, 2.1.14 and 2.2.2: type
1 *Actual* "actual feedback", 2 *General* "general data" / "original readings", 3 *Real* "real
data without gravity and bias"; the SDK puts the number on the wire unchanged), one
:class:`ForceReading` per sample:

* ``general`` — the sensor's original reading: every load plus its bias (offset) and noise,
  unfiltered;
* ``actual`` — ``general`` less the zero offset (what :meth:`Force.zero` took), low-pass
  filtered at the sensor filter's cut-off: the tool's weight is still in it;
* ``real`` — ``actual`` less the weight of the sensor's tool payload (:meth:`Force.
  set_tool_payload`) at the sensor's current orientation: what the world does to the tool.

**Force control** (JAKA's model; docs/interface.md, "Force"): per axis of the force-control
frame (the active tool's frame, moments about the TCP, or the base frame's axes at the TCP) an
admittance (:class:`AdmittanceAxis`): the axis moves at ``v = v_max · (w + constant − rebound ·
x) / ft_user`` — ``w`` the measured wrench component, ``x`` the displacement since force control
started, ``v_max`` :data:`COMPLIANT_SPEED` — so ``ft_user`` is the force that moves the axis at
the compliant speed limit and ``rebound`` the stiffness pulling it back. The compliance type
chooses what :meth:`Force.enable_admittance` runs: ``NONE`` admittance (``constant`` not used),
``CONSTANT_FORCE`` admittance around ``constant`` (the force the tool exerts along the axis:
+10 on z presses 10 N along the tool's z, the sensor then reads −10), ``VELOCITY`` velocity
compliance (moves slow down in steps as the wrench nears the compliance condition: level and
rates, :class:`VelocityCompliance`). Tool drive (hand guiding) is the same law with its own
axes (:class:`ToolDriveAxis`: ``rigidity`` in ``ft_user``'s place). The compliance condition
(6 values, 0 = not checked) stops any motion whose wrench exceeds it, as a protective stop; the
soft limit stops the arm when the sensor's own reading (``actual``) exceeds it.

Units: N, N·m, m, kg, rad, Hz; a rebound N/mm on x y z and N·m/rad on rx ry rz (the unit
requests and the wire give it, converted once where a law needs SI: :func:`rebound_to_si`).
Results follow the contract: a refused request changes nothing; every refusal says why (-9 no sensor / sensor off
/ wrong mode, -10 busy, -2 out of range, naming the field, the value and the limit).
"""
from __future__ import annotations

import threading
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from enum import IntEnum
from typing import NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ..common.results import Code, Result

#: the names of a wrench's six components, and of the six axes of force control
AXES = ("x", "y", "z", "rx", "ry", "rz")
WRENCH_NAMES = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: the URDF link the sensor frame is (and the header frame of the wrench topics)
SENSOR_FRAME = "flange"
#: m/s², the base frame's gravity (z up)
GRAVITY = np.array([0.0, 0.0, -9.81])
#: m/s and rad/s: the compliant speed limit, the speed an axis reaches at ``ft_user``
#: (``rigidity`` for tool drive) and never exceeds under force control
COMPLIANT_SPEED = (0.1, 0.1, 0.1, 0.5, 0.5, 0.5)


class ReadingType(IntEnum):
    """``get_torque_sensor_data``'s ``type`` (JAKA's ``TorqSensorDataType``), numbered as
    JAKA's header numbers it and its SDK sends it: 1, 2, 3."""

    ACTUAL = 1
    GENERAL = 2
    REAL = 3

    @classmethod
    def span(cls) -> Tuple[int, int]:
        """The lowest and highest type (the range a request is checked against)."""
        return int(min(cls)), int(max(cls))


class ForceFrame(IntEnum):
    """The frame force control's axes are in (JAKA's ``FTFrameType``)."""

    TOOL = 0        # the active tool's axes, moments about the TCP
    WORLD = 1       # the base frame's axes, moments about the TCP


class ComplianceType(IntEnum):
    """``set_compliant_type``'s ``compliance_type``."""

    NONE = 0
    CONSTANT_FORCE = 1
    VELOCITY = 2


class IdentificationState(IntEnum):
    """Payload identification's state, numbered as JAKA's ``get_torq_sensor_identify_staus``
    answers it."""

    DONE = 0            # done, or never run
    RUNNING = 1
    FAILED = 2


class ForceMode:
    """What force control does now (:attr:`ForceSettings.mode`)."""

    OFF = "off"
    ADMITTANCE = "admittance"
    CONSTANT_FORCE = "constant_force"
    VELOCITY_COMPLIANCE = "velocity_compliance"
    TOOL_DRIVE = "tool_drive"
    IDENTIFYING = "payload_identification"


class ForceReading(NamedTuple):
    """One sample of the sensor (the module says what each is): 6-vectors, N and N·m, sensor
    frame. ``status`` 1 while the sensor is on and reporting, 0 off; ``errcode`` the sensor's
    error code (0 none)."""

    actual: np.ndarray
    general: np.ndarray
    real: np.ndarray
    status: int = 1
    errcode: int = 0

    def of(self, kind: int) -> np.ndarray:
        """The reading of :class:`ReadingType` ``kind``."""
        return (self.actual, self.general, self.real)[int(ReadingType(kind)) - 1]


@dataclass(frozen=True)
class AdmittanceAxis:
    """One axis of ``set_admit_ctrl_config``: ``enabled`` (JAKA's ``opt``); ``ft_user`` (N or
    N·m) the wrench that moves the axis at :data:`COMPLIANT_SPEED`; ``rebound`` (N/mm or
    N·m/rad, the unit requests and the wire give it: :func:`rebound_to_si`) pulling it back to where force control started; ``constant`` (N or N·m) the force
    the tool exerts along the axis under constant-force control; ``normal_track`` JAKA's
    normal tracking."""

    enabled: bool = False
    ft_user: float = 0.0
    rebound: float = 0.0
    constant: float = 0.0
    normal_track: bool = False


@dataclass(frozen=True)
class ToolDriveAxis:
    """One axis of ``set_tool_drive_config``: ``enabled`` (``opt``); ``rigidity`` (N or N·m)
    the hand's force that moves the axis at :data:`COMPLIANT_SPEED`; ``rebound`` (N/mm or
    N·m/rad) as in :class:`AdmittanceAxis`."""

    enabled: bool = False
    rigidity: float = 0.0
    rebound: float = 0.0


@dataclass(frozen=True)
class VelocityCompliance:
    """``set_vel_compliant_ctrl``: ``level`` 1–3 uses ``level`` + 1 rates, 1 > rate1 > … > 0
    (the unused ones 0). The wrench's largest share of the compliance condition,
    ``max |w_i| / condition_i``, splits into ``level`` + 2 equal bands below 1: in the first the
    move runs at full speed, in band k at ``rates[k-1]`` of it; at the condition it stops."""

    level: int = 1
    rates: Tuple[float, float, float, float] = (0.5, 0.25, 0.0, 0.0)

    def speed_factor(self, share: float) -> float:
        """The share of a move's speed at ``share`` (0 … 1) of the compliance condition."""
        bands = self.level + 2
        k = min(int(share * bands), bands - 1)
        return 1.0 if k == 0 else float(self.rates[k - 1])


@dataclass(frozen=True)
class SensorPayload:
    """The tool hanging on the sensor: ``mass`` kg at ``centroid`` (m, sensor frame)."""

    mass: float = 0.0
    centroid: np.ndarray = field(default_factory=lambda: np.zeros(3))


@dataclass(frozen=True)
class IdentificationStatus:
    """Payload identification (JAKA's ``get_torq_sensor_identify_staus``): ``state`` an
    :class:`IdentificationState`; ``progress`` 0–1; ``message`` what it does or did;
    ``result`` the payload found (None until one is)."""

    state: IdentificationState = IdentificationState.DONE
    progress: float = 0.0
    message: str = "no identification has run"
    result: Optional[SensorPayload] = None


def gravity_wrench(payload: "SensorPayload", rotation: np.ndarray,
                   gravity: np.ndarray = GRAVITY) -> np.ndarray:
    """The load (N, N·m, sensor frame) of ``payload`` hanging still on a sensor turned
    ``rotation`` (sensor → base, 3x3) under ``gravity`` (m/s², base frame: the arm's mounting
    turns it, :mod:`jaka_driver.common.installation`): its weight, and that weight's moment
    about the sensor — what ``real`` takes out of ``actual``."""
    weight = payload.mass * (rotation.T @ gravity)
    return np.concatenate([weight, np.cross(payload.centroid, weight)])


def frame_name(frame: int) -> str:
    """A :class:`ForceFrame` in words."""
    return "tool" if frame == ForceFrame.TOOL else "base (world)"


def wrench_text(w) -> str:
    """A wrench in words: ``Fx 1.2, …, Mz 0.03``."""
    return ", ".join(f"{n} {v:.3g}" for n, v in zip(WRENCH_NAMES, w))


def rebound_to_si(axis: int, value: float) -> float:
    """A rebound as the facet, requests and the wire give it — N/mm on x y z (a stiffness in
    the length unit payload centroids and JAKA's poses use), N·m/rad on rx ry rz — → N/m or
    N·m/rad: the one conversion, where a control law works in SI (the twin's)."""
    return float(value) * 1000.0 if axis < 3 else float(value)


def _six(value: float = 0.0) -> np.ndarray:
    return np.full(6, float(value))


@dataclass(frozen=True)
class ForceSettings:
    """Everything force control is set to, and what it does now (``mode``, a
    :class:`ForceMode` value). ``mounted`` False: the arm has no sensor and nothing else
    here means anything. Wrenches are 6-vectors (N, N·m); ``soft_limit`` and ``range`` in the
    sensor frame, ``condition`` in the force-control frame (0 = not checked)."""

    mounted: bool = False
    sensor_on: bool = False
    range: np.ndarray = field(default_factory=_six)
    filter_hz: float = 0.0
    soft_limit: np.ndarray = field(default_factory=_six)
    tool_payload: SensorPayload = field(default_factory=SensorPayload)
    compensation: bool = True
    compliance_type: int = ComplianceType.NONE
    velocity: VelocityCompliance = field(default_factory=VelocityCompliance)
    admittance: Tuple[AdmittanceAxis, ...] = (AdmittanceAxis(),) * 6
    tool_drive: Tuple[ToolDriveAxis, ...] = (ToolDriveAxis(),) * 6
    frame: int = ForceFrame.TOOL
    tool_drive_frame: int = ForceFrame.TOOL
    condition: np.ndarray = field(default_factory=_six)
    mode: str = ForceMode.OFF


class KeptSettings:
    """What a facet keeps of force control — its :class:`ForceSettings` and the
    identification's status — changed from any thread under one lock, each replaced whole, so
    a reader always gets one consistent value."""

    def __init__(self, settings: ForceSettings):
        self._lock = threading.Lock()
        self.reset(settings)

    def reset(self, settings: ForceSettings) -> None:
        with self._lock:
            self._settings = settings
            self._identification = IdentificationStatus()

    @property
    def value(self) -> ForceSettings:
        return self._settings

    @property
    def identification(self) -> IdentificationStatus:
        return self._identification

    def report(self, status: IdentificationStatus) -> None:
        with self._lock:
            self._identification = status

    def update(self, **changes) -> None:
        with self._lock:
            self._settings = replace(self._settings, **changes)

    def update_row(self, table: str, axis: int, row) -> None:
        """Row ``axis`` of the six-axis table ``table`` (read, changed and written at once)."""
        with self._lock:
            rows = list(getattr(self._settings, table))
            rows[axis] = row
            self._settings = replace(self._settings, **{table: tuple(rows)})


class Force(ABC):
    """A flange force/torque sensor and force control on it (the module says what each
    means). Every method answers a :class:`Result` and never blocks for long; values arrive
    already checked by the driver's door (ranges, the arm's state), the facet checks what only
    it knows (a sensor, its state, a busy arm)."""

    @property
    @abstractmethod
    def absent(self) -> Optional[str]:
        """Why there is no sensor (the refusal's message), or None when there is one."""

    @abstractmethod
    def settings(self) -> ForceSettings:
        """What force control is set to and does now (never refused)."""

    @abstractmethod
    def set_sensor_on(self, on: bool) -> Result:
        """Switch the sensor on (it reports from the next sample) or off."""

    @abstractmethod
    def zero(self) -> Result:
        """Take the sensor's offset now (averaged over the last samples): ``actual`` reads the
        sensor tool payload's weight from then on, ``real`` zero."""

    @abstractmethod
    def set_tool_payload(self, mass: float, centroid: np.ndarray) -> Result:
        """The sensor's tool payload: ``mass`` kg at ``centroid`` (m, sensor frame), what
        ``real`` subtracts."""

    @abstractmethod
    def start_identification(self, poses: Sequence[np.ndarray]) -> Result:
        """Move through ``poses`` (joints, rad; one pose: JAKA's end pose, measured on the way
        there too), measure the sensor at rest at each, and find the tool's mass and centroid.
        Returns at once, as a move: ``value`` = (completion, planned duration s); the
        completion's value is the :class:`SensorPayload` found."""

    @abstractmethod
    def identification_status(self) -> IdentificationStatus:
        """Where the identification is, or what it found."""

    @abstractmethod
    def set_filter(self, cutoff_hz: float) -> Result:
        """The low-pass filter of ``actual`` and ``real`` (Hz; 0 = off)."""

    @abstractmethod
    def set_soft_limit(self, limit: np.ndarray) -> Result:
        """Stop the arm when ``|actual_i|`` exceeds ``limit_i`` (6, N and N·m)."""

    @abstractmethod
    def set_admittance(self, axis: int, config: AdmittanceAxis) -> Result:
        """Axis ``axis`` (0–5: x y z rx ry rz of the force-control frame) of admittance."""

    @abstractmethod
    def set_compliance_type(self, compensation: bool, kind: int) -> Result:
        """``compensation``: force control works on ``real`` (True) or ``actual``; ``kind`` a
        :class:`ComplianceType`: what :meth:`enable_admittance` runs."""

    @abstractmethod
    def set_velocity_compliance(self, config: VelocityCompliance) -> Result:
        """The levels of velocity compliance."""

    @abstractmethod
    def set_tool_drive(self, axis: int, config: ToolDriveAxis) -> Result:
        """Axis ``axis`` (0–5 of the tool drive frame) of tool drive."""

    @abstractmethod
    def set_frame(self, frame: int) -> Result:
        """The force-control frame (:class:`ForceFrame`)."""

    @abstractmethod
    def set_tool_drive_frame(self, frame: int) -> Result:
        """The tool drive frame (:class:`ForceFrame`)."""

    @abstractmethod
    def set_condition(self, wrench: np.ndarray) -> Result:
        """The compliance condition (6, N and N·m in the force-control frame; 0 = not
        checked): any motion whose wrench exceeds it is stopped (protective stop)."""

    @abstractmethod
    def enable_admittance(self, on: bool) -> Result:
        """Start (or end) what the compliance type says: admittance, constant force, velocity
        compliance."""

    @abstractmethod
    def enable_tool_drive(self, on: bool) -> Result:
        """Start (or end) tool drive: the arm follows the hand on the tool."""

    @abstractmethod
    def disable(self) -> Result:
        """End every force control (the arm comes to rest where it is)."""


class NoForceSensor(Force):
    """An arm without a sensor: every request is refused with -9 and ``reason``."""

    def __init__(self, reason: str):
        self._refusal = Result.failure(Code.WRONG_MODE, reason)
        self._reason = reason

    @property
    def absent(self) -> Optional[str]:
        return self._reason

    def settings(self) -> ForceSettings:
        return ForceSettings()

    def identification_status(self) -> IdentificationStatus:
        return IdentificationStatus(message=self._reason)

    def _refuse(self, *_args) -> Result:
        return self._refusal

    set_sensor_on = zero = set_tool_payload = start_identification = set_filter = _refuse
    set_soft_limit = set_admittance = set_compliance_type = set_velocity_compliance = _refuse
    set_tool_drive = set_frame = set_tool_drive_frame = set_condition = _refuse
    enable_admittance = enable_tool_drive = disable = _refuse


#: How to give an arm a sensor: the end of every "no sensor" refusal.
HOW_TO_MOUNT = ("mount one with the node parameter ~force_sensor true (launch argument "
                "force_sensor:=true), or force_sensor: mounted: true in config/<model>.yaml")
