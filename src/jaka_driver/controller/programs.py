"""A controller's own programs: the ``backend.programs`` facet of the controller backend
(:class:`~jaka_driver.backend.programs.Programs`), on JAKA's program commands written as JAKA's
SDK writes them (:mod:`jaka_driver.protocol.programs`; docs/protocol.md, "Programs").

* **load** sends ``load_program`` with the name and the ".jks" JAKA's SDK appends to every name;
  a trailing ".jks" on the name asked is taken off first, so that ``pick`` and ``pick.jks``
  load the same program here as on the twin (JAKA's SDK would send ``pick.jks.jks`` for the
  second). The loaded name is reported without its ".jks", as the twin reports it.
* **play**, **pause**, **resume** send ``play_program``, ``pause_program``,
  ``resume_program``; **stop** sends ``stop_program`` and then waits as JAKA's SDK's
  ``program_abort`` waits: ``get_motion_state`` every 100 ms until the queue is empty and not
  full, at most 1 s.
* **user variables**: ``query_user_defined_variable`` and ``modify_user_defined_variable``;
  a value set is read back (every 100 ms, up to 1 s, as the SDK confirms its settings).

**The program's state without a request per status sample.** The status packet carries no
program state on record: ``interp_state`` is read as one only by third-party clients (its
meaning, 0 idle … 3 running, is not JAKA's), ``paused`` not at all by JAKA's SDK. What is on
record is ``get_program_state``'s string, so this facet asks it — every
:data:`STATE_POLL` s (4 Hz, half the rate at which JAKA's own ROS node asks it, so a
controller is known to bear it), at once after each program command this driver sends, and
``get_current_line`` with it while a program runs or is paused. Every sample then carries the
state last read (:meth:`ControllerPrograms.status` never waits): ``motion_state`` follows this
driver's own commands at once and a pendant's within 0.25 s.

Thread-safe; the poll runs in its own thread (``jaka-programs``) while the link is up.
"""
from __future__ import annotations

import logging
import threading
from typing import Optional

from ..backend.programs import Programs, ProgramState, ProgramStatus, UserVariable
from ..common.results import Code, CommandRefused, Result
from ..host import realtime
from ..protocol import commands
from ..protocol import programs as wire
from .commander import Commander, answers

log = logging.getLogger(__name__)

#: s between two ``get_program_state`` requests
STATE_POLL = 0.25
#: ``programState`` (the SDK's 0, 1, 2) → the facet's state
_STATES = {0: ProgramState.IDLE, 1: ProgramState.RUNNING, 2: ProgramState.PAUSED}


class ControllerPrograms(Programs):
    """The controller's programs through ``send`` (see the module). :meth:`start` and
    :meth:`stop_polling` run and end the state poll."""

    def __init__(self, send: Commander):
        self.send = send
        self._lock = threading.Lock()
        self._status = ProgramStatus()
        self._wake = threading.Event()
        self._quit = threading.Event()
        self._unreadable = ""             # why the last state read failed (logged once)
        self._thread: Optional[threading.Thread] = None

    # ---- the state poll ---------------------------------------------------------------
    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="jaka-programs", daemon=True)
        self._thread.start()

    def stop_polling(self) -> None:
        self._quit.set()
        self._wake.set()
        if self._thread is not None:
            self._thread.join(2.0)

    def refresh(self) -> None:
        """Read the state now (a new connection, a program command sent)."""
        self._wake.set()

    @realtime.runs_periodically
    def _run(self) -> None:
        while not self._quit.is_set():
            self._wake.wait(STATE_POLL)
            self._wake.clear()
            if self._quit.is_set():
                return
            if self.send.link.connected:
                self._read_state()

    def _read_state(self) -> None:
        try:
            state = _STATES[self.send.read(wire.get_program_state(),
                                           wire.reply_program_state)]
            line = (self.send.read(wire.get_current_line(), wire.reply_current_line)
                    if state != ProgramState.IDLE else 0)
            with self._lock:
                before = self._status
            name = before.name
            if state != before.state or not name:
                name = wire.without_jks(self.send.read(wire.get_loaded_program(),
                                                    wire.reply_loaded_program))
        except CommandRefused as refusal:
            # an unreadable state leaves the one read last, as JAKA's SDK leaves its output
            if refusal.message != self._unreadable:
                log.info("program state not read: %s", refusal.message)
                self._unreadable = refusal.message
            return
        self._unreadable = ""
        with self._lock:
            self._status = ProgramStatus(state, name, line, "")

    # ---- the facet ----------------------------------------------------------------------
    def status(self) -> ProgramStatus:
        with self._lock:
            return self._status

    def _sent(self, request, what: str) -> Result:
        """Send a program command, then read the state at once."""
        try:
            self.send.accepted(request)
        finally:
            self._read_state()
        return Result.success(what)

    @answers
    def load(self, name: str) -> Result:
        program = wire.without_jks(name)
        self._sent(wire.load_program(program), "load_program sent")
        return Result.success(f"program {program!r} loaded (load_program "
                              f"{program}{wire.JKS})")

    @answers
    def loaded(self) -> Result:
        name = wire.without_jks(self.send.read(wire.get_loaded_program(),
                                            wire.reply_loaded_program))
        return Result.success(f"program {name!r} loaded" if name else "no program loaded",
                              name)

    @answers
    def play(self) -> Result:
        return self._sent(wire.play_program(), "play_program sent")

    @answers
    def pause(self) -> Result:
        return self._sent(wire.pause_program(), "pause_program sent")

    @answers
    def resume(self) -> Result:
        return self._sent(wire.resume_program(), "resume_program sent")

    @answers
    def stop(self) -> Result:
        """``stop_program``, then waits for the queue to be empty as JAKA's SDK's
        ``program_abort`` does (2 when it is not within 1 s)."""
        try:
            self.send.settled(commands.stop_program(), commands.get_motion_state(),
                              commands.reply_motion_state,
                              lambda m: m.queue == 0 and not m.queue_full, "program stop")
        finally:
            self._read_state()
        return Result.success("stop_program sent; the motion queue is empty")

    @answers
    def variables(self) -> Result:
        listed = [UserVariable(v.id, v.value, v.alias) for v in self._read_variables()]
        return Result.success(f"{len(listed)} user variables", listed)

    def _read_variables(self) -> list:
        return self.send.read(wire.query_user_defined_variable(), wire.reply_user_variables)

    @answers
    def set_variable(self, var_id: int, value: float, alias: str) -> Result:
        """``modify_user_defined_variable`` (JAKA's SDK's ``set_user_var``), which renames too:
        an empty ``alias`` sends the name the variable has, so it keeps it. A variable the
        controller does not list is refused (-2) before anything is sent."""
        known = {v.id: v for v in self._read_variables()}
        if var_id not in known:
            ids = ", ".join(str(k) for k in sorted(known)) or "none"
            raise CommandRefused(Code.INVALID_PARAMETER, f"id is {var_id}, not a user variable "
                                 f"of the controller (ids: {ids})")
        name = alias or known[var_id].alias

        def there(listed) -> bool:
            return any(v.id == var_id and abs(v.value - value) <= 1e-9 * max(1.0, abs(value))
                       and v.alias == name for v in listed)
        self.send.settled(wire.modify_user_defined_variable(var_id, value, name),
                          wire.query_user_defined_variable(), wire.reply_user_variables,
                          there, f"user variable {var_id}")
        return Result.success(f"user variable {var_id} ({name}) = {value:g}, read back")
