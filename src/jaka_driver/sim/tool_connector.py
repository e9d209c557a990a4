"""The twin's tool connector: :class:`~jaka_driver.backend.tool_io.ToolIO` on the physics loop
and the IO board, offered as ``SimBackend.tool_io``.

* **Settings** (supply, pin modes, channel modes and comm) are kept and read back as set; the
  rules are the facet's (``backend/tool_io.py``).
* **Tool DI/DO/AI** are the IO board's tool points (IO type 1).
* **A device** (:class:`~.tool_device.ToolDevice`, a gripper or a suction cup) hangs on it by
  :meth:`SimToolIO.attach`. It hears the supply change (``power``), each frame sent on a channel
  whose pins are in RS485 mode and whose mode is Modbus or raw (``rs485``), each change of the
  tool DOs (``tool_outputs``), and runs its own state machine once per cycle (``on_cycle``); the
  tool DIs it drives (``tool_inputs``) are written into the board each cycle, so every sample
  carries them.
* **Signals** are polled from ``device.read_register`` at each signal's frequency, counted in
  the twin's 8 ms cycles from the cycle the signal was added (its first read in the next cycle,
  then every 125/f cycles, rounded up): the same requests give the same values at the same sim
  time. A signal is polled only while its channel's pins are in RS485 mode and its mode is
  Modbus RTU; a read the device does not answer leaves the latest value.

Every call to the device is made in the physics thread inside a cycle, or under the physics
loop's lock from a request: never two at once, never during a cycle's steps. A device that
raises is logged (once per kind of call) and goes on: nothing it does stops the physics thread.
"""
from __future__ import annotations

import logging
import math
import threading
from dataclasses import replace
from typing import Optional, Tuple

from ..backend.tool_io import (ChannelComm, ChannelMode, Signal, ToolIO, ToolIOSettings,
                               check_signal, frame_refusal, with_value)
from ..common.constants import SERVO_CYCLE
from ..protocol.fields import IOType
from .io_board import INPUT, OUTPUT, IoBoard
from .tool_device import ToolDevice

log = logging.getLogger(__name__)

#: the twin's cycles per second (125)
CYCLES_PER_SECOND = round(1.0 / SERVO_CYCLE)


class _Poll:
    """When a signal is read next: ``k``-th read at cycle ``start + ceil(k · 125 / f)``."""

    __slots__ = ("start", "k")

    def __init__(self, start: int):
        self.start, self.k = start, 0

    def due(self, cycle: int, frequency: int) -> bool:
        return cycle >= self.start + math.ceil(self.k * CYCLES_PER_SECOND / frequency)


class SimToolIO(ToolIO):
    """The twin's tool connector on ``io`` (the board) and ``lock`` (the physics loop's: held
    by every cycle). :meth:`on_cycle` goes into the physics loop's per-cycle work."""

    def __init__(self, io: IoBoard, lock: threading.RLock):
        self._io = io
        self._lock = lock
        self._settings = ToolIOSettings()
        self._signals: Tuple[Signal, ...] = ()
        self._polls: dict[str, _Poll] = {}
        self._cycle = 0
        self._device: Optional[ToolDevice] = None
        self._outputs: Tuple[float, ...] = self._tool_outputs()
        self._failed: set = set()               # the device's calls that raised (logged once)
        io.listeners.append(self._output_written)

    def _call(self, what: str, *args, default=None):
        """``device.<what>(*args)``; an exception is logged once and answers ``default``."""
        try:
            return getattr(self._device, what)(*args)
        except Exception:  # noqa: BLE001 - a device never takes the physics thread down
            if what not in self._failed:
                self._failed.add(what)
                log.exception("tool connector: the device's %s failed", what)
            return default

    # ---- the device -------------------------------------------------------------------------
    def attach(self, device: Optional[ToolDevice]) -> None:
        """Hang ``device`` on the connector (None: take it off). It is told the supply's
        voltage and the tool DOs at once."""
        with self._lock:
            self._device = device
            if device is not None:
                self._call("power", self._settings.volts)
                self._call("tool_outputs", self._outputs)

    @property
    def device(self) -> Optional[ToolDevice]:
        return self._device

    def on_cycle(self, _d=None) -> None:
        """The cycle's work, in the physics thread after its steps: the device's state machine,
        the tool DIs it drives into the board, then the signals that are due."""
        self._cycle += 1
        if self._device is None:
            return
        self._call("on_cycle")
        for index, level in (self._call("tool_inputs") or {}).items():
            try:
                if self._io.read("digital", INPUT, IOType.TOOL, index) != level:
                    self._io.write_input("digital", IOType.TOOL, index, float(level))
            except (IndexError, KeyError):
                pass                                 # a pin this arm's connector lacks
        if self._signals:
            self._poll()

    def _poll(self) -> None:
        settings, cycle = self._settings, self._cycle
        polled = []
        changed = False
        for signal in self._signals:
            poll = self._polls[signal.name]
            if poll.due(cycle, signal.frequency):
                poll.k += 1
                if (settings.channel_modes[signal.channel] == ChannelMode.MODBUS
                        and settings.in_rs485(signal.channel)):
                    value = self._call("read_register", signal.channel, signal.sig_type,
                                       signal.address)
                    if value is not None and value != signal.value:
                        signal, changed = with_value(signal, value), True
            polled.append(signal)
        if changed:
            self._signals = tuple(polled)

    def reset(self) -> None:
        """A fresh twin's connector (after the board's reset): default settings (supply off),
        no signals; the device told of the supply and the tool DOs that changed."""
        with self._lock:
            powered = self._settings.volts
            self._settings = ToolIOSettings()
            self._signals, self._polls = (), {}
            if self._device is not None and powered:
                self._call("power", 0.0)
            outputs = self._tool_outputs()
            if outputs != self._outputs:
                self._outputs = outputs
                if self._device is not None:
                    self._call("tool_outputs", outputs)

    # ---- tool DOs -----------------------------------------------------------------------------
    def _tool_outputs(self) -> Tuple[float, ...]:
        return self._io.values().get(("digital", IOType.TOOL, OUTPUT), ())

    def _output_written(self, signal: str, io_type: int) -> None:
        if signal != "digital" or io_type != IOType.TOOL:
            return
        with self._lock:
            outputs = self._tool_outputs()
            if outputs != self._outputs:
                self._outputs = outputs
                if self._device is not None:
                    self._call("tool_outputs", outputs)

    # ---- ToolIO --------------------------------------------------------------------------------
    def settings(self) -> ToolIOSettings:
        return self._settings

    def signals(self) -> Tuple[Signal, ...]:
        return self._signals

    def _apply_power(self, enabled: bool, voltage_code: int) -> None:
        with self._lock:
            before = self._settings.volts
            self._settings = replace(self._settings, power_on=enabled, voltage_code=voltage_code)
            if self._device is not None and self._settings.volts != before:
                self._call("power", self._settings.volts)

    def _apply_pin_mode(self, pin_type: int, mode: int) -> None:
        with self._lock:
            modes = list(self._settings.pin_modes)
            modes[pin_type] = mode
            self._settings = replace(self._settings, pin_modes=tuple(modes))

    def _apply_channel_mode(self, channel: int, mode: int) -> None:
        with self._lock:
            modes = list(self._settings.channel_modes)
            modes[channel] = mode
            self._settings = replace(self._settings, channel_modes=tuple(modes))

    def _apply_comm(self, channel: int, comm: ChannelComm) -> None:
        with self._lock:
            comms = list(self._settings.comm)
            comms[channel] = comm
            self._settings = replace(self._settings, comm=tuple(comms))

    def _apply_frame(self, channel: int, frame: bytes) -> None:
        with self._lock:
            # checked by the facet against the settings; again under the lock, as they stand
            if self._device is not None and frame_refusal(self._settings, channel) is None:
                self._call("rs485", channel, frame, self._settings.comm[channel].baudrate)

    def _apply_add_signal(self, signal: Signal) -> None:
        with self._lock:
            check_signal(signal, self._signals)       # again, as the signals stand now
            self._polls[signal.name] = _Poll(self._cycle + 1)
            self._signals = self._signals + (signal,)

    def _apply_delete_signal(self, name: str) -> None:
        with self._lock:
            self._polls.pop(name, None)
            self._signals = tuple(s for s in self._signals if s.name != name)
