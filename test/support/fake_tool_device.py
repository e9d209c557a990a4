"""A small fake of a device on the twin's tool connector (the ToolDevice interface,
jaka_driver.sim.tool_device), for the tests of the connector through the emulator: it records
every frame, and its register 0x0202 answers the last position a DH-style frame
(``01 06 01 03 hi lo``) set, while powered."""
from __future__ import annotations


class FakeToolDevice:
    POSITION = 0x0202

    def __init__(self):
        self.volts, self.frames, self.position = 0.0, [], 0

    def power(self, volts):
        self.volts = volts

    def rs485(self, channel, frame, baudrate):
        self.frames.append((channel, bytes(frame), baudrate))
        if len(frame) >= 6 and frame[:4] == bytes([1, 6, 1, 3]):
            self.position = frame[4] << 8 | frame[5]

    def read_register(self, channel, sig_type, address):
        return self.position if self.volts and address == self.POSITION else None

    def tool_outputs(self, levels):
        pass

    def tool_inputs(self):
        return {}

    def on_cycle(self):
        pass
