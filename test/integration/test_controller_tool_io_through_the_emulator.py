"""The controller backend's tool connector against the emulator over real TCP, with a small
fake device on the emulator's twin: each setting is read back from the controller, the rules
are checked against what the controller reports, a frame reaches the twin's device, and a
signal's latest value comes back both from get_tio_signals and from the status packets'
tio_rs_signals (the default profile's packet carries them), with no request at all; from a
controller whose packets do not carry them (the recorded zu5s-1.5.14), the backend asks
get_tio_signals itself at 10 Hz, so the value comes back all the same.
The emulator runs on the wall clock: the waits are bounded polls."""
from __future__ import annotations

import pytest

from support.emulated_arm import LINK_TIMEOUTS
from support.fake_tool_device import FakeToolDevice
from support.ros_harness import wait_until

from jaka_driver.backend.tool_io import ChannelComm, Signal
from jaka_driver.controller import ControllerBackend
from jaka_driver.emulator import Emulator


@pytest.fixture(scope="module")
def device(emu):
    d = FakeToolDevice()
    emu.backend.tool_io.attach(d)
    yield d
    emu.backend.tool_io.attach(None)


@pytest.fixture(scope="module")
def tio(emu, device):
    b = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                          **LINK_TIMEOUTS)
    b.start()
    yield b.tool_io
    b.shutdown()


def test_settings_read_back_from_the_controller_and_a_frame_reaches_the_twins_device(
        emu, tio, device):
    twin = emu.backend.tool_io
    assert tio.send_frame(1, [1, 6, 1, 3, 1, 0xF4]).code == -9     # the AI pins are analog
    r = tio.set_power(1, 0)
    assert r.ok and r.value == (True, 0) and device.volts == 24.0
    assert tio.set_pin_mode(2, 1).value == 1 and twin.settings().pin_modes[2] == 1
    assert tio.set_channel_mode(1, 0).value == 0
    comm = ChannelComm(1, 115200, 8, 1, 78)
    assert tio.set_channel_comm(1, comm).value == comm and twin.settings().comm[1] == comm
    r = tio.send_frame(1, [1, 6, 1, 3, 1, 0xF4])
    assert r.ok, r.message
    assert device.frames == [(1, bytes([1, 6, 1, 3, 1, 0xF4]), 115200)]
    assert tio.read_settings().value == twin.settings()
    r = tio.set_channel_comm(1, ChannelComm(baudrate=300))
    assert r.code == -2 and "baudrate is 300, expected 4800–230400" in r.message


def test_a_signal_comes_back_from_get_tio_signals_and_from_every_packet(emu, tio, device):
    r = tio.add_signal(Signal("grip_pos", 1, 3, 0x0202, frequency=10))
    assert r.ok and [s.name for s in r.value] == ["grip_pos"]
    assert wait_until(lambda: tio.read_signals().value[0].value == 500, 1.0)
    device.position = 321                          # the packets bring it, nothing is asked
    assert wait_until(lambda: tio.signals()[0].value == 321, 1.0)
    r = tio.delete_signal("grip_pos")
    assert r.ok and r.value == () and emu.backend.tool_io.signals() == ()


def test_a_controller_whose_packets_carry_no_signals_is_asked_for_them():
    device = FakeToolDevice()
    with Emulator("zu5", command_port=0, status_port=0, profile="zu5s-1.5.14",
                  start="enabled", programs=None) as emu:
        assert "tio_rs_signals" not in emu.profile.packet_keys
        emu.backend.tool_io.attach(device)
        b = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                              **LINK_TIMEOUTS)
        b.start()
        try:
            tio = b.tool_io
            assert tio.set_power(1, 0).ok and tio.set_pin_mode(2, 1).ok
            assert tio.add_signal(Signal("grip_pos", 1, 3, 0x0202, frequency=10)).ok
            device.position = 654                 # nothing is asked by the test from here
            assert wait_until(lambda: tio.signals()[0].value == 654, 1.0), tio.signals()
        finally:
            b.shutdown()
