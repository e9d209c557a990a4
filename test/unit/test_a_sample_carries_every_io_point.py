"""Every IO point a sample carries (RobotState.io, what ~io_states publishes): from a status
packet written from the evidence (test/data/status_packet.json: cabinet 135/64, tool 8/8/2,
relays 4, the three fieldbus slaves 64 each, no extension module) every array with its type and
direction, as it came; an extension module's arrays when extio's num is above 0 (as JAKA's SDK
reads it); the twin's IO board as one read-only object until the next write."""
from __future__ import annotations

import json

import pytest

from support.fake_controller import load_status_packet

from jaka_driver.controller.status_view import packet_io
from jaka_driver.protocol import parse_status
from jaka_driver.sim.io_board import IoBoard


@pytest.fixture
def packet() -> dict:
    return json.loads(load_status_packet())


def test_a_packet_gives_every_kind_with_its_type_and_direction(packet):
    packet["dout"][3] = 1
    packet["relay_io"][2] = 1
    packet["pn_dev_aout"][63] = 1.5
    io = packet_io(parse_status(packet))
    sizes = {key: len(values) for key, values in io.items()}
    assert sizes == {("digital", 0, 0): 135, ("digital", 0, 1): 135, ("analog", 0, 0): 64,
                     ("analog", 0, 1): 64, ("digital", 1, 0): 8, ("digital", 1, 1): 8,
                     ("analog", 1, 0): 2, ("digital", 3, 1): 4,
                     **{(signal, bus, path): 64 for bus in (4, 5, 6)
                        for signal in ("digital", "analog") for path in (0, 1)}}
    assert io[("digital", 0, 1)][3] == 1 and sum(io[("digital", 0, 1)]) == 1
    assert io[("digital", 3, 1)] == (0, 0, 1, 0)
    assert io[("analog", 5, 1)][63] == 1.5


def test_an_extension_module_is_read_when_extio_counts_one(packet):
    assert not any(key[1] == 2 for key in packet_io(parse_status(packet)))    # num 0
    packet["extio"] = {"num": 1, "status": [[0, 1], [1, 0, 1], [0.5], [2.5, 0.0]]}
    io = packet_io(parse_status(packet))
    assert (io[("digital", 2, 0)], io[("digital", 2, 1)], io[("analog", 2, 0)],
            io[("analog", 2, 1)]) == ((0, 1), (1, 0, 1), (0.5,), (2.5, 0.0))


def test_a_malformed_array_is_noted_and_left_out(packet):
    packet["mb_slave_din"] = "x"
    packet["extio"] = {"num": 1, "status": [[0]]}
    status = parse_status(packet)
    assert {"mb_slave_din", "extio"} <= set(status.malformed)
    io = packet_io(status)
    assert ("digital", 4, 0) not in io and ("digital", 4, 1) in io
    assert not any(key[1] == 2 for key in io)


def test_the_twins_board_is_one_read_only_object_until_the_next_write():
    board = IoBoard({("digital", 0, 1): 4, ("analog", 1, 0): 2, ("digital", 2, 0): 0})
    first = board.values()
    assert board.values() is first and ("digital", 2, 0) not in first    # no points: absent
    with pytest.raises(TypeError):
        first[("digital", 0, 1)] = (1, 1, 1, 1)
    board.write_output("digital", 0, 2, 1.0)
    second = board.values()
    assert second is not first and second[("digital", 0, 1)] == (0.0, 0.0, 1.0, 0.0)
    assert first[("digital", 0, 1)] == (0.0, 0.0, 0.0, 0.0)          # what that sample had
