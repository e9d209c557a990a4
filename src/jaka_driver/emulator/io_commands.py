"""IO commands as JAKA's SDK addresses them: ``type`` 0 cabinet, 1 tool, 2 extension, 3 relay
(outputs only), 4 Modbus slave, 5 Profinet slave, 6 EtherNet/IP slave; ``index`` counted from 1
on the wire (the SDK sends its 0-based index + 1, for every type), so index 0 is answered with
an error that says so. The sizes are the profile's (:mod:`.profiles`); every output set shows at
once in its get command and in the status packet's array (``dout``, ``relay_io``,
``mb_slave_dout``, …).
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping, Tuple

from ..common.models import io_level
from ..protocol.fields import Cmd, Field, IOType
from .replies import ERROR_REQUEST, Answer, Rejected
from .status_packet import extio, io_values, zeros_of
from .twin_controller import TwinController
from .wire_fields import flag, integer, number, shown, shown_name

SIGNALS = ("digital", "analog")
INPUT, OUTPUT = 0, 1


class IoCommands:
    def __init__(self, controller: TwinController):
        self.c = controller

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        c = self.c
        return {
            Cmd.SET_DIGITAL_OUTPUT: lambda r: self._set_output(r, "digital"),
            Cmd.SET_ANALOG_OUTPUT: lambda r: self._set_output(r, "analog"),
            Cmd.GET_DIGITAL_INPUT: lambda r: self._read(r, "digital", INPUT),
            Cmd.GET_DIGITAL_OUTPUT: lambda r: self._read(r, "digital", OUTPUT),
            Cmd.GET_ANALOG_INPUT: lambda r: self._read(r, "analog", INPUT),
            Cmd.GET_ANALOG_OUTPUT: lambda r: self._read(r, "analog", OUTPUT),
            Cmd.GET_DIGITAL_INPUT_STATUS: lambda r: Answer({Field.DIN_STATUS: io_values(
                c, ("digital", IOType.CABINET, INPUT))[:c.profile.din_status_count]}),
            Cmd.GET_EXTIO_STATUS: lambda r: Answer({"extio_status": extio(c)}),
            Cmd.GET_FUNCDI_STATUS: lambda r: Answer({"funcdi_status": zeros_of("funcdi")}),
            "emulator_set_input": self._set_input,
        }

    def _address(self, req, signal: str, path: int) -> Tuple[int, int]:
        """(type, 0-based index) of an IO point that exists."""
        io_type = integer(req, Field.IO_TYPE, 0, max(IOType))
        index = integer(req, Field.INDEX, 0, 1_000_000)
        if index == 0:
            raise Rejected(f"{shown_name(req)}: index 0 does not exist: the wire counts IO from "
                           "1 (JAKA's SDK sends its own index + 1)", ERROR_REQUEST)
        self.c.check_io(signal, io_type, path, index - 1, shown_name(req))
        return io_type, index - 1

    def _set_output(self, req, signal: str) -> Answer:
        io_type, index = self._address(req, signal, OUTPUT)
        value = io_level(signal, flag(req, Field.VALUE) if signal == "digital"
                         else number(req, Field.VALUE))
        self.c.set_output(signal, io_type, index, value)
        return Answer()

    def _read(self, req, signal: str, path: int) -> Answer:
        io_type, index = self._address(req, signal, path)
        value = self.c.read_io(signal, path, io_type, index)
        return Answer({Field.VALUE: int(value) if signal == "digital" else float(value)})

    def _set_input(self, req) -> Answer:
        """emulator_set_input: drive an input as the world outside would (1-based index)."""
        signal = req.get("signal")
        signal = signal.strip().lower() if isinstance(signal, str) else signal
        if signal not in SIGNALS:
            raise Rejected(f"emulator_set_input: 'signal' must be 'digital' or 'analog'; got "
                           f"{shown(signal)}", ERROR_REQUEST)
        io_type, index = self._address(req, signal, INPUT)
        value = io_level(signal, number(req, Field.VALUE))
        self.c.set_input(signal, io_type, index, value)
        return Answer()
