"""The command port (10001): :class:`CommandClient`, a blocking client, one request and its
reply at a time.

It does not reconnect by itself: the backend owns that policy; ``connect`` and ``close`` are
idempotent, so a policy can simply call them again.

No input escapes as anything but the library's own errors: a reply that cannot be parsed closes
its connection (the bytes after it could not be trusted) and raises
:class:`~.errors.ProtocolError`. Every drop is counted (``CommandClient.replies_dropped``).
"""
from __future__ import annotations

import logging
import socket
import threading
import time
from typing import Any, Mapping, Optional

from . import errors
from .commands import encode
from .connect import RECV_SIZE, open_connection
from .errors import ConnectionLost, InvalidArgument, MalformedInput, ProtocolError
from .fields import COMMAND_PORT, Field
from .replies import Reply, command_names_match, parse_reply
from .wire import HeadDecoder

_log = logging.getLogger(__name__)
#: A reply longer than this without its end is not a controller's (the longest, ``get_data``,
#: is a status packet: under 10 kB).
MAX_REPLY_BYTES = 1 << 18
_WHITESPACE = b" \t\r\n"


class _Connection:
    """One open command socket and the bytes received on it but not yet consumed."""

    def __init__(self, sock: socket.socket):
        self.sock = sock
        self.buf = bytearray()
        self.head = HeadDecoder()   # of ``buf``
        self.closed_locally = False

    def close(self) -> None:
        self.closed_locally = True
        try:
            # shutdown wakes a thread blocked in recv() on this socket; close alone may not.
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self.sock.close()


class CommandClient:
    """Blocking client of the command port.

    Thread-safe: any number of threads may call :meth:`call`; requests go out one at a time
    and each waits for its own reply (the protocol has no request ids, so replies can only be
    matched by order). :meth:`close` may be called from any thread, also while a call waits.

    ``timeout`` (s) is the default time a :meth:`call` waits for its reply; ``connect_timeout``
    (s, default ``timeout``) bounds :meth:`connect`.

    Counters, cumulative over connections: ``replies`` (parsed), ``replies_dropped`` (bytes
    that were no reply — not JSON, nested too deep, longer than :data:`MAX_REPLY_BYTES`, not an
    object, no ``errorCode``), ``text_repaired`` (replies with invalid UTF-8 in a string).
    """

    def __init__(self, host: str, port: int = COMMAND_PORT, timeout: float = 1.0,
                 connect_timeout: Optional[float] = None):
        self.host = host
        self.port = int(port)
        self.timeout = float(timeout)
        self.connect_timeout = float(timeout if connect_timeout is None else connect_timeout)
        if not (self.timeout > 0.0 and self.connect_timeout > 0.0):
            raise InvalidArgument("timeout and connect_timeout must be > 0 s")
        self._call_lock = threading.Lock()    # one request in flight
        self._conn_lock = threading.Lock()    # guards swapping self._conn
        self._conn: Optional[_Connection] = None
        self.replies = 0
        self.replies_dropped = 0
        self.text_repaired = 0

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    @property
    def connected(self) -> bool:
        """Whether a connection is open (as far as we know: a peer close is noticed at the next
        call)."""
        return self._conn is not None

    def connect(self) -> None:
        """Open the connection; does nothing if it is open. Raises :class:`ConnectFailed`."""
        with self._conn_lock:
            if self._conn is None:
                self._conn = _Connection(open_connection(self.host, self.port,
                                                         self.connect_timeout, "command"))

    def close(self) -> None:
        """Close the connection; does nothing if it is closed. A call waiting for its reply
        raises :class:`ConnectionLost`."""
        with self._conn_lock:
            conn, self._conn = self._conn, None
        if conn is not None:
            conn.close()

    def __enter__(self) -> "CommandClient":
        self.connect()
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def call(self, request: Mapping[str, Any], timeout: Optional[float] = None) -> Reply:
        """Send one request (a dict from :mod:`.commands`) and return the controller's reply.

        A reply with a non-zero ``errorCode`` is returned (``reply.ok`` False), not raised.
        Raises :class:`~.errors.InvalidArgument` (nothing sent), :class:`ConnectionLost`,
        :class:`~.errors.TimeoutError` (the connection is then closed) or
        :class:`ProtocolError`.
        """
        payload = encode(request)
        name = request[Field.CMD_NAME]
        wait = self.timeout if timeout is None else float(timeout)
        if not wait > 0.0:
            raise InvalidArgument(f"timeout must be > 0 s; got {wait}")
        with self._call_lock:
            conn = self._conn
            if conn is None:
                raise ConnectionLost(f"not connected to the controller at {self.address}; "
                                     "call connect() first")
            deadline = time.monotonic() + wait
            if conn.buf.strip(_WHITESPACE):
                _log.warning("discarding %d unexpected bytes from %s before sending %r",
                             len(conn.buf), self.address, name)
            conn.buf.clear()
            conn.head.reset()
            try:
                conn.sock.settimeout(wait)
                conn.sock.sendall(payload)
            except socket.timeout:
                self._discard(conn)
                raise errors.TimeoutError(
                    f"could not send {name!r} to {self.address} within {wait:.3f} s; the "
                    "connection was closed, call connect() again") from None
            except OSError as exc:
                lost = self._lost(conn, name, f"sending failed ({exc})")
                self._discard(conn)
                raise lost from None
            try:
                reply = parse_reply(self._read_object(conn, name, deadline, wait))
            except ProtocolError:
                self.replies_dropped += 1
                raise
            self.replies += 1
            if reply.cmd_name and not command_names_match(name, reply.cmd_name):
                self._discard(conn)
                raise ProtocolError(
                    f"sent {name!r} but the reply is for {reply.cmd_name!r}: replies are out of "
                    "step with requests; the connection was closed, call connect() again")
            return reply

    # ---- internals -------------------------------------------------------------------------
    def _discard(self, conn: _Connection) -> None:
        with self._conn_lock:
            if self._conn is conn:
                self._conn = None
        conn.close()

    def _lost(self, conn: _Connection, name: str, what: str) -> ConnectionLost:
        # Call before _discard(): it tells a close() from another thread from a peer close.
        if conn.closed_locally:
            return ConnectionLost(f"the connection to {self.address} was closed by close() while "
                                  f"{name!r} waited for its reply")
        return ConnectionLost(f"{what} while waiting for the reply to {name!r} from "
                              f"{self.address}; call connect() again (is another client holding "
                              "the command port, or was the controller restarted?)")

    def _read_object(self, conn: _Connection, name: str, deadline: float, wait: float):
        while True:
            obj = self._take_object(conn, name)
            if obj is not None:
                return obj
            remaining = deadline - time.monotonic()
            try:
                if remaining <= 0:
                    raise socket.timeout
                conn.sock.settimeout(remaining)
                chunk = conn.sock.recv(RECV_SIZE)
            except socket.timeout:
                self._discard(conn)
                partial = (f"; {len(conn.buf)} bytes of an incomplete reply arrived: "
                           f"{bytes(conn.buf[:80])!r}" if conn.buf else "")
                raise errors.TimeoutError(
                    f"no reply to {name!r} from {self.address} within {wait:.3f} s{partial}; the "
                    "connection was closed (a late reply could not be told apart from the next "
                    "one), call connect() again") from None
            except OSError as exc:
                lost = self._lost(conn, name, f"the connection broke ({exc})")
                self._discard(conn)
                raise lost from None
            if not chunk:
                got = f" after {len(conn.buf)} bytes of the reply" if conn.buf else ""
                lost = self._lost(conn, name, f"the controller closed the connection{got}")
                self._discard(conn)
                raise lost
            conn.buf += chunk

    def _take_object(self, conn: _Connection, name: str):
        """The next complete JSON object from the buffer, or None if it is not complete yet.
        Bytes that can never become one close the connection (ProtocolError)."""
        start = 0
        while start < len(conn.buf) and conn.buf[start] in _WHITESPACE:
            start += 1
        if start:
            del conn.buf[:start]
            conn.head.reset()
        if not conn.buf:
            return None
        if conn.buf[0] != ord("{"):
            self._discard(conn)
            raise ProtocolError(f"the reply to {name!r} from {self.address} is not a JSON object: "
                                f"{bytes(conn.buf[:80])!r}; is {self.address} really a JAKA "
                                "command port? The connection was closed")
        try:
            decoded = conn.head.decode(conn.buf)
        except MalformedInput as exc:
            self._discard(conn)
            raise MalformedInput(f"the reply to {name!r} from {self.address} is malformed: "
                                 f"{exc}; the connection was closed") from None
        if decoded is None:
            if len(conn.buf) > MAX_REPLY_BYTES:
                self._discard(conn)
                raise MalformedInput(f"the reply to {name!r} from {self.address} has no end "
                                     f"after {len(conn.buf)} bytes; the connection was closed")
            return None
        del conn.buf[:decoded.used]
        if decoded.repaired:
            self.text_repaired += 1
        return decoded.value
