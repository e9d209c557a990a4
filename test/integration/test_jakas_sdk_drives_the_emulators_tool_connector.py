"""JAKA's SDK's twelve tool-connector functions (test/support/jaka_sdk_tio.py: the measured
requests, byte for byte, and the SDK's strict reading of the replies) against the emulator,
whose answers come from the twin's tool connector with a small fake device hung on it:

- each function sends exactly the measured request and returns 0; every setting reads back;
- JAKA's demo sequence (24 V, AI pins to RS485L, channel 1 Modbus at 115200 8N1, DH frames of 6
  bytes and of 8 with the CRC) puts the frames on the twin's device as sent;
- a signal on the device's register is polled at its frequency into get_tio_signals and into
  the status packet's tio_rs_signals (the default profile's packet has the key; the recorded
  zu5s-1.5.14 packet has not);
- what the connector refuses (a frame on a channel not in RS485 mode, 4799 baud, 11 Hz) is a
  non-zero errorCode (the SDK's 2) with the rule's words, and changes nothing.

The emulator's twin runs on the wall clock: the signal waits are bounded polls.
"""
from __future__ import annotations

import json
import socket
import zlib

import pytest

from support.jaka_sdk_model import RC_FAILED, RC_OK, JakaSdk
from support.jaka_sdk_tio import SDK_REQUESTS, JakaSdkTio, packet_signals
from support.fake_tool_device import FakeToolDevice
from support.ros_harness import wait_until

from jaka_driver.emulator import Emulator
from jaka_driver.emulator.profiles import profile_named

DH_INIT = [0x01, 0x06, 0x01, 0x00, 0x00, 0x01]           # DH: initialise
DH_500 = [0x01, 0x06, 0x01, 0x03, 0x01, 0xF4]            # DH: position 500 ‰
DH_500_CRC = DH_500 + [0x78, 0x21]                      # the same with its CRC (lo, hi)


@pytest.fixture(scope="module")
def emu():
    with Emulator("zu5", command_port=0, status_port=0) as emulator:
        yield emulator


@pytest.fixture
def device(emu):
    device = FakeToolDevice()
    emu.backend.tool_io.reset()
    emu.backend.tool_io.attach(device)
    yield device
    emu.backend.tool_io.attach(None)
    emu.backend.tool_io.reset()


@pytest.fixture
def tio(emu, device):
    sdk = JakaSdk("127.0.0.1", emu.command_port, emu.data_port)
    yield JakaSdkTio(sdk)
    sdk.close()


def packet(emu) -> dict:
    """One status packet from the data port (data_request, as the SDK asks for it)."""
    with socket.create_connection(("127.0.0.1", emu.data_port), timeout=5) as sock:
        sock.sendall(b'{"cmdName":"data_request"}')
        inflater, text = zlib.decompressobj(), b""
        while not inflater.eof:
            text += inflater.decompress(sock.recv(65536))
    return json.loads(text)


def test_each_function_sends_the_measured_request_and_returns_0(tio):
    sdk = tio.sdk
    assert tio.set_tio_pin_mode(2, 1) == RC_OK           # channel 1's pins to RS485L first
    for (function, args), measured in SDK_REQUESTS.items():
        out = getattr(tio, function)(*args)
        rc = out if isinstance(out, int) else out[0]
        assert rc == RC_OK, f"{function}{args} returned {rc}"
        assert sdk.sent[-1] == measured, function
    assert tio.get_tio_vout_param() == (RC_OK, (1, 1))
    assert tio.get_tio_pin_mode(1) == (RC_OK, 18)
    assert tio.get_rs485_chn_mode(1) == (RC_OK, 1)
    assert tio.get_rs485_chn_comm(0) == (RC_OK, (9, 115200, 8, 1, 78))
    assert tio.get_rs485_signal_info() == (RC_OK, [])    # added, then deleted


def test_jakas_demo_sequence_reaches_the_twins_device_and_its_signal_comes_back(emu, tio,
                                                                                device):
    assert tio.set_tio_vout_param(1, 0) == RC_OK          # 24 V
    assert device.volts == 24.0
    assert tio.set_tio_pin_mode(2, 1) == RC_OK           # AI pins → RS485L
    assert tio.set_rs485_chn_mode(1, 0) == RC_OK         # channel 1 → Modbus RTU
    assert tio.set_rs485_chn_comm(1, 1, 115200, 8, 1, 78) == RC_OK
    assert tio.add_tio_rs_signal("grip_pos", 1, 3, 0x0202, 10) == RC_OK
    for frame in (DH_INIT, DH_500, DH_500_CRC):
        assert tio.send_tio_rs_command(1, frame) == RC_OK
    assert device.frames == [(1, bytes(f), 115200) for f in (DH_INIT, DH_500, DH_500_CRC)]
    row = ("grip_pos", 1, 3, 0x0202, 500, 10)
    assert wait_until(lambda: tio.get_rs485_signal_info() == (RC_OK, [row]), 1.0)
    assert packet_signals(packet(emu)) == [row]
    assert emu.profile.packet_keys is None                # the default: every key the SDK reads
    assert "tio_rs_signals" not in profile_named("zu5s-1.5.14").packet_keys


def test_what_the_connector_refuses_is_a_failure_with_its_reason_and_changes_nothing(tio,
                                                                                     device):
    sdk = tio.sdk
    assert tio.send_tio_rs_command(1, DH_500) == RC_FAILED   # the AI pins are analog
    reply = sdk.call("send_tio_rs_command", chn_id=1, cmdBuf=DH_500)[1]
    assert reply["errorCode"] == "2" and "the AI pins' mode is 0, expected 1" in reply["errorMsg"]
    assert device.frames == []
    rc, reply = sdk.call("set_rs485_chn_comm", baudrate=4799, chn_id=1, databit=8, parity=78,
                         slaveId=1, stopbit=1)
    assert rc == RC_FAILED and "baudrate is 4799, expected 4800–230400" in reply["errorMsg"]
    assert tio.get_rs485_chn_comm(1) == (RC_OK, (1, 115200, 8, 1, 78))
    assert tio.add_tio_rs_signal("grip_pos", 1, 3, 0x0202, 11) == RC_FAILED
    assert "frequency is 11 Hz, expected 1–10 Hz" in sdk.call(
        "add_tio_rs_signal", frequency=11, tio_signal_chnId=1, tio_signal_name="g",
        tio_signal_sigAddr=1, tio_signal_sigType=3)[1]["errorMsg"]
    assert tio.set_rs485_chn_mode(2, 0) == RC_FAILED
    assert tio.get_rs485_chn_mode(2)[0] == RC_FAILED
    assert tio.set_tio_vout_param(1, 2) == RC_FAILED
    assert tio.get_tio_vout_param() == (RC_OK, (0, 0))
    assert tio.get_rs485_signal_info() == (RC_OK, [])
