"""The status port's subscribers (port 10000): every packet goes to each of them without ever
waiting for one.

A client that opens the status port and stops reading exists in the wild; with a blocking send
it held the broadcaster, and every other subscriber saw the stream stop. Here each socket is
non-blocking and the broadcaster only ever hands the kernel what it takes at once:

* the rest of a packet the kernel did not take is kept (one packet at most per subscriber) and
  sent first next period, so a subscriber never receives half a packet followed by another;
* while that rest is still pending, the new packet is **skipped** for this subscriber (counted);
* a subscriber that has taken no byte for :data:`STALL_LIMIT` s is **dropped** (its socket
  closed): a reader that resumes after that reconnects, as after any lost link.

Each socket's send buffer is :data:`SEND_BUFFER` bytes, so a reader that falls behind gets
skipped packets within a few periods instead of seconds of stale ones queued in the kernel.
"""
from __future__ import annotations

import logging
import socket
import threading
import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional

from ..protocol.tcp_server import close_socket

log = logging.getLogger(__name__)

STALL_LIMIT = 5.0        # s without a byte taken before a subscriber is dropped
SEND_BUFFER = 64 * 1024  # bytes of kernel send buffer per subscriber (~10 packets)


@dataclass
class SubscriberStats:
    """What one subscriber got: ``sent`` packets delivered whole to the kernel, ``skipped``
    packets it was not sent because it had not taken the one before."""

    peer: str
    sent: int = 0
    skipped: int = 0


@dataclass
class _Subscriber:
    sock: socket.socket
    stats: SubscriberStats
    rest: Optional[memoryview] = None          # unsent tail of the packet in flight
    last_progress: float = field(default_factory=time.monotonic)


class StatusSubscribers:
    """Thread-safe set of status subscribers. :meth:`push` is called by one broadcaster."""

    def __init__(self, stall_limit: float = STALL_LIMIT):
        self.stall_limit = stall_limit
        self._lock = threading.Lock()
        self._subscribers: Dict[socket.socket, _Subscriber] = {}
        self.dropped = 0        # subscribers closed for not reading

    def __len__(self) -> int:
        with self._lock:
            return len(self._subscribers)

    def add(self, sock: socket.socket) -> None:
        try:
            peer = "%s:%d" % sock.getpeername()[:2]
        except OSError:
            peer = "?"
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SEND_BUFFER)
        sock.setblocking(False)
        with self._lock:
            self._subscribers[sock] = _Subscriber(sock, SubscriberStats(peer))

    def stats(self) -> List[SubscriberStats]:
        """Per-subscriber counters of the subscribers connected now."""
        with self._lock:
            return [SubscriberStats(s.stats.peer, s.stats.sent, s.stats.skipped)
                    for s in self._subscribers.values()]

    def push(self, packet: bytes) -> None:
        """Hand ``packet`` to every subscriber that can take it now; never blocks."""
        with self._lock:
            subscribers = list(self._subscribers.values())
        now = time.monotonic()
        for sub in subscribers:
            try:
                if sub.rest is not None and not self._send(sub, sub.rest, now):
                    sub.stats.skipped += 1
                    if now - sub.last_progress > self.stall_limit:
                        self._drop(sub, f"took no status byte for {self.stall_limit:g} s")
                    continue
                self._send(sub, memoryview(packet), now)
            except OSError as exc:    # reset or closed by the client
                self._drop(sub, str(exc) or type(exc).__name__, quiet=True)

    def _send(self, sub: _Subscriber, data: memoryview, now: float) -> bool:
        """Send what the kernel takes of ``data``; True when all of it went."""
        try:
            n = sub.sock.send(data)
        except BlockingIOError:
            n = 0
        if n:
            sub.last_progress = now
        if n == len(data):
            sub.rest = None
            sub.stats.sent += 1
            return True
        sub.rest = data[n:]
        return False

    def _drop(self, sub: _Subscriber, why: str, quiet: bool = False) -> None:
        with self._lock:
            if self._subscribers.pop(sub.sock, None) is None:
                return
        if not quiet:
            self.dropped += 1
            log.warning("emulator: status subscriber %s dropped: %s", sub.stats.peer, why)
        close_socket(sub.sock)

    def close_all(self) -> int:
        """Close every subscriber; how many there were."""
        with self._lock:
            subscribers, self._subscribers = list(self._subscribers.values()), {}
        for sub in subscribers:
            close_socket(sub.sock)
        return len(subscribers)
