"""The status reader keeps ``torqsensor`` as bytes and reads it only when they changed (its
settings and a stopped sensor's zeros come again packet after packet): the same bytes give the
very same reading, other bytes their own, and bytes that do not read as a torqsensor make the
field malformed — whatever the packet before them was."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from jaka_driver.protocol import encode_status, parse_status
from jaka_driver.protocol.status_packet import decode_read_keys

PACKET = json.loads((Path(__file__).resolve().parents[1] / "data" / "status_packet.json")
                    .read_text())


def _read(torqsensor):
    fields = dict(PACKET, torqsensor=torqsensor)
    return parse_status(decode_read_keys(encode_status(fields)))


def _sensor(status: int, errcode: int, actual):
    return [[1, ["", 0], [0.5, [0, 0, 20]]], [status, errcode, actual, [0.0] * 6, [0.0] * 6]]


def test_the_same_bytes_give_the_same_reading_and_other_bytes_their_own():
    first = _read(_sensor(1, 0, [1.0, 2.0, 3.0, 0.1, 0.2, 0.3]))
    again = _read(_sensor(1, 0, [1.0, 2.0, 3.0, 0.1, 0.2, 0.3]))
    assert again.torque_sensor is first.torque_sensor      # read once
    moved = _read(_sensor(1, 7, [1.5, 2.0, 3.0, 0.1, 0.2, 0.3]))
    assert moved.torque_sensor is not first.torque_sensor
    np.testing.assert_array_equal(moved.torque_sensor.actual, [1.5, 2.0, 3.0, 0.1, 0.2, 0.3])
    assert (moved.sensor_errcode, moved.torque_sensor.errcode) == (7, 7)
    assert first.torque_sensor.actual[0] == 1.0            # the earlier reading untouched


def test_unreadable_bytes_are_malformed_after_a_good_packet_and_before_one():
    good = _read(_sensor(1, 0, [0.0] * 6))
    assert "torqsensor" not in good.malformed
    short = _read(_sensor(1, 3, [0.0] * 5))                # a wrench of five numbers
    assert "torqsensor" in short.malformed and short.torque_sensor is None
    assert short.sensor_errcode == 3                       # what could be read is kept
    bad = _read([[True], "x"])
    assert "torqsensor" in bad.malformed and bad.sensor_errcode == 0
    assert _read(_sensor(1, 0, [0.0] * 6)).torque_sensor is not None
