"""The tool connector on a controller: :class:`~jaka_driver.backend.tool_io.ToolIO` with JAKA's
twelve TIO commands, sent as JAKA's SDK sends them (docs/protocol.md, "Tool connector"; the
encoders are :mod:`jaka_driver.protocol.tool_io`).

**Each setting is read back** with its get (``get_tio_vout_param``, ``get_tio_pin_mode``,
``get_rs485_chn_mode``, ``get_rs485_chn_comm``), polled for up to 1 s as the backend confirms its
other settings (:meth:`~.commander.Commander.settled`); a controller that acknowledges a set but
never reports it is refused with 2. JAKA's SDK itself waits for none of them (measured). Every
setting is read at each connection too, so the rules (a frame's channel in RS485 mode) are
checked against what the controller has. A controller that does not know the TIO commands
(older firmware) leaves the defaults and logs it; its requests come back refused with 2.

**Signals** come back from ``get_tio_signals`` (each add and delete reads them) and from every
status packet that carries ``tio_rs_signals`` (later firmware; not the recorded fw 1.5.14):
the packet's values replace the latest. A controller whose packets do not carry them is asked
``get_tio_signals`` every :data:`SIGNAL_POLL` s while there are signals (its own thread,
``jaka-tio-signals``, while the link is up): JAKA polls a signal at most at 10 Hz, so no value
is older than a poll of the controller plus 0.1 s, and a gripper's state on such a controller
moves as on a later one.
"""
from __future__ import annotations

import logging
import threading
from dataclasses import replace
from typing import Optional, Tuple

from ..backend.tool_io import ChannelComm, PinType, Signal, ToolIO, ToolIOSettings
from ..common.results import CommandRefused, Result
from ..host import realtime
from ..protocol import tool_io as wire
from ..protocol.status_packet import StatusPacket
from .commander import Commander, answers

log = logging.getLogger(__name__)

#: s between two ``get_tio_signals`` of a controller whose packets carry no signals: a
#: signal's highest polling rate, 10 Hz
SIGNAL_POLL = 0.1


def _signal(row: wire.SignalRow) -> Signal:
    return Signal(row.name, row.channel, row.sig_type, row.address, row.value, row.frequency)


class ControllerToolIO(ToolIO):
    """The connector of the controller behind ``send`` (see the module)."""

    def __init__(self, send: Commander):
        self.send = send
        self._lock = threading.Lock()
        self._settings = ToolIOSettings()
        self._signals: Tuple[Signal, ...] = ()
        self._packets_carry_signals = False     # a packet had tio_rs_signals
        self._quit = threading.Event()
        self._thread: Optional[threading.Thread] = None
        self._unreadable = ""                   # why the last poll failed (logged once)

    # ---- the signals' poll, for packets without them ---------------------------------------------
    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="jaka-tio-signals", daemon=True)
        self._thread.start()

    def stop_polling(self) -> None:
        self._quit.set()
        if self._thread is not None:
            self._thread.join(2.0)

    @realtime.runs_periodically
    def _run(self) -> None:
        while not self._quit.wait(SIGNAL_POLL):
            if self._signals and not self._packets_carry_signals and self.send.link.connected:
                self._poll_signals()

    def _poll_signals(self) -> None:
        try:
            self._read_signals()
        except CommandRefused as refusal:
            # the values read last stay, as a controller keeps a signal's last value
            if refusal.message != self._unreadable:
                log.info("tool connector signals not read: %s", refusal.message)
                self._unreadable = refusal.message
        else:
            self._unreadable = ""

    # ---- what the controller reports -----------------------------------------------------------
    def settings(self) -> ToolIOSettings:
        return self._settings

    def signals(self) -> Tuple[Signal, ...]:
        return self._signals

    def _update(self, **changes) -> None:
        with self._lock:
            self._settings = replace(self._settings, **changes)

    def read_all(self) -> None:
        """Every setting and the signals, at each connection (the supervisor thread). A
        controller without the commands keeps the defaults."""
        try:
            self._read_everything()
        except CommandRefused as refused:
            log.info("tool connector not read (%s): its settings are taken as JAKA's defaults",
                     refused.message)

    def _read_everything(self) -> ToolIOSettings:
        read = self.send.read
        on, code = read(wire.get_tio_vout_param(), wire.reply_vout)
        pins = tuple(read(wire.get_tio_pin_mode(p), wire.reply_pin_mode) for p in PinType)
        modes = tuple(read(wire.get_rs485_chn_mode(c), wire.reply_chn_mode) for c in (0, 1))
        comm = tuple(ChannelComm(*read(wire.get_rs485_chn_comm(c), wire.reply_chn_comm))
                     for c in (0, 1))
        with self._lock:
            self._settings = ToolIOSettings(bool(on), code, pins, modes, comm)
        self._read_signals()
        return self._settings

    @answers
    def read_settings(self) -> Result:
        """The settings as the controller reports them now (every get asked)."""
        return Result.success("tool connector settings", self._read_everything())

    def on_packet(self, status: StatusPacket) -> None:
        """A status packet's ``tio_rs_signals``, when it has them: the latest values."""
        rows = status.tio_rs_signals
        if rows is not None:
            self._packets_carry_signals = True
            signals = tuple(_signal(r) for r in rows)
            if signals != self._signals:
                self._signals = signals

    # ---- the transport ----------------------------------------------------------------------------
    def _apply_power(self, enabled: bool, voltage_code: int) -> None:
        wanted = (int(enabled), voltage_code)
        on, code = self.send.settled(wire.set_tio_vout_param(*wanted), wire.get_tio_vout_param(),
                                     wire.reply_vout, lambda v: tuple(v) == wanted,
                                     "tool power")
        self._update(power_on=bool(on), voltage_code=code)

    def _apply_pin_mode(self, pin_type: int, mode: int) -> None:
        got = self.send.settled(wire.set_tio_pin_mode(pin_type, mode),
                                wire.get_tio_pin_mode(pin_type), wire.reply_pin_mode,
                                lambda v: v == mode, "tool pin mode")
        modes = list(self._settings.pin_modes)
        modes[pin_type] = got
        self._update(pin_modes=tuple(modes))

    def _apply_channel_mode(self, channel: int, mode: int) -> None:
        got = self.send.settled(wire.set_rs485_chn_mode(channel, mode),
                                wire.get_rs485_chn_mode(channel), wire.reply_chn_mode,
                                lambda v: v == mode, "RS485 channel mode")
        modes = list(self._settings.channel_modes)
        modes[channel] = got
        self._update(channel_modes=tuple(modes))

    def _apply_comm(self, channel: int, comm: ChannelComm) -> None:
        wanted = (comm.slave_id, comm.baudrate, comm.databit, comm.stopbit, comm.parity)
        got = self.send.settled(wire.set_rs485_chn_comm(channel, *wanted),
                                wire.get_rs485_chn_comm(channel), wire.reply_chn_comm,
                                lambda v: tuple(v) == wanted, "RS485 channel comm")
        comms = list(self._settings.comm)
        comms[channel] = ChannelComm(*got)
        self._update(comm=tuple(comms))

    def _apply_frame(self, channel: int, frame: bytes) -> None:
        self.send.accepted(wire.send_tio_rs_command(channel, list(frame)))

    def _apply_add_signal(self, signal: Signal) -> None:
        self.send.accepted(wire.add_tio_rs_signal(signal.name, signal.channel, signal.sig_type,
                                                  signal.address, signal.frequency))

    def _apply_delete_signal(self, name: str) -> None:
        self.send.accepted(wire.del_tio_rs_signal(name))

    def _read_signals(self) -> Tuple[Signal, ...]:
        rows = self.send.read(wire.get_tio_signals(), wire.reply_signals)
        self._signals = tuple(_signal(r) for r in rows)
        return self._signals
