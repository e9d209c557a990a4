"""The one exception family of the protocol library.

Everything the library raises on purpose derives from :class:`JakaProtocolError`, so a caller can
catch the whole family in one place and map it to a result code (docs/interface.md, "Result codes": -1 not connected,
-3 communication error or timeout). The subclasses also derive from the matching built-in
exception (``ConnectionError``, ``TimeoutError``, ``ValueError``) so generic handlers work too.

Messages say what happened and what to do about it.
"""
from __future__ import annotations

import builtins


class JakaProtocolError(Exception):
    """Base class of every error the protocol library raises."""


class ProtocolError(JakaProtocolError):
    """The controller sent something that is not a valid reply (not JSON, not an object, no
    ``errorCode``, a reply to another command, a field of the wrong type)."""


class MalformedInput(ProtocolError):
    """Bytes that can never become a valid message: not JSON (a ``NaN`` literal, an integer too
    long to convert, invalid UTF-8 outside a string, brackets that do not match), nested deeper
    than any real one, or longer than any real one without an end. The reader drops them and
    counts the drop; framing may be lost with them."""


class ConnectFailed(JakaProtocolError, builtins.ConnectionError):
    """The TCP connection to the controller could not be opened (refused, unreachable, timed
    out)."""


class ConnectionLost(JakaProtocolError, builtins.ConnectionError):
    """The connection is not open: it was closed by the peer, broke, or was never opened."""


class TimeoutError(JakaProtocolError, builtins.TimeoutError):  # noqa: A001 - the brief's name
    """No complete reply arrived in time. The connection has been closed, because without
    request ids a late reply could not be told apart from the next one."""


class InvalidArgument(JakaProtocolError, builtins.ValueError):
    """A command was asked for with a value that cannot be encoded (wrong length, not finite,
    out of the protocol's range). Nothing was sent."""


class CommandRejected(JakaProtocolError):
    """A typed reply accessor was used on a reply whose ``errorCode`` is not ``"0"``.

    ``reply`` keeps the controller's answer (``error_code``, ``error_msg``)."""

    def __init__(self, reply):
        super().__init__(
            f"controller rejected '{reply.cmd_name}': errorCode {reply.error_code!r}, "
            f"errorMsg {reply.error_msg!r}")
        self.reply = reply
