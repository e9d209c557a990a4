"""What the twin's tool connector (:mod:`.tool_connector`) asks of a device on it: a gripper, a
suction cup. The interface both sides code against (duck typing); the devices live elsewhere.
"""
from __future__ import annotations

from typing import Protocol, Sequence


class ToolDevice(Protocol):
    """Something on the twin's tool connector (a gripper, a suction cup). All calls come from the
    physics thread between two cycles, or from a request holding simulated time: never two at once.
    Units: V, Hz; frames are the bytes exactly as a client sent them."""

    def power(self, volts: float) -> None:
        """The tool supply changed: 24.0 or 12.0 when on, 0.0 when off. Unpowered, a device
        answers nothing and ignores frames."""

    def rs485(self, channel: int, frame: bytes, baudrate: int) -> None:
        """A frame sent on RS485 channel ``channel`` (0 = RS485H, 1 = RS485L) whose pins are in RS485
        mode and whose channel mode is Modbus RTU (0) or raw (1); ``baudrate`` the channel's setting.
        The device checks slave id, CRC (both a 6-byte frame without CRC, as JAKA's demos send, and 8
        bytes with it are accepted; a wrong CRC is ignored), function and register itself.
        No reply travels back: JAKA's send_tio_rs_command returns only an error code."""

    def read_register(self, channel: int, sig_type: int, address: int) -> int | None:
        """What a Modbus read of one register answers: sig_type 3 holding register (FC03), 4 input
        register (FC04). None: no answer (unpowered, another channel, unknown address). The
        connector's signal poller calls this at each signal's frequency, counted in cycles."""

    def tool_outputs(self, levels: Sequence[float]) -> None:
        """The tool digital outputs (index 0 first) each time one changes (a suction cup's valve)."""

    def tool_inputs(self) -> dict[int, float]:
        """Tool digital inputs the device drives (index → level): a suction cup's vacuum switch."""

    def on_cycle(self) -> None:
        """Once per 8 ms cycle, in the physics thread, after the cycle's steps: the device's own
        state machine (a gripper's motion toward its target, grip state, object detection)."""
