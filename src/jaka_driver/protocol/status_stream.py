"""The port-10000 status stream's framing: bytes in any number of TCP reads → whole packets.

The controller pushes JSON objects back to back with no delimiter, each starting with
``{"len": N`` (docs/protocol.md, "Status packet"); a packet can be several kB and arrives in any
number of TCP reads. The decoder resynchronises on the token ``{"len":``, so a lost or damaged
byte costs at most one packet, and it never holds more than ``max_buffer`` bytes. A packet's
fields become a :class:`~.status_packet.StatusPacket` in :mod:`.status_packet`.
"""
from __future__ import annotations

import re
from typing import Any, Callable, Dict, List, Optional

from .errors import MalformedInput
from .wire import HeadDecoder, decode_whole

#: Every packet starts with these bytes (``len`` first; a space may follow the colon).
PACKET_START = b'{"len":'
_LEN_VALUE = re.compile(rb'\{"len":\s*(\d{1,9})')
#: Default cap of the decoder's buffer: ~100 packets of the largest size observed (8979 B).
MAX_BUFFER = 1 << 20
#: A declared ``len`` above this is not believed (7× the largest packet observed).
MAX_PACKET = 1 << 16
_CLOSING_BRACE = ord("}")


class StatusStreamDecoder:
    """Incremental decoder: bytes in, whole packets (dicts) out.

    ``decode`` turns the bytes of one whole packet into its dict, or None when they are not
    exactly one JSON object (then the careful reader decides): by default every key as JSON
    reads it (:func:`~.wire.decode_whole`); a reader that only parses the packets passes
    :func:`~.status_packet.decode_read_keys`, which decodes only what the parser reads.

    Not thread-safe: one reader feeds it. Counters (cumulative):

    * ``packets`` — packets decoded;
    * ``bytes_dropped`` — bytes thrown away (garbage between packets, broken packets, overflow);
    * ``packets_dropped`` — packets lost: a malformed object (not JSON, nested too deep: see
      :class:`~.wire.HeadDecoder`), an unfinished one skipped at the next token, or the buffer
      discarded because it grew past ``max_buffer`` without a decodable packet;
    * ``fields_dropped`` — fields of decoded packets that were malformed and read as their
      default (:func:`~.status_packet.parse_status`'s ``malformed``; the readers of
      :mod:`.status_client` count them);
    * ``text_repaired`` — packets with invalid UTF-8 inside a string (kept as U+FFFD).

    A packet is declared broken when it cannot be decoded although the next token has
    arrived and the buffer holds at least the packet's declared ``len``; the ``len`` check keeps
    a nested ``{"len":`` from being mistaken for the next packet. ``len`` also says when a
    packet has all arrived and where to cut it for the compiled parser (:meth:`_take_declared`,
    the usual case: one pass in C, no copy to ``str``, no parse of a packet's first TCP segments
    on their own); the decoder does not otherwise rely on it: a ``len`` that understates sends
    its packet the careful way (:class:`~.wire.HeadDecoder`), one that overstates makes it wait
    for the next token first, and one above :data:`MAX_PACKET` is ignored.
    """

    def __init__(self, max_buffer: int = MAX_BUFFER,
                 decode: Callable[[bytes], Optional[Dict[str, Any]]] = decode_whole):
        if max_buffer < 2 * len(PACKET_START):
            raise ValueError(f"max_buffer must be at least {2 * len(PACKET_START)} bytes")
        self.max_buffer = int(max_buffer)
        self._decode = decode
        self.packets = 0
        self.bytes_dropped = 0
        self.packets_dropped = 0
        self.fields_dropped = 0
        self.text_repaired = 0
        self._buf = bytearray()
        self._head = HeadDecoder()
        # Where to look for a '}' in the buffer before trying to decode again: a packet can only
        # have completed if a '}' arrived since the last failed attempt.
        self._scan_from = 0

    @property
    def buffered(self) -> int:
        """Bytes held, waiting for the rest of a packet."""
        return len(self._buf)

    def reset(self) -> None:
        """Forget buffered bytes (e.g. on a new connection); the counters are kept."""
        self._buf.clear()
        self._scan_from = 0
        self._head.reset()

    def feed(self, data: bytes) -> List[Dict[str, Any]]:
        """Add received bytes; return the packets they completed, in order."""
        self._buf += data
        packets: List[Dict[str, Any]] = []
        while self._buf:
            start = self._buf.find(PACKET_START)
            if start < 0:
                self._drop_all_but_token_prefix()
                break
            if start > 0:
                self._drop(start)
            declared = self._declared_length()
            if declared is not None:
                if len(self._buf) >= declared:
                    packet = self._take_declared(declared)
                    if packet is not None:
                        packets.append(packet)
                        continue
                elif self._buf.find(PACKET_START, 1) < 0:
                    # Not all of it has arrived (a packet spans several TCP segments on a real
                    # network) and nothing follows it yet: no parse before it has.
                    break
            try:
                packet = self._try_decode()
            except MalformedInput:
                self._drop_broken()
                continue
            if packet is not None:
                packets.append(packet)
                continue
            following = self._buf.find(PACKET_START, 1)
            if following < 0:
                break   # incomplete: wait for more bytes
            if declared is not None and len(self._buf) < declared:
                # The token may belong to a nested object ({"len": ...} inside the packet):
                # only a packet that stays undecodable past its own length is broken.
                break
            # A new packet starts where this one cannot be decoded: this one is broken.
            self._drop(following)
            self.packets_dropped += 1
        if len(self._buf) > self.max_buffer:
            self._drop(len(self._buf))
            self.packets_dropped += 1
        self.packets += len(packets)
        return packets

    def _take_declared(self, n: int):
        """The packet at the head cut at its declared length ``n`` (all arrived) and parsed
        whole by the compiled parser (:func:`~.wire.decode_whole`), or None when those bytes
        are not one JSON object — then :meth:`_try_decode` reads the head the careful way.
        ``len`` is only a hint: bytes that parse whole from the packet's ``{`` are that
        packet, whatever ``len`` means on a controller."""
        if self._buf[n - 1] != _CLOSING_BRACE:
            return None
        packet = self._decode(self._buf[:n])
        if not isinstance(packet, dict):
            return None
        del self._buf[:n]
        self._scan_from = 0
        self._head.reset()
        return packet

    def _try_decode(self):
        """The packet at the head, or None while it is unfinished; raises MalformedInput."""
        if self._buf.find(b"}", self._scan_from) < 0:
            self._scan_from = len(self._buf)
            return None
        decoded = self._head.decode(self._buf)
        if decoded is None:
            self._scan_from = len(self._buf)
            return None
        del self._buf[:decoded.used]
        self._scan_from = 0
        if decoded.repaired:
            self.text_repaired += 1
        return decoded.value

    def _drop_broken(self) -> None:
        """Drop the malformed packet at the head: up to the next token, or all of it."""
        following = self._buf.find(PACKET_START, 1)
        if following < 0:
            self._drop_all_but_token_prefix()
        else:
            self._drop(following)
        self.packets_dropped += 1

    def _declared_length(self):
        match = _LEN_VALUE.match(self._buf)
        if match is None:
            return None
        n = int(match.group(1))
        # A corrupt or oddly defined length must not hold the stream back for long.
        return n if n <= MAX_PACKET else None

    def _drop(self, n: int) -> None:
        del self._buf[:n]
        self.bytes_dropped += n
        self._scan_from = 0
        self._head.reset()

    def _drop_all_but_token_prefix(self) -> None:
        # Keep a tail that may be the beginning of a token split across reads.
        keep = 0
        for k in range(min(len(PACKET_START) - 1, len(self._buf)), 0, -1):
            if self._buf.endswith(PACKET_START[:k]):
                keep = k
                break
        self._drop(len(self._buf) - keep)
