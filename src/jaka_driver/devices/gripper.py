"""A register-map gripper driven through the tool connector (``backend.tool_io``), the same
code on the twin and on a controller: commands go out as Modbus RTU frames with
``tool_io.send``, the state comes back through the connector's TIO signals on the status
registers (``tool_io.add_signal`` once, ``tool_io.signals()`` each read), which the connector
polls at their frequency (at most 10 Hz, JAKA's limit).

The calls this module makes of the facet are all of it: ``set_power``, ``set_pin_mode``,
``set_channel_mode``, ``set_channel_comm``, ``send``, ``add_signal``, ``remove_signal``,
``signals``. A facet's refusal comes back as its :class:`Result`, unchanged.

Units: opening m (distance between the pads), force N per jaw, speed and force settings %,
positions on the registers ‰ of the stroke.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ..common.results import Result
from .modbus_frames import write_register
from .register_maps import GripperFigures, GripState, RegisterMap

#: JAKA's numbers: the tool pins that carry each RS485 channel (set_tio_pin_mode's pin type:
#: 1 the DO pins = RS485H, channel 0; 2 the AI pins = RS485L, channel 1), the pin mode that
#: makes them RS485, and the channel mode Modbus RTU
PINS_OF_CHANNEL = {0: 1, 1: 2}
PIN_MODE_RS485 = 1
CHANNEL_MODBUS = 0
SIGNAL_PREFIX = "gripper_"
HOLDING_REGISTER = 3          # a TIO signal's sig_type: FC03


@dataclass(frozen=True)
class ConnectorSetup:
    """How the gripper hangs on the tool connector (launch arguments): the supply (V), the
    RS485 channel (0 RS485H, 1 RS485L), the gripper's slave id and baud rate, whether frames
    carry their CRC (JAKA's demos send 6 bytes without), and the signals' polling rate (Hz)."""

    volts: float = 24.0
    channel: int = 1
    slave: int = 1
    baudrate: int = 115200
    crc: bool = False
    frequency: int = 10


@dataclass(frozen=True)
class GripperState:
    """What the status registers said at their last poll: initialised, the opening (m and ‰),
    the grip state (None before any poll answered) and whether an object is held."""

    initialised: bool
    opening: float
    position: int
    grip_state: Optional[GripState]

    @property
    def object_held(self) -> bool:
        return self.grip_state == GripState.CAUGHT


class ModbusGripper:
    """A gripper of ``registers`` / ``figures`` on the tool connector ``tool_io``, hung on it
    as ``setup`` says (see the module)."""

    def __init__(self, tool_io, registers: RegisterMap, figures: GripperFigures,
                 setup: ConnectorSetup = ConnectorSetup()):
        self.tool_io = tool_io
        self.registers = registers
        self.figures = figures
        self.setup = setup
        self.force_pct = int(registers.defaults.get("force", 100))
        self.speed_pct = int(registers.defaults.get("speed", 100))

    # ---- the tool connector ---------------------------------------------------------------
    def set_up(self) -> Result:
        """Power the tool, put the channel's pins in RS485 mode and the channel in Modbus RTU
        at the gripper's baud rate, and add one signal per status register: JAKA's demo
        sequence. The first refusal ends it and is answered."""
        s, io = self.setup, self.tool_io
        steps = [lambda: io.set_power(True, s.volts),
                 lambda: io.set_pin_mode(PINS_OF_CHANNEL.get(s.channel, -1), PIN_MODE_RS485),
                 lambda: io.set_channel_mode(s.channel, CHANNEL_MODBUS),
                 lambda: io.set_channel_comm(s.channel, s.slave, s.baudrate, 8, 1, 0)]
        for role, address in self.registers.reads.items():
            steps.append(lambda role=role, address=address: io.add_signal(
                SIGNAL_PREFIX + role, s.channel, HOLDING_REGISTER, address, s.frequency))
        for step in steps:
            result = step()
            if not result.ok:
                return result
        return Result.success(f"{self.registers.model} gripper on RS485 channel {s.channel}, "
                              f"slave {s.slave}, {s.baudrate} baud, tool supply {s.volts:g} V")

    def take_down(self) -> Result:
        """Remove the gripper's signals."""
        for role in self.registers.reads:
            self.tool_io.remove_signal(SIGNAL_PREFIX + role)
        return Result.success("gripper signals removed")

    # ---- commands ---------------------------------------------------------------------------
    def _write(self, role: str, value: int) -> Result:
        frame = write_register(self.setup.slave, self.registers.writes[role], value,
                               crc=self.setup.crc)
        return self.tool_io.send(self.setup.channel, frame)

    def initialise(self, full: bool = False) -> Result:
        """Initialise (DH: 1), or calibrate fully (0xA5)."""
        values = self.registers.init_values
        return self._write("init", values[-1] if full and len(values) > 1 else values[0])

    def set_force(self, percent: int) -> Result:
        result = self._write("force", int(percent))
        if result.ok:
            self.force_pct = int(percent)
        return result

    def set_speed(self, percent: int) -> Result:
        result = self._write("speed", int(percent))
        if result.ok:
            self.speed_pct = int(percent)
        return result

    def move_to(self, opening: float) -> Result:
        """Go to ``opening`` m between the pads (‰ of the stroke on the register)."""
        return self._write("position", self.permille(opening))

    def permille(self, opening: float) -> int:
        lo, hi = self.registers.position_range
        return int(round(min(max(opening / self.figures.stroke * 1000.0, lo), hi)))

    # ---- state --------------------------------------------------------------------------------
    def state(self) -> GripperState:
        """The status registers' latest polled values (``tool_io.signals()``)."""
        values = {}
        for row in self.tool_io.signals():
            name = _field(row, "name")
            if isinstance(name, str) and name.startswith(SIGNAL_PREFIX):
                values[name[len(SIGNAL_PREFIX):]] = _field(row, "value")
        grip = values.get("grip_state")
        try:
            grip = GripState(int(grip)) if grip is not None else None
        except ValueError:
            grip = None
        position = int(values.get("position") or 0)
        return GripperState(initialised=bool(values.get("init_state")),
                            opening=position / 1000.0 * self.figures.stroke,
                            position=position, grip_state=grip)

    @property
    def powered(self) -> bool:
        """The gripper answers its status registers: a poll came back."""
        return any(_field(row, "name") == SIGNAL_PREFIX + "init_state"
                   and _field(row, "value") is not None for row in self.tool_io.signals())


def _field(row, name: str):
    """A signal row's field, whether the facet gives rows as mappings or as records."""
    return row[name] if isinstance(row, dict) else getattr(row, name)

