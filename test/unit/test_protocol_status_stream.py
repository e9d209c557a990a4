"""The port-10000 stream: packets come out whole whatever the read boundaries, garbage and broken
packets are skipped and counted, the buffer stays bounded, ``len`` is self-consistent, and a
packet becomes a StatusPacket in driver units."""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jaka_driver.protocol import StatusPacket, StatusStreamDecoder, encode_status, parse_status
from jaka_driver.protocol.status_stream import PACKET_START

DATA = Path(__file__).resolve().parents[1] / "data"

# ---- packets -------------------------------------------------------------------------------

json_scalars = st.one_of(st.none(), st.booleans(), st.integers(-10**9, 10**9),
                         st.floats(allow_nan=False, allow_infinity=False), st.text(max_size=12))
json_values = st.recursive(
    json_scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=5),
                            st.dictionaries(st.text(max_size=6), inner, max_size=4)),
    max_leaves=8)
# keys may be anything (also a nested "len": the decoder must not take it for a new packet)
packets = st.dictionaries(st.text(min_size=1, max_size=10).filter(lambda k: k != "len"),
                          json_values, max_size=6).map(lambda d: json.loads(encode_status(d)))


def sample_packet(i=0):
    return {"joint_actual_position": [i, 90.0, -45.5, 0, 0, 180], "errcode": "0x0",
            "errmsg": "机器人", "din": [0, 1] * 20}


def feed_in_pieces(decoder, data, cuts):
    out = []
    bounds = [0, *sorted(set(cuts)), len(data)]
    for a, b in zip(bounds, bounds[1:]):
        out += decoder.feed(data[a:b])
    return out


@settings(max_examples=120, deadline=None)
@given(st.lists(packets, min_size=1, max_size=5), st.data())
def test_any_split_yields_the_same_packets(pkts, data):
    stream = b"".join(encode_status(p) for p in pkts)
    cuts = data.draw(st.lists(st.integers(0, len(stream)), max_size=40))
    decoder = StatusStreamDecoder()
    assert feed_in_pieces(decoder, stream, cuts) == pkts
    assert (decoder.bytes_dropped, decoder.packets_dropped, decoder.buffered) == (0, 0, 0)
    assert decoder.packets == len(pkts)


def test_byte_by_byte_and_all_at_once():
    stream = b"".join(encode_status(sample_packet(i)) for i in range(3))
    one_by_one = StatusStreamDecoder()
    got = [p for i in range(len(stream)) for p in one_by_one.feed(stream[i:i + 1])]
    assert [p["joint_actual_position"][0] for p in got] == [0, 1, 2]
    assert [p["joint_actual_position"][0] for p in StatusStreamDecoder().feed(stream)] == [0, 1, 2]


@settings(max_examples=100, deadline=None)
@given(st.lists(st.binary(max_size=30).filter(lambda b: b"{" not in b), min_size=3, max_size=3),
       st.data())
def test_garbage_between_packets_is_skipped_and_counted(garbage, data):
    pkts = [encode_status(sample_packet(i)) for i in range(2)]
    stream = garbage[0] + pkts[0] + garbage[1] + pkts[1] + garbage[2]
    cuts = data.draw(st.lists(st.integers(0, len(stream)), max_size=10))
    decoder = StatusStreamDecoder()
    got = feed_in_pieces(decoder, stream, cuts)
    assert [p["joint_actual_position"][0] for p in got] == [0, 1]
    assert decoder.packets_dropped == 0
    # trailing garbage is counted once the next packet (or more garbage) shows it is not a token
    decoder.feed(encode_status(sample_packet(9)))
    assert decoder.bytes_dropped == sum(map(len, garbage))


def test_truncated_packet_is_dropped_and_the_stream_resyncs():
    a, b, c = (encode_status(sample_packet(i)) for i in range(3))
    decoder = StatusStreamDecoder()
    assert decoder.feed(a[: len(a) // 2]) == []   # could still complete
    got = decoder.feed(b + c)
    assert [p["joint_actual_position"][0] for p in got] == [1, 2]
    assert decoder.packets_dropped == 1
    assert decoder.bytes_dropped == len(a) // 2


def test_corrupted_packet_is_dropped():
    a, b = (encode_status(sample_packet(i)) for i in range(2))
    broken = a.replace(b'"errcode"', b'"errcode" ]]')
    decoder = StatusStreamDecoder()
    got = decoder.feed(broken + b)
    assert [p["joint_actual_position"][0] for p in got] == [1]
    assert (decoder.packets_dropped, decoder.bytes_dropped) == (1, len(broken))


def test_token_split_across_reads_is_kept():
    pkt = encode_status(sample_packet())
    decoder = StatusStreamDecoder()
    assert decoder.feed(b"junk" + pkt[:3]) == []
    assert decoder.buffered == 3 and decoder.bytes_dropped == 4
    assert len(decoder.feed(pkt[3:])) == 1


def test_buffer_is_bounded():
    decoder = StatusStreamDecoder(max_buffer=1000)
    # a packet that never ends
    decoder.feed(PACKET_START + b'1,"x":"' + b"a" * 600)
    decoder.feed(b"a" * 600)
    assert decoder.buffered == 0
    assert decoder.packets_dropped == 1 and decoder.bytes_dropped > 1000
    # and the decoder still works afterwards
    assert len(decoder.feed(encode_status(sample_packet()))) == 1
    # garbage without any token is never held
    decoder.feed(b"x" * 5000)
    assert decoder.buffered == 0


def test_nested_len_key_does_not_break_an_incomplete_packet():
    pkt = encode_status({"a": {"len": 3, "b": [1, 2]}, "c": "x" * 50})
    decoder = StatusStreamDecoder()
    assert decoder.feed(pkt[:30]) == []
    assert decoder.feed(pkt[30:]) == [json.loads(pkt)]
    assert decoder.packets_dropped == 0


# ---- the compiled parser's path ------------------------------------------------------------

@pytest.fixture
def no_python_parser(monkeypatch):
    """json's parser made to fail: what still decodes went through the compiled one."""
    from jaka_driver.protocol import wire

    class Refuse:
        def raw_decode(self, text):
            raise AssertionError("the pure-Python parser was used")
    monkeypatch.setattr(wire, "_STRICT", Refuse())


def test_a_whole_packet_never_reaches_the_pure_python_parser(no_python_parser):
    """The 8 ms packet of the default profile's size, whole or with the next one's first bytes
    behind it, is cut at its ``len`` and parsed by the compiled parser."""
    fields = json.loads((DATA / "status_packet.json").read_text())
    a, b = encode_status(fields), encode_status(sample_packet(1))
    assert len(a) > 6000
    decoder = StatusStreamDecoder()
    assert decoder.feed(a) == [json.loads(a)]
    assert decoder.feed(b + a[:100]) == [json.loads(b)]
    assert decoder.buffered == 100 and decoder.packets_dropped == 0


@pytest.mark.parametrize("declared", [10, 500, 10**6])
def test_a_wrong_len_costs_no_packet(declared):
    """``len`` is a hint: too short, too long or beyond belief, the packets still come whole
    (the careful path), in order, nothing dropped."""
    body = json.loads(encode_status(sample_packet(0)))
    body["len"] = declared
    from jaka_driver.protocol.wire import encode_json_spaced
    pkts = [encode_json_spaced(body), encode_status(sample_packet(1))]
    decoder = StatusStreamDecoder()
    got = decoder.feed(pkts[0]) + decoder.feed(pkts[1])
    assert [p["joint_actual_position"][0] for p in got] == [0, 1]
    assert (decoder.packets_dropped, decoder.bytes_dropped) == (0, 0)


@pytest.mark.parametrize("data", [
    b'{"a": 1} {"b": 2}', b' {"a": 1}', b'{"a": NaN}', b'{"a": "\xff"}', b'{"a": "\\ud800"}',
    b'{"a": [1, 2}', b'{"a": ' + b"[" * 100_000 + b"]" * 100_000 + b"}", b'"text"', b"",
    b'{"a": 1', b"[1] ", b'{"a": 1}]'])
def test_what_is_not_exactly_one_value_is_left_to_the_careful_reader(data):
    from jaka_driver.protocol.wire import decode_whole
    assert decode_whole(data) is None


@settings(max_examples=100, deadline=None)
@given(packets)
def test_the_compiled_parser_reads_a_packet_as_json_does(packet):
    from jaka_driver.protocol.wire import decode_whole
    data = encode_status(packet)
    assert decode_whole(data) == json.loads(data) == packet
    assert decode_whole(bytearray(data)) == packet


# ---- encode_status -------------------------------------------------------------------------

@settings(max_examples=100)
@given(packets)
def test_len_is_the_packet_length_in_bytes(packet):
    wire = encode_status(packet)
    assert wire.startswith(PACKET_START)
    assert json.loads(wire)["len"] == len(wire)


@pytest.mark.parametrize("size", [0, 1, 80, 90, 981, 990, 9979, 9990, 99980])
def test_len_across_digit_boundaries(size):
    wire = encode_status({"x": "a" * size, "len": 12345})
    assert json.loads(wire)["len"] == len(wire)


def test_encode_status_takes_numpy_and_utf8():
    wire = encode_status({"joint_actual_position": np.zeros(6), "task_state": np.int64(4),
                          "errmsg": "碰撞"})
    packet = json.loads(wire.decode("utf-8"))
    assert packet["joint_actual_position"] == [0.0] * 6 and packet["task_state"] == 4
    assert packet["len"] == len(wire)


# ---- parse_status --------------------------------------------------------------------------

FULL = {
    "joint_actual_position": [0, 90, -90, 45, 0, 180],
    "joint_position": [0, 90, -90, 45, 0, 179],
    "actual_position": [500.0, 10.0, 300.0, 180.0, 0.0, -90.0],
    "powered_on": 1, "enabled": True, "emergency_stop": 0, "protective_stop": 1,
    "on_soft_limit": 0, "inpos": True, "paused": False, "drag_status": False,
    "task_state": 4, "task_mode": 2, "interp_state": 3,
    "errcode": "0x0F0034", "errmsg": "collision detected", "rapidrate": 0.5,
    "current_tool_id": 2, "current_user_id": 1,
    "din": [0, 1, 0], "dout": [1, 0], "ain": [0.5], "aout": [1.5, 2.5],
    "tio_din": [0] * 8, "tio_dout": [1] * 8, "tio_ain": [0.1, 0.2],
}


def test_parse_status_converts_to_the_sdk_units():
    s = parse_status(json.loads(encode_status(FULL)))
    np.testing.assert_allclose(s.joint_position, np.radians(FULL["joint_actual_position"]))
    np.testing.assert_allclose(s.joint_command[5], math.radians(179))
    np.testing.assert_allclose(s.tcp_pose[:3], [500, 10, 300])
    # rpy (180, 0, -90) deg → rad, unchanged otherwise
    np.testing.assert_allclose(s.tcp_pose[3:], [math.pi, 0, -math.pi / 2])
    assert (s.powered, s.enabled, s.emergency_stop, s.protective_stop) == (True, True, False, True)
    assert (s.inpos, s.paused, s.drag_status, s.on_soft_limit) == (True, False, False, False)
    assert (s.task_state, s.task_mode, s.interp_state) == (4, 2, 3)
    assert s.errcode == 0x0F0034 and s.has_error and s.errmsg == "collision detected"
    assert (s.current_tool_id, s.current_user_id, s.rapidrate) == (2, 1, 0.5)
    assert s.din == (0, 1, 0) and s.aout == (1.5, 2.5) and len(s.tio_dout) == 8
    assert s.tio_ain == (0.1, 0.2)
    assert s.missing == ()
    with pytest.raises(ValueError):
        s.joint_position[0] = 1.0   # the record is immutable, arrays included


@pytest.mark.parametrize("raw, code", [("0x0", 0), ("0", 0), (0, 0), ("0x10030", 0x10030),
                                       ("0F0034", 0x0F0034)])
def test_errcode_formats(raw, code):
    s = parse_status({**FULL, "errcode": raw})
    assert s.errcode == code and "errcode" not in s.missing


def test_missing_and_malformed_fields_get_defaults_and_are_noted():
    s = parse_status({"len": 10, "joint_actual_position": [1, 2, 3], "powered_on": 1,
                      "errcode": "oops", "enabled": "perhaps"})
    assert isinstance(s, StatusPacket)
    assert np.all(np.isnan(s.joint_position)) and np.all(np.isnan(s.tcp_pose))
    assert s.powered is True and s.enabled is False and s.din == ()
    assert s.errcode == -1 and s.has_error   # unreadable is not "no error"
    assert parse_status({}).errcode == 0
    for key in ("joint_actual_position", "actual_position", "errcode", "enabled", "din",
                "task_state"):
        assert key in s.missing
    assert "powered_on" not in s.missing


def test_parse_status_refuses_a_non_object():
    from jaka_driver.protocol import ProtocolError
    with pytest.raises(ProtocolError):
        parse_status([1, 2])


def test_an_io_array_read_again_is_read_as_it_is_now():
    """The IO arrays are remembered from the last packet (they rarely change): a packet whose
    array equals the last one's reads the same floats, one with a changed value reads it, and
    one equal by value but holding a bool or a NaN is still malformed."""
    first = parse_status({**FULL, "din": [0, 1, 0], "mb_slave_din": [1, 1]})
    again = parse_status({**FULL, "din": [0, 1, 0], "mb_slave_din": [1, 1]})
    assert again.din == first.din == (0.0, 1.0, 0.0)
    assert again.fieldbus["mb_slave_din"] == (1.0, 1.0)
    assert all(type(v) is float for v in again.din)
    changed = parse_status({**FULL, "din": [0, 1, 1], "mb_slave_din": [1, 0]})
    assert changed.din == (0.0, 1.0, 1.0) and changed.fieldbus["mb_slave_din"] == (1.0, 0.0)
    as_bools = parse_status({**FULL, "din": [0, True, 1], "mb_slave_din": [True, False]})
    assert {"din", "mb_slave_din"} <= set(as_bools.malformed)
    assert as_bools.din == () and "mb_slave_din" not in as_bools.fieldbus
    parse_status({**FULL, "din": [0.5, 1.0]})
    with_nan = parse_status({**FULL, "din": [0.5, math.nan]})
    assert "din" in with_nan.malformed
    assert parse_status({**FULL, "din": [0.5, 1.0]}).din == (0.5, 1.0)


@given(st.lists(packets, min_size=1, max_size=6))
@settings(max_examples=60, deadline=None)
def test_a_stream_encoder_writes_what_encode_status_writes(stream):
    """The emulator's encoder keeps the encoding of a value it is handed again (the same
    object); packet after packet its bytes are encode_status's, whether a value is new, the
    same object again, or an equal new one."""
    from jaka_driver.protocol.status_encoder import StatusEncoder
    encoder = StatusEncoder()
    kept = {"din": [0, 1] * 8, "funcdi": [[-1, -1]] * 3}
    for fields in stream:
        fields = {**fields, **kept, "joints": [0.1, 0.2, float(len(fields))]}
        assert encoder.encode(fields) == encode_status(fields)
        kept = {"din": kept["din"] if len(fields) % 2 else list(kept["din"]) + [1],
                "funcdi": kept["funcdi"]}


@settings(max_examples=200, deadline=None)
@given(st.one_of(st.floats(allow_nan=False, allow_infinity=False), st.integers(),
                 st.booleans(), st.none(), st.text()))
def test_a_stream_encoder_writes_every_scalar_as_json_does(value):
    from jaka_driver.protocol.status_encoder import StatusEncoder
    assert StatusEncoder().encode({"x": value}) == encode_status({"x": value})


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_a_stream_encoder_refuses_what_is_not_json(value):
    from jaka_driver.protocol.status_encoder import StatusEncoder
    with pytest.raises(ValueError):
        StatusEncoder().encode({"x": value})


# ---- the receiver's decoder: only the keys parse_status reads --------------------------------

def _same_status(a, b, path="status"):
    """Field by field, into the torque sensor's record; arrays NaN-equal."""
    import dataclasses
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if dataclasses.is_dataclass(x):
            _same_status(x, y, f"{path}.{f.name}")
        elif isinstance(x, np.ndarray):
            assert np.array_equal(x, y, equal_nan=True), f"{path}.{f.name}"
        else:
            assert x == y, f"{path}.{f.name}"


@pytest.mark.parametrize("fixture", ["status_packet.json", "status_packet_fw1.5.14.json"])
def test_the_receivers_decoder_reads_packets_as_parse_status_reads_json(fixture):
    """Packet after packet — the IO arrays unchanged (read from their remembered bytes), then
    one changed — the StatusPacket is the one parse_status makes of the whole JSON."""
    from jaka_driver.protocol.status_packet import decode_read_keys
    fields = json.loads((DATA / fixture).read_text())
    for i in range(3):
        fields["joint_actual_position"][0] = 10.0 * i
        if i == 2:
            fields["din"] = [1] + fields["din"][1:]
        data = encode_status(fields)
        _same_status(parse_status(decode_read_keys(data)), parse_status(json.loads(data)))
    (packet,) = StatusStreamDecoder(decode=decode_read_keys).feed(data)
    assert "din" in packet and "len" not in packet   # only the keys parse_status reads


@pytest.mark.parametrize("wrong", [b"[true, 0, 1]", b'"text"', b'{"a": 1}', b"[[1], 2]",
                                   b'[1, "x"]', b"[1e999, 0]"])
def test_a_malformed_io_array_is_named_as_json_s_reader_names_it(wrong):
    """The receiver's decoder (after the good array was remembered) and the default decoder
    read the same packet: din malformed, nothing else."""
    from jaka_driver.protocol.status_packet import decode_read_keys
    fields = json.loads((DATA / "status_packet.json").read_text())
    good = encode_status(fields)
    fields["din"] = "DIN"
    data = encode_status(fields).replace(b'"DIN"', wrong)    # len now a hint only
    fast = StatusStreamDecoder(decode=decode_read_keys)
    fast.feed(good)
    (packet,) = fast.feed(data + good)[:1]
    status = parse_status(packet)
    assert status.malformed == ("din",) and status.din == ()
    _same_status(status, parse_status(StatusStreamDecoder().feed(data + good)[0]))


def test_unreadable_bytes_of_an_io_array_are_a_malformed_field_not_a_drop():
    """The compiled parser only skims the arrays it leaves undecoded: invalid UTF-8 inside
    one is found when it is read, and only that field is lost."""
    from jaka_driver.protocol.status_packet import decode_read_keys
    data = encode_status({**sample_packet(), "din": ["ERR"]}).replace(b"ERR", b"\xff\xfe")
    status = parse_status(decode_read_keys(data))
    assert status.malformed == ("din",) and list(status.joint_position) != []
