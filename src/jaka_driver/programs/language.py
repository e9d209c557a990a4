"""A program as the runner executes it: statements with the line they came from, numeric
expressions over user variables, and the variables a program declares. The text format is
docs/programs.md's; :mod:`.parser` reads it into these.

Units are the driver's interface's: joints rad, rad/s, rad/s²; poses mm + rotation vector
(rad) in the active user frame, mm/s, mm/s²; time s; analog IO V.
"""
from __future__ import annotations

import math
import operator
from dataclasses import dataclass
from typing import Callable, Mapping, Optional, Tuple, Union


class ProgramError(Exception):
    """A program that cannot be read: where (1-based ``line`` and ``column``) and what was
    expected there."""

    def __init__(self, line: int, column: int, message: str):
        super().__init__(f"line {line}, column {column}: {message}")
        self.line, self.column, self.message = line, column, message


class StepError(Exception):
    """A step that cannot be carried out as written (a loop count that is not a whole number,
    a division by zero): the program stops with its line and this message."""


# ---- numbers: literals, variables, arithmetic ------------------------------------------------
@dataclass(frozen=True)
class Number:
    value: float

    def evaluate(self, values: Mapping[int, float]) -> float:
        return self.value


@dataclass(frozen=True)
class Variable:
    """A user variable, by its ``id`` (what the program reads even after a rename) and the
    ``alias`` it was written with."""

    id: int
    alias: str

    def evaluate(self, values: Mapping[int, float]) -> float:
        return values[self.id]


_OPERATIONS: Mapping[str, Callable[[float, float], float]] = {
    "+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv}


@dataclass(frozen=True)
class Arithmetic:
    op: str
    left: "Expr"
    right: "Expr"

    def evaluate(self, values: Mapping[int, float]) -> float:
        a, b = self.left.evaluate(values), self.right.evaluate(values)
        if self.op == "/" and b == 0.0:
            raise StepError(f"division by zero ({a:g} / 0)")
        result = _OPERATIONS[self.op](a, b)
        if not math.isfinite(result):
            raise StepError(f"{a:g} {self.op} {b:g} is not a finite number")
        return result


@dataclass(frozen=True)
class Negated:
    operand: "Expr"

    def evaluate(self, values: Mapping[int, float]) -> float:
        return -self.operand.evaluate(values)


Expr = Union[Number, Variable, Arithmetic, Negated]
Vector = Tuple[Expr, ...]

#: comparison operators of wait_input and wait_until
COMPARISONS: Mapping[str, Callable[[float, float], bool]] = {
    "==": operator.eq, "!=": operator.ne, "<": operator.lt, "<=": operator.le,
    ">": operator.gt, ">=": operator.ge}


def vector(values: Vector, variables: Mapping[int, float]) -> list[float]:
    return [e.evaluate(variables) for e in values]


# ---- statements -----------------------------------------------------------------------------
@dataclass(frozen=True)
class JointMove:
    line: int
    joints: Vector                      # rad
    speed: Expr                         # rad/s
    accel: Expr                         # rad/s²; 0 = the default


@dataclass(frozen=True)
class LinearMove:
    line: int
    pose: Vector                        # mm + rotation vector rad
    speed: Expr                         # mm/s
    accel: Expr                         # mm/s²; 0 = the default


@dataclass(frozen=True)
class CircularMove:
    line: int
    mid: Vector                         # mm + rotation vector rad
    end: Vector
    speed: Expr                         # mm/s
    accel: Expr                         # mm/s²; 0 = the default
    turns: Expr
    mode: Expr                          # attitude rule 0–3


@dataclass(frozen=True)
class SetOutput:
    line: int
    signal: str                         # "digital" / "analog"
    io_type: int                        # 0 cabinet, 1 tool, 2 extension
    index: int
    value: Expr


@dataclass(frozen=True)
class Wait:
    line: int
    seconds: Expr


@dataclass(frozen=True)
class WaitInput:
    line: int
    signal: str
    io_type: int
    index: int
    op: str
    value: Expr
    timeout: Optional[Expr]             # s; None = as long as it takes


@dataclass(frozen=True)
class WaitUntil:
    line: int
    variable: Variable
    op: str
    value: Expr
    timeout: Optional[Expr]


@dataclass(frozen=True)
class SetVariable:
    line: int
    variable: Variable
    value: Expr


@dataclass(frozen=True)
class Repeat:
    line: int
    count: Optional[Expr]               # None = forever
    body: Tuple["Statement", ...]


Statement = Union[JointMove, LinearMove, CircularMove, SetOutput, Wait, WaitInput, WaitUntil,
                  SetVariable, Repeat]
#: the statements that move the arm (a pause inside one brings the arm to rest on its path)
MOVES = (JointMove, LinearMove, CircularMove)


@dataclass(frozen=True)
class Declaration:
    """``var <id> <alias> = <value>``: the variable the program uses, set to ``value`` when the
    program is loaded."""

    line: int
    id: int
    alias: str
    value: float


@dataclass(frozen=True)
class Program:
    name: str
    statements: Tuple[Statement, ...]
    variables: Tuple[Declaration, ...]
