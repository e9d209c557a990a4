"""User programs and user variables, answered as a controller that has none: the emulator runs
no JAKA programs (its motion comes from commands only).

What JAKA's software polls must read as a healthy idle controller: JAKA's ROS node asks for
``get_program_state`` about 8 times a second and its SDK compares ``programState`` as a string
(a number there killed the node), so it is ``"idle"``; ``get_loaded_program`` names none (``""``)
and ``get_current_line`` is 0. Loading a program answers errorCode "2" (it does not exist);
play, pause and resume answer "2" (nothing loaded, running or paused); ``stop_program`` stops
motion (:mod:`.arm_commands`), as on a controller.
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping

from ..protocol.fields import Cmd, Field, ProgramState
from .replies import Answer, Rejected
from .wire_fields import shown, shown_name

NO_PROGRAMS = "(the emulator has no user programs)"


def _refuse(req: Mapping, why: str) -> Answer:
    raise Rejected(f"{shown_name(req)}: {why} {NO_PROGRAMS}")


def _load(req: Mapping) -> Answer:
    name = req.get(Field.PROGRAM_NAME)
    name = name[:80] if isinstance(name, str) else shown(name)
    return _refuse(req, f"program {name} does not exist")


PROGRAM_COMMANDS: Dict[str, Callable[[Mapping], Answer]] = {
    Cmd.GET_PROGRAM_STATE: lambda r: Answer({Field.PROGRAM_STATE: ProgramState.IDLE}),
    Cmd.GET_LOADED_PROGRAM: lambda r: Answer({Field.PROGRAM_NAME: ""}),
    Cmd.GET_CURRENT_LINE: lambda r: Answer({Field.CURRENT_LINE: 0}),
    Cmd.GET_EXIST_PROGRAMS: lambda r: Answer({"programs": []}),
    Cmd.LOAD_PROGRAM: _load,
    Cmd.PLAY_PROGRAM: lambda r: _refuse(r, "no program loaded"),
    Cmd.PAUSE_PROGRAM: lambda r: _refuse(r, "no program running"),
    Cmd.RESUME_PROGRAM: lambda r: _refuse(r, "no program paused"),
    Cmd.QUERY_USER_DEFINED_VARIABLE: lambda r: Answer({Field.VAR_LIST: []}),
    Cmd.MODIFY_USER_DEFINED_VARIABLE: lambda r: _refuse(
        r, "no such user variable: none is defined"),
}
