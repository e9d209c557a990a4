"""A JAKA controller's IO and what the status packet reads of the arm besides the sample (a part
of :class:`~.twin_controller.TwinController`): outputs set, inputs and outputs read (index from
0, checked against the arm's IO sizes), the inputs and faults the world outside drives (the
emulator's own commands), the TCP's speed and the ``torqsensor`` of a packet.
"""
from __future__ import annotations

import threading

from ..backend import Backend, RobotState, Twin
from ..common.models import RobotModel
from .replies import ERROR_REQUEST, Rejected
from .torque_sensor import TorqueSensorSettings


class ArmIo:
    """IO, the outside world's inputs and faults, and the packet's readings."""

    # set by TwinController.__init__
    backend: Backend
    twin: Twin
    model: RobotModel
    lock: threading.RLock
    sensor: TorqueSensorSettings

    def set_output(self, signal: str, io_type: int, index: int, value: float) -> None:
        """Output ``index`` (from 0; checked with :meth:`check_io`) = ``value``."""
        with self.lock:
            self.backend.set_io(signal, io_type, index, value)

    def read_io(self, signal: str, path: int, io_type: int, index: int) -> float:
        """An input (``path`` 0) or output (1), ``index`` from 0 (checked with
        :meth:`check_io`)."""
        return self.backend.get_io(signal, path, io_type, index).value

    def io_values(self) -> dict:
        """Every IO array as it stands (:meth:`jaka_driver.backend.Twin.io_snapshot`)."""
        return self.twin.io_snapshot()

    def io_count(self, signal: str, io_type: int, path: int) -> int:
        return int(self.model.io_sizes.get((signal, io_type, path), 0))

    def check_io(self, signal: str, io_type: int, path: int, index: int, what: str) -> None:
        count = self.io_count(signal, io_type, path)
        kind = "output" if path else "input"
        if count == 0:
            raise Rejected(f"{what}: IO type {io_type} has no {signal} {kind}s on this "
                           "controller", ERROR_REQUEST)
        if not 0 <= index < count:
            raise Rejected(f"{what}: {signal} {kind} index {index + 1} of type {io_type} does not "
                           f"exist (this type has {count}, numbered from 1)", ERROR_REQUEST)

    def set_input(self, signal: str, io_type: int, index: int, value: float) -> None:
        """Input ``index`` (from 0; checked with :meth:`check_io`) = ``value``, as the world
        outside would drive it."""
        with self.lock:
            self.twin.set_input(signal, io_type, index, value)

    def emergency_stop(self, pressed: bool) -> str:
        with self.lock:
            result = (self.twin.press_emergency_stop() if pressed
                      else self.twin.release_emergency_stop())
            return result.message

    def protective_stop(self, reason: str) -> str:
        with self.lock:
            return self.twin.trigger_protective_stop(reason).message

    def torqsensor(self, st: RobotState) -> list:
        """The status packet's ``torqsensor`` for the sample ``st``: the stored settings, and,
        when the arm carries a sensor (the backend's ``force``), the twin's sensor payload and
        the sample's three readings (:meth:`.torque_sensor.TorqueSensorSettings.monitor`)."""
        force = self.backend.force
        if force.absent is not None:
            return self.sensor.monitor()
        payload = force.settings().tool_payload
        return self.sensor.monitor((payload.mass, payload.centroid * 1000.0, st.force))

    def tcp_speed(self, st: RobotState) -> float:
        """m/s of the active tool's origin in the sample ``st``."""
        return self.twin.tcp_speed(st)
