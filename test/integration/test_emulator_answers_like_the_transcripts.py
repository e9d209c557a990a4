"""Conformance: the fixture transcripts (test/data/, written from a real controller's
transcripts and JAKA's SDK) replayed against the emulator — every reply has the transcript's
keys, value types and text layout; every status packet (port 10000, and zlib on port 10004)
has the fixture packet's keys, types and array sizes."""
from __future__ import annotations

import json
import socket
import zlib

import pytest

from fake_controller import load_status_packet, load_transcript

from jaka_driver.emulator import Emulator
from jaka_driver.protocol.wire import decode_first_object


@pytest.fixture(scope="module")
def emu():
    with Emulator("zu5", command_port=0, status_port=0) as emulator:
        yield emulator


def _read_object(sock: socket.socket) -> str:
    buf = b""
    while True:
        buf += sock.recv(65536)
        try:
            _, used = decode_first_object(buf)
            return buf[:used].decode()
        except ValueError:
            continue


def _same_shape(expected, got, where: str) -> None:
    if isinstance(expected, bool) or isinstance(got, bool):
        assert type(got) is type(expected), f"{where}: {got!r} is not a {type(expected).__name__}"
    elif isinstance(expected, (int, float)):
        assert isinstance(got, (int, float)), f"{where}: {got!r} is not a number"
        if isinstance(expected, int) and not isinstance(expected, bool):
            assert isinstance(got, int), f"{where}: {got!r} should be an integer"
    elif isinstance(expected, list):
        assert isinstance(got, list), where
        if expected and where.split(".")[-1] not in ("tio_ain",):
            assert len(got) == len(expected), f"{where}: {len(got)} entries, not {len(expected)}"
    elif isinstance(expected, dict):
        assert isinstance(got, dict), where
        for key in expected:
            assert key in got, f"{where}: no {key!r}"
            _same_shape(expected[key], got[key], f"{where}.{key}")
    else:
        assert type(got) is type(expected), f"{where}: {got!r} is not a {type(expected).__name__}"


def test_every_transcript_exchange_is_answered_with_its_keys_types_and_layout(emu):
    with socket.create_connection((emu.host, emu.command_port), timeout=30) as sock:
        for request, reply_text, note in load_transcript():
            sock.sendall(request.encode())
            got_text = _read_object(sock)
            expected, got = json.loads(reply_text), json.loads(got_text)
            name = expected["cmdName"]
            assert got_text == json.dumps(got), f"{name}: not the controller's layout"
            assert got["errorCode"] == expected["errorCode"], (name, got["errorMsg"], note)
            if name == "wait_complete":
                continue
            assert set(got) == set(expected), (name, sorted(set(got) ^ set(expected)))
            for key in expected:
                if key not in ("errorMsg",):
                    _same_shape(expected[key], got[key], f"{name}.{key}")


def test_status_packets_on_10000_and_10004_have_every_key_type_and_size(emu):
    fixture = json.loads(load_status_packet())
    with socket.create_connection((emu.host, emu.status_port), timeout=5) as sock:
        text = _read_object(sock)
    assert text.startswith('{"len": ') and json.loads(text)["len"] == len(text.encode())
    assert text == json.dumps(json.loads(text)) and '"errcode": "0x' in text
    with socket.create_connection((emu.host, emu.data_port), timeout=5) as sock:
        sock.sendall(b'{"cmdName":"data_request"}')
        inflater, data = zlib.decompressobj(), b""
        while not inflater.eof:
            chunk = sock.recv(65536)
            data += chunk
            inflater.decompress(chunk)
    assert len(data) < 8200, "the SDK reads the reply into 8200 bytes"
    polled = zlib.decompress(data).decode()
    assert polled[0] == "{" and polled[2:5] == "len" and polled[-1] == "}"
    for packet in (json.loads(text), json.loads(polled)):
        assert packet["len"] > 0
        _same_shape({k: v for k, v in fixture.items() if k != "len"}, packet, "packet")
