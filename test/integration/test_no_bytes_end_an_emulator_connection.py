"""Malformed input of any kind on the emulator's request ports (commands 10001, data_request
10004) gets an error reply, and the connection goes on answering: nesting 100 000 deep,
invalid UTF-8, NaN/Infinity literals, numbers beyond a double, a 10 000-digit integer, a
megabyte without a closing brace, a lone ``}``, binary garbage. No thread dies: the same
connection answers a valid request after each, and so does every other connection."""
from __future__ import annotations

import json
import random
import socket
import time

import pytest

from support.raw_client import RawClient
from support.ros_harness import wait_until


VALID = b'{"cmdName":"get_program_state"}'

#: (what, bytes, a phrase the error message has)
MALFORMED = [
    ("100 000-deep array", b'{"cmdName": "get_version", "x": ' + b"[" * 100_000
     + b"]" * 100_000 + b"}", "nested"),
    ("100 000-deep object", b'{"a": ' * 100_000 + b"1" + b"}" * 100_000, "nested"),
    ("invalid UTF-8", b'{"cmdName": "get_version", "x": "\xff\xfe\xc3"}', "not UTF-8"),
    ("NaN", b'{"cmdName": "rapid_rate", "rate_value": NaN}', "NaN"),
    ("Infinity", b'{"cmdName": "rapid_rate", "rate_value": Infinity}', "Infinity"),
    ("-Infinity", b'{"cmdName": "get_version", "x": [-Infinity]}', "Infinity"),
    ("1e999", b'{"cmdName": "rapid_rate", "rate_value": 1e999}', "beyond a double"),
    ("10 000-digit integer", b'{"cmdName": "set_tool_id", "tool_id": ' + b"7" * 10_000 + b"}",
     "digits"),
    ("a lone }", b"}", "not a JSON object"),
    ("an array", b"[1, 2, 3]", "not a JSON object"),
    ("a string escape of half a character", b'{"cmdName": "\\ud800"}', "unknown command"),
    ("no cmdName", b'{"speed": 3}', "cmdName"),
    ("trailing comma", b'{"cmdName": "get_version",}', "malformed JSON"),
]


class Connection(RawClient):
    def replies_until_quiet(self, quiet: float) -> list:
        out = []
        while True:
            try:
                out.append(self.read(quiet))
            except socket.timeout:
                return out

    def answers_a_valid_request(self) -> bool:
        self.send(VALID)
        reply = self.read()
        return reply["errorCode"] == "0" and reply["programState"] == "idle"


EMULATOR = dict(start="enabled")


@pytest.fixture(params=["command", "data"])
def port(request, emu):
    return emu.command_port if request.param == "command" else emu.data_port


@pytest.mark.parametrize("what, data, phrase", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_request_gets_an_error_reply_and_the_connection_goes_on(port, what, data,
                                                                          phrase):
    c = Connection(port)
    bystander = Connection(port)
    try:
        t0 = time.monotonic()
        c.send(data)
        reply = c.read()
        assert time.monotonic() - t0 < 3.0
        assert reply["errorCode"] == "1" and phrase in reply["errorMsg"], (what, reply)
        assert list(reply)[:2] == ["errorCode", "errorMsg"]
        assert c.answers_a_valid_request(), what
        assert bystander.answers_a_valid_request(), what
    finally:
        c.close()
        bystander.close()


def test_a_megabyte_without_a_closing_brace_is_answered_at_once(port):
    c = Connection(port)
    try:
        t0 = time.monotonic()
        c.send(b'{"cmdName": "get_version", "x": "' + b"a" * (1 << 20) + b"  ")
        reply = c.read()
        # at the limit, not after the idle time (1 s) of an incomplete request
        assert reply["errorCode"] == "1" and "longer than" in reply["errorMsg"]
        assert time.monotonic() - t0 < 0.9
        assert c.answers_a_valid_request()
    finally:
        c.close()


def test_binary_garbage_gets_error_replies_and_the_connection_goes_on(port):
    rng = random.Random(23)
    c = Connection(port)
    try:
        for _ in range(5):
            c.send(bytes(rng.randrange(256) for _ in range(20_000)))
        # an opened '{' in the garbage may hold the rest until the idle time (1 s) drops it
        replies = c.replies_until_quiet(1.6)
        assert replies and all(r["errorCode"] == "1" for r in replies), replies[:3]
        assert c.answers_a_valid_request()
    finally:
        c.close()


def test_a_deep_but_complete_request_within_the_limit_is_answered(port):
    c = Connection(port)
    try:
        nested = json.dumps({"cmdName": "get_program_state", "x": [[[[[[[[1]]]]]]]]})
        c.send(nested.encode())
        assert c.read()["programState"] == "idle"
    finally:
        c.close()


def test_every_connection_thread_is_still_serving(emu):
    # after every test above, the emulator serves as before and has no connection left over
    c = Connection(emu.command_port)
    try:
        assert c.answers_a_valid_request()
        assert wait_until(lambda: emu.server.client_count["command"] == 1, 2.0)
    finally:
        c.close()
