"""Program control (JAKA's SDK's ten program functions): requests as the SDK writes them and
its replies as it reads them (docs/protocol.md, "Programs").

* ``load_program`` — the SDK **always appends ".jks"** to the name it is given ("x" →
  "x.jks", "x.jks" → "x.jks.jks", "" → ".jks"); :func:`load_program` does the same, so a
  controller or the emulator sees what JAKA's own clients send.
* ``get_program_state`` answers ``programState`` as a **string** ("idle", "running",
  "paused"); the SDK returns 0, 1, 2 for them — so does :func:`reply_program_state`.
* user variables: ``var_list`` of ``{id int, value double, alias string}``.
"""
from __future__ import annotations

from typing import List, NamedTuple

from .errors import ProtocolError
from .fields import Cmd, Field, ProgramState
from .replies import Reply
from .reply_values import field as _field, int_field as _int_field
from .request_values import Request, command as _cmd, integer as _integer
from .request_values import number as _number
from .wire import clean_text

#: what JAKA's SDK appends to every program name it loads
JKS = ".jks"
#: ``programState`` → the SDK's number
PROGRAM_STATES = {ProgramState.IDLE: 0, ProgramState.RUNNING: 1, ProgramState.PAUSED: 2}
#: the most user variables JAKA's SDK reads from one reply
MAX_VARIABLES = 100


def without_jks(name: str) -> str:
    """A program's name as a client meant it: blanks around it and the ".jks" JAKA's SDK
    appends to every name taken off (once)."""
    name = str(name).strip()
    return name[:-len(JKS)] if name.endswith(JKS) else name


def load_program(name: str) -> Request:
    """Load the program ``name``: sent as ``name + ".jks"``, as JAKA's SDK sends it."""
    return _cmd(Cmd.LOAD_PROGRAM, **{Field.PROGRAM_NAME: f"{name}{JKS}"})


def get_loaded_program() -> Request:
    """Reply: :func:`reply_loaded_program`."""
    return _cmd(Cmd.GET_LOADED_PROGRAM)


def play_program() -> Request:
    return _cmd(Cmd.PLAY_PROGRAM)


def pause_program() -> Request:
    return _cmd(Cmd.PAUSE_PROGRAM)


def resume_program() -> Request:
    return _cmd(Cmd.RESUME_PROGRAM)


def get_program_state() -> Request:
    """Reply: :func:`reply_program_state`."""
    return _cmd(Cmd.GET_PROGRAM_STATE)


def get_current_line() -> Request:
    """Reply: :func:`reply_current_line`."""
    return _cmd(Cmd.GET_CURRENT_LINE)


def query_user_defined_variable() -> Request:
    """Reply: :func:`reply_user_variables`."""
    return _cmd(Cmd.QUERY_USER_DEFINED_VARIABLE)


def modify_user_defined_variable(var_id: int, value: float, alias: str) -> Request:
    """User variable ``var_id`` = ``value``, named ``alias`` (keys in the SDK's sorted order)."""
    return dict(sorted(_cmd(Cmd.MODIFY_USER_DEFINED_VARIABLE, **{
        Field.ALIAS_NEW: str(alias), Field.ID_NEW: _integer(var_id, "user variable id"),
        Field.VALUE_NEW: _number(value, "user variable value")}).items()))


def reply_loaded_program(reply: Reply) -> str:
    """``get_loaded_program`` → ``programName``, as the controller sent it (".jks" included)."""
    raw = _field(reply, Field.PROGRAM_NAME)
    if not isinstance(raw, str):
        raise ProtocolError(f"'programName' should be a string; got {raw!r}")
    return clean_text(raw)


def reply_program_state(reply: Reply) -> int:
    """``get_program_state`` → 0 idle, 1 running, 2 paused (the SDK's numbers). The wire's
    value is a string; a number or another word is a :class:`ProtocolError` (JAKA's SDK aborts
    on a number and leaves its output unchanged on another word)."""
    raw = _field(reply, Field.PROGRAM_STATE)
    if not isinstance(raw, str) or raw not in PROGRAM_STATES:
        raise ProtocolError(f"'programState' should be one of "
                            f"{', '.join(map(repr, PROGRAM_STATES))}; got {raw!r}")
    return PROGRAM_STATES[raw]


def reply_current_line(reply: Reply) -> int:
    """``get_current_line`` → the line the program runs."""
    return _int_field(reply, Field.CURRENT_LINE)


class UserVariable(NamedTuple):
    id: int
    value: float
    alias: str


def reply_user_variables(reply: Reply) -> List[UserVariable]:
    """``query_user_defined_variable`` → the first :data:`MAX_VARIABLES` entries of
    ``var_list``, each ``{id int, value number, alias string}``; any other shape is a
    :class:`ProtocolError` (JAKA's SDK crashes on a scalar where it indexes)."""
    raw = _field(reply, Field.VAR_LIST)
    if not isinstance(raw, list):
        raise ProtocolError(f"'var_list' should be an array; got {str(raw)[:120]}")
    out = []
    for i, entry in enumerate(raw[:MAX_VARIABLES]):
        if not isinstance(entry, dict):
            raise ProtocolError(f"'var_list' entry {i} should be an object; got {entry!r}")
        var_id, value, alias = (entry.get(k) for k in ("id", "value", "alias"))
        if isinstance(var_id, bool) or not isinstance(var_id, int) or \
                isinstance(value, bool) or not isinstance(value, (int, float)) or \
                not isinstance(alias, str):
            raise ProtocolError(f"'var_list' entry {i} should be {{id int, value number, "
                                f"alias string}}; got {entry!r}")
        out.append(UserVariable(var_id, float(value), clean_text(alias)))
    return out
