"""The emulator's sockets: the command port (10001), the status port (10000) and the
``data_request`` port (10004).

* Command port: any number of clients at once, one thread each; requests are split by
  :mod:`.framing`, executed one at a time by :class:`~.handlers.CommandHandlers` (a controller
  runs one command at a time), and each gets exactly one reply.
* Replies go out in the controller's layout (a space after ``:`` and ``,``): public clients
  search the text for ``"errorCode": "``.
* ``wait_complete`` waits for the motion queue outside the command lock (other clients are
  served meanwhile), at most :data:`WAIT_COMPLETE_LIMIT` s.
* Data port: each ``{"cmdName":"data_request"}`` is answered with one status packet,
  zlib-compressed, as JAKA's SDK reads status.
* Status port: any number of clients; one thread encodes a packet every ``period`` s (8 ms,
  the controller cycle) and sends it to all of them. A client that cannot take a packet within
  :data:`SEND_TIMEOUT` s is dropped, so one stuck reader cannot stall the others.

:meth:`EmulatorServer.drop_clients` closes every client connection while the listening sockets
stay open — what a controller reboot or a network glitch looks like to a client that
reconnects.
"""
from __future__ import annotations

import logging
import socket
import threading
import time
from typing import Callable, Dict, List

from ..constants import SERVO_CYCLE
from ..protocol.fields import DATA_REQUEST_MAX_BYTES
from ..protocol.status_stream import encode_data_reply, encode_status
from ..protocol.wire import encode_json_spaced
from .framing import RequestSplitter
from .handlers import CommandHandlers

log = logging.getLogger(__name__)

STATUS_PERIOD = SERVO_CYCLE     # s, the controller publishes once per cycle
SEND_TIMEOUT = 0.5       # s a status client may block a send before it is dropped
IDLE_TIMEOUT = 1.0       # s an incomplete request may wait for its remaining bytes
WAIT_COMPLETE_LIMIT = 600.0   # s a wait_complete waits for the motion queue
_POLL = 0.1              # s, how often blocked threads look at the stop flag


def _listen(host: str, port: int) -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    # A restarted emulator must get its port back at once, not after TIME_WAIT.
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
    except OSError:
        sock.close()
        raise
    sock.listen(16)
    sock.settimeout(_POLL)
    return sock


def _close(sock: socket.socket) -> None:
    try:
        sock.shutdown(socket.SHUT_RDWR)   # wakes a thread blocked in recv on it
    except OSError:
        pass
    sock.close()


class EmulatorServer:
    """Serves ``handlers`` on ``command_port`` and the packets of ``status_source()`` (a dict
    of status fields) on ``status_port``. Port 0 picks a free port; the bound ports are in
    :attr:`command_port` and :attr:`status_port` after :meth:`start`."""

    def __init__(self, handlers: CommandHandlers, status_source: Callable[[], Dict],
                 host: str = "127.0.0.1", command_port: int = 10001, status_port: int = 10000,
                 period: float = STATUS_PERIOD, data_port: int = 10004):
        self.handlers = handlers
        self.status_source = status_source
        self.host = host
        self.command_port = int(command_port)
        self.status_port = int(status_port)
        self.data_port = int(data_port)
        self.period = float(period)
        self._lock = threading.Lock()          # guards the client lists
        self._exec_lock = threading.Lock()     # one command at a time
        self._command_clients: Dict[socket.socket, threading.Thread] = {}
        self._status_clients: List[socket.socket] = []
        self._listeners: List[socket.socket] = []
        self._threads: List[threading.Thread] = []
        self._quit = threading.Event()
        self.packets_sent = 0

    # ---- life cycle --------------------------------------------------------------------
    def start(self) -> None:
        listeners = []
        try:
            for port in (self.command_port, self.status_port, self.data_port):
                listeners.append(_listen(self.host, port))
        except OSError:
            for sock in listeners:
                sock.close()
            raise
        command, status, data = listeners
        self._listeners = listeners
        self.command_port = command.getsockname()[1]
        self.status_port = status.getsockname()[1]
        self.data_port = data.getsockname()[1]
        for target, args, name in ((self._accept, (command, self._serve_commands), "commands"),
                                   (self._accept, (status, self._add_status_client), "status"),
                                   (self._accept, (data, self._serve_data), "data"),
                                   (self._broadcast, (), "broadcast")):
            thread = threading.Thread(target=target, args=args, daemon=True,
                                      name=f"emulator-{name}")
            thread.start()
            self._threads.append(thread)

    def stop(self) -> None:
        """Close everything and join every thread. Idempotent."""
        self._quit.set()
        for thread in self._threads:
            thread.join(2.0)
        for sock in self._listeners:
            sock.close()
        self._listeners = []
        self._threads = []
        self.drop_clients()
        with self._lock:
            threads = list(self._command_clients.values())
        for thread in threads:
            if thread is not threading.current_thread():
                thread.join(2.0)

    def __enter__(self) -> "EmulatorServer":
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

    def drop_clients(self) -> None:
        """Close every client connection on both ports; the ports keep listening."""
        with self._lock:
            clients = list(self._command_clients) + self._status_clients
            self._status_clients = []
        for sock in clients:
            _close(sock)
        if clients:
            log.warning("emulator: dropped %d client connection(s)", len(clients))

    @property
    def client_count(self) -> Dict[str, int]:
        with self._lock:
            return {"command": len(self._command_clients), "status": len(self._status_clients)}

    # ---- accepting ----------------------------------------------------------------------------
    def _accept(self, listener: socket.socket, serve: Callable[[socket.socket], None]) -> None:
        while not self._quit.is_set():
            try:
                conn, _ = listener.accept()
            except socket.timeout:
                continue
            except OSError:
                break
            try:
                conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                serve(conn)
            except OSError:   # the client vanished at once
                conn.close()

    def _serve_commands(self, conn: socket.socket) -> None:
        self._serve_client(conn, self._command_loop, "emulator-client")

    def _serve_data(self, conn: socket.socket) -> None:
        self._serve_client(conn, self._data_loop, "emulator-data-client")

    def _serve_client(self, conn: socket.socket, loop: Callable[[socket.socket], None],
                      name: str) -> None:
        """One thread per request/reply client (command and data ports alike)."""
        thread = threading.Thread(target=loop, args=(conn,), daemon=True, name=name)
        with self._lock:
            self._command_clients[conn] = thread
        thread.start()

    def _data_loop(self, conn: socket.socket) -> None:
        """Port 10004: one zlib-compressed packet per data_request (other commands answered as
        on the command port)."""
        self._client_loop(conn, self._answer_data)

    def _answer_data(self, conn: socket.socket, request) -> bool:
        if not (isinstance(request, dict) and request.get("cmdName") == "data_request"):
            return self._answer(conn, request)
        reply = encode_data_reply(self.status_source())
        if len(reply) > DATA_REQUEST_MAX_BYTES:
            log.error("emulator: data_request reply of %d bytes exceeds the SDK's %d",
                      len(reply), DATA_REQUEST_MAX_BYTES)
        try:
            conn.sendall(reply)
        except OSError:
            return False
        return True

    def _add_status_client(self, conn: socket.socket) -> None:
        conn.settimeout(SEND_TIMEOUT)
        with self._lock:
            self._status_clients.append(conn)

    # ---- command connections ---------------------------------------------------------------
    def _command_loop(self, conn: socket.socket) -> None:
        self._client_loop(conn, self._answer)

    def _client_loop(self, conn: socket.socket, answer) -> None:
        """Read requests from ``conn`` until it closes; ``answer(conn, request)`` replies to
        each and says whether the connection goes on."""
        splitter = RequestSplitter()
        last_data = time.monotonic()
        try:
            conn.settimeout(_POLL)
            while not self._quit.is_set():
                try:
                    data = conn.recv(65536)
                except socket.timeout:
                    if splitter.pending and time.monotonic() - last_data > IDLE_TIMEOUT:
                        if not answer(conn, splitter.expire()):
                            break
                    continue
                if not data:
                    break
                last_data = time.monotonic()
                if not all(answer(conn, request) for request in splitter.feed(data)):
                    break
        except OSError:
            pass   # closed by drop_clients/stop, or reset by the client: this connection ends
        finally:
            with self._lock:
                self._command_clients.pop(conn, None)
            _close(conn)

    def _answer(self, conn: socket.socket, request) -> bool:
        """Execute one request and send its reply; False when the connection is to end."""
        if request is None:
            return True
        self.handlers.wait_before(request, WAIT_COMPLETE_LIMIT)
        with self._exec_lock:
            reply, then = self.handlers.handle(request)
        try:
            conn.sendall(encode_json_spaced(reply))
        except OSError:
            return False
        if then == "drop_all":
            self.drop_clients()
            return False
        return then != "close"

    # ---- status stream ------------------------------------------------------------------------
    def _broadcast(self) -> None:
        deadline = time.monotonic()
        while not self._quit.is_set():
            with self._lock:
                clients = list(self._status_clients)
            if clients:
                try:
                    packet = encode_status(self.status_source())
                except Exception:  # noqa: BLE001 - the stream must survive a bad sample
                    log.exception("emulator: building the status packet failed")
                    packet = None
                if packet is not None:
                    for sock in clients:
                        self._send_status(sock, packet)
            deadline += self.period
            delay = deadline - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            elif delay < -self.period:
                deadline = time.monotonic()   # fell behind (stall): resynchronise, no burst

    def _send_status(self, sock: socket.socket, packet: bytes) -> None:
        try:
            sock.sendall(packet)
            self.packets_sent += 1
        except OSError:
            with self._lock:
                if sock in self._status_clients:
                    self._status_clients.remove(sock)
            _close(sock)
