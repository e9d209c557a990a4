"""The JAKA controller TCP/JSON protocol, without ROS.

* :mod:`.units` — deg⇄rad, wire pose (mm, RPY deg) ⇄ driver pose (mm, rotation vector rad).
* :mod:`.fields` — every name on the wire, and the command table with confidence levels.
* :mod:`.commands` — request encoders (driver units in, wire dicts out).
* :mod:`.replies` — reply decoding and typed accessors (re-exported by :mod:`.commands`).
* :mod:`.status_stream` — port-10000 stream decoder/encoder and :class:`RobotStatus`.
* :mod:`.client` — :class:`CommandClient` (port 10001) and :class:`StatusReceiver` (port 10000).
* :mod:`.errors` — the :class:`JakaProtocolError` family.

Typical use::

    from jaka_driver.protocol import CommandClient, commands

    with CommandClient("10.5.5.100") as client:
        reply = client.call(commands.get_joint_pos())
        q = commands.reply_joint_pos(reply)          # rad
"""
from . import commands, fields, replies, units
from .client import CommandClient, StatusReceiver
from .commands import encode
from .errors import (CommandRejected, ConnectFailed, ConnectionLost, InvalidArgument,
                     JakaProtocolError, ProtocolError, TimeoutError)
from .fields import COMMAND_PORT, COMMANDS, STATUS_PORT, Cmd, Field, StatusField
from .replies import Reply, parse_reply
from .status_stream import RobotStatus, StatusStreamDecoder, encode_status, parse_status

__all__ = [
    "commands", "fields", "replies", "units",
    "CommandClient", "StatusReceiver",
    "Reply", "encode", "parse_reply",
    "JakaProtocolError", "ProtocolError", "ConnectFailed", "ConnectionLost", "TimeoutError",
    "InvalidArgument", "CommandRejected",
    "COMMAND_PORT", "STATUS_PORT", "COMMANDS", "Cmd", "Field", "StatusField",
    "RobotStatus", "StatusStreamDecoder", "encode_status", "parse_status",
]
