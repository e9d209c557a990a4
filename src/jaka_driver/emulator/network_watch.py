"""A controller's network-loss handling on the twin: ``set_network_exception_handle`` and what
it does when the client that sent it is gone (docs/protocol.md, "Network loss").

JAKA's SDK sends ``{"cmdName":"set_network_exception_handle","motType":2,"timeLimit":100.0}``:
when its connection has been lost ``timeLimit`` ms, the controller keeps (0), pauses (1) or
aborts (2) the motion under way. The evidence records the request and its reply
(``errorCode`` "0") only; how a controller decides that a connection is lost is not on record.
The emulator reads it as a client would expect it to:

* the setting is the controller's (the last one sent wins), and it watches the command
  connections that sent it;
* such a connection is *lost* when it ends — the peer closed it (a killed process: the kernel
  closes its sockets), reset it, or it was dropped (``emulator_drop_connections``) — and no
  other connection that sent the setting is still open (a second client that asked for the
  same handling, a driver's monitor beside it, still holds the link);
* if no new command connection arrives within the time limit (a client that comes back in
  time), the action applies to whatever moves then: queued moves and their queue, a jog, a
  servo stream (its ramp held where the setpoint is), a program.

The actions, on the twin's face only (:class:`~.twin_controller.TwinController`, the
contract): **abort** is ``stop_program`` (the program ends, the queue is emptied, the arm
decelerates to rest) and leaves servo mode; **pause** brings a planned move to rest on its own
path and keeps it there with the queue behind it (``stop_program`` ends it; no TCP command
outside programs resumes a move, none is on record), stops a jog, holds a servo stream where it
is (servo mode kept: a client that comes back may stream on), and pauses a program
(``resume_program`` resumes it); **keep** does nothing.

Time is the twin's clock (``backend.clock``): the wall clock in the emulator, whose twin paces
its 8 ms cycles to it; the action takes effect at the cycle after the limit has passed.
"""
from __future__ import annotations

import logging
import threading
from contextlib import contextmanager
from typing import Callable, Dict, Iterator, Mapping, Optional, Tuple

from ..protocol.fields import Cmd, Field
from ..protocol.network_loss import NetworkLossAction
from .replies import Answer
from .twin_controller import TwinController
from .wire_fields import integer, number

log = logging.getLogger(__name__)


class NetworkWatch:
    """``set_network_exception_handle`` on ``controller``, and the command connections it
    watches. The server runs each command connection inside :meth:`connection`; the handler
    (:meth:`table`) runs in that connection's thread."""

    def __init__(self, controller: TwinController):
        self.c = controller
        self._lock = threading.Lock()
        self._local = threading.local()       # .token: the connection this thread serves
        self._setting: Optional[Tuple[NetworkLossAction, float]] = None   # (action, s)
        self._watched: set = set()            # tokens of the connections that sent it
        self._pending: Optional[threading.Event] = None   # set: the loss no longer counts
        self._closed = False
        #: what happened at the last loss (a log line's text), for tests and the log
        self.last_action: Optional[str] = None

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        return {Cmd.SET_NETWORK_EXCEPTION_HANDLE: self._set_handle}

    @property
    def setting(self) -> Optional[Tuple[NetworkLossAction, float]]:
        """(action, time limit s), None until a client sent one."""
        return self._setting

    def _set_handle(self, req: Mapping) -> Answer:
        action = NetworkLossAction(integer(req, Field.MOT_TYPE, 0, len(NetworkLossAction) - 1))
        limit = number(req, Field.TIME_LIMIT, lo=0.0) / 1000.0
        with self._lock:
            self._setting = (action, limit)
            token = getattr(self._local, "token", None)
            if token is not None:
                self._watched.add(token)
        log.info("emulator: on network loss: %s the motion after %g ms", action.word,
                 limit * 1000.0)
        return Answer()

    @contextmanager
    def connection(self) -> Iterator[None]:
        """Serve one command connection inside this: its arrival cancels a pending loss (the
        client is back in time), its end is a loss if it sent the setting."""
        token = object()
        self._local.token = token
        with self._lock:
            if self._pending is not None:
                self._pending.set()
                self._pending = None
                log.info("emulator: a client connected within the network-loss time limit; "
                         "the motion goes on")
        try:
            yield
        finally:
            self._local.token = None
            self._ended(token)

    def close(self) -> None:
        """The emulator stops: connections that end from now on are not losses."""
        with self._lock:
            self._closed = True
            if self._pending is not None:
                self._pending.set()

    def _ended(self, token: object) -> None:
        with self._lock:
            if token not in self._watched:
                return
            self._watched.discard(token)
            if self._closed or self._setting is None or self._watched:
                return                        # another client that asked for it is still here
            action, limit = self._setting
            if self._pending is not None:     # one loss at a time: the earlier one counts
                return
            cancel = self._pending = threading.Event()
        threading.Thread(target=self._expire, args=(cancel, action, limit), daemon=True,
                         name="emulator-network-loss").start()

    def _expire(self, cancel: threading.Event, action: NetworkLossAction,
                limit: float) -> None:
        if self.c.backend.clock.wait(cancel, limit):
            return
        with self._lock:
            if cancel.is_set():
                return
            self._pending = None
        self.last_action = self.apply(action)
        log.warning("emulator: the client's connection has been lost %g ms: %s",
                    limit * 1000.0, self.last_action)

    def apply(self, action: NetworkLossAction) -> str:
        """Do ``action`` to the motion under way; what was done, in words."""
        c = self.c
        if action is NetworkLossAction.KEEP:
            return "the motion goes on (keep)"
        if action is NetworkLossAction.ABORT:
            c.stop()                          # program, queue, move, jog; servo held
            if c.state().servo_mode:
                c.set_servo_mode(False)
            return "motion aborted (abort)"
        if c.program_running():
            c.pause_program()
            return "program paused (pause)"
        with c.lock:
            if c.state().servo_mode:
                c.backend.stop_move()         # the servo target held where the setpoint is
                return "servo stream held (pause)"
            c.backend.jog_stop()              # a jog stops; a planned move pauses
            c.backend.pause_motion()
        return "motion paused on its path (pause)"
