"""Programs and user variables over JAKA's program commands, as JAKA's SDK sends and reads them
(docs/protocol.md, "Programs"): the programs of the emulator's programs folder, in the twin's
format (docs/programs.md), run by the twin's engine on the emulator's controller rules
(:mod:`.program_steps`).

* ``load_program`` — ``programName`` as JAKA's SDK sends it, with the ".jks" it appends to every
  name: ``pick.jks`` finds ``pick.jdp`` (a name is a file name, never a path). A program that
  does not exist, or cannot be read, is refused with "2" and the reason.
* ``get_loaded_program`` — the name with ".jks", as it was loaded; ``""`` when none.
* ``play_program``, ``pause_program``, ``resume_program`` — "2" when there is nothing loaded,
  running or paused, or (play, resume) when the arm may not move; ``stop_program`` stops the
  program and the motion (:mod:`.arm_commands`).
* ``get_program_state`` — ``programState`` a **string**, "idle", "running" or "paused" (JAKA's
  SDK compares strings; a number there killed JAKA's ROS node); ``get_current_line`` — the line
  of the running step in its file (0 when idle).
* ``query_user_defined_variable`` — ``var_list`` of ``{id int, value double, alias string}``;
  ``modify_user_defined_variable`` — ``id_new``, ``value_new``, ``alias_new`` (an empty alias
  keeps the name); an id no program declared is refused with "2".
* ``get_exist_programs`` — the folder's programs, each with ".jks".
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping

from ..protocol.fields import Cmd, Field
from ..protocol.programs import JKS
from .replies import Answer, Rejected, done
from .twin_controller import TwinController
from .wire_fields import integer, number, text


class ProgramCommands:
    def __init__(self, controller: TwinController):
        self.c = controller
        self.programs = controller.programs

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        c = self.c
        return {
            Cmd.GET_PROGRAM_STATE: lambda r: Answer(
                {Field.PROGRAM_STATE: self.programs.status().state.word}),
            Cmd.GET_LOADED_PROGRAM: self._loaded,
            Cmd.GET_CURRENT_LINE: lambda r: Answer(
                {Field.CURRENT_LINE: int(self.programs.status().line)}),
            Cmd.GET_EXIST_PROGRAMS: lambda r: Answer(
                {"programs": [f"{name}{JKS}" for name in self.programs.available()]}),
            Cmd.LOAD_PROGRAM: self._load,
            Cmd.PLAY_PROGRAM: lambda r: done(c.play_program()),
            Cmd.PAUSE_PROGRAM: lambda r: done(c.pause_program()),
            Cmd.RESUME_PROGRAM: lambda r: done(c.resume_program()),
            Cmd.QUERY_USER_DEFINED_VARIABLE: self._variables,
            Cmd.MODIFY_USER_DEFINED_VARIABLE: self._modify_variable,
        }

    def _loaded(self, _req) -> Answer:
        name = self.programs.status().name
        return Answer({Field.PROGRAM_NAME: f"{name}{JKS}" if name else ""})

    def _load(self, req) -> Answer:
        name = text(req, Field.PROGRAM_NAME)
        result = self.programs.load(name)
        if not result.ok:
            raise Rejected(f"load_program: {result.message}")
        return Answer()

    def _variables(self, _req) -> Answer:
        listed = self.programs.variables().value
        return Answer({Field.VAR_LIST: [{"id": v.id, "value": float(v.value), "alias": v.alias}
                                        for v in listed]})

    def _modify_variable(self, req) -> Answer:
        result = self.programs.set_variable(integer(req, Field.ID_NEW, 1, 100),
                                            number(req, Field.VALUE_NEW),
                                            text(req, Field.ALIAS_NEW, default=""))
        if not result.ok:
            raise Rejected(f"modify_user_defined_variable: {result.message}")
        return Answer()
