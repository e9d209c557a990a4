"""The ``~joint_command`` topic's message read from its bytes: a ``trajectory_msgs/
JointTrajectory`` reduced to what a servo target needs — the joint names and the first point's
positions (rad) — and checked as the topic's rules say.

rospy builds a full JointTrajectory per message: a Header with its Time, six decoded strings,
a JointTrajectoryPoint per point with four float tuples and a Duration. At 125 Hz that was the
topic's one cost above the servo_j service's (11 µs a message, measured in the node beside the
handler's own). :class:`TrajectoryTarget` has the same type and MD5 sum, so every publisher of
JointTrajectory connects unchanged; it unpacks the names as bytes and the first point's
positions, and skips the rest. A list of names it has checked once is kept (as bytes) with the
order it maps to, so a stream of the same names is one lookup a message.
"""
from __future__ import annotations

import struct
from typing import Sequence

import genpy
from trajectory_msgs.msg import JointTrajectory

from ..common.results import Code, Result

_U32 = struct.Struct("<I")
_HEADER_FIXED = 12          # seq, stamp.secs, stamp.nsecs: 3 × uint32
_KNOWN_NAME_LISTS = 16      # distinct name orders remembered (a client sends one)


class TrajectoryTarget(genpy.Message):
    """A JointTrajectory as the joint stream reads it (``rospy.Subscriber`` data class):
    ``names`` (bytes, as sent), ``point_count`` and ``first_positions`` (rad, as sent; empty
    without a point). A message too short for what it says it holds raises
    :class:`genpy.DeserializationError`, as the generated class does."""

    __slots__ = ("names", "point_count", "first_positions")
    _type = JointTrajectory._type
    _md5sum = JointTrajectory._md5sum
    _full_text = JointTrajectory._full_text
    _has_header = JointTrajectory._has_header
    _slot_types: list = []

    def __init__(self):
        self.names: tuple = ()
        self.point_count = 0
        self.first_positions: tuple = ()

    def deserialize(self, data: bytes) -> "TrajectoryTarget":
        try:
            end = _HEADER_FIXED
            (length,) = _U32.unpack_from(data, end)
            end += 4 + length                           # header.frame_id
            (count,) = _U32.unpack_from(data, end)
            end += 4
            names = []
            for _ in range(count):
                (length,) = _U32.unpack_from(data, end)
                end += 4
                names.append(data[end:end + length])
                end += length
            (self.point_count,) = _U32.unpack_from(data, end)
            end += 4
            if self.point_count:
                (length,) = _U32.unpack_from(data, end)
                self.first_positions = struct.unpack_from(f"<{length}d", data, end + 4)
        except struct.error as exc:
            raise genpy.DeserializationError(exc) from exc
        self.names = tuple(names)
        return self

    def serialize(self, buff) -> None:
        raise NotImplementedError("TrajectoryTarget only reads: publish a JointTrajectory")


class TrajectoryReader:
    """The six positions (rad, the model's order) of :class:`TrajectoryTarget` messages for
    ``joint_names`` (the model's)."""

    def __init__(self, joint_names: Sequence[str]):
        self._joint_names = list(joint_names)
        self._sorted = sorted(self._joint_names)
        #: names as sent (bytes) → for each model joint, its index in the message
        self._orders: dict[tuple, list[int]] = {}

    def positions(self, msg: TrajectoryTarget) -> "list | Result":
        """The positions, or the refusal naming the field, the value and the limit."""
        if msg.point_count != 1:
            return Result.failure(Code.INVALID_PARAMETER, f"points has {msg.point_count} "
                                  "points, expected 1 (one servo target per message)")
        order = self._orders.get(msg.names)
        if order is None:
            names = [n.decode("utf-8", "replace") for n in msg.names]
            if sorted(names) != self._sorted:
                return Result.failure(Code.INVALID_PARAMETER, f"joint_names is {names}, "
                                      f"expected the six joints {self._joint_names} in any "
                                      "order")
            order = [names.index(name) for name in self._joint_names]
            if len(self._orders) < _KNOWN_NAME_LISTS:
                self._orders[msg.names] = order
        positions = msg.first_positions
        if len(positions) != len(order):
            return Result.failure(Code.INVALID_PARAMETER, f"points[0].positions has "
                                  f"{len(positions)} values, expected {len(order)}")
        return [positions[i] for i in order]
