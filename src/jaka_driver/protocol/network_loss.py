"""What the controller does with the motion under way when its client's connection is lost:
``set_network_exception_handle``, as JAKA's SDK 2.1.14 writes it (docs/protocol.md, "Network
loss").

``{"cmdName":"set_network_exception_handle","motType":2,"timeLimit":100.0}``: ``motType`` is
the action (:class:`NetworkLossAction`: keep 0, pause 1, abort 2), ``timeLimit`` how long the
connection must have been lost first, in **ms**. The reply carries only ``errorCode`` (a
string, "0" accepted); nothing reads the setting back.
"""
from __future__ import annotations

from enum import IntEnum

from .errors import InvalidArgument
from .fields import Cmd, Field
from .request_values import Request, command as _cmd, number as _number


class NetworkLossAction(IntEnum):
    """``motType``: the SDK's MOT_KEEP, MOT_PAUSE, MOT_ABORT."""
    KEEP = 0      # the motion goes on to its end
    PAUSE = 1     # the motion is brought to rest and held
    ABORT = 2     # the motion is stopped and ended

    @property
    def word(self) -> str:
        """``keep``, ``pause`` or ``abort`` (the driver's parameter values)."""
        return self.name.lower()

    @classmethod
    def named(cls, word: str) -> "NetworkLossAction":
        """The action called ``word`` (``keep``, ``pause``, ``abort``, any case)."""
        try:
            return cls[str(word).strip().upper()]
        except KeyError:
            raise InvalidArgument(f"network loss action {word!r}; expected one of "
                                  f"{', '.join(a.word for a in cls)}") from None


def set_network_exception_handle(time_limit_ms: float, action: NetworkLossAction) -> Request:
    """After the connection has been lost ``time_limit_ms`` (ms, ≥ 0), ``action``."""
    try:
        action = NetworkLossAction(action)
    except ValueError:
        raise InvalidArgument(f"network loss action {action!r}; expected 0 keep, 1 pause or "
                              "2 abort") from None
    return _cmd(Cmd.SET_NETWORK_EXCEPTION_HANDLE,
                **{Field.MOT_TYPE: int(action),
                   Field.TIME_LIMIT: _number(time_limit_ms, "network loss time limit (ms)",
                                             lo=0.0)})
