"""Port 10004: the reply to ``data_request``, one status packet compressed with zlib
(docs/protocol.md, "Status packet") — both ends."""
from __future__ import annotations

import zlib
from typing import Any, Dict, Mapping

from .errors import MalformedInput, ProtocolError
from .status_encoder import encode_status
from .wire import HeadDecoder


def encode_data_reply(fields: Mapping[str, Any]) -> bytes:
    """Server side of port 10004: the reply to ``data_request``, one status packet
    (:func:`encode_status`) compressed with zlib."""
    return zlib.compress(encode_status(fields), 6)


def decode_data_reply(data: bytes) -> Dict[str, Any]:
    """Client side of port 10004: a whole zlib reply → the packet's fields. Raises
    :class:`~.errors.ProtocolError` when it does not decompress to one JSON object."""
    try:
        text = zlib.decompress(data)
    except zlib.error as exc:
        raise ProtocolError(f"the data_request reply ({len(data)} bytes) is not a "
                            f"zlib-compressed JSON status packet: {exc}") from None
    return data_reply_fields(text, len(data))


def data_reply_fields(text: bytes, compressed_size: int) -> Dict[str, Any]:
    """The fields of a data_request reply already decompressed (``text``; it arrived as
    ``compressed_size`` bytes). Raises :class:`~.errors.ProtocolError` when it is not one JSON
    object."""
    try:
        decoded = HeadDecoder().decode(text)
    except MalformedInput as exc:
        raise MalformedInput(f"the data_request reply ({compressed_size} bytes) is not a "
                             f"zlib-compressed JSON status packet: {exc}") from None
    if decoded is None:
        raise MalformedInput(f"the data_request reply ({compressed_size} bytes) ends before "
                             "its JSON object does")
    if not isinstance(decoded.value, dict):
        raise MalformedInput("the data_request reply is not a JSON object")
    return decoded.value
