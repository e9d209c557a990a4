"""The twin's IO: cabinet, tool and extension, digital and analog, inputs and outputs.

Sizes come from ``config/<model>.yaml`` (``RobotModel.io_sizes``). Outputs are set by
``set_io``; inputs only by fault injection (``/jaka_driver/sim/set_input``) or by the optional
loopback wiring, where output n drives input n of the same signal and type.
"""
from __future__ import annotations

import threading
from types import MappingProxyType

import numpy as np

INPUT, OUTPUT = 0, 1


class IoBoard:
    def __init__(self, sizes: dict, loopback: bool = False):
        self._lock = threading.Lock()
        self._points = {key: np.zeros(count) for key, count in sizes.items()}
        self.loopback = loopback
        self._values = None             # the read-only copy values() hands out, until a write
        #: called ``(signal, io_type)`` after each output write, outside the lock (the tool
        #: connector hands the tool DOs to its device: sim/tool_connector.py)
        self.listeners: list = []

    def read(self, signal: str, path: int, io_type: int, index: int) -> float:
        with self._lock:
            return float(self._points[(signal, io_type, path)][index])

    def write_output(self, signal: str, io_type: int, index: int, value: float) -> None:
        with self._lock:
            self._values = None
            self._points[(signal, io_type, OUTPUT)][index] = value
            if self.loopback:
                inputs = self._points.get((signal, io_type, INPUT))
                if inputs is not None and index < len(inputs):
                    inputs[index] = value
        for listener in self.listeners:
            listener(signal, io_type)

    def write_input(self, signal: str, io_type: int, index: int, value: float) -> None:
        with self._lock:
            self._values = None
            self._points[(signal, io_type, INPUT)][index] = value

    def reset(self) -> None:
        """Every input and output back to 0."""
        with self._lock:
            self._values = None
            for values in self._points.values():
                values[:] = 0.0

    def values(self):
        """Every array as it stands, read-only (``RobotState.io``): the same object until the
        next write, so a sample costs no copy and an unchanged board compares at once."""
        with self._lock:
            if self._values is None:
                self._values = MappingProxyType(
                    {key: tuple(v.tolist()) for key, v in self._points.items() if v.size})
            return self._values

    def snapshot(self) -> dict:
        """Copies of every array, keyed (signal, type, path)."""
        with self._lock:
            return {key: values.copy() for key, values in self._points.items()}
