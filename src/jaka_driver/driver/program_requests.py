"""Robot programs through the door: ``driver.programs`` (:class:`ProgramRequests`), the one
door of the ``backend.programs`` facet (docs/programs.md): load, the loaded
name, play, pause, resume, stop, their state and user variables, whatever runs them — the
driver's own engine on the twin (each step back through this door: :mod:`.program_steps`), a
controller's own programs on a controller. -9 on a backend without programs.
"""
from __future__ import annotations

from ..backend import Programs, ProgramStatus
from ..common.results import Code, CommandRefused, Result, invalid
from . import checks as check
from .door import RequestPart, answers


class ProgramRequests(RequestPart):
    """The program requests (see the module)."""

    def _programs(self) -> Programs:
        programs = self.backend.programs
        if programs is None:     # a backend from before the facet was never None
            raise CommandRefused(Code.WRONG_MODE, "programs are not available on this backend")
        return programs

    @answers
    def load(self, name: str) -> Result:
        """Load the program ``name`` (".jks", as JAKA's SDK appends it, is taken off)."""
        text = str(name).strip()
        if not text:
            raise invalid("name is empty, expected a program's name")
        return self._programs().load(text)

    @answers
    def loaded(self) -> Result:
        """The loaded program's name in ``Result.value`` ("" when none)."""
        return self._programs().loaded()

    @answers
    def play(self) -> Result:
        """Run the loaded program from its start: the arm must be free to move (no other
        move, jog, servo or drag mode; powered, enabled, no error)."""
        programs = self._programs()
        self.door.not_jogging()
        if self.door.move_lock.locked():
            raise CommandRefused(Code.BUSY, "play refused: a move is running")
        self.door.ready(program_step=True)
        return programs.play()

    @answers
    def pause(self) -> Result:
        """Hold the running program: between steps, or its move at rest on its path."""
        return self._programs().pause()

    @answers
    def resume(self) -> Result:
        """Continue the paused program (the arm must be ready to move again)."""
        programs = self._programs()
        self.door.ready(program_step=True)
        return programs.resume()

    @answers
    def stop(self) -> Result:
        """End the running or paused program; its move comes to rest."""
        return self._programs().stop()

    def status(self) -> ProgramStatus:
        """State, loaded name, current line, last error (idle without programs)."""
        programs = self.backend.programs
        return programs.status() if programs is not None else ProgramStatus()

    def watch(self, on_status) -> bool:
        """``on_status(status)`` at every change, in order (:meth:`Programs.watch`); False
        where the backend cannot report changes as they happen (poll :meth:`status`)."""
        programs = self.backend.programs
        return programs.watch(on_status) if programs is not None else False

    @answers
    def variables(self) -> Result:
        """Every user variable (``Result.value``: :class:`UserVariable` list, by id)."""
        return self._programs().variables()

    @answers
    def set_variable(self, var_id: int, value: float, alias: str = "") -> Result:
        """User variable ``var_id`` = ``value``, renamed ``alias`` unless it is empty."""
        v = check.finite("value", value)
        return self._programs().set_variable(int(var_id), v, str(alias))
