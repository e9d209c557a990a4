"""One small TCP server: listen, accept, serve each connection, close everything.

The controller side of the protocol for whoever plays it — the emulator's three ports, and the
fakes the tests script — so that listening, accepting, the connection threads and a clean stop
are written once. What is said on a connection is the caller's ``serve(conn)``.

Threads: one accepting thread per server; with ``threaded`` (request/reply clients) one more
per connection, which runs ``serve(conn)`` and closes the connection when it returns; without
(a handler that only hands the socket on, such as the status port's subscribers, which another
thread feeds) ``serve`` runs in the accepting thread and owns the socket from then on.
:meth:`TcpServer.stop` closes the listener and every connection it serves and joins every
thread it started.
"""
from __future__ import annotations

import logging
import socket
import threading
from typing import Callable, Dict, List, Optional

log = logging.getLogger(__name__)

POLL = 0.1      # s, how often the accepting thread looks at the stop flag


def close_socket(sock: socket.socket) -> None:
    """Shut down and close ``sock``, whatever state it is in (a thread blocked in ``recv`` on it
    wakes up)."""
    try:
        sock.shutdown(socket.SHUT_RDWR)
    except OSError:
        pass
    sock.close()


class TcpServer:
    """Serves ``serve(conn)`` on ``host``:``port`` (0: a free port, read :attr:`port` after
    :meth:`start`). ``name`` names its threads; ``nodelay`` sets TCP_NODELAY on each
    connection (replies and packets go out at once, not when Nagle's timer says)."""

    def __init__(self, serve: Callable[[socket.socket], None], host: str = "127.0.0.1",
                 port: int = 0, *, name: str = "tcp-server", threaded: bool = True,
                 nodelay: bool = True, backlog: int = 16):
        self._serve = serve
        self.host = host
        self.port = int(port)
        self.name = name
        self.threaded = threaded
        self.nodelay = nodelay
        self.backlog = backlog
        #: set by :meth:`stop`: a handler's loop ends when it is
        self.stopping = threading.Event()
        self._lock = threading.Lock()
        self._listener: Optional[socket.socket] = None
        self._accepting: Optional[threading.Thread] = None
        self._clients: Dict[socket.socket, threading.Thread] = {}
        self._finished: List[threading.Thread] = []

    # ---- life cycle ----------------------------------------------------------------------
    def start(self) -> "TcpServer":
        """Bind and listen (raises OSError when the port is taken) and start accepting."""
        sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        # A restarted server must get its port back at once, not after TIME_WAIT.
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            sock.bind((self.host, self.port))
        except OSError:
            sock.close()
            raise
        sock.listen(self.backlog)
        sock.settimeout(POLL)
        self._listener = sock
        self.port = sock.getsockname()[1]
        self._accepting = threading.Thread(target=self._accept, args=(sock,), daemon=True,
                                           name=self.name)
        self._accepting.start()
        return self

    def stop(self, timeout: float = 2.0) -> None:
        """Stop accepting, close every connection, join every thread. Idempotent."""
        self.stopping.set()
        if self._accepting is not None:
            self._accepting.join(timeout)
        if self._listener is not None:
            self._listener.close()
        self.close_clients()
        with self._lock:
            threads = list(self._clients.values()) + self._finished
        for thread in threads:
            if thread is not threading.current_thread():
                thread.join(timeout)

    def __enter__(self) -> "TcpServer":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # ---- connections -------------------------------------------------------------------------
    @property
    def client_count(self) -> int:
        """Connections being served now (``threaded`` servers)."""
        with self._lock:
            return len(self._clients)

    def close_clients(self) -> int:
        """Close every connection being served (the port keeps listening); how many."""
        with self._lock:
            clients = list(self._clients)
        for conn in clients:
            close_socket(conn)
        return len(clients)

    def threads_alive(self) -> bool:
        """Whether any thread this server started still runs."""
        with self._lock:
            threads = [self._accepting, *self._clients.values(), *self._finished]
        return any(t is not None and t.is_alive() for t in threads)

    # ---- internals ------------------------------------------------------------------------------
    def _accept(self, listener: socket.socket) -> None:
        while not self.stopping.is_set():
            try:
                conn, _ = listener.accept()
            except socket.timeout:
                continue
            except OSError:
                break
            try:
                if self.nodelay:
                    conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                if self.threaded:
                    self._start_client(conn)
                else:
                    self._serve(conn)
            except OSError:   # the client vanished at once
                conn.close()

    def _start_client(self, conn: socket.socket) -> None:
        thread = threading.Thread(target=self._run_client, args=(conn,), daemon=True,
                                  name=f"{self.name}-client")
        with self._lock:
            self._clients[conn] = thread
        thread.start()

    def _run_client(self, conn: socket.socket) -> None:
        try:
            self._serve(conn)
        except OSError:
            pass      # closed by stop()/close_clients(), or reset by the client
        except Exception:  # noqa: BLE001 - a bug must cost this connection, never the server
            log.exception("%s: a client connection failed", self.name)
        finally:
            with self._lock:
                self._clients.pop(conn, None)
                # kept until it has ended, so that stop() can join it
                self._finished = [t for t in self._finished if t.is_alive()]
                self._finished.append(threading.current_thread())
            close_socket(conn)
