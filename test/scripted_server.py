"""A tiny scripted TCP server for the protocol client's tests: real sockets on 127.0.0.1, a
handler per accepted connection, everything closed and joined at the end."""
from __future__ import annotations

import socket
import threading

from jaka_driver.protocol.wire import decode_first_object


class ScriptedServer:
    """Listens on an ephemeral port; serves each accepted connection with ``serve(conn)`` in its
    own thread. Everything is closed and joined by :meth:`close`."""

    def __init__(self, serve):
        self._serve = serve
        self.stopping = threading.Event()
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.listener.settimeout(0.05)
        self.port = self.listener.getsockname()[1]
        self.connections = []
        self.threads = []
        self.accepted = threading.Event()
        self._accept_thread = threading.Thread(target=self._accept, daemon=True)
        self._accept_thread.start()

    def _accept(self):
        while not self.stopping.is_set():
            try:
                conn, _ = self.listener.accept()
            except socket.timeout:
                continue
            except OSError:
                return
            self.connections.append(conn)
            t = threading.Thread(target=self._run, args=(conn,), daemon=True)
            self.threads.append(t)
            t.start()
            self.accepted.set()

    def _run(self, conn):
        try:
            self._serve(conn, self)
        except OSError:
            pass

    def close(self):
        self.stopping.set()
        self._accept_thread.join(2)
        self.listener.close()
        for conn in self.connections:
            try:
                conn.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            conn.close()
        for t in self.threads:
            t.join(2)
        assert not any(t.is_alive() for t in [self._accept_thread, *self.threads])


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
