"""The emulator's request splitter takes any bytes, split anywhere, without raising: every item
it yields is a decoded JSON object or a Malformed with a reason, and a valid request after the
damage is read whole once the damage is closed or expired. Its second guard holds too: with the
depth limit lifted, Python's own parser runs out of recursion and that is a Malformed, not an
exception."""
from __future__ import annotations

import json

from hypothesis import given, settings
from hypothesis import strategies as st

from jaka_driver.emulator.framing import MAX_DEPTH, Malformed, RequestSplitter

VALID = {"cmdName": "get_version", "sdk_version": "x"}


def _feed_in_pieces(splitter: RequestSplitter, data: bytes, cuts) -> list:
    out, start = [], 0
    for cut in sorted(c % (len(data) + 1) for c in cuts) + [len(data)]:
        out += splitter.feed(data[start:cut])
        start = cut
    return out


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=400), st.lists(st.integers(0, 10_000), max_size=6))
def test_any_bytes_split_anywhere_yield_objects_or_reasons(data, cuts):
    splitter = RequestSplitter()
    items = _feed_in_pieces(splitter, data, cuts)
    late = splitter.expire()
    for item in items + ([late] if late else []):
        assert isinstance(item, (dict, Malformed)), item
        if isinstance(item, Malformed):
            assert item.reason
    # the splitter is empty again and reads the next request whole
    assert splitter.feed(json.dumps(VALID).encode()) == [VALID]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from([b"{", b"}", b"[", b"]", b'"', b"\\", b"a", b":", b","]),
                max_size=300), st.lists(st.integers(0, 10_000), max_size=6))
def test_structure_bytes_alone_never_confuse_the_scan(pieces, cuts):
    splitter = RequestSplitter()
    _feed_in_pieces(splitter, b"".join(pieces), cuts)
    splitter.expire()
    assert splitter.pending == 0
    assert splitter.feed(b'{"cmdName": "get_version", "sdk_version": "x"}') == [VALID]


def test_a_request_split_byte_by_byte_is_read_once_whole():
    text = json.dumps({"cmdName": "set_user_offsets", "name": 'a "quoted" {brace} \\',
                       "userffset": [1.5, 2, 3, 0, 0, 90], "id": 3}).encode()
    splitter = RequestSplitter()
    items = [item for byte in text for item in splitter.feed(bytes([byte]))]
    assert items == [json.loads(text)]


def test_nesting_beyond_the_limit_is_refused_without_parsing():
    deep = b'{"x": ' + b"[" * (MAX_DEPTH + 1) + b"]" * (MAX_DEPTH + 1) + b"}"
    [item] = RequestSplitter().feed(deep)
    assert isinstance(item, Malformed) and "nested" in item.reason


def test_python_running_out_of_recursion_is_a_malformed_request_too():
    deep = b'{"x": ' + b"[" * 100_000 + b"]" * 100_000 + b"}"
    [item] = RequestSplitter(max_depth=10 ** 9).feed(deep)
    assert isinstance(item, Malformed) and "recursion" in item.reason


def test_numbers_that_are_not_json_or_not_doubles_are_refused():
    splitter = RequestSplitter()
    for literal in (b"NaN", b"Infinity", b"-Infinity", b"1e999", b"-1e999", b"9" * 21):
        [item] = splitter.feed(b'{"cmdName": "rapid_rate", "rate_value": ' + literal + b"}")
        assert isinstance(item, Malformed), literal
    [ok] = splitter.feed(b'{"v": ' + b"9" * 20 + b', "w": 1e308}')
    assert ok == {"v": int("9" * 20), "w": 1e308}
