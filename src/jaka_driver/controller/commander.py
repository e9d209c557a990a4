"""Requests to the controller, answered in the contract's terms.

:class:`Commander` sends one request over a :class:`~.connection.ControllerLink` and turns what
can go wrong into a :class:`~jaka_driver.common.results.CommandRefused` carrying the contract's code
(docs/interface.md, "Result codes"):

* link down, or lost during the call → -1 at once (nothing waits for a link that is not there);
* no reply within the call timeout, or a reply that is not a valid one → -3 (the link then
  reconnects, since without request ids a late reply could not be matched);
* a value the protocol cannot encode → -2;
* ``errorCode`` other than ``"0"`` → 2, with the controller's ``errorMsg``;
* a setting the controller acknowledged but does not report within :data:`SETTLE_TIMEOUT`
  (:meth:`Commander.settled`) → 2: it did not do it.

:func:`answers` turns such a refusal back into the method's :class:`~jaka_driver.common.Result`,
so backend methods never raise.
"""
from __future__ import annotations

import time
from typing import Any, Callable, Mapping, Optional, TypeVar

from ..common.results import Code, CommandRefused, Result, answers
from ..protocol import errors
from ..protocol.replies import Reply
from ..protocol.status_packet import StatusPacket
from .connection import ControllerLink
from .status_view import StatusView

T = TypeVar("T")

#: JAKA's SDK confirms a setting by reading it back every 100 ms for up to 1 s (and fails the
#: call otherwise); :meth:`Commander.settled` does the same.
SETTLE_POLL = 0.1       # s
SETTLE_TIMEOUT = 1.0    # s


class Commander:
    """Sends requests over ``link``; :meth:`confirmed` watches the packets of ``view``, at most
    ``confirm_timeout`` s."""

    #: s between two looks at the link while waiting for a packet (the packets wake the wait)
    LINK_CHECK = 0.1

    def __init__(self, link: ControllerLink, view: StatusView, confirm_timeout: float):
        self.link = link
        self.view = view
        self.confirm_timeout = float(confirm_timeout)

    def require_link(self) -> None:
        if not self.link.connected:
            raise CommandRefused(Code.NOT_CONNECTED, self.link.down_message())

    def call(self, request: Mapping[str, Any], timeout: Optional[float] = None) -> Reply:
        """The reply, which may be a rejection; protocol failures become refusals."""
        name = request.get("cmdName")
        try:
            return self.link.call(request, timeout)
        except errors.ConnectionLost as exc:   # NotConnected included
            raise CommandRefused(Code.NOT_CONNECTED, f"{name}: {exc}") from None
        except errors.TimeoutError:
            wait = timeout or self.link.call_timeout
            raise CommandRefused(Code.COMMUNICATION_ERROR, f"{name}: no reply from the "
                                 f"controller within {wait:.2f} s; reconnecting") from None
        except errors.InvalidArgument as exc:
            raise CommandRefused(Code.INVALID_PARAMETER, f"{name}: {exc}") from None
        except errors.JakaProtocolError as exc:
            raise CommandRefused(Code.COMMUNICATION_ERROR, f"{name}: {exc}") from None

    def accepted(self, request: Mapping[str, Any], timeout: Optional[float] = None) -> Reply:
        """:meth:`call`, and a rejection becomes a refusal with code 2."""
        reply = self.call(request, timeout)
        if not reply.ok:
            text = reply.error_msg or f"errorCode {reply.error_code}"
            raise CommandRefused(Code.CONTROLLER_REJECTED,
                                 f"controller rejected {request.get('cmdName')}: {text}")
        return reply

    def read(self, request: Mapping[str, Any], accessor: Callable[[Reply], T]) -> T:
        """An accepted reply's value through ``accessor`` (a ``commands.reply_*``); a reply
        without the expected field is a communication error (-3)."""
        return self.parse(self.accepted(request), accessor)

    @staticmethod
    def parse(reply: Reply, accessor: Callable[[Reply], T]) -> T:
        """``accessor(reply)``; a reply without the expected field is a refusal (-3)."""
        try:
            return accessor(reply)
        except errors.ProtocolError as exc:
            raise CommandRefused(Code.COMMUNICATION_ERROR, str(exc)) from None

    def settled(self, request: Mapping[str, Any], readback: Mapping[str, Any],
                accessor: Callable[[Reply], T], done: Callable[[T], bool], what: str) -> T:
        """Send the setting ``request``, then read ``readback`` through ``accessor`` at once and
        every :data:`SETTLE_POLL` s until ``done(value)``, at most :data:`SETTLE_TIMEOUT` s —
        as JAKA's SDK confirms drag mode, servo mode, tool and user ids and IO. Returns the value
        read; a controller that acknowledges but never reports the setting is refused with 2
        (it did not do it: fw 1.5.14 acknowledges servo_move while moves are queued and stays
        out of servo mode)."""
        self.accepted(request)
        deadline = time.monotonic() + SETTLE_TIMEOUT
        while True:
            value = self.read(readback, accessor)
            if done(value):
                return value
            if time.monotonic() >= deadline:
                raise CommandRefused(
                    Code.CONTROLLER_REJECTED,
                    f"{what}: the controller acknowledged {request.get('cmdName')} but "
                    f"{readback.get('cmdName')} still reads {value!r} after "
                    f"{SETTLE_TIMEOUT:g} s")
            time.sleep(SETTLE_POLL)

    def confirmed(self, request: Mapping[str, Any], arrived: Callable[[StatusPacket], bool],
                  what: str) -> None:
        """Send ``request`` and wait until a status packet satisfies ``arrived`` (power and
        enable: the reply says accepted, the stream says done)."""
        self.accepted(request, timeout=self.confirm_timeout)
        deadline = time.monotonic() + self.confirm_timeout
        while True:
            left = deadline - time.monotonic()
            if self.view.wait_until(arrived, max(0.0, min(left, self.LINK_CHECK))):
                return
            self.require_link()
            if left <= 0:
                break
        raise CommandRefused(Code.COMMUNICATION_ERROR, f"{what}: the controller accepted it but "
                             f"the status stream did not show it within "
                             f"{self.confirm_timeout:g} s")
