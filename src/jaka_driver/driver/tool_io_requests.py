"""The door's tool-connector requests, offered by :class:`~.robot_driver.RobotDriver` as
``driver.tool_io`` (:class:`ToolIORequests`) on the backend's tool connector
(jaka_driver.backend.tool_io), whichever backend it is.

Order of checks: a connector at all (-9, saying why there is none) → the request's fields and
the connector's state, by the rules written once in ``backend/tool_io.py`` (-2 naming the field,
the value and the limit; a frame on a channel not in RS485 mode, or in torque-sensor mode, -9
with the reason). No arm state is required: the connector's settings move nothing (JAKA's demos
disable the arm first; no controller is on record refusing otherwise). Simulated time stands
still while a request is in here (``answers``). The request's units: volts for the supply
(24 or 12), the wire's codes otherwise (docs/interface.md, "Tool connector").
"""
from __future__ import annotations

from typing import Sequence

from ..backend.tool_io import (CHANNEL_NAMES, VOLTAGES, ChannelComm, PinType, Signal,
                               check_channel, check_pin_mode, voltage_code_of)
from ..common.results import Code, CommandRefused, Result
from .door import RequestPart, answers


class ToolIORequests(RequestPart):
    """Tool-connector requests through ``door`` (see the module)."""

    @property
    def _tio(self):
        tio = self.backend.tool_io
        if tio.absent is not None:
            raise CommandRefused(Code.WRONG_MODE, tio.absent)
        return tio

    @answers(react=False)
    def state(self) -> Result:
        """``value``: (present, settings, signals) as last read back — never refused (a backend
        without a connector answers False and its defaults). A read polled by the state topic:
        no reaction window."""
        tio = self.backend.tool_io
        return Result.success(tio.absent or "tool connector",
                              (tio.absent is None, tio.settings(), tio.signals()))

    @answers
    def set_power(self, enable: bool, volts: float) -> Result:
        """Tool supply on or off at ``volts`` (24 or 12); ``value``: (on, voltage code) read
        back."""
        tio = self._tio
        return tio.set_power(int(bool(enable)), voltage_code_of(volts))

    def _read(self):
        """The settings as the connector reports them now (a controller is asked)."""
        result = self._tio.read_settings()
        if not result.ok:
            raise CommandRefused(result.code, result.message)
        return result.value

    @answers
    def power(self) -> Result:
        """``value``: (on, voltage code) as the connector reports them."""
        s = self._read()
        return Result.success(f"tool power {'on' if s.power_on else 'off'}, "
                              f"{VOLTAGES[s.voltage_code]:g} V", (s.power_on, s.voltage_code))

    @answers
    def pin_mode(self, pin_type: int) -> Result:
        """``value``: the mode of the DI (0), DO (1) or AI (2) pins."""
        pin_type, _ = check_pin_mode(pin_type, 0)
        mode = self._read().pin_modes[pin_type]
        return Result.success(f"{PinType(pin_type).name} pins' mode {mode:#04x}", mode)

    @answers
    def channel_mode(self, channel: int) -> Result:
        """``value``: channel ``channel``'s mode (0 Modbus RTU, 1 raw, 2 torque sensor)."""
        channel = check_channel(channel)
        mode = self._read().channel_modes[channel]
        return Result.success(f"channel {channel} ({CHANNEL_NAMES[channel]}) mode {mode}", mode)

    @answers
    def channel_comm(self, channel: int) -> Result:
        """``value``: channel ``channel``'s :class:`ChannelComm`."""
        channel = check_channel(channel)
        comm = self._read().comm[channel]
        return Result.success(f"channel {channel} ({CHANNEL_NAMES[channel]}) comm", comm)

    @answers
    def set_pin_mode(self, pin_type: int, mode: int) -> Result:
        return self._tio.set_pin_mode(pin_type, mode)

    @answers
    def set_channel_mode(self, channel: int, mode: int) -> Result:
        return self._tio.set_channel_mode(channel, mode)

    @answers
    def set_channel_comm(self, channel: int, comm: ChannelComm) -> Result:
        return self._tio.set_channel_comm(channel, comm)

    @answers
    def send_frame(self, channel: int, frame: Sequence[int]) -> Result:
        return self._tio.send_frame(channel, frame)

    @answers
    def add_signal(self, name: str, channel: int, sig_type: int, address: int,
                   frequency: int) -> Result:
        return self._tio.add_signal(Signal(name, channel, sig_type, address, 0, frequency))

    @answers
    def delete_signal(self, name: str) -> Result:
        return self._tio.delete_signal(name)

    @answers
    def signals(self) -> Result:
        """``value``: every signal with its latest value."""
        return self._tio.read_signals()
