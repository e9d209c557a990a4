"""The installation angle on the controller backend, through the emulator (docs/protocol.md,
"Mounting"): JAKA's SDK's literal request (§11: deg, 16 digits) is answered with a string
errorCode "0" and turns the emulator's twin's gravity; the reply of get_installation_angle has
the SDK's shape ``[[s, x, y, z], [rx, ry, rz deg]]``; the driver's request reaches the twin and
is read back; a value out of JAKA's range is a wrong request ("1") and changes nothing."""
import json
import math
import socket

import numpy as np
import pytest

from support.emulated_arm import driver_on_emulator

SET = b'{"angleX":28.64788975654116,"angleZ":57.29577951308232,"cmdName":"set_installation_angle"}'


def exchange(port, request: bytes) -> dict:
    with socket.create_connection(("127.0.0.1", port), timeout=3.0) as sock:
        sock.sendall(request)
        return json.loads(sock.recv(65536))


@pytest.fixture(scope="module")
def arm():
    with driver_on_emulator(programs=None) as pair:
        yield pair


def test_the_sdks_request_turns_the_twins_gravity_and_reads_back_in_its_shape(arm):
    emu, _ = arm
    reply = exchange(emu.command_port, SET)
    assert reply["errorCode"] == "0" and isinstance(reply["errorCode"], str)
    mounting = emu.backend.installation_angle().value
    assert (mounting.tilt_x, mounting.rot_z) == pytest.approx((0.5, 1.0))
    got = exchange(emu.command_port, b'{"cmdName":"get_installation_angle"}')
    quat, rpy = got["installation_angle"]
    assert len(quat) == 4 and rpy == pytest.approx([28.64789, 0.0, 57.29578], abs=1e-5)
    s, x, y, z = quat
    assert np.allclose([x, y, z, s], mounting.quaternion, atol=1e-6)
    bad = exchange(emu.command_port, b'{"angleX":181.0,"angleZ":0.0,'
                                     b'"cmdName":"set_installation_angle"}')
    assert bad["errorCode"] == "1" and "angleX" in bad["errorMsg"] and "180" in bad["errorMsg"]
    assert emu.backend.installation_angle().value.tilt_x == pytest.approx(0.5)


def test_the_driver_mounts_the_controllers_arm_and_reads_it_back(arm):
    emu, driver = arm
    result = driver.set_installation_angle(math.pi / 2, math.radians(30))
    assert result.ok, result.message
    reading = driver.installation_angle().value
    assert reading.tilt_x == pytest.approx(math.pi / 2, abs=1e-5)
    assert reading.rot_z == pytest.approx(math.radians(30), abs=1e-5)
    # on the wall gravity is the base's −y, whichever way the wall faces (the turn about z)
    assert emu.backend.installation_angle().value.gravity == pytest.approx([0.0, -9.81, 0.0],
                                                                           abs=1e-9)
    assert driver.set_installation_angle(0.0, 0.0).ok
