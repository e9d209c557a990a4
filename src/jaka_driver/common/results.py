"""Result codes and the one library exception of jaka_driver.

Every service of the driver answers with a code and a message (docs/interface.md, "Result codes"):
``1`` success, ``<= 0`` failure with nothing moved or changed (or the motion stopped, for -12),
``2`` the controller rejected the command. The codes follow the JAKA SDK error table.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from enum import IntEnum
from typing import Any, Callable


class Code(IntEnum):
    """Result codes of the JAKA SDK table, as the driver's services return them in ``ret``."""

    OK = 1
    NOT_CONNECTED = -1
    INVALID_PARAMETER = -2
    COMMUNICATION_ERROR = -3
    IK_FAILED = -4
    EMERGENCY_STOP = -5
    NOT_POWERED = -6
    NOT_ENABLED = -7
    SERVO_MODE_OFF = -8
    WRONG_MODE = -9
    BUSY = -10
    MOTION_STOPPED = -12
    CONTROLLER_REJECTED = 2


@dataclass(frozen=True)
class Result:
    """What a command did: ``code`` (a :class:`Code` value), a human ``message`` in the
    caller's units, and for queries a ``value`` (a pose, joint vector or IO value)."""

    code: int
    message: str
    value: Any = None

    @property
    def ok(self) -> bool:
        return self.code == Code.OK

    @classmethod
    def success(cls, message: str, value: Any = None) -> "Result":
        return cls(int(Code.OK), message, value)

    @classmethod
    def failure(cls, code: int, message: str) -> "Result":
        return cls(int(code), message)


class CommandRefused(Exception):
    """Raised inside the driver when a request cannot be carried out; the door catches it and
    answers ``Result(code, message)``. The message names the field, the value and the limit."""

    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = int(code)
        self.message = message

    def result(self) -> Result:
        return Result.failure(self.code, self.message)


def invalid(message: str) -> CommandRefused:
    """Shorthand for the commonest refusal, -2 invalid parameter."""
    return CommandRefused(Code.INVALID_PARAMETER, message)


def answers(method: Callable) -> Callable:
    """A refusal raised inside ``method`` becomes its Result."""
    @functools.wraps(method)
    def wrapper(*args, **kwargs) -> Result:
        try:
            return method(*args, **kwargs)
        except CommandRefused as refusal:
            return refusal.result()
    return wrapper
