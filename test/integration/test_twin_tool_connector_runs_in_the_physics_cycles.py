"""The twin's tool connector in the physics loop (zu5 twin in simulated time, through the
driver's door): the device's state machine runs once per 8 ms cycle, a 10 Hz signal is read
exactly 10 times a second of sim time at the same cycles on every run, a tool DO set with
set_io reaches the device, and the tool DI the device drives is in the samples."""
import math

import pytest

from support.sensor_twin import fresh, twin_with_sensor

from jaka_driver.backend.tool_io import ChannelComm

TOOL = 1


class CountingDevice:
    """Counts its cycles; register 0x0202 answers the cycle count; DI 0 follows DO 1."""

    def __init__(self, clock):
        self.clock, self.cycles, self.reads, self.dos = clock, 0, [], []
        self.volts = 0.0

    def power(self, volts):
        self.volts = volts

    def rs485(self, channel, frame, baudrate):
        pass

    def read_register(self, channel, sig_type, address):
        self.reads.append(round(self.clock.now(), 3))
        self.answered = self.cycles
        return self.cycles if self.volts else None

    def tool_outputs(self, levels):
        self.dos.append(tuple(levels))

    def tool_inputs(self):
        return {0: self.dos[-1][1] if self.dos else 0.0}

    def on_cycle(self):
        self.cycles += 1


@pytest.fixture(scope="module")
def driver():
    with twin_with_sensor(sensor=False) as d:
        yield d


def one_second_of_polling(driver):
    """From a fresh twin: set up channel 1, add a 10 Hz signal, run 1 s of sim time; the sim
    times of the reads relative to the add, what the device answered last and the signal's
    value."""
    for _ in fresh(driver):
        device = CountingDevice(driver.clock)
        driver.backend.tool_io.attach(device)
        try:
            t = driver.tool_io
            assert t.set_power(True, 24).ok and t.set_pin_mode(2, 1).ok
            assert t.set_channel_comm(1, ChannelComm()).ok
            t0 = driver.clock.now()
            assert t.add_signal("count", 1, 3, 0x0202, 10).ok
            driver.clock.sleep(1.0)
            value = t.signals().value[0].value
            return [round(r - t0, 3) for r in device.reads], device.answered, value
        finally:
            driver.backend.tool_io.attach(None)


def test_a_10_hz_signal_is_read_10_times_a_second_at_the_same_cycles_each_run(driver):
    first = one_second_of_polling(driver)
    reads, answered, value = first
    print(f"reads at {reads} s after the add; value {value}")
    # in the first cycle stepped after the add (the clock reads its start), then every 12.5
    # cycles rounded up: cycles 0, 13, 25, 38, 50 …
    assert reads == [round(math.ceil(k * 12.5) * 0.008, 3) for k in range(10)]
    assert value == answered > 0                                 # the latest read
    assert one_second_of_polling(driver) == first                # bit for bit the same


def test_a_tool_do_reaches_the_device_and_its_di_is_in_the_samples(driver):
    for _ in fresh(driver):
        device = CountingDevice(driver.clock)
        driver.backend.tool_io.attach(device)
        try:
            assert driver.set_io("digital", TOOL, 1, 1.0).ok
            assert device.dos[-1] == (0.0, 1.0)
            driver.clock.sleep(0.016)
            assert driver.state().io[("digital", TOOL, 0)][0] == 1.0
        finally:
            driver.backend.tool_io.attach(None)
