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
* Status port: any number of clients; one thread encodes a packet every ``period`` s (the
  profile's push period) and hands it to all of them without ever waiting for one: a reader
  that stops reading is skipped, then dropped, and costs the others nothing
  (:mod:`.status_push`).
* No bytes end a connection thread: whatever arrives gets an error reply (:mod:`.framing`,
  and anything a handler or the reply's encoding raises is answered too).

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

from ..common.constants import SERVO_CYCLE
from ..protocol.fields import DATA_REQUEST_MAX_BYTES, ERROR_CODE_FAILED, Cmd, Field
from ..protocol.status_stream import encode_data_reply, encode_status
from .framing import RequestSplitter
from .handlers import CommandHandlers
from .replies import encode_reply, error_reply
from .status_push import StatusSubscribers, close_socket

log = logging.getLogger(__name__)

STATUS_PERIOD = SERVO_CYCLE     # s, the default of an EmulatorServer built directly
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


class EmulatorServer:
    """Serves ``handlers`` on ``command_port``, the packets of ``status_source()`` (a dict of
    status fields) every ``period`` s on ``status_port``, and one zlib packet per
    ``data_request`` on ``data_port``. Port 0 picks a free port; the bound ports are in
    :attr:`command_port`, :attr:`status_port` and :attr:`data_port` after :meth:`start`."""

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
        self._lock = threading.Lock()          # guards the client table
        self._exec_lock = threading.Lock()     # one command at a time
        self._command_clients: Dict[socket.socket, threading.Thread] = {}
        #: the status port's subscribers (their counters: :meth:`StatusSubscribers.stats`)
        self.subscribers = StatusSubscribers()
        self._listeners: List[socket.socket] = []
        self._threads: List[threading.Thread] = []
        self._quit = threading.Event()

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
            clients = list(self._command_clients)
        for sock in clients:
            close_socket(sock)
        count = len(clients) + self.subscribers.close_all()
        if count:
            log.warning("emulator: dropped %d client connection(s)", count)

    @property
    def client_count(self) -> Dict[str, int]:
        with self._lock:
            requesting = len(self._command_clients)
        return {"command": requesting, "status": len(self.subscribers)}

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
        if not (isinstance(request, dict) and request.get(Field.CMD_NAME) == Cmd.DATA_REQUEST):
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
        self.subscribers.add(conn)

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
        except Exception:  # noqa: BLE001 - a bug must cost this connection, never the server
            log.exception("emulator: a client connection failed")
        finally:
            with self._lock:
                self._command_clients.pop(conn, None)
            close_socket(conn)

    def _answer(self, conn: socket.socket, request) -> bool:
        """Execute one request and send its reply; False when the connection is to end."""
        if request is None:
            return True
        try:
            self.handlers.wait_before(request, WAIT_COMPLETE_LIMIT)
            with self._exec_lock:
                reply, then = self.handlers.handle(request)
            text = encode_reply(reply)
        except Exception as exc:  # noqa: BLE001 - every request gets a reply
            log.exception("emulator: answering a request failed")
            name = request.get(Field.CMD_NAME) if isinstance(request, dict) else ""
            reply = error_reply(name, f"the emulator failed to answer: {exc!r}"[:300],
                                ERROR_CODE_FAILED)
            then = None
            text = encode_reply(reply)
        try:
            conn.sendall(text)
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
            if len(self.subscribers):
                try:
                    self.subscribers.push(encode_status(self.status_source()))
                except Exception:  # noqa: BLE001 - the stream must survive a bad sample
                    log.exception("emulator: building the status packet failed")
            deadline += self.period
            delay = deadline - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            elif delay < -self.period:
                deadline = time.monotonic()   # fell behind (stall): resynchronise, no burst
