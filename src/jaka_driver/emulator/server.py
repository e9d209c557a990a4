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
  profile's push period), right after the end of the twin's cycle it shows
  (:mod:`.status_pace`), and hands it to all of them without ever waiting for one: a reader
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
from typing import Callable, Dict, Optional

from ..common.constants import SERVO_CYCLE
from ..host import realtime
from ..protocol.fields import DATA_REQUEST_MAX_BYTES, ERROR_CODE_FAILED, Cmd, Field
from ..protocol.data_reply import encode_data_reply
from ..protocol.status_encoder import StatusEncoder
from ..protocol.tcp_server import TcpServer
from .framing import RequestSplitter
from .handlers import CommandHandlers
from .replies import encode_reply, error_reply
from .status_pace import CycleSource, StatusPacer
from .status_push import StatusSubscribers

log = logging.getLogger(__name__)

STATUS_PERIOD = SERVO_CYCLE     # s, the default of an EmulatorServer built directly
IDLE_TIMEOUT = 1.0       # s an incomplete request may wait for its remaining bytes
WAIT_COMPLETE_LIMIT = 600.0   # s a wait_complete waits for the motion queue
_POLL = 0.1              # s, how often blocked threads look at the stop flag


class EmulatorServer:
    """Serves ``handlers`` on ``command_port``, the packets of ``status_source()`` (a dict of
    status fields) every ``period`` s on ``status_port`` — each right after the cycle of
    ``arm`` (the twin: its ``wait_for_sample`` and ``state``) it shows, or on a wall-clock
    timer without one (:class:`~.status_pace.StatusPacer`) — and one zlib packet per
    ``data_request`` on ``data_port``. Port 0 picks a free port; the bound ports are in
    :attr:`command_port`, :attr:`status_port` and :attr:`data_port` after :meth:`start`. Each
    port is a :class:`~jaka_driver.protocol.tcp_server.TcpServer`."""

    def __init__(self, handlers: CommandHandlers, status_source: Callable[[], Dict],
                 host: str = "127.0.0.1", command_port: int = 10001, status_port: int = 10000,
                 period: float = STATUS_PERIOD, data_port: int = 10004,
                 arm: Optional[CycleSource] = None):
        self.handlers = handlers
        self.status_source = status_source
        self.host = host
        self.period = float(period)
        #: when each status packet goes out (its counters: packets that followed their cycle,
        #: packets the wall clock paced while no cycle ended)
        self.pacer = StatusPacer(arm, self.period)
        self._exec_lock = threading.Lock()     # one command at a time
        #: the status port's subscribers (their counters: :meth:`StatusSubscribers.stats`)
        self.subscribers = StatusSubscribers()
        self._commands = TcpServer(self._command_loop, host, command_port,
                                   name="emulator-commands")
        self._status = TcpServer(self.subscribers.add, host, status_port, threaded=False,
                                 name="emulator-status")
        self._data = TcpServer(self._data_loop, host, data_port, name="emulator-data")
        self._broadcaster: Optional[threading.Thread] = None
        self._quit = threading.Event()

    @property
    def command_port(self) -> int:
        return self._commands.port

    @property
    def status_port(self) -> int:
        return self._status.port

    @property
    def data_port(self) -> int:
        return self._data.port

    # ---- life cycle --------------------------------------------------------------------
    def start(self) -> None:
        started = []
        try:
            for server in (self._commands, self._status, self._data):
                started.append(server.start())
        except OSError:
            for server in started:
                server.stop()
            raise
        self._broadcaster = threading.Thread(target=self._broadcast, daemon=True,
                                             name="emulator-broadcast")
        self._broadcaster.start()

    def stop(self) -> None:
        """Close everything and join every thread. Idempotent."""
        self._quit.set()
        if self._broadcaster is not None:
            self._broadcaster.join(2.0)
        for server in (self._commands, self._status, self._data):
            server.stop()
        self.subscribers.close_all()

    def __enter__(self) -> "EmulatorServer":
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

    def drop_clients(self) -> None:
        """Close every client connection on both ports; the ports keep listening."""
        count = (self._commands.close_clients() + self._data.close_clients()
                 + self.subscribers.close_all())
        if count:
            log.warning("emulator: dropped %d client connection(s)", count)

    @property
    def client_count(self) -> Dict[str, int]:
        return {"command": self._commands.client_count + self._data.client_count,
                "status": len(self.subscribers)}

    # ---- the data_request port --------------------------------------------------------------
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

    # ---- command connections ---------------------------------------------------------------
    def _command_loop(self, conn: socket.socket) -> None:
        with self.handlers.network.connection():    # its end may be a network loss
            self._client_loop(conn, self._answer)

    def _client_loop(self, conn: socket.socket, answer) -> None:
        """Read requests from ``conn`` until it closes; ``answer(conn, request)`` replies to
        each and says whether the connection goes on (the TcpServer closes it after, and
        keeps a failure of it to this connection)."""
        splitter = RequestSplitter()
        last_data = time.monotonic()
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
    @realtime.runs_periodically
    def _broadcast(self) -> None:
        encoder = StatusEncoder()       # the unchanged arrays are encoded once
        pacer = self.pacer
        while pacer.wait(self._quit):
            if not len(self.subscribers):
                continue
            try:
                self.subscribers.push(encoder.encode(self.status_source()))
            except Exception:  # noqa: BLE001 - the stream must survive a bad sample
                log.exception("emulator: building the status packet failed")
