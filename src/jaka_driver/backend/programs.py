"""Robot programs as a backend offers them: the facet ``backend.programs`` — never None: a
backend without programs offers :class:`NoPrograms`, which refuses every request with -9.

A controller keeps and runs its own programs (JAKA's program commands, docs/protocol.md); the
twin runs the driver's own program engine (:mod:`jaka_driver.programs`, the format of
docs/programs.md) on programs from a folder — handed to it by whoever builds it (the node, the
emulator), as a controller's parts are handed to it, so that ``sim/`` does not build what a
floor above it is — and each step of a program goes through an
executor the driver binds at construction (:meth:`Programs.bind`) — RobotDriver, so that a
step passes the same checks as the service call it stands for. The node reaches programs only
through RobotDriver, whatever backend it has.

States and their numbers are JAKA's SDK's (``get_program_state``): idle 0, running 1, paused 2.
Thread-safe, like the backend.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from enum import IntEnum
from pathlib import Path
from typing import Optional

from ..common.results import Code, Result


class ProgramState(IntEnum):
    """A program's state, numbered as JAKA's SDK returns it (its wire says "idle", "running",
    "paused")."""

    IDLE = 0
    RUNNING = 1
    PAUSED = 2

    @property
    def word(self) -> str:
        return self.name.lower()


@dataclass(frozen=True)
class ProgramStatus:
    """Where programs stand: the state, the loaded program's name ("" when none), the line
    being executed (1-based line of its file; 0 when none) and why the last run ended early
    ("" when it did not: it ended at its end, or was stopped)."""

    state: ProgramState = ProgramState.IDLE
    name: str = ""
    line: int = 0
    error: str = ""


@dataclass(frozen=True)
class UserVariable:
    """A user variable as JAKA's SDK reads one (``query_user_defined_variable``): ``id``, a
    number ``value`` and a name ``alias``."""

    id: int
    value: float
    alias: str


class Programs(ABC):
    """Load, play, pause, resume and stop programs; their state and user variables."""

    #: the folder the programs are files in (a twin's; its recordings go there too), or None
    #: where they are not files of this machine (a controller's, none at all)
    folder: Optional[Path] = None

    def bind(self, executor) -> None:
        """The executor every step of a program goes through (a
        :class:`jaka_driver.programs.Executor`; not imported here: the engine builds on this
        facet, not the other way round), for a backend that runs the driver's program engine
        (the twin); a controller runs its own steps and ignores it."""

    @abstractmethod
    def load(self, name: str) -> Result:
        """Load program ``name`` (refused while one runs or is paused)."""

    @abstractmethod
    def loaded(self) -> Result:
        """The loaded program's name (``Result.value``; "" when none)."""

    @abstractmethod
    def play(self) -> Result:
        """Run the loaded program from its first line."""

    @abstractmethod
    def pause(self) -> Result:
        """Pause the running program: between steps, or inside a move (the arm comes to rest
        on the move's path)."""

    @abstractmethod
    def resume(self) -> Result:
        """Continue a paused program where it stood (a paused move to its own end)."""

    @abstractmethod
    def stop(self) -> Result:
        """End the running or paused program (its move brought to rest); nothing more of it
        runs. Success also when none runs."""

    @abstractmethod
    def status(self) -> ProgramStatus:
        """The state, loaded name, current line and last error; never blocks for long."""

    def state_now(self) -> ProgramState:
        """The state alone, read without waiting for a lock (a twin's physics thread records it
        with each sample); by default the status's."""
        return self.status().state

    def watch(self, on_status) -> bool:
        """Call ``on_status(status)`` with every status at each change, in order, from the
        thread that made it (quick, never blocking); False where changes cannot be seen as
        they happen (a controller's programs: the caller polls :meth:`status`)."""
        return False

    @abstractmethod
    def variables(self) -> Result:
        """Every user variable (``Result.value``: a list of :class:`UserVariable` by id)."""

    @abstractmethod
    def set_variable(self, var_id: int, value: float, alias: str) -> Result:
        """Give user variable ``var_id`` the ``value`` and the name ``alias``."""

    def reset(self) -> None:
        """A fresh start (the twin's reset): no program running or loaded, no user variables.
        Nothing to do where programs are not the backend's own."""


class NoPrograms(Programs):
    """A backend without programs: every request is refused with -9 and ``reason``; the
    state is idle with nothing loaded."""

    def __init__(self, reason: str):
        self._refusal = Result.failure(Code.WRONG_MODE, reason)

    def status(self) -> ProgramStatus:
        return ProgramStatus()

    def _refuse(self, *_args) -> Result:
        return self._refusal

    load = loaded = play = pause = resume = variables = set_variable = _refuse

    def stop(self) -> Result:
        return Result.success("no program runs")
