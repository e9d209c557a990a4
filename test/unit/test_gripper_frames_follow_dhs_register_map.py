"""Modbus RTU frames on the tool connector as public code sends them to a DH gripper, read and
written through pymodbus: JAKA's demo frames of 6 bytes (no CRC) and the same with their CRC
(DH's manual prints ``01 06 01 00 00 01 49 F6`` for the initialisation), a wrong CRC refused,
FC16 and FC03 requests, and the register table's roles."""
import pytest

from jaka_driver.devices.modbus_frames import (read_registers, read_request, write_register,
                                               write_registers)
from jaka_driver.devices.register_maps import DH_PGI


def test_jakas_demo_frames_are_written_as_they_send_them():
    assert write_register(1, 0x0100, 1) == bytes.fromhex("010601000001")
    assert write_register(1, 0x0103, 500) == bytes.fromhex("0106010301F4")
    assert write_register(1, 0x0100, 1, crc=True) == bytes.fromhex("01060100000149F6")


@pytest.mark.parametrize("frame", ["010601000001", "01060100000149F6"])
def test_a_frame_with_or_without_its_crc_is_the_same_request(frame):
    request = read_request(bytes.fromhex(frame))
    assert (request.slave, request.function, request.address, request.values) == \
        (1, 6, 0x0100, (1,))


def test_a_wrong_crc_a_short_frame_and_a_stray_length_are_refused():
    assert read_request(bytes.fromhex("01060100000149F7")) is None
    assert read_request(bytes.fromhex("010601")) is None
    assert read_request(bytes.fromhex("0106010000010000FF")) is None
    assert read_request(b"") is None and read_request(b"\xff" * 300) is None


def test_fc16_and_fc03_requests_round_trip_with_and_without_crc():
    for crc in (False, True):
        many = read_request(write_registers(1, 0x0101, [30, 0, 500], crc=crc))
        assert (many.function, many.address, many.values) == (16, 0x0101, (30, 0, 500))
        read = read_request(read_registers(1, 0x0200, 3, crc=crc))
        assert (read.function, read.address, read.count) == (3, 0x0200, 3)


def test_dhs_register_table_names_its_roles():
    assert DH_PGI.slave == 1
    assert [DH_PGI.role_of_write(a) for a in (0x0100, 0x0101, 0x0103, 0x0104, 0x0300)] == \
        ["init", "force", "position", "speed", "save"]
    assert DH_PGI.status_registers() == (0x0200, 0x0201, 0x0202)
    assert DH_PGI.init_values == (1, 0xA5) and DH_PGI.force_range == (20, 100)
