"""CommandClient and StatusReceiver over real TCP sockets on 127.0.0.1, against tiny scripted
servers: replies, controller errors, timeouts, refused and broken connections, concurrency, and
the status thread's start/stop/loss reporting."""
import json
import socket
import threading
import time

import numpy as np
import pytest

from jaka_driver.protocol import (CommandClient, ConnectFailed, ConnectionLost, ProtocolError,
                                  StatusReceiver, TimeoutError, commands, encode_status)
from jaka_driver.protocol.errors import JakaProtocolError
from jaka_driver.protocol.wire import encode_json
from support.ros_harness import free_port
from support.scripted_server import ScriptedServer, requests_of
from support.threads import run_all


def reply_to(request, code="0", msg="", **fields):
    return encode_json({"cmdName": request["cmdName"], "errorCode": code, "errorMsg": msg,
                        **fields})


def controller(conn, server):
    """A well-behaved fake: answers a few commands the way the controller does."""
    for req in requests_of(conn, server):
        name = req["cmdName"]
        if name == "get_joint_pos":
            conn.sendall(reply_to(req, joint_pos=[0, 90, -90, 0, 45, 180]))
        elif name == "kine_forward":   # echoes the joints, so a caller can tell replies apart
            conn.sendall(reply_to(req, cartPosition=req["jointPosition"]))
        elif name == "joint_move":
            conn.sendall(reply_to(req, "2", "robot is not enabled"))
        elif name == "get_version":   # reply in many small pieces
            for i, byte in enumerate(reply_to(req, version="1.7.2")):
                conn.sendall(bytes([byte]))
                if i % 10 == 0:
                    time.sleep(0.001)
        elif name == "power_on":   # half a reply, then hang up
            data = reply_to(req)
            conn.sendall(data[: len(data) // 2])
            conn.shutdown(socket.SHUT_RDWR)
            return
        elif name == "power_off":
            conn.sendall(encode_json({"cmdName": "power_on", "errorCode": "0", "errorMsg": ""}))
        elif name == "get_robot_state":
            conn.sendall(b"HTTP/1.1 400 Bad Request\r\n\r\n")
        elif name == "get_tcp_pos":
            pass   # never answers
        else:
            conn.sendall(reply_to(req))


@pytest.fixture
def serve():
    servers = []

    def start(handler=controller):
        server = ScriptedServer(handler)
        servers.append(server)
        return server
    yield start
    for server in servers:
        server.close()


@pytest.fixture
def client(serve):
    server = serve()
    cli = CommandClient("127.0.0.1", server.port, timeout=0.5)
    cli.connect()
    yield cli
    cli.close()


@pytest.fixture(autouse=True)
def no_leaked_threads():
    before = set(threading.enumerate())
    yield
    deadline = time.monotonic() + 2
    while time.monotonic() < deadline and set(threading.enumerate()) - before:
        time.sleep(0.01)
    assert not set(threading.enumerate()) - before


# ---- CommandClient -------------------------------------------------------------------------

def test_reply_is_parsed_and_converted(client):
    reply = client.call(commands.get_joint_pos())
    assert reply.ok and reply.cmd_name == "get_joint_pos"
    np.testing.assert_allclose(commands.reply_joint_pos(reply),
                               np.radians([0, 90, -90, 0, 45, 180]))


def test_controller_error_is_a_reply_not_an_exception(client):
    reply = client.call(commands.joint_move([0] * 6, 1.0, 1.0))
    assert not reply.ok and reply.error_code == "2"
    assert reply.error_msg == "robot is not enabled"
    assert client.connected   # the connection stays usable
    assert client.call(commands.clear_error()).ok


def test_reply_split_into_many_pieces(client):
    assert commands.reply_version(client.call(commands.get_version())) == "1.7.2"


def test_timeout_when_the_server_never_answers(client):
    t0 = time.monotonic()
    with pytest.raises(TimeoutError, match="no reply to 'get_tcp_pos'") as info:
        client.call(commands.get_tcp_pos(), timeout=0.3)
    elapsed = time.monotonic() - t0
    # Wall clock: the client's socket timeout is wall time against a TCP peer (no sim time
    # there). time.monotonic resolves to µs; the 0.2 s above the timeout allow for a thread
    # waiting for a core on a loaded 2-core machine, never for an early return.
    assert 0.3 <= elapsed < 0.5
    assert isinstance(info.value, JakaProtocolError)
    assert not client.connected   # a late reply must not be taken for the next one
    with pytest.raises(ConnectionLost, match="connect"):
        client.call(commands.get_version())
    client.connect()   # and connecting again works
    assert client.call(commands.get_version()).ok


def test_default_timeout_applies(serve):
    server = serve()
    with CommandClient("127.0.0.1", server.port, timeout=0.2) as cli:
        t0 = time.monotonic()
        with pytest.raises(TimeoutError):
            cli.call(commands.get_tcp_pos())
        assert time.monotonic() - t0 < 0.4


def test_connection_refused():
    cli = CommandClient("127.0.0.1", free_port(), timeout=0.5)
    with pytest.raises(ConnectFailed, match="cannot open the command connection") as info:
        cli.connect()
    assert isinstance(info.value, ConnectionError) and not cli.connected
    with pytest.raises(ConnectionLost, match="call connect"):
        cli.call(commands.power_on())


def test_server_closing_mid_reply(client):
    with pytest.raises(ConnectionLost, match="closed the connection after") as info:
        client.call(commands.power_on())
    assert isinstance(info.value, ConnectionError)
    assert not client.connected


def test_reply_for_another_command_is_a_protocol_error(client):
    with pytest.raises(ProtocolError, match="out of step"):
        client.call(commands.power_off())
    assert not client.connected


def test_non_json_reply_is_a_protocol_error(client):
    with pytest.raises(ProtocolError, match="not a JSON object"):
        client.call(commands.get_robot_state())


def test_connect_and_close_are_idempotent(serve):
    server = serve()
    cli = CommandClient("127.0.0.1", server.port, timeout=0.5)
    cli.close()
    cli.connect()
    cli.connect()
    assert server.accepted.wait(1)
    time.sleep(0.05)   # a second connection, if any, would have been accepted by now
    assert cli.connected and len(server.connections) == 1
    cli.close()
    cli.close()
    assert not cli.connected
    cli.connect()
    assert cli.call(commands.get_joint_pos()).ok
    cli.close()


def test_close_from_another_thread_wakes_a_waiting_call(client):
    threading.Timer(0.1, client.close).start()
    t0 = time.monotonic()
    with pytest.raises(ConnectionLost, match="closed by close"):
        client.call(commands.get_tcp_pos(), timeout=2.0)
    assert time.monotonic() - t0 < 0.5


def test_concurrent_calls_each_get_their_own_reply(client):
    errors = []

    def worker(k):
        try:
            for i in range(20):
                q = np.radians([k, i, 0, 0, 0, 0])
                pose = client.call(commands.kine_forward(q)).fields["cartPosition"]
                assert pose[:2] == pytest.approx([k, i])
        except Exception as exc:  # noqa: BLE001 - reported below
            errors.append(exc)
    run_all([threading.Thread(target=worker, args=(k,), name=f"caller {k}") for k in range(4)],
            5.0)
    assert errors == []


def test_invalid_request_is_refused_without_sending(client):
    with pytest.raises(ValueError):
        client.call({"speed": 1})
    assert client.call(commands.get_joint_pos()).ok


# ---- StatusReceiver ------------------------------------------------------------------------

def status_packet(i):
    return encode_status({"joint_actual_position": [i, 90, 0, 0, 0, 0], "powered_on": 1,
                          "enabled": True, "errcode": "0x0",
                          "actual_position": [1, 2, 3, 0, 0, 90]})


def stream_then(chunks, then="hold"):
    """A status server: sends ``chunks`` (with a short pause between), then holds the
    connection open until the server stops, or closes it (``then="close"``)."""
    def serve(conn, server):
        for chunk in chunks:
            conn.sendall(chunk)
            time.sleep(0.005)
        if then == "close":
            conn.shutdown(socket.SHUT_RDWR)
            return
        server.stopping.wait()
    return serve


class Collector:
    def __init__(self):
        self.statuses = []
        self.lost = []
        self.got_all = threading.Event()
        self.lost_event = threading.Event()
        self.expected = None

    def on_status(self, status, received):
        self.statuses.append((status, received))
        if len(self.statuses) == self.expected:
            self.got_all.set()

    def on_lost(self, reason):
        self.lost.append(reason)
        self.lost_event.set()


def test_receiver_decodes_split_packets(serve):
    data = b"".join(status_packet(i) for i in range(5))
    chunks = [data[i:i + 37] for i in range(0, len(data), 37)]
    server = serve(stream_then(chunks))
    col = Collector()
    col.expected = 5
    rx = StatusReceiver("127.0.0.1", server.port, on_status=col.on_status,
                        on_connection_lost=col.on_lost, clock=lambda: 42.0)
    rx.start()
    try:
        assert col.got_all.wait(2)
        assert [round(np.degrees(s.joint_position[0])) for s, _ in col.statuses] == list(range(5))
        status, received = col.statuses[-1]
        assert received == 42.0 and status.powered and status.enabled and not status.has_error
        np.testing.assert_allclose(status.tcp_pose, [1, 2, 3, 0, 0, np.pi / 2], atol=1e-12)
        # the callback's owner keeps the packets: the receiver holds no copy of its own
        assert rx.latest is None and rx.decoder.packets == 5
    finally:
        rx.stop()
    assert not rx.running and col.lost == []   # a stop is not a loss


def test_receiver_without_a_callback_keeps_the_latest_packet(serve):
    server = serve(stream_then([status_packet(i) for i in range(3)]))
    rx = StatusReceiver("127.0.0.1", server.port, clock=lambda: 7.0)
    rx.start()
    try:
        deadline = time.monotonic() + 2
        while rx.decoder.packets < 3 and time.monotonic() < deadline:
            time.sleep(0.01)
        status, received = rx.latest
        assert received == 7.0 and round(np.degrees(status.joint_position[0])) == 2
    finally:
        rx.stop()


def test_receiver_reports_connection_loss(serve):
    server = serve(stream_then([status_packet(0)], then="close"))
    col = Collector()
    rx = StatusReceiver("127.0.0.1", server.port, on_status=col.on_status,
                        on_connection_lost=col.on_lost)
    rx.start()
    assert col.lost_event.wait(2)
    assert len(col.statuses) == 1 and len(col.lost) == 1
    assert "closed the status connection" in col.lost[0]
    deadline = time.monotonic() + 1
    while rx.running and time.monotonic() < deadline:
        time.sleep(0.01)
    assert not rx.running
    rx.start()   # a reconnect policy can just start again
    rx.stop()


def test_receiver_stall_timeout(serve):
    server = serve(stream_then([]))
    col = Collector()
    rx = StatusReceiver("127.0.0.1", server.port, on_connection_lost=col.on_lost,
                        stall_timeout=0.2)
    t0 = time.monotonic()
    rx.start()
    assert col.lost_event.wait(2)
    assert 0.2 <= time.monotonic() - t0 < 0.6 and "no status data" in col.lost[0]
    rx.stop()


def test_receiver_stop_is_prompt_and_idempotent(serve):
    server = serve(stream_then([]))
    rx = StatusReceiver("127.0.0.1", server.port)
    rx.stop()
    rx.start()
    rx.start()
    assert rx.running
    server.accepted.wait(1)
    assert len(server.connections) == 1
    t0 = time.monotonic()
    rx.stop()
    rx.stop()
    assert time.monotonic() - t0 < 0.5 and not rx.running


def test_receiver_connection_refused():
    rx = StatusReceiver("127.0.0.1", free_port())
    with pytest.raises(ConnectFailed, match="status connection"):
        rx.start()
    assert not rx.running


def test_callback_errors_do_not_kill_the_receiver(serve):
    server = serve(stream_then([status_packet(0), status_packet(1)]))
    seen = []
    done = threading.Event()

    def on_status(status, received):
        seen.append(status)
        if len(seen) == 2:
            done.set()
        raise RuntimeError("bug in a callback")
    rx = StatusReceiver("127.0.0.1", server.port, on_status=on_status)
    rx.start()
    try:
        assert done.wait(2)
    finally:
        rx.stop()


def test_json_of_status_packets_is_what_the_receiver_sees():
    # the receiver's input format is exactly what encode_status produces
    packet = json.loads(status_packet(3))
    assert packet["len"] == len(status_packet(3))
