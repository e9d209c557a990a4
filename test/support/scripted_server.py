"""A tiny scripted TCP server for the protocol client's tests: real sockets on 127.0.0.1, a
handler per accepted connection, everything closed and joined at the end — on the package's one
TCP server (jaka_driver.protocol.tcp_server), as the emulator and the fake controller are."""
from __future__ import annotations

import socket
import threading

from jaka_driver.protocol.tcp_server import TcpServer
from jaka_driver.protocol.wire import decode_first_object


class ScriptedServer:
    """Listens on an ephemeral port; serves each accepted connection with ``serve(conn, self)``
    in its own thread. Everything is closed and joined by :meth:`close`."""

    def __init__(self, serve):
        self._serve = serve
        self.connections = []
        self.accepted = threading.Event()
        self._server = TcpServer(self._run, name="scripted-server", nodelay=False).start()
        self.port = self._server.port
        self.stopping = self._server.stopping

    def _run(self, conn):
        self.connections.append(conn)
        self.accepted.set()
        self._serve(conn, self)

    def close(self):
        self._server.stop()
        assert not self._server.threads_alive()


def requests_of(conn, server):
    """Yield each JSON request arriving on ``conn`` until it closes or the server stops."""
    conn.settimeout(0.05)
    buf = bytearray()
    while not server.stopping.is_set():
        try:
            obj, used = decode_first_object(buf.lstrip())
            buf = bytearray(buf.lstrip()[used:])
            yield obj
            continue
        except ValueError:
            pass
        try:
            chunk = conn.recv(4096)
        except socket.timeout:
            continue
        if not chunk:
            return
        buf += chunk
