"""Force control above its transport, written once for every backend whose arm carries a sensor:
:class:`ForceRules`, the :class:`~.force.Force` facet's rules — which modes exist and which one
runs, what may start while what runs, what each refusal says, what a setting's answer says and
which reading a mode works on. A backend subclasses it and gives only its transport: how a
setting reaches the arm (the twin's physics thread; a controller's command and its read-back),
how force control and identification are started and ended there, and how the sensor is read
(docs/design.md, "Where a new capability lives", 3).

**The mode** (:class:`~.force.ForceMode`) is what holds the arm — the backend's running force
control or identification (:meth:`ForceRules.running_mode`) — else velocity compliance when it
is on (it lets moves run and only paces them, so it is a flag here), else off.

**What may start while what runs**: a setting of force control (admittance, tool drive, the
compliance type, both frames, the sensor's tool payload), zeroing, switching the sensor off,
and starting any force control or identification are refused with -10 while any force control
or identification runs; the filter, the soft limit, velocity compliance's levels and the
compliance condition may change at any time. Starting, zeroing and identification need the
sensor on (-9 otherwise).

Units: the facet's (:mod:`.force`). Every method answers a Result; a refusal changes nothing.
"""
from __future__ import annotations

from abc import abstractmethod
from typing import Optional, Sequence, Tuple

import numpy as np

from ..common.results import Code, CommandRefused, Result, answers
from ..common.sensor_spec import ForceSensorSpec
from .force import (AXES, WRENCH_NAMES, AdmittanceAxis, ComplianceType, Force, ForceMode,
                    ForceReading, ForceSettings, IdentificationStatus, KeptSettings,
                    SensorPayload, ToolDriveAxis, VelocityCompliance, frame_name,
                    wrench_text)

#: the force controls that hold the arm or pace its moves (``disable`` ends each of them)
RUNNING_MODES = (ForceMode.ADMITTANCE, ForceMode.CONSTANT_FORCE,
                 ForceMode.VELOCITY_COMPLIANCE, ForceMode.TOOL_DRIVE)
#: what ``enable_admittance(False)`` ends
ADMITTANCE_MODES = (ForceMode.ADMITTANCE, ForceMode.CONSTANT_FORCE,
                    ForceMode.VELOCITY_COMPLIANCE)


def words(mode: str) -> str:
    """A :class:`~.force.ForceMode` in words: ``constant force``."""
    return mode.replace("_", " ")


def wrench_used(reading: ForceReading, compensated: bool) -> np.ndarray:
    """The reading force control and the compliance condition work on: ``real`` (the sensor's
    tool payload taken out) when ``compensated`` (``set_compliance_type``'s
    ``sensor_compensation``), else ``actual``."""
    return reading.real if compensated else reading.actual


def fresh_settings(spec: ForceSensorSpec) -> ForceSettings:
    """Force control as a sensor starts: off, the soft limit at the sensor's range."""
    return ForceSettings(mounted=True, range=spec.range.copy(), soft_limit=spec.range.copy())


class ForceRules(Force):
    """The rules of force control on a sensor ``spec`` (see the module); a subclass gives the
    transport: the ``_send_…`` / ``_start_…`` / ``_stop`` methods (each returns what its
    answer adds: ``""`` on the twin, ``" (read back)"`` on a controller), ``sensor_on`` and
    ``running_mode``, and ``settings()`` (where it reads what the arm reports)."""

    #: how a refusal says the sensor is off was learnt (", as the controller reports it")
    SENSOR_OFF_SOURCE = ""

    def __init__(self, spec: ForceSensorSpec):
        self._spec = spec
        self._kept = KeptSettings(fresh_settings(spec))
        self._velocity_on = False

    # ---- what the transport gives ----------------------------------------------------------
    @abstractmethod
    def sensor_on(self) -> bool:
        """The sensor is on and reporting, as the arm says."""

    @abstractmethod
    def running_mode(self) -> Optional[str]:
        """The :class:`~.force.ForceMode` of the force control or identification that holds
        the arm now (None: nothing does)."""

    def _require_arm_ready(self, what: str) -> None:
        """Refuse ``what`` (a start) before anything else where the arm may not move at all;
        the twin's state checks are the door's, a controller's its identity's."""

    def _check_tool_drive(self, s: ForceSettings) -> None:
        """Refuse starting tool drive with the settings ``s`` where the transport cannot."""

    def _check_poses(self, poses: Sequence[np.ndarray]) -> None:
        """Refuse an identification through ``poses`` the transport cannot run."""

    @abstractmethod
    def _send_sensor_on(self, on: bool) -> str: ...

    @abstractmethod
    def _send_zero(self) -> str:
        """Zero the sensor; the whole answer."""

    @abstractmethod
    def _send_tool_payload(self, payload: SensorPayload) -> Tuple[SensorPayload, str]: ...

    @abstractmethod
    def _send_filter(self, cutoff_hz: float) -> Tuple[float, str]: ...

    @abstractmethod
    def _send_soft_limit(self, limit: np.ndarray) -> Tuple[np.ndarray, str]: ...

    @abstractmethod
    def _send_admittance(self, axis: int, config: AdmittanceAxis
                         ) -> Tuple[AdmittanceAxis, str]: ...

    @abstractmethod
    def _send_compliance_type(self, compensation: bool, kind: int) -> str: ...

    @abstractmethod
    def _send_velocity_compliance(self, config: VelocityCompliance) -> str: ...

    @abstractmethod
    def _send_tool_drive(self, axis: int, config: ToolDriveAxis
                         ) -> Tuple[ToolDriveAxis, str]: ...

    @abstractmethod
    def _send_frame(self, frame: int) -> str: ...

    @abstractmethod
    def _send_tool_drive_frame(self, frame: int) -> str: ...

    @abstractmethod
    def _send_condition(self, wrench: np.ndarray) -> str: ...

    @abstractmethod
    def _start_velocity_compliance(self) -> None: ...

    @abstractmethod
    def _start_run(self, mode: str, label: str, frame: int, s: ForceSettings) -> None:
        """Start ``mode`` (admittance, constant force, tool drive) in ``frame`` with the
        settings ``s``; refuse (-10) where the arm is busy."""

    @abstractmethod
    def _stop(self, mode: str) -> None:
        """End ``mode``, which runs: the arm comes to rest."""

    @abstractmethod
    def _send_disable(self, mode: str) -> None:
        """End every force control (``mode`` runs now, perhaps off)."""

    @abstractmethod
    def _identify(self, what: str, poses: Sequence[np.ndarray]) -> Result:
        """Start the identification through ``poses`` (see :meth:`~.force.Force.
        start_identification`)."""

    # ---- what it is and does ---------------------------------------------------------------
    @property
    def absent(self) -> Optional[str]:
        return None

    def _mode(self) -> str:
        running = self.running_mode()
        if running is not None:
            return running
        return ForceMode.VELOCITY_COMPLIANCE if self._velocity_on else ForceMode.OFF

    def identification_status(self) -> IdentificationStatus:
        return self._kept.identification

    # ---- the refusals --------------------------------------------------------------------
    def _require_sensor_on(self, what: str) -> None:
        if not self.sensor_on():
            raise CommandRefused(Code.WRONG_MODE, f"{what} refused: the force/torque sensor is "
                                 f"off{self.SENSOR_OFF_SOURCE} (switch it on first)")

    def _require_force_off(self, what: str) -> None:
        mode = self._mode()
        if mode != ForceMode.OFF:
            raise CommandRefused(Code.BUSY, f"{what} refused while {words(mode)} runs "
                                 "(disable_force_control first)")

    # ---- the sensor ------------------------------------------------------------------------
    @answers
    def set_sensor_on(self, on: bool) -> Result:
        on = bool(on)
        if not on:
            self._require_force_off("switching the sensor off")
        note = self._send_sensor_on(on)
        return Result.success(f"force/torque sensor {'on' if on else 'off'}{note}")

    @answers
    def zero(self) -> Result:
        self._require_sensor_on("zeroing")
        self._require_force_off("zeroing")
        return Result.success(self._send_zero())

    @answers
    def set_tool_payload(self, mass: float, centroid: np.ndarray) -> Result:
        self._require_force_off("the sensor's tool payload")
        payload, note = self._send_tool_payload(
            SensorPayload(float(mass), np.asarray(centroid, float).copy()))
        c = payload.centroid * 1000.0
        return Result.success(f"sensor tool payload {payload.mass:g} kg at ({c[0]:.1f}, "
                              f"{c[1]:.1f}, {c[2]:.1f}) mm{note}")

    @answers
    def set_filter(self, cutoff_hz: float) -> Result:
        hz, note = self._send_filter(float(cutoff_hz))
        return Result.success(f"sensor filter off{note}" if cutoff_hz == 0 else
                              f"sensor filter {hz:g} Hz{note}")

    @answers
    def set_soft_limit(self, limit: np.ndarray) -> Result:
        limit, note = self._send_soft_limit(np.asarray(limit, float).copy())
        return Result.success("sensor soft limit " + wrench_text(limit) + note)

    # ---- settings of force control ----------------------------------------------------------
    @answers
    def set_admittance(self, axis: int, config: AdmittanceAxis) -> Result:
        self._require_force_off("changing the admittance")
        row, note = self._send_admittance(axis, config)
        return Result.success(f"admittance {AXES[axis]}: " + (
            f"on, ft_user {row.ft_user:g}, rebound {row.rebound:g}, "
            f"constant {row.constant:g}" if row.enabled else "off") + note)

    @answers
    def set_compliance_type(self, compensation: bool, kind: int) -> Result:
        self._require_force_off("changing the compliance type")
        note = self._send_compliance_type(bool(compensation), int(kind))
        self._kept.update(compensation=bool(compensation), compliance_type=int(kind))
        return Result.success(f"compliance type {ComplianceType(kind).name.lower()}, "
                              f"{'compensated' if compensation else 'uncompensated'} wrench"
                              + note)

    @answers
    def set_velocity_compliance(self, config: VelocityCompliance) -> Result:
        note = self._send_velocity_compliance(config)
        self._kept.update(velocity=config)
        return Result.success(f"velocity compliance level {config.level}, rates "
                              f"{', '.join(f'{r:g}' for r in config.rates)}{note}")

    @answers
    def set_tool_drive(self, axis: int, config: ToolDriveAxis) -> Result:
        self._require_force_off("changing the tool drive")
        row, note = self._send_tool_drive(axis, config)
        return Result.success(f"tool drive {AXES[axis]}: " + (
            f"on, rigidity {row.rigidity:g}, rebound {row.rebound:g}"
            if row.enabled else "off") + note)

    @answers
    def set_frame(self, frame: int) -> Result:
        self._require_force_off("changing the force-control frame")
        note = self._send_frame(int(frame))
        self._kept.update(frame=int(frame))
        return Result.success(f"force control in the {frame_name(frame)} frame{note}")

    @answers
    def set_tool_drive_frame(self, frame: int) -> Result:
        self._require_force_off("changing the tool drive frame")
        note = self._send_tool_drive_frame(int(frame))
        self._kept.update(tool_drive_frame=int(frame))
        return Result.success(f"tool drive in the {frame_name(frame)} frame{note}")

    @answers
    def set_condition(self, wrench: np.ndarray) -> Result:
        wrench = np.asarray(wrench, float).copy()
        note = self._send_condition(wrench)
        self._kept.update(condition=wrench)
        checked = [f"{WRENCH_NAMES[i]} {v:g}" for i, v in enumerate(wrench) if v > 0]
        return Result.success("compliance condition " + (", ".join(checked) if checked else
                                                         "off (nothing checked)") + note)

    # ---- running force control --------------------------------------------------------------
    @answers
    def enable_admittance(self, on: bool) -> Result:
        if not on:
            return self._end(*ADMITTANCE_MODES)
        s = self.settings()
        if s.compliance_type == ComplianceType.VELOCITY:
            self._require_sensor_on("velocity compliance")
            self._require_force_off("velocity compliance")
            self._start_velocity_compliance()
            self._velocity_on = True
            return Result.success("velocity compliance on: moves slow down as the wrench nears "
                                  "the compliance condition")
        mode = (ForceMode.CONSTANT_FORCE if s.compliance_type == ComplianceType.CONSTANT_FORCE
                else ForceMode.ADMITTANCE)
        return self._start(mode, s.frame, s)

    @answers
    def enable_tool_drive(self, on: bool) -> Result:
        if not on:
            return self._end(ForceMode.TOOL_DRIVE)
        s = self.settings()
        self._check_tool_drive(s)
        return self._start(ForceMode.TOOL_DRIVE, s.tool_drive_frame, s)

    @answers
    def disable(self) -> Result:
        mode = self._mode()
        self._send_disable(mode)
        return self._ended(mode)

    def _start(self, mode: str, frame: int, s: ForceSettings) -> Result:
        label = words(mode)
        self._require_arm_ready(label)
        self._require_sensor_on(label)
        self._require_force_off(label)
        self._start_run(mode, label, frame, s)
        return Result.success(f"{label} on in the {frame_name(frame)} frame")

    def _end(self, *modes: str) -> Result:
        """End force control if it runs in one of ``modes``: the arm comes to rest."""
        mode = self._mode()
        if mode not in modes:
            return Result.success(f"{' / '.join(words(m) for m in modes)} was not on")
        self._stop(mode)
        return self._ended(mode)

    def _ended(self, mode: str) -> Result:
        """Force control is off (``mode`` was running)."""
        self._velocity_on = False
        if mode not in RUNNING_MODES:
            return Result.success("no force control was on")
        return Result.success(f"{words(mode)} off: the arm comes to rest")

    # ---- payload identification -------------------------------------------------------------
    @answers
    def start_identification(self, poses: Sequence[np.ndarray]) -> Result:
        what = "payload identification"
        self._check_poses(poses)
        self._require_arm_ready(what)
        self._require_sensor_on(what)
        self._require_force_off(what)
        return self._identify(what, poses)
