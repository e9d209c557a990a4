"""The status ports: :class:`StatusReceiver`, the reader thread of port 10000 (pushed packets),
and :class:`StatusPoller`, the reader thread of port 10004 (``data_request``, as JAKA's SDK
reads status).

Neither reconnects by itself: the backend owns that policy; ``start`` and ``stop`` are
idempotent, so a policy can simply call them again.

No input ends a thread: a status packet that cannot be parsed is dropped and the stream read
on. Every drop is counted (the receivers' ``decoder.packets_dropped`` and
``decoder.fields_dropped``).
"""
from __future__ import annotations

import logging
import socket
import threading
import time
import zlib
from contextlib import nullcontext
from typing import Callable, ContextManager, Optional, Tuple

from .commands import data_request, encode
from .connect import RECV_SIZE, open_connection
from .errors import ProtocolError
from .fields import DATA_REQUEST_MAX_BYTES, STATUS_PORT, STATUS_REQUEST_PORT
from .data_reply import data_reply_fields
from .status_packet import StatusPacket, decode_read_keys, parse_status
from .status_stream import MAX_BUFFER, StatusStreamDecoder

_log = logging.getLogger(__name__)

#: A status packet inflates to well under this (the longest seen: 9 kB).
MAX_INFLATED_BYTES = 1 << 16

StatusCallback = Callable[[StatusPacket, float], None]
LostCallback = Callable[[str], None]


class StatusReceiver:
    """Reads the status stream in its own thread.

    ``on_status(status, received)`` is called from that thread for every packet, with
    ``received`` = ``clock()`` (default ``time.time``, s) at the read that completed it.
    ``on_connection_lost(reason)`` is called once, from that thread, when the stream ends for
    any reason other than :meth:`stop` (peer closed, socket error, or no data for
    ``stall_timeout`` s if given); the thread then ends and :meth:`start` may be called again.
    Exceptions raised by the callbacks are logged and do not stop the thread.
    ``thread_context()`` is entered first in that thread and left as it ends (the owner's
    say on the thread, e.g. its scheduling; default: nothing).
    """

    _POLL = 0.1   # s; how often the thread looks at the stop flag and the stall timer

    def __init__(self, host: str, port: int = STATUS_PORT,
                 on_status: Optional[StatusCallback] = None,
                 on_connection_lost: Optional[LostCallback] = None,
                 connect_timeout: float = 1.0, stall_timeout: Optional[float] = None,
                 clock: Callable[[], float] = time.time, max_buffer: int = MAX_BUFFER,
                 thread_context: Callable[[], ContextManager] = nullcontext):
        self.host = host
        self.thread_context = thread_context
        self.port = int(port)
        self.on_status = on_status
        self.on_connection_lost = on_connection_lost
        self.connect_timeout = float(connect_timeout)
        self.stall_timeout = stall_timeout
        self._clock = clock
        #: The stream decoder; its counters (packets, bytes_dropped, packets_dropped) add up over
        #: every connection of this receiver. It decodes only the keys parse_status reads
        #: (its packets are for parse_status alone).
        self.decoder = StatusStreamDecoder(max_buffer, decode=decode_read_keys)
        self._lock = threading.Lock()
        self._thread: Optional[threading.Thread] = None
        self._sock: Optional[socket.socket] = None
        self._stop = threading.Event()
        self._latest: Optional[Tuple[StatusPacket, float]] = None

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    @property
    def running(self) -> bool:
        thread = self._thread
        return thread is not None and thread.is_alive()

    @property
    def latest(self) -> Optional[Tuple[StatusPacket, float]]:
        """The last (status, received) pair of a receiver without ``on_status`` (a reader that
        looks when it wants), or None before the first packet. With ``on_status`` the
        callback's owner keeps what it needs and this stays None: one copy of the latest
        packet, not one per layer."""
        return self._latest

    def start(self) -> None:
        """Connect and start the reader thread; does nothing if it runs. Raises
        :class:`ConnectFailed` (no thread is left behind)."""
        with self._lock:
            if self.running:
                return
            sock = open_connection(self.host, self.port, self.connect_timeout, "status")
            sock.settimeout(self._POLL)
            self._stop = threading.Event()
            self._sock = sock
            self.decoder.reset()
            self._thread = threading.Thread(target=self._run, args=(sock, self._stop),
                                            name=f"jaka-status-{self.address}", daemon=True)
            self._thread.start()

    def stop(self, timeout: float = 2.0) -> None:
        """Stop the thread and close the socket; does nothing if stopped. No
        ``on_connection_lost`` is reported for a stop."""
        with self._lock:
            thread, sock = self._thread, self._sock
            self._thread = self._sock = None
            self._stop.set()
        if sock is not None:
            try:
                sock.shutdown(socket.SHUT_RDWR)   # wakes the reader at once
            except OSError:
                pass
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout)

    def __enter__(self) -> "StatusReceiver":
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

    def _run(self, sock: socket.socket, stop: threading.Event) -> None:
        with self.thread_context():
            self._read(sock, stop)

    def _read(self, sock: socket.socket, stop: threading.Event) -> None:
        reason = None
        last_data = time.monotonic()
        try:
            while not stop.is_set():
                try:
                    chunk = sock.recv(RECV_SIZE)
                except socket.timeout:
                    if (self.stall_timeout is not None
                            and time.monotonic() - last_data > self.stall_timeout):
                        reason = (f"no status data from {self.address} for "
                                  f"{self.stall_timeout:.2f} s")
                        break
                    continue
                except OSError as exc:
                    reason = f"the status connection to {self.address} broke ({exc})"
                    break
                if not chunk:
                    reason = f"the controller at {self.address} closed the status connection"
                    break
                received = self._clock()
                last_data = time.monotonic()
                try:
                    packets = self.decoder.feed(chunk)
                except Exception:  # noqa: BLE001 - no input may end the status stream
                    _log.exception("status bytes from %s could not be decoded; dropped",
                                   self.address)
                    self.decoder.reset()
                    self.decoder.packets_dropped += 1
                    continue
                for packet in packets:
                    self._deliver_fields(packet, received)
        finally:
            sock.close()
        if reason is not None and not stop.is_set():
            self._lost(reason)

    def _lost(self, reason: str) -> None:
        _log.warning("%s", reason)
        if self.on_connection_lost is not None:
            try:
                self.on_connection_lost(reason)
            except Exception:  # noqa: BLE001 - a callback must not kill the reader
                _log.exception("on_connection_lost callback raised")

    def _deliver_fields(self, fields, received: float) -> None:
        """Parse one decoded packet and deliver it, counting its malformed fields."""
        try:
            status = parse_status(fields)
        except ProtocolError as exc:   # not an object: nothing of it is usable
            self.decoder.packets_dropped += 1
            _log.debug("status packet from %s dropped: %s", self.address, exc)
            return
        except Exception:  # noqa: BLE001 - no input may end the status stream
            self.decoder.packets_dropped += 1
            _log.exception("status packet from %s could not be read; dropped", self.address)
            return
        self.decoder.fields_dropped += len(status.malformed)
        self._deliver(status, received)

    def _deliver(self, status: StatusPacket, received: float) -> None:
        if self.on_status is None:
            self._latest = (status, received)
            return
        try:
            self.on_status(status, received)
        except Exception:  # noqa: BLE001 - a callback must not kill the reader
            _log.exception("on_status callback raised")


class StatusPoller(StatusReceiver):
    """Port 10004, as JAKA's SDK reads status: every ``period`` s it sends
    ``{"cmdName":"data_request"}`` and reads one zlib-compressed packet back. Same callbacks,
    life cycle and counters as :class:`StatusReceiver`; ``stall_timeout`` bounds the wait for
    one reply.

    A reply is read to the end of its zlib stream, so one that is unusable — more than the
    SDK's :data:`~.fields.DATA_REQUEST_MAX_BYTES` compressed bytes, inflating past
    :data:`MAX_INFLATED_BYTES` (a zlib bomb is inflated in bounded pieces and thrown away), not
    a JSON object — is a counted drop and the next request follows. Bytes that are not zlib at
    all end the connection: where the next reply begins is then unknown."""

    def __init__(self, host: str, port: int = STATUS_REQUEST_PORT, *, period: float = 0.008,
                 **kwargs):
        super().__init__(host, port, **kwargs)
        self.period = float(period)

    def _read(self, sock: socket.socket, stop: threading.Event) -> None:
        reason = None
        request = encode(data_request())
        wait = self.stall_timeout if self.stall_timeout is not None else 1.0
        next_request = time.monotonic()
        try:
            while not stop.is_set():
                try:
                    sock.sendall(request)
                    reply = self._read_reply(sock, stop, wait)
                except (OSError, ProtocolError) as exc:
                    if isinstance(exc, ProtocolError):
                        self.decoder.packets_dropped += 1
                    reason = f"status requests to {self.address} failed ({exc})"
                    break
                if reply is None:
                    break   # stopped
                received = self._clock()
                try:
                    if not reply[0]:
                        raise ProtocolError(f"the data_request reply of {reply[1]} bytes is "
                                            f"longer than the SDK's {DATA_REQUEST_MAX_BYTES} "
                                            f"or inflates past {MAX_INFLATED_BYTES} bytes")
                    # only the keys parse_status reads; the careful reader for the rest
                    fields = decode_read_keys(reply[0])
                    if fields is None:
                        fields = data_reply_fields(*reply)
                except ProtocolError as exc:
                    self.decoder.packets_dropped += 1
                    _log.debug("status reply from %s dropped: %s", self.address, exc)
                else:
                    self.decoder.packets += 1
                    self._deliver_fields(fields, received)
                next_request += self.period
                delay = next_request - time.monotonic()
                if delay > 0:
                    stop.wait(delay)
                else:
                    next_request = time.monotonic()   # fell behind: no burst of requests
        finally:
            sock.close()
        if reason is not None and not stop.is_set():
            self._lost(reason)

    def _read_reply(self, sock: socket.socket, stop: threading.Event,
                    wait: float) -> Optional[Tuple[bytes, int]]:
        """One whole zlib stream from ``sock`` (its end is where zlib says it ends), inflated as
        it arrives: (the packet's text, the number of compressed bytes). A reply too long to use
        comes back as ``(b"", size)``, which no reader takes for a packet."""
        inflater = zlib.decompressobj()
        size = 0
        text = bytearray()
        too_long = False
        deadline = time.monotonic() + wait
        while not inflater.eof:
            if stop.is_set():
                return None
            try:
                chunk = sock.recv(RECV_SIZE)
            except socket.timeout:
                if time.monotonic() > deadline:
                    raise ProtocolError(f"no whole data_request reply within {wait:.2f} s "
                                        f"({size} bytes arrived)") from None
                continue
            if not chunk:
                raise ProtocolError("the controller closed the connection")
            size += len(chunk)
            too_long = too_long or size > DATA_REQUEST_MAX_BYTES
            try:
                while not inflater.eof:
                    # Bounded pieces: a zlib bomb never sits in memory whole.
                    piece = inflater.decompress(chunk, MAX_INFLATED_BYTES)
                    chunk = inflater.unconsumed_tail
                    if not too_long:
                        text += piece
                        too_long = len(text) > MAX_INFLATED_BYTES
                    if not chunk and len(piece) < MAX_INFLATED_BYTES:
                        break   # this input is used up; more is on its way
            except zlib.error as exc:
                raise ProtocolError(f"the data_request reply is not zlib data ({exc})") from None
            if too_long:
                text.clear()
        if too_long:
            _log.debug("data_request reply from %s of %d bytes is too long to use", self.address,
                       size)
            return b"", size
        return bytes(text), size
