"""The JAKA controller TCP/JSON protocol, without ROS.

The library depends on nothing else in ``jaka_driver`` and speaks the units of JAKA's SDK: joints
rad, Cartesian poses ``[x, y, z mm, rx, ry, rz rad]``, IO indices 0-based; the wire's degrees and
1-based IO indices stay inside it. docs/protocol.md describes the protocol it implements.

* :mod:`.units` — deg⇄rad, wire pose (mm, RPY deg) ⇄ API pose (mm, RPY rad).
* :mod:`.fields` — every name on the wire, and the command table with confidence levels.
* :mod:`.commands` — request encoders (driver units in, wire dicts out).
* :mod:`.replies` — reply decoding and typed accessors (re-exported by :mod:`.commands`).
* :mod:`.request_values` / :mod:`.reply_values` — the encoders' and the accessors' toolkit: a
  request's values checked and put together, a reply's fields read as JAKA's SDK reads them.
* :mod:`.torque_sensor` — the torque sensor and force control: requests as JAKA's SDK sends
  them, its replies, and the status packet's ``torqsensor``.
* :mod:`.tool_io` — the tool connector (TIO): JAKA's twelve requests as its SDK sends them,
  their replies, and the status packet's ``tio_rs_signals`` rows.
* :mod:`.wire` — the JSON layouts (compact requests, spaced controller output) and decoding.
* status packets: :mod:`.status_stream` — the port-10000 stream's framing (bytes → packets);
  :mod:`.status_packet` — :class:`StatusPacket` and :func:`parse_status` (a packet's fields in
  the SDK's units); :mod:`.status_encoder` — packets written as a controller writes them (the
  emulator's side); :mod:`.data_reply` — port 10004's zlib reply to ``data_request``.
* :mod:`.command_client` — :class:`CommandClient` (port 10001); :mod:`.status_client` —
  :class:`StatusReceiver` (port 10000) and :class:`StatusPoller` (port 10004); both connect
  with :mod:`.connect`.
* :mod:`.errors` — the :class:`JakaProtocolError` family.
* :mod:`.tcp_server` — :class:`TcpServer`, the other end: listening, accepting and serving
  connections for whoever plays the controller (the emulator, the tests' fakes).

Typical use::

    from jaka_driver.protocol import CommandClient, commands

    with CommandClient("10.5.5.100") as client:
        reply = client.call(commands.get_joint_pos())
        q = commands.reply_joint_pos(reply)          # rad
"""
from . import commands, fields, replies, tool_io, torque_sensor, units
from .command_client import CommandClient
from .commands import encode
from .errors import (CommandRejected, ConnectFailed, ConnectionLost, InvalidArgument,
                     JakaProtocolError, ProtocolError, TimeoutError)
from .fields import (COMMAND_PORT, COMMANDS, STATUS_PORT, STATUS_REQUEST_PORT, Cmd, Field,
                     StatusField)
from .replies import Reply, parse_reply
from .status_client import StatusPoller, StatusReceiver
from .data_reply import decode_data_reply, encode_data_reply
from .status_encoder import encode_status
from .status_packet import StatusPacket, parse_status
from .status_stream import StatusStreamDecoder
from .tcp_server import TcpServer

__all__ = [
    "commands", "fields", "replies", "tool_io", "torque_sensor", "units",
    "CommandClient", "StatusReceiver", "StatusPoller",
    "Reply", "encode", "parse_reply",
    "JakaProtocolError", "ProtocolError", "ConnectFailed", "ConnectionLost", "TimeoutError",
    "InvalidArgument", "CommandRejected",
    "COMMAND_PORT", "STATUS_PORT", "STATUS_REQUEST_PORT", "COMMANDS", "Cmd", "Field",
    "StatusField", "StatusPacket", "StatusStreamDecoder", "encode_status", "parse_status",
    "encode_data_reply", "decode_data_reply", "TcpServer",
]
