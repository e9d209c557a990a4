"""A register-map gripper driven through the tool connector (``backend.tool_io``,
:class:`~jaka_driver.backend.tool_io.ToolIO`), the same code on the twin and on a controller:
commands go out as Modbus RTU frames with ``send_frame``, the state comes back through the
connector's TIO signals on the status registers (``add_signal`` once, ``signals()`` each read),
which the connector polls at their frequency (at most 10 Hz, JAKA's limit).

The calls this module makes of the facet are all of it: ``set_power``, ``set_pin_mode``,
``set_channel_mode``, ``set_channel_comm``, ``send_frame``, ``add_signal``,
``delete_signal``, ``signals`` and ``settings``. A facet's refusal comes back as its
:class:`Result`, unchanged.

**Powered** is what the connector reports of its supply (``settings().power_on``; a controller's
as last read back): a signal keeps its latest value when the gripper does not answer (the twin's
connector; a controller reports the last value it read), so a signal's value cannot tell an
unpowered gripper from a quiet one. **Initialised** is the init-state signal's value, and only
while the supply is on: a power cycle loses DH's calibration, and the signal may still hold the
1 read before it.

Units: opening m (distance between the pads), force N per jaw, speed and force settings %,
positions on the registers ‰ of the stroke.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ..backend.tool_io import (AI_RS485L, DO_RS485H, ChannelComm, ChannelMode, PinType, Signal,
                               voltage_code_of)
from ..common.results import CommandRefused, Result
from .modbus_frames import write_register
from .register_maps import GripperFigures, GripState, RegisterMap

#: JAKA's numbers: the tool pins that carry each RS485 channel and the mode that makes them
#: RS485 (set_tio_pin_mode: channel 0 = RS485H on the DO pins, both nibbles 0xF; channel 1 =
#: RS485L on the AI pins, mode 1)
PINS_OF_CHANNEL = {0: (PinType.DO, DO_RS485H), 1: (PinType.AI, AI_RS485L)}
SIGNAL_PREFIX = "gripper_"
HOLDING_REGISTER = 3          # a TIO signal's sig_type: FC03
PARITY_NONE = 78              # 'N': DH's 8N1


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
    the grip state (None while it is not polled) and whether an object is held."""

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
        at the gripper's slave id and baud rate (8N1), and poll one signal per status register:
        JAKA's demo sequence. A signal the connector has already (a second set-up) is kept when
        it is the gripper's, replaced otherwise. The first refusal ends it and is answered."""
        s, io = self.setup, self.tool_io
        try:
            voltage = voltage_code_of(s.volts)
        except CommandRefused as refused:
            return refused.result()
        pin_type, pin_mode = PINS_OF_CHANNEL.get(s.channel, (-1, -1))
        steps = [lambda: io.set_power(1, voltage),
                 lambda: io.set_pin_mode(pin_type, pin_mode),
                 lambda: io.set_channel_mode(s.channel, int(ChannelMode.MODBUS)),
                 lambda: io.set_channel_comm(s.channel, ChannelComm(
                     s.slave, s.baudrate, 8, 1, PARITY_NONE))]
        have = {signal.name: signal for signal in io.signals()}
        for signal in self.wanted_signals():
            old = have.get(signal.name)
            if old is not None and (old.channel, old.sig_type, old.address, old.frequency) == (
                    signal.channel, signal.sig_type, signal.address, signal.frequency):
                continue
            if old is not None:
                steps.append(lambda name=signal.name: io.delete_signal(name))
            steps.append(lambda signal=signal: io.add_signal(signal))
        for step in steps:
            result = step()
            if not result.ok:
                return result
        return Result.success(f"{self.registers.model} gripper on RS485 channel {s.channel}, "
                              f"slave {s.slave}, {s.baudrate} baud, tool supply {s.volts:g} V")

    def wanted_signals(self) -> tuple[Signal, ...]:
        """The TIO signals of the status registers, named ``gripper_<role>``."""
        s = self.setup
        return tuple(Signal(SIGNAL_PREFIX + role, s.channel, HOLDING_REGISTER, address, 0,
                            s.frequency) for role, address in self.registers.reads.items())

    def take_down(self) -> Result:
        """Delete the gripper's signals."""
        names = {signal.name for signal in self.tool_io.signals()}
        for role in self.registers.reads:
            if SIGNAL_PREFIX + role in names:
                result = self.tool_io.delete_signal(SIGNAL_PREFIX + role)
                if not result.ok:
                    return result
        return Result.success("gripper signals deleted")

    # ---- commands ---------------------------------------------------------------------------
    def _write(self, role: str, value: int) -> Result:
        frame = write_register(self.setup.slave, self.registers.writes[role], value,
                               crc=self.setup.crc)
        return self.tool_io.send_frame(self.setup.channel, frame)

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
        """The status registers' latest polled values (``tool_io.signals()``); not initialised
        while the supply is off (see the module); grip state None while its signal is not
        polled (no set-up yet)."""
        values = {}
        for signal in self.tool_io.signals():
            if signal.name.startswith(SIGNAL_PREFIX):
                values[signal.name[len(SIGNAL_PREFIX):]] = signal.value
        grip = values.get("grip_state")
        try:
            grip = GripState(int(grip)) if grip is not None else None
        except ValueError:
            grip = None
        position = int(values.get("position") or 0)
        return GripperState(initialised=self.powered and bool(values.get("init_state")),
                            opening=position / 1000.0 * self.figures.stroke,
                            position=position, grip_state=grip)

    @property
    def powered(self) -> bool:
        """The connector's tool supply is on (as it reports it)."""
        return bool(self.tool_io.settings().power_on)
