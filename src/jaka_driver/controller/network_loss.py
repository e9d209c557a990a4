"""What the controller does with the motion under way when this driver's connection is lost:
``set_network_exception_handle``, sent at every connection (docs/protocol.md, "Network loss").

A real arm must not carry on when the PC that drives it crashes mid-stream: by default the
controller is told to abort the motion once the connection has been lost 100 ms. The setting
lives in the controller and outlasts the connection it came on, so it is sent again at each
reconnect (another client may have changed it meanwhile). A controller that refuses it (older
firmware) is logged as a warning and stays in the backend's ``describe()`` (``/diagnostics``):
the arm then does whatever the controller was set to do before.
"""
from __future__ import annotations

import logging
import math

from ..common.results import CommandRefused
from ..protocol.network_loss import NetworkLossAction, set_network_exception_handle
from .commander import Commander

log = logging.getLogger(__name__)

DEFAULT_ACTION = "abort"
DEFAULT_TIME_LIMIT = 0.1   # s


class NetworkLossHandling:
    """``action`` (``keep``, ``pause``, ``abort``) after the connection has been lost
    ``time_limit`` s. Raises ``ValueError`` for an unknown action or a time limit that is not
    a finite number ≥ 0."""

    def __init__(self, action: str = DEFAULT_ACTION, time_limit: float = DEFAULT_TIME_LIMIT):
        try:
            self.action = NetworkLossAction.named(action)
        except Exception as exc:   # InvalidArgument: the parameter's own error
            raise ValueError(str(exc)) from None
        self.time_limit = float(time_limit)
        if not (math.isfinite(self.time_limit) and self.time_limit >= 0.0):
            raise ValueError(f"network loss time limit {time_limit!r} s; expected a time "
                             "≥ 0 s")
        #: what the controller answered the last time it was told (diagnostics)
        self.outcome = "not sent yet"

    @property
    def setting(self) -> str:
        """``abort the motion 100 ms after the connection is lost``."""
        return (f"{self.action.word} the motion {self.time_limit * 1000:g} ms after the "
                "connection is lost")

    def send_to(self, send: Commander) -> bool:
        """Tell the controller (at a connection); True if it accepted. Never raises."""
        request = set_network_exception_handle(self.time_limit * 1000.0, self.action)
        try:
            send.accepted(request)
        except CommandRefused as refusal:
            self.outcome = f"refused: {refusal.message}"
            log.warning("the controller refused set_network_exception_handle (%s): %s; on a "
                        "lost connection it does what it was set to before", self.setting,
                        refusal.message)
            return False
        self.outcome = "accepted"
        log.info("on network loss the controller will %s", self.setting)
        return True

    def describe(self) -> dict:
        return {"network loss": f"{self.setting} ({self.outcome})"}
