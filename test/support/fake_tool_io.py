"""A stand-in for the twin's tool connector facet (``backend.tool_io``, built on another
branch) with the calls the gripper code makes of it and the calls it makes of its device
(sim/tool_device.py's ToolDevice): the supply, pin and channel modes, frames on a channel
(refused with the reason unless the channel's pins are RS485 and its mode Modbus or raw),
Modbus signals polled at their frequency counted in 8 ms cycles, and the tool DOs. It is
attached to a SimBackend's physics loop as the facet is: the device's cycle and the polls run
at the end of every cycle."""
from __future__ import annotations

from jaka_driver.common.results import Code, Result
from jaka_driver.common.constants import SERVO_CYCLE

#: JAKA's pin types (0 DI, 1 DO = RS485H's pins, 2 AI = RS485L's) and channels (0 RS485H,
#: 1 RS485L)
CHANNEL_PINS = {0: 1, 1: 2}


class FakeToolIo:
    def __init__(self, backend):
        self.device = backend.tool_device
        self.volts = 0.0
        self.pin_modes = {0: 0, 1: 0, 2: 0}
        self.channel_modes = {0: 2, 1: 2}          # 2: torque sensor, neither Modbus nor raw
        self.comm = {0: 115200, 1: 115200}
        self.outputs = [0.0, 0.0]
        self.rows: dict[str, dict] = {}
        self.sent: list[tuple[int, bytes]] = []
        self._cycle = 0
        backend._physics.on_cycle.append(self._on_cycle)

    # ---- the facet's calls ------------------------------------------------------------------
    def set_power(self, on: bool, volts: float = 24.0) -> Result:
        self.volts = float(volts) if on else 0.0
        self.device.power(self.volts)
        return Result.success("tool power set")

    def set_pin_mode(self, pin_type: int, mode: int) -> Result:
        self.pin_modes[pin_type] = mode
        return Result.success("pin mode set")

    def set_channel_mode(self, channel: int, mode: int) -> Result:
        self.channel_modes[channel] = mode
        return Result.success("channel mode set")

    def set_channel_comm(self, channel: int, slave: int, baudrate: int, databits: int,
                         stopbits: int, parity: int) -> Result:
        self.comm[channel] = baudrate
        return Result.success("channel comm set")

    def send(self, channel: int, frame: bytes) -> Result:
        if self.pin_modes.get(CHANNEL_PINS.get(channel, -1)) != 1:
            return Result.failure(Code.WRONG_MODE, f"channel {channel}'s pins are not RS485")
        if self.channel_modes.get(channel) not in (0, 1):
            return Result.failure(Code.WRONG_MODE, f"channel {channel} is neither Modbus nor raw")
        self.sent.append((channel, bytes(frame)))
        self.device.rs485(channel, bytes(frame), self.comm[channel])
        return Result.success("sent")

    def add_signal(self, name: str, channel: int, sig_type: int, address: int,
                   frequency: int) -> Result:
        self.rows[name] = {"name": name, "channel": channel, "sig_type": sig_type,
                           "address": address, "value": None, "frequency": frequency}
        return Result.success("signal added")

    def remove_signal(self, name: str) -> Result:
        self.rows.pop(name, None)
        return Result.success("signal removed")

    def signals(self) -> list[dict]:
        return [dict(row) for row in self.rows.values()]

    def set_output(self, index: int, level: float) -> None:
        self.outputs[index] = level
        self.device.tool_outputs(list(self.outputs))

    # ---- what the facet does each cycle ----------------------------------------------------
    def _on_cycle(self, d) -> None:
        self.device.on_cycle()
        self._cycle += 1
        for row in self.rows.values():
            every = max(1, round(1.0 / (row["frequency"] * SERVO_CYCLE)))
            if self._cycle % every == 0:
                row["value"] = self.device.read_register(row["channel"], row["sig_type"],
                                                         row["address"])
