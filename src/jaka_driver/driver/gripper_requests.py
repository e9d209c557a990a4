"""The door's gripper requests, offered by :class:`~.robot_driver.RobotDriver` as
``driver.gripper``: a register-map gripper on the tool connector
(:class:`jaka_driver.devices.ModbusGripper`, reaching the arm through ``backend.tool_io``
only), or :class:`NoGripper` when the driver was started without one.

Order of checks: a gripper at all (-9, saying how to get one) → the fields (-2: force 20–100 %,
speed 1–100 %, opening 0…stroke m, effort ≥ 0 N; each refusal names field, value and limit)
→ for a move, the gripper's own state (-9: not powered — the tool connector's supply is off —
or not initialised: its init-state signal is not 1) → the tool connector's own refusals, passed on. A refused request changes
nothing. Methods answer a :class:`Result`, never raise, and hold simulated time while they act
(:func:`.door.answers`).
"""
from __future__ import annotations

from ..common.results import Code, CommandRefused, Result
from ..devices import ConnectorSetup, GripperState, ModbusGripper
from ..devices.register_maps import FIGURES, MAPS
from .door import Door, RequestPart, answers

GRIPPERS = ("none",) + tuple(MAPS)
HOW_TO_MOUNT = ("start the driver with gripper:=dh_pgi (a DH-Robotics gripper on the tool "
                "connector's RS485 channel)")


class GripperRequests(RequestPart):
    """The gripper named ``kind`` (a register map of :mod:`jaka_driver.devices.register_maps`)
    on the backend's tool connector, hung on it as ``setup`` says."""

    absent = None

    def __init__(self, door: Door, kind: str, setup: ConnectorSetup = ConnectorSetup()):
        super().__init__(door)
        if kind not in MAPS:
            raise ValueError(f"gripper is {kind!r}, expected one of {', '.join(GRIPPERS)}")
        self.kind = kind
        self.device = ModbusGripper(door.backend.tool_io, MAPS[kind], FIGURES[kind], setup)
        self.stroke = FIGURES[kind].stroke

    @answers
    def set_up(self) -> Result:
        """The tool connector set up for the gripper (power, pins, channel, signals)."""
        return self.device.set_up()

    @answers
    def initialise(self, full: bool = False) -> Result:
        return self.device.initialise(bool(full))

    @answers
    def set_force(self, percent: int) -> Result:
        lo, hi = self.device.registers.force_range
        _within("force", percent, lo, hi, "%")
        return self.device.set_force(int(percent))

    @answers
    def set_speed(self, percent: int) -> Result:
        lo, hi = self.device.registers.speed_range
        _within("speed", percent, lo, hi, "%")
        return self.device.set_speed(int(percent))

    @answers
    def move(self, opening: float, max_effort: float = 0.0) -> Result:
        """Go to ``opening`` m between the pads; ``max_effort`` N per jaw sets the force first
        (0: the force as it is, as MoveIt's gripper controller sends it)."""
        _within("position", opening, 0.0, self.stroke, "m")
        if not max_effort >= 0.0:
            raise CommandRefused(Code.INVALID_PARAMETER,
                                 f"max_effort {max_effort} N is below the limit 0 N")
        state = self.device.state()
        if not self.device.powered:
            raise CommandRefused(Code.WRONG_MODE, "the gripper is not powered (the tool "
                                 "connector's supply is off): switch the tool supply on")
        if not state.initialised:
            raise CommandRefused(Code.WRONG_MODE, "the gripper is not initialised: call "
                                 "gripper/initialise first")
        if max_effort > 0.0:
            pct = self.device.figures.percent(max_effort, self.device.registers.force_range)
            result = self.device.set_force(pct)
            if not result.ok:
                return result
        result = self.device.move_to(float(opening))
        if not result.ok:
            return result
        return Result.success(f"gripper to {opening * 1000:.1f} mm "
                              f"({self.device.permille(opening)} ‰)")

    def state(self) -> GripperState:
        """The latest polled state (no request: nothing held)."""
        return self.device.state()

    @property
    def powered(self) -> bool:
        return self.device.powered


class NoGripper:
    """No gripper: every request refused (-9) with how to get one."""

    kind = "none"
    stroke = 0.0
    absent = f"no gripper on this arm ({HOW_TO_MOUNT})"
    powered = False

    def _refuse(self, *args, **kwargs) -> Result:
        return Result.failure(Code.WRONG_MODE, self.absent)

    set_up = initialise = set_force = set_speed = move = _refuse

    def state(self) -> GripperState:
        return GripperState(False, 0.0, 0, None)


def _within(field: str, value, lo, hi, unit: str) -> None:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise CommandRefused(Code.INVALID_PARAMETER, f"{field} {value!r} is not a number")
    if not lo <= v <= hi:
        raise CommandRefused(Code.INVALID_PARAMETER,
                             f"{field} {value} {unit} is outside {lo}–{hi} {unit}")
