"""Reading a program's text (docs/programs.md) into a :class:`~.language.Program`.

One statement a line; ``#`` starts a comment; blank lines are allowed. Every error is a
:class:`~.language.ProgramError` with the 1-based line and column and what was expected there
(``line 4, column 27: expected a number or a variable after 'speed', found 'fast'``). Nothing
about the robot is checked here — the limits are the executor's, at run time, with the
line of the step.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

from .language import (COMPARISONS, Arithmetic, CircularMove, Declaration, Expr, JointMove,
                       LinearMove, Negated, Number, Program, ProgramError, Repeat, SetOutput,
                       SetVariable, Statement, Variable, Wait, WaitInput, WaitUntil)

#: the largest program read, bytes (a program is a page of text, not a data file)
MAX_BYTES = 1_000_000
MAX_NESTING = 32
#: user variable ids, as JAKA's SDK reads at most 100 of them
VARIABLE_IDS = (1, 100)
SIGNALS = ("digital", "analog")
IO_TYPES = {"cabinet": 0, "tool": 1, "extension": 2}

_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<op>==|!=|<=|>=|[<>=+\-*/()\[\],])
""", re.VERBOSE)


@dataclass(frozen=True)
class Token:
    kind: str            # "number", "name", "op", "end" (of the line)
    text: str
    column: int          # 1-based


def _tokens(text: str, line: int) -> List[Token]:
    out, pos = [], 0
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None:
            raise ProgramError(line, pos + 1, f"unexpected character {text[pos]!r}")
        if m.lastgroup != "space":
            out.append(Token(m.lastgroup, m.group(), pos + 1))
        pos = m.end()
    out.append(Token("end", "end of line", len(text) + 1))
    return out


def _shown(token: Token) -> str:
    return token.text if token.kind == "end" else repr(token.text)


class _Line:
    """The tokens of one line, read left to right."""

    def __init__(self, tokens: List[Token], line: int, aliases: Dict[str, int]):
        self.tokens, self.pos, self.line, self.aliases = tokens, 0, line, aliases

    @property
    def next(self) -> Token:
        return self.tokens[self.pos]

    def take(self) -> Token:
        token = self.tokens[self.pos]
        self.pos += 1
        return token

    def fail(self, expected: str, token: Optional[Token] = None) -> ProgramError:
        token = token or self.next
        return ProgramError(self.line, token.column, f"expected {expected}, found "
                            f"{_shown(token)}")

    def expect(self, text: str, what: Optional[str] = None) -> Token:
        if self.next.text != text or self.next.kind == "end":
            raise self.fail(what or repr(text))
        return self.take()

    def word(self, choices: Sequence[str], what: str) -> str:
        token = self.next
        if token.kind != "name" or token.text not in choices:
            raise self.fail(f"{what} ({' or '.join(choices)})")
        return self.take().text

    def whole(self, what: str) -> int:
        token = self.next
        if token.kind != "number" or not re.fullmatch(r"\d+", token.text):
            raise self.fail(f"{what} (a whole number)")
        return int(self.take().text)

    def done(self) -> None:
        if self.next.kind != "end":
            raise self.fail("the end of the line (or a # comment)")

    # ---- numeric expressions: + - * / ( ) unary minus, numbers, variables ----------------
    def expr(self, after: str) -> Expr:
        left = self._term(after)
        while self.next.text in ("+", "-") and self.next.kind == "op":
            op = self.take().text
            left = Arithmetic(op, left, self._term(after))
        return left

    def _term(self, after: str) -> Expr:
        left = self._factor(after)
        while self.next.text in ("*", "/") and self.next.kind == "op":
            op = self.take().text
            left = Arithmetic(op, left, self._factor(after))
        return left

    def _factor(self, after: str) -> Expr:
        token = self.next
        if token.kind == "op" and token.text == "-":
            self.take()
            return Negated(self._factor(after))
        if token.kind == "op" and token.text == "(":
            self.take()
            inner = self.expr(after)
            self.expect(")", "')'")
            return inner
        if token.kind == "number":
            value = float(self.take().text)
            if not math.isfinite(value):
                raise ProgramError(self.line, token.column, f"{token.text} is not a finite "
                                   "number")
            return Number(value)
        if token.kind == "name":
            return self.variable()
        raise self.fail(f"a number or a variable {after}")

    def variable(self) -> Variable:
        token = self.next
        if token.kind != "name":
            raise self.fail("a variable's name")
        if token.text not in self.aliases:
            declared = ", ".join(sorted(self.aliases)) or "none"
            raise ProgramError(self.line, token.column, f"{token.text!r} is not a declared "
                               f"variable (declared: {declared}; declare it with "
                               f"'var <id> {token.text} = <value>')")
        self.take()
        return Variable(self.aliases[token.text], token.text)

    def values(self, n: int, what: str) -> Tuple[Expr, ...]:
        """``[e1, ..., en]``: ``n`` expressions."""
        self.expect("[", f"'[' and the {n} values of {what}")
        out = [self.expr(f"in {what}")]
        while self.next.text == ",":
            self.take()
            out.append(self.expr(f"in {what}"))
        if self.next.text != "]":
            raise self.fail(f"',' or ']' in {what}")
        if len(out) != n:
            raise ProgramError(self.line, self.next.column, f"{what} has {len(out)} values, "
                               f"expected {n}")
        self.take()
        return tuple(out)

    def options(self, allowed: Dict[str, str], required: Sequence[str]) -> Dict[str, Expr]:
        """``name value`` pairs in any order, each once: ``allowed`` maps each name to its
        unit (for the messages); ``required`` must all be there."""
        found: Dict[str, Expr] = {}
        while self.next.kind != "end":
            token = self.next
            if token.kind != "name" or token.text not in allowed:
                raise self.fail(" or ".join(repr(k) for k in allowed if k not in found)
                                or "the end of the line")
            if token.text in found:
                raise ProgramError(self.line, token.column, f"{token.text!r} is given twice")
            self.take()
            found[token.text] = self.expr(f"after {token.text!r} ({allowed[token.text]})")
        for name in required:
            if name not in found:
                raise self.fail(f"{name!r} and its value ({allowed[name]})")
        return found


def _io_address(ln: _Line) -> Tuple[str, int, int]:
    signal = ln.word(SIGNALS, "the signal")
    if ln.next.kind == "name":
        io_type = IO_TYPES[ln.word(tuple(IO_TYPES), "the IO type")]
    else:
        io_type = ln.whole("the IO type (cabinet, tool, extension, or 0–2)")
        if io_type > 2:
            raise ProgramError(ln.line, ln.tokens[ln.pos - 1].column, f"IO type is "
                               f"{io_type}, expected 0–2 (cabinet, tool, extension)")
    return signal, io_type, ln.whole("the channel index (from 0)")


def _comparison(ln: _Line) -> str:
    token = ln.next
    if token.kind != "op" or token.text not in COMPARISONS:
        raise ln.fail(f"a comparison ({' '.join(COMPARISONS)})")
    return ln.take().text


_MOVE_OPTIONS = {"speed": "", "accel": ""}


def _statement(ln: _Line, keyword: Token) -> Statement:
    """The statement ``keyword`` starts (a repeat's body is added by :func:`parse`)."""
    n, k = ln.line, keyword.text
    zero = Number(0.0)
    if k == "joint_move":
        joints = ln.values(6, "the joint targets (rad)")
        o = ln.options({"speed": "rad/s", "accel": "rad/s²"}, ["speed"])
        return JointMove(n, joints, o["speed"], o.get("accel", zero))
    if k == "linear_move":
        pose = ln.values(6, "the pose (mm, rotation vector rad)")
        o = ln.options({"speed": "mm/s", "accel": "mm/s²"}, ["speed"])
        return LinearMove(n, pose, o["speed"], o.get("accel", zero))
    if k == "circular_move":
        ln.expect("mid", "'mid' and the middle pose")
        mid = ln.values(6, "the middle pose (mm, rotation vector rad)")
        ln.expect("end", "'end' and the end pose")
        end = ln.values(6, "the end pose (mm, rotation vector rad)")
        o = ln.options({"speed": "mm/s", "accel": "mm/s²", "turns": "extra circles",
                        "mode": "attitude rule 0–3"}, ["speed"])
        return CircularMove(n, mid, end, o["speed"], o.get("accel", zero),
                            o.get("turns", zero), o.get("mode", zero))
    if k == "set_output":
        signal, io_type, index = _io_address(ln)
        ln.expect("=", "'=' and the value")
        value = ln.expr("after '='")
        ln.done()
        return SetOutput(n, signal, io_type, index, value)
    if k == "wait":
        seconds = ln.expr("after 'wait' (seconds)")
        ln.done()
        return Wait(n, seconds)
    if k == "wait_input":
        signal, io_type, index = _io_address(ln)
        op = _comparison(ln)
        value = ln.expr(f"after {op!r}")
        o = ln.options({"timeout": "s"}, [])
        return WaitInput(n, signal, io_type, index, op, value, o.get("timeout"))
    if k == "wait_until":
        variable = ln.variable()
        op = _comparison(ln)
        value = ln.expr(f"after {op!r}")
        o = ln.options({"timeout": "s"}, [])
        return WaitUntil(n, variable, op, value, o.get("timeout"))
    if k == "set":
        variable = ln.variable()
        ln.expect("=", "'=' and the new value")
        value = ln.expr("after '='")
        ln.done()
        return SetVariable(n, variable, value)
    if k == "repeat":
        if ln.next.text == "forever" and ln.next.kind == "name":
            ln.take()
            count = None
        else:
            count = ln.expr("after 'repeat' (a count, or 'forever')")
        ln.done()
        return Repeat(n, count, ())
    raise ProgramError(n, keyword.column, f"expected a statement ({', '.join(STATEMENTS)}), "
                       f"found {keyword.text!r}")


STATEMENTS = ("joint_move", "linear_move", "circular_move", "set_output", "wait", "wait_input",
              "wait_until", "set", "repeat", "end", "var")


def _declaration(ln: _Line, ids: Dict[int, int]) -> Declaration:
    id_token = ln.next
    var_id = ln.whole("the variable's id")
    lo, hi = VARIABLE_IDS
    if not lo <= var_id <= hi:
        raise ProgramError(ln.line, id_token.column, f"variable id is {var_id}, expected "
                           f"{lo}–{hi}")
    if var_id in ids:
        raise ProgramError(ln.line, id_token.column, f"variable id {var_id} is already "
                           f"declared on line {ids[var_id]}")
    name = ln.next
    if name.kind != "name" or name.text in STATEMENTS or name.text == "forever":
        raise ln.fail("the variable's name (a letter or '_', then letters, digits, '_')")
    if name.text in ln.aliases:
        raise ProgramError(ln.line, name.column, f"variable {name.text!r} is already declared")
    ln.take()
    ln.expect("=", "'=' and its initial value")
    negative = ln.next.text == "-" and ln.next.kind == "op"
    if negative:
        ln.take()
    token = ln.next
    if token.kind != "number":
        raise ln.fail("a number (the initial value)")
    ln.take()
    ln.done()
    value = float(token.text)
    return Declaration(ln.line, var_id, name.text, -value if negative else value)


def parse(text: str, name: str = "") -> Program:
    """The :class:`Program` written in ``text`` (docs/programs.md), called ``name``."""
    if len(text.encode("utf-8", "replace")) > MAX_BYTES:
        raise ProgramError(1, 1, f"the program is longer than {MAX_BYTES} bytes")
    aliases: Dict[str, int] = {}
    ids: Dict[int, int] = {}
    declarations: List[Declaration] = []
    blocks: List[Tuple[Optional[Repeat], List[Statement]]] = [(None, [])]
    for n, raw in enumerate(text.splitlines(), start=1):
        code = raw.split("#", 1)[0]
        tokens = _tokens(code, n)
        if tokens[0].kind == "end":
            continue
        ln = _Line(tokens, n, aliases)
        keyword = ln.take()
        if keyword.kind != "name":
            raise ProgramError(n, keyword.column, f"expected a statement "
                               f"({', '.join(STATEMENTS)}), found {_shown(keyword)}")
        if keyword.text == "var":
            if len(blocks) > 1:
                raise ProgramError(n, keyword.column, "variables are declared outside "
                                   "repeat blocks")
            declaration = _declaration(ln, ids)
            aliases[declaration.alias], ids[declaration.id] = declaration.id, n
            declarations.append(declaration)
            continue
        if keyword.text == "end":
            ln.done()
            if len(blocks) == 1:
                raise ProgramError(n, keyword.column, "'end' without a 'repeat' it closes")
            opener, body = blocks.pop()
            blocks[-1][1].append(Repeat(opener.line, opener.count, tuple(body)))
            continue
        statement = _statement(ln, keyword)
        if isinstance(statement, Repeat):
            if len(blocks) > MAX_NESTING:
                raise ProgramError(n, keyword.column, f"repeat blocks nest more than "
                                   f"{MAX_NESTING} deep")
            blocks.append((statement, []))
        else:
            blocks[-1][1].append(statement)
    if len(blocks) > 1:
        opener = blocks[-1][0]
        raise ProgramError(opener.line, 1, f"the 'repeat' of line {opener.line} has no 'end'")
    return Program(name, tuple(blocks[0][1]), tuple(declarations))
