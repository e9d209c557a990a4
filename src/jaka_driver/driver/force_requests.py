"""The door's force requests: the flange force/torque sensor and force control, offered by
:class:`~.robot_driver.RobotDriver` as ``driver.force`` (:class:`ForceRequests`) on the
backend's force capability (jaka_driver.backend.force), whichever backend it is.

Order of checks (docs/interface.md, "Force"): a sensor at all (-9, saying how to mount one:
nothing a request changes can fix that) → the request's fields (-2,
:mod:`jaka_driver.backend.force_checks`) → the arm's state where the request moves the arm or
acts on its readings (the checks of a move: e-stop, power, enable, an error, drag mode -9,
servo mode -9, another motion -10) → the capability's own (the sensor off -9, force control
running -10). A refused request changes nothing. Methods take the request's units
(:mod:`jaka_driver.backend.force_checks`) and answer a :class:`Result`; they never raise, and
are safe from many threads at once, as RobotDriver's.
"""
from __future__ import annotations

from typing import Callable, Optional, Sequence

import numpy as np

from ..backend import force_checks as fcheck
from ..backend.force import IdentificationStatus, ReadingType
from ..common.results import Code, CommandRefused, Result
from . import checks as check
from .door import Door, RequestPart, answers


class ForceRequests(RequestPart):
    """Force requests through ``door`` (see the module): its state checks, and ``run_move`` —
    the door's one move loop (:meth:`.moves.MoveRequests.run_move`) — for the payload
    identification, which moves the arm as a move does."""

    def __init__(self, door: Door, run_move: Callable[..., Result]):
        super().__init__(door)
        self._run_move = run_move

    @property
    def _force(self):
        return self.backend.force

    def _sensor(self) -> np.ndarray:
        """The sensor's range (N, N·m); refused (-9) without a sensor."""
        absent = self._force.absent
        if absent is not None:
            raise CommandRefused(Code.WRONG_MODE, absent)
        return self._force.settings().range

    def _arm_still(self, what: str) -> None:
        """The arm may be taken over by force control: ready, and nothing else moves."""
        if self.door.moving:
            raise CommandRefused(Code.BUSY, f"{what} refused while the arm moves (a move, a "
                                 "jog or a velocity jog)")
        self.door.ready()

    # ---- readings and the sensor -------------------------------------------------------------
    @answers(react=False)
    def settings(self) -> Result:
        """What force control is set to and does (``value``: a ForceSettings, SI units);
        never refused: without a sensor ``mounted`` is False. A read, polled by the node's
        state watcher: it does not open a reaction window in sim time (which, 10 times a
        second, would keep the twin's time from ever advancing)."""
        force = self._force
        return Result.success(force.absent or "force control settings", force.settings())

    @answers
    def sensor_data(self, kind: int) -> Result:
        """The latest reading of ``kind`` (1 actual, 2 general, 3 real:
        :class:`ReadingType`, as JAKA numbers them): ``value`` = (wrench
        (6, N and N·m, sensor frame), status, errcode)."""
        self._sensor()
        k = ReadingType(check.integer_in("type", kind, *ReadingType.span()))
        reading = self.backend.state().force
        if reading is None:
            raise CommandRefused(Code.WRONG_MODE, "no reading: the force/torque sensor is off "
                                 "(switch it on first)")
        return Result.success(f"{k.name.lower()} wrench in the sensor frame",
                              (reading.of(k).copy(), reading.status, reading.errcode))

    @answers
    def sensor_enable(self, on: bool) -> Result:
        """Switch the sensor on or off (off is refused while force control runs)."""
        self._sensor()
        return self._force.set_sensor_on(bool(on))

    @answers
    def zero_sensor(self) -> Result:
        """Take the sensor's offset now; refused while the arm moves (the offset would hold
        its inertia)."""
        self._sensor()
        if self.door.moving:
            raise CommandRefused(Code.BUSY, "zeroing refused while the arm moves")
        st = self.backend.state()
        if st.drag_mode:
            raise CommandRefused(Code.WRONG_MODE, "zeroing refused in drag mode (a hand on "
                                 "the arm would be zeroed away)")
        return self._force.zero()

    @answers
    def set_sensor_payload(self, mass: float, centroid_mm: Sequence[float]) -> Result:
        """The sensor's tool payload: ``mass`` kg at ``centroid_mm`` (mm, sensor frame)."""
        self._sensor()
        c = check.vector("centroid", centroid_mm, 3)
        m, centroid = check.payload(self.model, mass,
                                    tuple((f"centroid[{i}]", v) for i, v in enumerate(c)))
        return self._force.set_tool_payload(m, centroid)

    @answers
    def sensor_payload(self) -> Result:
        """``value`` = (mass kg, centroid mm (3,)) of the sensor's tool payload."""
        self._sensor()
        p = self._force.settings().tool_payload
        return Result.success("the sensor's tool payload", (p.mass, p.centroid * 1000.0))

    @answers
    def set_filter(self, cutoff_hz: float) -> Result:
        self._sensor()
        return self._force.set_filter(fcheck.filter_hz(cutoff_hz))

    @answers
    def set_soft_limit(self, limit: Sequence[float]) -> Result:
        rng = self._sensor()
        return self._force.set_soft_limit(fcheck.wrench_limits("soft limit", limit, rng,
                                                               zero_allowed=False))

    # ---- payload identification --------------------------------------------------------------
    @answers
    def identify_payload(self, joint_positions: Sequence[float], apply: bool = False,
                         feedback: Optional[Callable[[IdentificationStatus], None]] = None,
                         period: float = 0.1) -> Result:
        """Move through ``joint_positions`` (rad, 6 per pose; one pose: measured on the way
        there too), measure the sensor at rest at each and find the tool's mass and centroid:
        ``value`` = (mass kg, centroid mm (3,)). ``apply``: make it the sensor's tool payload.
        ``feedback(status)`` every ``period`` s while it runs. Blocks, as a move (refused
        while anything else moves; stop_move stops it, -12)."""
        self._sensor()
        poses = fcheck.identification_poses(joint_positions, self.model)
        force = self._force

        def monitor(_t, _st):
            if feedback is not None:
                feedback(force.identification_status())
            return None

        result = self._run_move("payload identification",
                                lambda st: force.start_identification(poses), monitor, period)
        if not result.ok:
            return result
        payload = result.value
        value = (payload.mass, payload.centroid * 1000.0)
        if apply:
            applied = force.set_tool_payload(payload.mass, payload.centroid)
            if not applied.ok:
                return Result(applied.code, f"{result.message}; not applied: "
                              f"{applied.message}", value)
            return Result.success(f"{result.message}; now the sensor's tool payload", value)
        return Result.success(result.message, value)

    def identification_status(self) -> IdentificationStatus:
        """Where the identification is, or what it found."""
        return self._force.identification_status()

    # ---- force control settings ----------------------------------------------------------------
    @answers
    def set_admittance(self, axis: int, opt: int, ft_user: float, ft_rebound: float,
                       ft_constant: float, normal_track: int = 0) -> Result:
        """Axis ``axis`` of admittance (JAKA's set_admit_ctrl_config): ``ft_user`` N or N·m,
        ``ft_rebound`` N/mm or N·m/rad, ``ft_constant`` N or N·m."""
        rng = self._sensor()
        i = fcheck.axis(axis)
        return self._force.set_admittance(i, fcheck.admittance(i, opt, ft_user, ft_rebound,
                                                               ft_constant, normal_track, rng))

    @answers
    def set_compliance_type(self, sensor_compensation: bool, compliance_type: int) -> Result:
        """0 none (admittance), 1 constant force, 2 velocity compliance; compensation: force
        control acts on the gravity-compensated wrench."""
        self._sensor()
        kind = check.integer_in("compliance_type", compliance_type, 0, 2)
        return self._force.set_compliance_type(bool(sensor_compensation), kind)

    @answers
    def set_velocity_compliance(self, level: int, rates: Sequence[float]) -> Result:
        self._sensor()
        return self._force.set_velocity_compliance(fcheck.velocity_compliance(level, rates))

    @answers
    def set_tool_drive(self, axis: int, opt: int, rigidity: float, rebound: float) -> Result:
        """Axis ``axis`` of tool drive: ``rigidity`` N or N·m, ``rebound`` N/mm or N·m/rad."""
        rng = self._sensor()
        i = fcheck.axis(axis)
        return self._force.set_tool_drive(i, fcheck.tool_drive(i, opt, rigidity, rebound, rng))

    @answers
    def set_frame(self, frame: int) -> Result:
        self._sensor()
        return self._force.set_frame(fcheck.frame("frame", frame))

    @answers
    def set_tool_drive_frame(self, frame: int) -> Result:
        self._sensor()
        return self._force.set_tool_drive_frame(fcheck.frame("frame", frame))

    @answers
    def set_compliance_condition(self, wrench: Sequence[float]) -> Result:
        rng = self._sensor()
        return self._force.set_condition(fcheck.wrench_limits("condition", wrench, rng,
                                                              zero_allowed=True))

    # ---- running force control ----------------------------------------------------------------
    @answers
    def enable_admittance(self, on: bool) -> Result:
        """Start what the compliance type says (refused unless the arm may move and nothing
        else moves), or end it."""
        self._sensor()
        if on:
            s = self._force.settings()
            if s.compliance_type == 2:
                if not np.any(s.condition > 0):
                    raise CommandRefused(Code.INVALID_PARAMETER, "velocity compliance needs a "
                                         "compliance condition (it slows moves as the wrench "
                                         "nears it): set_compliance_condition first")
                self.door.ready()
            else:
                if not any(a.enabled for a in s.admittance):
                    raise CommandRefused(Code.INVALID_PARAMETER, "no admittance axis is "
                                         "enabled: set_admittance with opt 1 first")
                self._arm_still("force control")
        return self._force.enable_admittance(bool(on))

    @answers
    def enable_tool_drive(self, on: bool) -> Result:
        self._sensor()
        if on:
            if not any(a.enabled for a in self._force.settings().tool_drive):
                raise CommandRefused(Code.INVALID_PARAMETER, "no tool drive axis is enabled: "
                                     "set_tool_drive with opt 1 first")
            self._arm_still("tool drive")
        return self._force.enable_tool_drive(bool(on))

    @answers
    def disable(self) -> Result:
        """End every force control; accepted whatever runs."""
        self._sensor()
        return self._force.disable()
