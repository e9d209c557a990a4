"""Malformed controller output over real TCP sockets on 127.0.0.1: the command client, the
port-10000 status receiver and the port-10004 status poller each survive every kind — nesting
100 000 deep, invalid UTF-8, NaN/Infinity, numbers too large for a float or too long for an
int, a megabyte without a closing brace, fields of the wrong type, a zlib bomb — with a counted
drop, never a dead thread: a reply that cannot be parsed closes its connection (the next
connect works), a packet that cannot be parsed is skipped and the stream read on."""
import math
import time
import zlib
from contextlib import contextmanager

import numpy as np
import pytest

from jaka_driver.protocol import (CommandClient, ProtocolError, StatusPoller, StatusReceiver,
                                  commands, encode_status)
from jaka_driver.protocol.command_client import MAX_REPLY_BYTES
from jaka_driver.protocol.errors import MalformedInput
from malformed_inputs import DEEP, STATUS_KEYS_READ
from scripted_server import ScriptedServer, requests_of

OK_VERSION = b'{"errorCode": "0", "errorMsg": "", "cmdName": "get_version", "version": "1.5.14"}'


@pytest.fixture
def serve():
    servers = []

    def start(handler):
        servers.append(ScriptedServer(handler))
        return servers[-1]
    yield start
    for server in servers:
        server.close()


def wait_for(predicate, timeout=2.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.01)
    return predicate()


def answering(first_reply: bytes):
    """A command port whose first reply (over all connections) is ``first_reply``; every later
    request gets a good get_version reply."""
    sent = []

    def serve(conn, server):
        for _ in requests_of(conn, server):
            # counted before sending: the client may close while the malformed reply is still
            # going out (it can tell it is malformed before its end), and the send then fails
            first = not sent
            sent.append(1)
            conn.sendall(first_reply if first else OK_VERSION)
    return serve


def reply_with(text: bytes) -> bytes:
    return b'{"errorCode": "0", "errorMsg": "", "cmdName": "get_version", "version": ' + text + b"}"


# (name, the bytes of the reply): none of them can ever be a valid reply
MALFORMED_REPLIES = [
    ("nested-100000-deep", reply_with(b"[" * DEEP + b"]" * DEEP)),
    ("nested-100000-deep-never-closed", reply_with(b"[" * DEEP)[:-1]),
    ("invalid-utf8-outside-a-string", reply_with(b"\xff\xfe")),
    ("nan-literal", reply_with(b"NaN")),
    ("infinity-literal", reply_with(b"Infinity")),
    ("10000-digit-integer", reply_with(b"9" * 10_000)),
    ("a-megabyte-without-a-closing-brace", reply_with(b'"' + b"x" * (1 << 20))[:-1]),
    ("a-bracket-closing-the-wrong-kind", reply_with(b"[1, 2}")),
]


@pytest.mark.parametrize("reply", [m[1] for m in MALFORMED_REPLIES],
                         ids=[m[0] for m in MALFORMED_REPLIES])
def test_a_malformed_reply_is_a_counted_drop_that_closes_only_its_connection(serve, reply):
    server = serve(answering(reply))
    client = CommandClient("127.0.0.1", server.port, timeout=2.0)
    client.connect()
    try:
        t0 = time.monotonic()
        with pytest.raises(MalformedInput) as info:
            client.call(commands.get_version())
        # told at once, not after the reply timeout; one of the library's own errors
        assert time.monotonic() - t0 < 1.5
        assert isinstance(info.value, ProtocolError) and "connection was closed" in str(info.value)
        assert (client.replies_dropped, client.replies, client.connected) == (1, 0, False)
        client.connect()
        assert commands.reply_version(client.call(commands.get_version())) == "1.5.14"
        assert (client.replies_dropped, client.replies) == (1, 1)
    finally:
        client.close()


def test_the_reply_size_bound_is_far_above_any_real_reply():
    assert MAX_REPLY_BYTES >= 20 * 10_000 and MAX_REPLY_BYTES < 1 << 20


def test_a_reply_without_error_code_is_a_counted_drop_on_a_connection_that_stays(serve):
    server = serve(answering(b'{"cmdName": "get_version", "version": "x"}'))
    with CommandClient("127.0.0.1", server.port, timeout=2.0) as client:
        with pytest.raises(ProtocolError, match="errorCode"):
            client.call(commands.get_version())
        assert client.replies_dropped == 1 and client.connected
        assert client.call(commands.get_version()).ok


def test_invalid_utf8_inside_a_reply_string_is_kept_as_a_replacement_character(serve):
    server = serve(answering(b'{"errorCode": "2", "errorMsg": "\xc5\xf6\xd7\xb2 failed", '
                             b'"cmdName": "get_version"}'))
    with CommandClient("127.0.0.1", server.port, timeout=2.0) as client:
        reply = client.call(commands.get_version())
        assert not reply.ok and reply.error_msg.endswith(" failed") and "\ufffd" in reply.error_msg
        assert (client.text_repaired, client.replies_dropped, client.connected) == (1, 0, True)
        reply.error_msg.encode("utf-8")   # re-encodable: a ROS message can carry it


def test_a_number_too_large_for_a_float_is_refused_by_the_accessor_not_taken_as_infinite(serve):
    server = serve(answering(b'{"errorCode": "0", "errorMsg": "", "cmdName": "get_joint_pos", '
                             b'"joint_pos": [1e999, 0, 0, 0, 0, 0]}'))
    with CommandClient("127.0.0.1", server.port, timeout=2.0) as client:
        reply = client.call(commands.get_joint_pos())
        with pytest.raises(ProtocolError, match="finite"):
            commands.reply_joint_pos(reply)
        assert client.connected and client.replies_dropped == 0


# ---- port 10000: the status stream -------------------------------------------------------------

def good(i):
    return encode_status({"joint_actual_position": [i, 0, 0, 0, 0, 0], "errcode": "0x0",
                          "powered_on": 1})


def packet_with(text: bytes) -> bytes:
    return b'{"len": 200, "joint_actual_position": ' + text + b"}"


MALFORMED_PACKETS = [
    ("nested-100000-deep", packet_with(b"[" * DEEP + b"]" * DEEP)),
    ("invalid-utf8-outside-a-string", packet_with(b"\xff\xfe")),
    ("nan-literal", packet_with(b"[NaN, 0, 0, 0, 0, 0]")),
    ("infinity-literal", packet_with(b"[-Infinity, 0, 0, 0, 0, 0]")),
    ("10000-digit-integer", packet_with(b"[" + b"9" * 10_000 + b", 0, 0, 0, 0, 0]")),
    ("a-megabyte-without-a-closing-brace", packet_with(b'"' + b"x" * (1 << 20) + b'"')[:-1]),
]


class Collector:
    def __init__(self):
        self.statuses, self.lost = [], []

    def on_status(self, status, received):
        self.statuses.append(status)

    def on_lost(self, reason):
        self.lost.append(reason)

    def firsts(self):
        return [round(math.degrees(s.joint_position[0])) for s in self.statuses]


@contextmanager
def receiving(serve, *chunks):
    """A StatusReceiver reading a server that streams ``chunks``: (collector, receiver)."""
    server = serve(streaming(*chunks))
    col = Collector()
    rx = StatusReceiver("127.0.0.1", server.port, on_status=col.on_status,
                        on_connection_lost=col.on_lost)
    rx.start()
    try:
        yield col, rx
    finally:
        rx.stop()


def streaming(*chunks):
    def serve(conn, server):
        for chunk in chunks:
            conn.sendall(chunk)
            time.sleep(0.01)
        server.stopping.wait()
    return serve


@pytest.mark.parametrize("packet", [m[1] for m in MALFORMED_PACKETS],
                         ids=[m[0] for m in MALFORMED_PACKETS])
def test_a_malformed_status_packet_is_a_counted_drop_and_the_stream_reads_on(serve, packet):
    with receiving(serve, good(1), packet, good(2), good(3)) as (col, rx):
        assert wait_for(lambda: len(col.statuses) == 3, 5.0), col.firsts()
        assert col.firsts() == [1, 2, 3] and rx.decoder.packets_dropped == 1
        assert rx.running and col.lost == []


def test_a_number_too_large_for_a_float_is_a_dropped_field_not_an_infinite_joint(serve):
    with receiving(serve, good(1), packet_with(b"[1e999, 0, 0, 0, 0, 0]"), good(2)) as (col, rx):
        assert wait_for(lambda: len(col.statuses) == 3)
        assert np.all(np.isnan(col.statuses[1].joint_position))
        assert col.statuses[1].malformed == ("joint_actual_position",)
        assert rx.decoder.fields_dropped == 1 and rx.decoder.packets_dropped == 0


def test_every_field_of_the_wrong_type_is_counted_and_the_packet_still_arrives(serve):
    keys = STATUS_KEYS_READ
    wrong = encode_status({key: {"not": ["what", "the", "controller", "sends"]} for key in keys})
    with receiving(serve, wrong, good(2)) as (col, rx):
        assert wait_for(lambda: len(col.statuses) == 2)
        assert set(col.statuses[0].malformed) == set(keys)
        assert rx.decoder.fields_dropped == len(keys) and col.statuses[0].errcode == -1


def test_invalid_utf8_in_a_status_string_is_repaired_and_counted(serve):
    packet = encode_status({"joint_actual_position": [5, 0, 0, 0, 0, 0], "errcode": "0x1",
                            "errmsg": "ERRMSG"}).replace(b"ERRMSG", b"\xc5\xf6\xd7\xb2")
    with receiving(serve, packet, good(2)) as (col, rx):
        assert wait_for(lambda: len(col.statuses) == 2)
        assert "\ufffd" in col.statuses[0].errmsg   # GBK bytes: not UTF-8
        assert rx.decoder.text_repaired == 1 and rx.decoder.packets_dropped == 0


# ---- port 10004: the data_request poller -------------------------------------------------------

def data_port(*replies):
    """Answers the n-th data_request with ``replies[n]`` (the last one repeats)."""
    count = []

    def serve(conn, server):
        for req in requests_of(conn, server):
            assert req == {"cmdName": "data_request"}
            conn.sendall(replies[min(len(count), len(replies) - 1)])
            count.append(1)
    return serve


def good_z(i):
    return zlib.compress(good(i))


BOMB = zlib.compress(b'{"len": 1, "x": "' + b"0" * (8 << 20) + b'"}', 9)
MALFORMED_DATA_REPLIES = [
    ("zlib-bomb", BOMB),
    ("nested-100000-deep", zlib.compress(packet_with(b"[" * DEEP + b"]" * DEEP), 9)),
    ("nan-literal", zlib.compress(packet_with(b"[NaN, 0, 0, 0, 0, 0]"))),
    ("10000-digit-integer", zlib.compress(packet_with(b"[" + b"9" * 10_000 + b"]"))),
    ("ends-before-its-object", zlib.compress(good(1)[:-5])),
    ("a-json-array", zlib.compress(b"[1, 2, 3]")),
    ("longer-than-the-sdks-buffer", zlib.compress(encode_status(
        {"x": [f"{i:08x}" for i in range(5000)]}), 0)),
]


def test_the_zlib_bomb_is_what_it_claims():
    assert len(BOMB) < 8200 and len(zlib.decompress(BOMB)) > 8 << 20


@pytest.mark.parametrize("reply", [m[1] for m in MALFORMED_DATA_REPLIES],
                         ids=[m[0] for m in MALFORMED_DATA_REPLIES])
def test_a_malformed_data_request_reply_is_a_counted_drop_and_polling_goes_on(serve, reply):
    server = serve(data_port(good_z(1), reply, good_z(2)))
    col = Collector()
    poller = StatusPoller("127.0.0.1", server.port, on_status=col.on_status,
                          on_connection_lost=col.on_lost, period=0.02, stall_timeout=2.0)
    poller.start()
    try:
        assert wait_for(lambda: 2 in col.firsts(), 5.0), col.firsts()
        assert col.firsts()[:2] == [1, 2] and poller.decoder.packets_dropped == 1
        assert poller.running and col.lost == []
    finally:
        poller.stop()


def test_bytes_that_are_not_zlib_end_the_poll_connection_as_a_counted_loss(serve):
    server = serve(data_port(good_z(1), b"HTTP/1.1 400 Bad Request\r\n\r\n", good_z(2)))
    col = Collector()
    poller = StatusPoller("127.0.0.1", server.port, on_status=col.on_status,
                          on_connection_lost=col.on_lost, period=0.02, stall_timeout=2.0)
    poller.start()
    try:
        assert wait_for(lambda: col.lost, 3.0)
        assert "not zlib" in col.lost[0] and col.firsts() == [1]
        assert poller.decoder.packets_dropped == 1
        assert wait_for(lambda: not poller.running)
    finally:
        poller.stop()

