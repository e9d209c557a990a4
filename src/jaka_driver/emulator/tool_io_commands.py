"""JAKA's twelve tool-connector (TIO) commands, answered from the twin's tool connector (the
backend's ``tool_io`` facet, :class:`~jaka_driver.sim.tool_connector.SimToolIO`): the supply,
pin modes, channel modes and comm are stored there and read back; a frame on a channel whose
pins are in RS485 mode and whose mode is Modbus or raw reaches the device on the twin's tool
connector; signals are polled from it at their frequency (in the twin's cycles) and carried by
``get_tio_signals`` and, where the profile's packet has the key, by the status packet's
``tio_rs_signals``.

Wire forms as JAKA's SDK writes and reads them (docs/protocol.md, "Tool connector"). A missing
or malformed field is refused with "1"; a value outside the connector's rules with "1" and the
rule's message (field, value, limit); a frame the channel's state forbids with "2".
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping

from ..backend.tool_io import (ChannelComm, Signal, ToolIO, check_channel, check_pin_mode)
from ..common.results import Code, CommandRefused, Result
from ..protocol.fields import Cmd, Field
from .replies import ERROR_REFUSED, ERROR_REQUEST, Answer, Rejected
from .wire_fields import integer, required, shown, shown_name

_INT = (-(2 ** 31), 2 ** 31 - 1)
#: the SDK's keys for the tool power output, and the spelling some clients send
_TIO_VOUT_KEYS = ((Field.TIO_VOUT_ENA, "tio_vout_enable"), (Field.TIO_VOUT_VOL, "tio_vout_voltage"))


def _int(req: Mapping, key: str) -> int:
    return integer(req, key, *_INT)


def _done(req: Mapping, result: Result) -> Answer:
    """The facet's answer on the wire: its refusal with "1" (a value) or "2" (the state)."""
    if result.ok:
        return Answer()
    code = ERROR_REQUEST if result.code == Code.INVALID_PARAMETER else ERROR_REFUSED
    raise Rejected(f"{shown_name(req)}: {result.message}", code)


def _checked(req: Mapping, check: Callable, *args):
    try:
        return check(*args)
    except CommandRefused as refused:
        raise Rejected(f"{shown_name(req)}: {refused.message}", ERROR_REQUEST) from None


def signal_rows(tool_io: ToolIO) -> list:
    """Signals as the wire carries them: [name, chn_id, sig_type, sig_addr, value, frequency]."""
    return [[s.name, s.channel, s.sig_type, s.address, s.value, s.frequency]
            for s in tool_io.signals()]


class ToolIoCommands:
    """Handlers of the twelve TIO commands on the twin's ``tool_io`` facet."""

    def __init__(self, tool_io: ToolIO):
        self.tio = tool_io

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        t = self.tio
        return {
            Cmd.SET_TIO_VOUT_PARAM: self._set_vout,
            Cmd.GET_TIO_VOUT_PARAM: lambda r: Answer(
                {Field.TIO_VOUT_ENA: int(t.settings().power_on),
                 Field.TIO_VOUT_VOL: t.settings().voltage_code}),
            Cmd.SET_TIO_PIN_MODE: lambda r: _done(r, t.set_pin_mode(
                _int(r, Field.PIN_TYPE), _int(r, Field.PIN_MODE))),
            Cmd.GET_TIO_PIN_MODE: self._get_pin_mode,
            Cmd.SET_RS485_CHN_MODE: lambda r: _done(r, t.set_channel_mode(
                _int(r, Field.CHN_ID), _int(r, Field.CHN_MODE))),
            Cmd.GET_RS485_CHN_MODE: lambda r: Answer({Field.CHN_MODE: int(
                t.settings().channel_modes[self._channel(r, Field.CHN_ID)])}),
            Cmd.SET_RS485_CHN_COMM: lambda r: _done(r, t.set_channel_comm(
                _int(r, Field.CHN_ID_COMM), ChannelComm(
                    _int(r, Field.SLAVE_ID), _int(r, Field.BAUDRATE), _int(r, Field.DATABIT),
                    _int(r, Field.STOPBIT), _int(r, Field.PARITY)))),
            Cmd.GET_RS485_CHN_COMM: self._get_comm,
            Cmd.ADD_TIO_RS_SIGNAL: self._add_signal,
            Cmd.DEL_TIO_RS_SIGNAL: lambda r: _done(r, t.delete_signal(
                self._name(r))),
            Cmd.SEND_TIO_RS_COMMAND: self._send,
            Cmd.GET_TIO_SIGNALS: lambda r: Answer({Field.SIGNALS: signal_rows(t)}),
        }

    def _channel(self, req: Mapping, key: str) -> int:
        return _checked(req, check_channel, _int(req, key), key)

    def _set_vout(self, req: Mapping) -> Answer:
        """Either value may be left out: it keeps its value."""
        if not any(k in req for pair in _TIO_VOUT_KEYS for k in pair):
            raise Rejected(f"set_tio_vout_param: missing field {Field.TIO_VOUT_ENA!r} or "
                           f"{Field.TIO_VOUT_VOL!r}", ERROR_REQUEST)
        s = self.tio.settings()
        values = []
        for (key, other), current in zip(_TIO_VOUT_KEYS, (int(s.power_on), s.voltage_code)):
            spelt = key if key in req else other
            values.append(_int(req, spelt) if spelt in req else current)
        return _done(req, self.tio.set_power(*values))

    def _get_pin_mode(self, req: Mapping) -> Answer:
        pin_type, _ = _checked(req, check_pin_mode, _int(req, Field.PIN_TYPE), 0)
        return Answer({Field.PIN_MODE: int(self.tio.settings().pin_modes[pin_type])})

    def _get_comm(self, req: Mapping) -> Answer:
        c = self.tio.settings().comm[self._channel(req, Field.CHN_ID_COMM)]
        return Answer({Field.SLAVE_ID: c.slave_id, Field.BAUDRATE: c.baudrate,
                       Field.DATABIT: c.databit, Field.STOPBIT: c.stopbit,
                       Field.PARITY: c.parity})

    @staticmethod
    def _name(req: Mapping) -> str:
        name = required(req, Field.SIGNAL_NAME)
        if not isinstance(name, str):
            raise Rejected(f"{shown_name(req)}: {Field.SIGNAL_NAME!r} must be a string; got "
                           f"{shown(name)}", ERROR_REQUEST)
        return name

    def _add_signal(self, req: Mapping) -> Answer:
        return _done(req, self.tio.add_signal(Signal(
            self._name(req), _int(req, Field.SIGNAL_CHN_ID), _int(req, Field.SIGNAL_SIG_TYPE),
            _int(req, Field.SIGNAL_SIG_ADDR), 0, _int(req, Field.FREQUENCY))))

    def _send(self, req: Mapping) -> Answer:
        data = required(req, Field.CMD_BUF)
        if not isinstance(data, list) or not all(
                isinstance(b, int) and not isinstance(b, bool) for b in data):
            raise Rejected(f"{shown_name(req)}: {Field.CMD_BUF!r} must be a list of bytes; got "
                           f"{shown(data)}", ERROR_REQUEST)
        return _done(req, self.tio.send_frame(_int(req, Field.CHN_ID_COMM), data))
