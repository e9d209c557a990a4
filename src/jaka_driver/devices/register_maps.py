"""Register maps of the grippers a JAKA tool connector drives over Modbus RTU: one table per
gripper model, read by the twin's gripper (``sim/gripper.py``) and by the gripper driver above
the tool connector (:mod:`.gripper`), so a second model is a second table, not a rewrite.

A table names the slave id the gripper answers by default and the holding register of each
role. Values are the gripper's own: position and opening in ‰ of the stroke (0 closed,
1000 fully open), force and speed in % of the maker's range.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from typing import Mapping


class GripState(IntEnum):
    """DH's grip state (register 0x0201): what the fingers did with the last position."""

    MOVING = 0
    REACHED = 1          # at the commanded position, nothing between the fingers
    CAUGHT = 2           # stopped on an object before the commanded position
    DROPPED = 3          # had caught an object, then closed past where it was


@dataclass(frozen=True)
class RegisterMap:
    """One gripper model's Modbus registers (holding registers, FC03 read, FC06/FC16 write).

    ``writes``: role → register of the commands (``init``, ``force``, ``position``, ``speed``,
    ``save``); ``reads``: role → register of the status (``init_state``, ``grip_state``,
    ``position``). ``init_values`` are the values the init register accepts (DH: 1, and 0xA5
    for a full calibration); ``force_range`` / ``speed_range`` the accepted %."""

    model: str
    slave: int
    writes: Mapping[str, int]
    reads: Mapping[str, int]
    init_values: tuple[int, ...] = (1,)
    force_range: tuple[int, int] = (20, 100)
    speed_range: tuple[int, int] = (1, 100)
    position_range: tuple[int, int] = (0, 1000)
    defaults: Mapping[str, int] = field(default_factory=dict)

    def role_of_write(self, address: int) -> str | None:
        for role, reg in self.writes.items():
            if reg == address:
                return role
        return None

    def status_registers(self) -> tuple[int, ...]:
        """The registers a controller polls as TIO signals, in ``reads``' order."""
        return tuple(self.reads.values())


#: DH-Robotics PGE / PGI / AG grippers (DH's Modbus RTU manual: 115200 8N1, slave 1).
DH_PGI = RegisterMap(
    model="dh_pgi",
    slave=1,
    writes={"init": 0x0100, "force": 0x0101, "position": 0x0103, "speed": 0x0104,
            "save": 0x0300},
    reads={"init_state": 0x0200, "grip_state": 0x0201, "position": 0x0202},
    init_values=(1, 0xA5),
    defaults={"force": 100, "speed": 100, "position": 1000},
)

@dataclass(frozen=True)
class GripperFigures:
    """A gripper's published figures, what turns the registers' ‰ and % into m and N."""

    stroke: float          # m, both fingers together
    force_min: float       # N per jaw at the lowest force setting
    force_max: float       # N per jaw at 100 %
    stroke_time: float     # s, open → closed at 100 % speed
    mass: float            # kg

    def force(self, percent: float, force_range: tuple[int, int] = (20, 100)) -> float:
        """N per jaw at ``percent``: linear from the lowest setting's minimum to 100 %'s
        maximum."""
        lo, hi = force_range
        return self.force_min + (self.force_max - self.force_min) * (percent - lo) / (hi - lo)

    def percent(self, newtons: float, force_range: tuple[int, int] = (20, 100)) -> int:
        """The force setting (%) nearest ``newtons`` per jaw, within ``force_range``."""
        lo, hi = force_range
        pct = lo + (newtons - self.force_min) * (hi - lo) / (self.force_max - self.force_min)
        return int(round(min(max(pct, lo), hi)))


#: DH-Robotics AG-95's datasheet: stroke 95 mm, gripping force 45–160 N, opening / closing
#: 0.7 s, 1 kg (docs/twin.md cites it). The twin's parallel gripper carries these figures.
DH_FIGURES = GripperFigures(stroke=0.095, force_min=45.0, force_max=160.0, stroke_time=0.7,
                            mass=1.0)

MAPS = {DH_PGI.model: DH_PGI}
FIGURES = {DH_PGI.model: DH_FIGURES}
