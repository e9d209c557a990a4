"""The link to one JAKA controller: both TCP connections, kept up by a supervisor thread.

A :class:`ControllerLink` owns a :class:`~jaka_driver.protocol.CommandClient` (port 10001) and
the status connection(s) chosen by ``status_source`` (docs/protocol.md, "Status packet"):

* ``"stream"`` (default): :class:`~jaka_driver.protocol.StatusReceiver` on port 10000, the packet
  a controller pushes every 8 ms unasked — no request per sample, and what third-party clients
  read. A real controller serves both ports; the stream costs the controller and the network
  least, so it is the default;
* ``"request"``: :class:`~jaka_driver.protocol.StatusPoller` on port 10004, one ``data_request``
  per 8 ms, as JAKA's SDK reads status (for a network where only the SDK's ports are open);
* ``"both"``: both at once; every packet of either feeds the driver (a check that the two
  agree, and status survives on one port while the other stalls until the stall is noticed).

It treats them as one thing: the link is *up* when all are open and a first status packet has
arrived, and *down* as soon as any of them fails (peer closed, socket error, a call timed out, or no status packet for
``stall_timeout`` s). Going down closes both, so the two never disagree about the controller.

Policy (docs/design.md, "Reconnect"):

* While down, :meth:`call` raises :class:`NotConnected` at once: a service never waits for a
  link that is not there.
* The supervisor retries with exponential backoff, 0.5 s doubling to 10 s. A *refused*
  connection means the controller host is up and its server is (re)starting; those retries are
  capped at :data:`REFUSED_RETRY_MAX` so the link is back within a few seconds of the server
  returning, while an unreachable host (SYNs into the void, each costing a connect timeout)
  backs off all the way.
* Nothing is resent after a reconnect: the link carries only what callers send from then on.
* Each change of state is logged once (``logging``; the node routes it to rosout).

Threads: the supervisor thread connects and reconnects; the status receiver's thread delivers
packets to ``on_status``; any thread may :meth:`call`.
"""
from __future__ import annotations

import logging
import threading
import time
from typing import Any, Callable, Mapping, Optional, Tuple

from ..host import realtime
from ..protocol import CommandClient, StatusPoller, StatusReceiver, errors
from ..protocol.fields import STATUS_REQUEST_PORT
from ..protocol.replies import Reply
from ..protocol.status_packet import StatusPacket

log = logging.getLogger(__name__)

STATUS_SOURCES = ("stream", "request", "both")

BACKOFF_START = 0.5      # s, first retry interval after a failed attempt
BACKOFF_MAX = 10.0       # s, the interval doubles up to this
REFUSED_RETRY_MAX = 2.0  # s, retry interval cap while the host refuses (its server restarts)


class NotConnected(errors.ConnectionLost):
    """The link is down; nothing was sent."""


StatusHook = Callable[[StatusPacket, float], None]


class ControllerLink:
    """Both connections to the controller at ``host``, and the reconnect supervisor.

    ``on_status(status, received)`` gets every status packet (receiver thread; ``received`` is
    ``time.time()`` at the read); the link keeps none of them: the hook's owner keeps the
    latest (the controller backend's :class:`~.status_view.StatusView`). ``on_up(first)`` runs in the supervisor thread each time the
    link comes up (``first`` True the first time); ``on_down(reason)`` runs once per loss, in
    whichever thread noticed it. Hooks must not block for long; exceptions are logged.

    Timeouts, s: ``connect_timeout`` per TCP connect, ``call_timeout`` default wait for a reply,
    ``stall_timeout`` silence on the status port that counts as a lost link,
    ``first_packet_timeout`` wait for the first status packet of a new connection.
    """

    def __init__(self, host: str, command_port: int, status_port: int, *,
                 status_source: str = "stream", data_port: int = STATUS_REQUEST_PORT,
                 connect_timeout: float = 1.0, call_timeout: float = 1.0,
                 stall_timeout: float = 0.5, first_packet_timeout: float = 1.0,
                 on_status: Optional[StatusHook] = None,
                 on_up: Optional[Callable[[bool], None]] = None,
                 on_down: Optional[Callable[[str], None]] = None):
        self.host = host
        self.command_port = int(command_port)
        self.status_port = int(status_port)
        if status_source not in STATUS_SOURCES:
            raise ValueError(f"status_source must be one of {STATUS_SOURCES}; got "
                             f"{status_source!r}")
        self.status_source = status_source
        self.data_port = int(data_port)
        self.connect_timeout = float(connect_timeout)
        self.call_timeout = float(call_timeout)
        self.stall_timeout = float(stall_timeout)
        self.first_packet_timeout = float(first_packet_timeout)
        self._on_status = on_status
        self._on_up = on_up
        self._on_down = on_down
        self._lock = threading.Lock()
        self._client: Optional[CommandClient] = None
        self._receivers: Tuple[StatusReceiver, ...] = ()
        self._generation = 0          # bumps on every new connection; stale callbacks see it
        self._up = threading.Event()
        self._wake = threading.Event()  # tells the supervisor a link went down (or to quit)
        self._quit = threading.Event()
        self._thread: Optional[threading.Thread] = None
        self._first_packet = threading.Event()
        self._attempted = threading.Event()   # the first connection attempt has ended
        self._ever_up = False
        self.down_since: Optional[float] = time.monotonic()
        self.down_reason = "not connected yet"
        self.next_attempt: Optional[float] = None   # monotonic time of the next retry
        self.reconnects = 0
        self._closed_counts: dict = {}   # counters of the connections closed so far

    # ---- facts -------------------------------------------------------------------------
    @property
    def address(self) -> str:
        return f"{self.host}:{self.command_port}/{self.status_port}"

    @property
    def connected(self) -> bool:
        return self._up.is_set()

    def counters(self) -> dict:
        """What the connections received and dropped, added up over every connection since
        :meth:`start` (diagnostics): replies on the command port; packets, dropped bytes,
        dropped packets and dropped (malformed) fields per status port; messages whose text
        had invalid UTF-8 repaired."""
        with self._lock:
            totals = dict(self._closed_counts)
            for name, value in self._counts_of(self._client, self._receivers).items():
                totals[name] = totals.get(name, 0) + value
        return totals

    def _counts_of(self, client, receivers) -> dict:
        counts: dict = {}
        if client is not None:
            counts.update({"command replies": client.replies,
                           "command replies dropped": client.replies_dropped,
                           "command replies repaired": client.text_repaired})
        for receiver in receivers:
            d = receiver.decoder
            port = f"status port {receiver.port}"
            counts.update({f"{port} packets": d.packets,
                           f"{port} bytes dropped": d.bytes_dropped,
                           f"{port} packets dropped": d.packets_dropped,
                           f"{port} fields dropped": d.fields_dropped,
                           f"{port} packets repaired": d.text_repaired})
        return counts

    def down_message(self) -> str:
        """Why a request cannot be sent now, for a -1 answer."""
        retry = ""
        if self.next_attempt is not None:
            retry = f"; next attempt in {max(0.0, self.next_attempt - time.monotonic()):.1f} s"
        return (f"not connected to the controller at {self.host} ({self.down_reason}); "
                f"reconnecting by itself{retry}")

    # ---- life cycle ----------------------------------------------------------------------
    def start(self, wait: float) -> bool:
        """Start the supervisor; return whether its first attempt brought the link up (waits
        for that attempt, at most ``wait`` s)."""
        if self._thread is None:
            self._quit.clear()
            self._thread = threading.Thread(target=self._supervise, daemon=True,
                                            name=f"jaka-link-{self.host}")
            self._thread.start()
        self._attempted.wait(wait)
        return self._up.is_set()

    def stop(self) -> None:
        """Close both connections and end the supervisor. Idempotent; no ``on_down``."""
        self._quit.set()
        self._wake.set()
        thread, self._thread = self._thread, None
        self._close_connections()
        if thread is not None and thread is not threading.current_thread():
            thread.join(self.connect_timeout + self.first_packet_timeout + 2.0)

    # ---- requests ---------------------------------------------------------------------------
    def call(self, request: Mapping[str, Any], timeout: Optional[float] = None) -> Reply:
        """Send one request and return its reply (which may be a rejection).

        Raises :class:`NotConnected` (nothing sent), :class:`~jaka_driver.protocol.errors.
        ConnectionLost` or ``TimeoutError`` (the link is then down and reconnecting),
        :class:`~jaka_driver.protocol.errors.ProtocolError`, or ``InvalidArgument``.
        """
        with self._lock:
            client, generation = self._client, self._generation
        if client is None or not self._up.is_set():
            raise NotConnected(self.down_message())
        try:
            return client.call(request, timeout)
        except errors.TimeoutError:
            self.lost(f"no reply to {request.get('cmdName')!r} within "
                      f"{timeout or self.call_timeout:.2f} s", generation)
            raise
        except errors.ConnectionLost as exc:
            self.lost(str(exc), generation)
            raise
        except errors.ProtocolError as exc:
            if not client.connected:   # the client closed a connection it could not trust
                self.lost(str(exc), generation)
            raise

    def lost(self, reason: str, generation: Optional[int] = None) -> None:
        """Declare the link down (from any thread). A report about an older connection than
        the current one is ignored."""
        with self._lock:
            if generation is not None and generation != self._generation:
                return
            if not self._up.is_set():
                return
            self._up.clear()
            self.down_since = time.monotonic()
            self.down_reason = reason
        log.warning("connection to the JAKA controller at %s lost: %s; reconnecting "
                    "(backoff %.1f s doubling to %.0f s)", self.host, reason, BACKOFF_START,
                    BACKOFF_MAX)
        self._close_connections()
        self._hook(self._on_down, reason)
        self._wake.set()

    # ---- internals ----------------------------------------------------------------------------
    def _hook(self, hook, *args) -> None:
        if hook is None:
            return
        try:
            hook(*args)
        except Exception:  # noqa: BLE001 - a hook must not kill the link
            log.exception("controller link hook %s failed", getattr(hook, "__name__", hook))

    def _close_connections(self) -> None:
        with self._lock:
            client, receivers = self._client, self._receivers
            self._client, self._receivers = None, ()
            for name, value in self._counts_of(client, receivers).items():
                self._closed_counts[name] = self._closed_counts.get(name, 0) + value
        for receiver in receivers:
            receiver.stop()
        if client is not None:
            client.close()

    def _supervise(self) -> None:
        interval = BACKOFF_START
        failures = 0
        while not self._quit.is_set():
            if self._up.is_set():
                self._wake.wait()
                self._wake.clear()
                interval, failures = BACKOFF_START, 0
                # The first retry waits too: a controller that just closed on us (restarting,
                # or handing the port to another client) is not hammered at once.
                self.next_attempt = time.monotonic() + interval
                if self._quit.wait(interval):
                    break
                interval = min(interval * 2.0, BACKOFF_MAX)
                continue
            try:
                self._connect()
            except (errors.JakaProtocolError, OSError) as exc:
                self._close_connections()
                self._attempted.set()
                failures += 1
                refused = isinstance(exc.__context__, ConnectionRefusedError)
                delay = min(interval, REFUSED_RETRY_MAX) if refused else interval
                if failures == 1 and not self._ever_up:   # after a loss, "lost" said it
                    log.warning("cannot connect to the JAKA controller at %s: %s; retrying in "
                                "the background", self.address, exc)
                else:
                    log.debug("reconnect attempt %d to %s failed: %s", failures, self.address,
                              exc)
                self.next_attempt = time.monotonic() + delay
                if self._quit.wait(delay):
                    break
                interval = min(interval * 2.0, BACKOFF_MAX)
                continue
            self.next_attempt = None
            self._attempted.set()
            first = not self._ever_up
            self._ever_up = True
            if not first:
                self.reconnects += 1
                log.warning("reconnected to the JAKA controller at %s after %.1f s; no motion "
                            "was resumed", self.address, time.monotonic() - self.down_since)
            else:
                log.info("connected to the JAKA controller at %s", self.address)
            self._hook(self._on_up, first)

    def _connect(self) -> None:
        """Open both connections and wait for a first status packet; raises on failure."""
        with self._lock:
            self._generation += 1
            generation = self._generation
        client = CommandClient(self.host, self.command_port, timeout=self.call_timeout,
                               connect_timeout=self.connect_timeout)
        hooks = dict(
            on_status=lambda status, received: self._status(status, received, generation),
            on_connection_lost=lambda reason: self.lost(reason, generation),
            connect_timeout=self.connect_timeout, stall_timeout=self.stall_timeout,
            thread_context=realtime.periodic_thread)
        receivers = []
        if self.status_source in ("stream", "both"):
            receivers.append(StatusReceiver(self.host, self.status_port, **hooks))
        if self.status_source in ("request", "both"):
            receivers.append(StatusPoller(self.host, self.data_port, **hooks))
        with self._lock:
            self._client, self._receivers = client, tuple(receivers)
        self._first_packet.clear()
        client.connect()
        for receiver in receivers:
            receiver.start()
        if not self._first_packet.wait(self.first_packet_timeout):
            ports = " and ".join(str(r.port) for r in receivers)
            raise errors.ConnectFailed(
                f"the status port {self.host}:{ports} accepted the connection but sent no "
                f"status packet within {self.first_packet_timeout:.1f} s")
        with self._lock:
            if (generation != self._generation or self._client is not client
                    or not all(r.running for r in receivers) or not client.connected):
                raise errors.ConnectionLost("the new connection was lost while starting")
            self._up.set()

    def _status(self, status: StatusPacket, received: float, generation: int) -> None:
        if generation != self._generation:
            return
        self._first_packet.set()
        self._hook(self._on_status, status, received)
