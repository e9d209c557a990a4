"""Malformed controller output, decoded without sockets: the head decoder tells an unfinished
value from one that can never be valid (and raises nothing but MalformedInput), the status
stream decoder drops and counts a malformed packet and keeps the ones around it, and
parse_status reads a field of the wrong type as its default and names it in ``malformed`` — for
every key it reads. The same inputs over real sockets: test/integration/
test_protocol_readers_survive_malformed_input.py."""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaka_driver.protocol import StatusStreamDecoder, encode_status, parse_status
from jaka_driver.protocol.errors import MalformedInput
from jaka_driver.protocol.wire import MAX_NESTING, HeadDecoder
from support.malformed_inputs import DEEP, STATUS_KEYS_READ as READ_KEYS

FIXTURE = json.loads((Path(__file__).parents[1] / "data" / "status_packet.json").read_text())

# (name, bytes at the head of a buffer): each can never become a valid value
MALFORMED = [
    ("nested-100000-deep", b'{"x": ' + b"[" * DEEP + b"]" * DEEP + b"}"),
    ("nested-100000-deep-unclosed", b'{"x": ' + b"[" * DEEP),
    ("invalid-utf8-outside-a-string", b'{"x": \xff\xfe}'),
    ("nan-literal", b'{"x": NaN}'),
    ("infinity-literal", b'{"x": [1, Infinity]}'),
    ("minus-infinity-literal", b'{"x": -Infinity}'),
    ("10000-digit-integer", b'{"x": ' + b"7" * 10_000 + b"}"),
    ("bracket-closing-the-wrong-kind", b'{"x": [1, 2}'),
    ("not-a-bracket", b"HTTP/1.1 400 Bad Request\r\n\r\n{}"),
]
UNFINISHED = [b'{"x": 1', b'{"x": tru', b'{"x": "ab}', b'{"x": "\\', b'{"x": [[1, 2], [',
              b'{"x": -', b'{"x": 1e9']


@pytest.mark.parametrize("data", [m[1] for m in MALFORMED], ids=[m[0] for m in MALFORMED])
def test_the_head_decoder_calls_bytes_that_can_never_be_json_malformed(data):
    with pytest.raises(MalformedInput):
        HeadDecoder().decode(data)


@pytest.mark.parametrize("data", UNFINISHED)
def test_the_head_decoder_waits_for_the_rest_of_an_unfinished_value(data):
    assert HeadDecoder().decode(data) is None


def test_a_value_fed_one_byte_at_a_time_comes_out_once_whole():
    data = json.dumps({"s": "a}]\\\"[{", "n": [1, [2, {"t": "ü"}]], "z": 1e300}).encode()
    head, buf, out = HeadDecoder(), bytearray(), []
    for byte in data + b"{":
        buf.append(byte)
        decoded = head.decode(buf)
        if decoded is not None:
            out.append((len(buf), decoded))
            del buf[:decoded.used]
    assert len(out) == 1 and out[0][0] == len(data) and out[0][1].used == len(data)
    assert out[0][1].value == json.loads(data) and not out[0][1].repaired


def test_invalid_utf8_inside_a_string_is_kept_and_reported_repaired():
    packet = b'{"errmsg": "\xc5\xf6\xd7\xb2", "x": 1}'   # GBK, not UTF-8
    decoded = HeadDecoder().decode(packet + b' {"next"')
    assert decoded.repaired and decoded.value["x"] == 1 and decoded.used == len(packet)


def test_a_number_too_large_for_a_float_decodes_as_infinity():
    assert HeadDecoder().decode(b'{"x": 1e999}').value == {"x": math.inf}


def test_nesting_is_refused_just_past_its_limit_and_accepted_at_it():
    assert HeadDecoder().decode(b"[" * MAX_NESTING + b"]" * MAX_NESTING) is not None
    with pytest.raises(MalformedInput, match="nested more than"):
        HeadDecoder().decode(b"[" * (MAX_NESTING + 1) + b" ")


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=300), st.integers(0, 300))
def test_no_bytes_make_the_head_decoder_raise_anything_else(data, cut):
    head = HeadDecoder()
    for buf in (data, b"{" + data, data[:cut]):
        try:
            head.decode(buf)
        except MalformedInput:
            pass
        head.reset()


# ---- the status stream decoder -----------------------------------------------------------------

def good(i):
    return encode_status({"joint_actual_position": [i, 0, 0, 0, 0, 0], "errcode": "0x0"})


@pytest.mark.parametrize("data", [m[1] for m in MALFORMED[:-1]], ids=[m[0] for m in MALFORMED[:-1]])
def test_the_stream_decoder_drops_one_malformed_packet_and_keeps_its_neighbours(data):
    broken = b'{"len": 99, ' + data[1:]
    decoder = StatusStreamDecoder()
    out = decoder.feed(good(1) + broken + good(2))
    assert [p["joint_actual_position"][0] for p in out] == [1, 2]
    assert decoder.packets_dropped == 1 and decoder.packets == 2
    assert decoder.buffered == 0


def test_a_megabyte_without_a_closing_brace_is_dropped_and_the_stream_resumes():
    decoder = StatusStreamDecoder()
    out = decoder.feed(good(1) + b'{"len": 9, "x": "' + b"a" * (1 << 20))
    out += decoder.feed(b'" ' + good(2))
    assert [p["joint_actual_position"][0] for p in out] == [1, 2]
    assert decoder.packets_dropped == 1 and decoder.bytes_dropped > 1 << 20


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=200), st.integers(0, 400))
def test_no_bytes_make_the_stream_decoder_raise(noise, where):
    stream = good(1) + good(2)
    where = min(where, len(stream))
    decoder = StatusStreamDecoder()
    decoder.feed(stream[:where] + noise + stream[where:] + good(3))
    assert decoder.packets + decoder.packets_dropped >= 1


# ---- parse_status: wrong types in every key it reads --------------------------------------------

WRONG = {"object": {"a": 1}, "text": "text", "null": None, "nested": [[1, 2]],
         "infinity": math.inf, "nan-list": [math.nan] * 6, "huge-int": 10 ** 400,
         "deep": json.loads("[" * 60 + "]" * 60)}
# the few pairs that are right after all (a string is an errmsg; a huge int is an int)
VALID = {("errmsg", "text"), ("powered_on", "huge-int"), ("enabled", "huge-int"),
         ("emergency_stop", "huge-int"), ("protective_stop", "huge-int"),
         ("on_soft_limit", "huge-int"), ("inpos", "huge-int"), ("paused", "huge-int"),
         ("drag_status", "huge-int"), ("task_state", "huge-int"), ("task_mode", "huge-int"),
         ("interp_state", "huge-int"), ("current_tool_id", "huge-int"),
         ("current_user_id", "huge-int"), ("errcode", "huge-int"), ("motion_line", "huge-int")}


def test_the_fixture_reads_with_nothing_malformed():
    status = parse_status(FIXTURE)
    assert status.malformed == () and status.missing == ()
    assert status.homed == (1,) * 9 and status.sensor_errcode == 0
    np.testing.assert_allclose(status.joint_velocity, np.zeros(6))
    np.testing.assert_allclose(status.joint_torque, [1.9, 32.6, 12.8, 0.7, 0.4, 0.1])


@pytest.mark.parametrize("key", READ_KEYS)
def test_a_field_of_the_wrong_type_reads_as_its_default_and_is_named(key):
    default = parse_status({})
    for name, value in WRONG.items():
        if (key, name) in VALID:
            continue
        status = parse_status({**FIXTURE, key: value})
        assert status.malformed == (key,), (name, status.malformed)
        assert key in status.missing
        for attr in ("joint_position", "tcp_pose", "joint_velocity", "joint_torque"):
            value_of = getattr(status, attr)
            assert np.all(np.isfinite(value_of)) or np.all(np.isnan(value_of))
        if key == "errcode":
            assert status.errcode == -1   # unreadable is not "no error"
        elif key == "joint_actual_position":
            assert np.all(np.isnan(status.joint_position))
        elif key == "powered_on":
            assert status.powered == default.powered


def test_every_key_wrong_at_once_still_gives_a_packet():
    status = parse_status({key: {"a": [1]} for key in READ_KEYS})
    assert set(status.malformed) == set(READ_KEYS)
    assert status.errcode == -1 and not status.powered and np.all(np.isnan(status.tcp_pose))
