"""Programs from a folder, run by the driver's engine: the ``backend.programs`` facet of the twin
(:class:`~jaka_driver.backend.programs.Programs`).

A program called ``name`` is the file ``<folder>/<name>.jdp`` in the format of
docs/programs.md. JAKA's SDK appends ".jks" to every name it loads, so a trailing ".jks" (or
".jdp") is taken off first: ``pick``, ``pick.jks`` and ``pick.jdp`` all load ``pick.jdp``, whose
name is then ``pick``. A name is a file name, never a path: nothing outside the folder is read —
but for ``track/<name>``, the replay program generated from a recording (:mod:`.track`), in
the folder ``track/`` of the programs folder.
Steps run through the executor bound with :meth:`FolderPrograms.bind` (RobotDriver's door on
the twin).
"""
from __future__ import annotations

import re
from pathlib import Path
from typing import Callable, List, Optional

from ..backend.programs import Programs, ProgramState, ProgramStatus
from ..backend.recording import TRACK_FOLDER
from ..common.results import Code, Result
from ..protocol.programs import without_jks
from .language import ProgramError
from .parser import parse
from .runner import ProgramRunner
from .variables import UserVariables

SUFFIX = ".jdp"
_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.\-]*")
#: what names a replay program generated from a recording (``track/<name>``, as on JAKA's
#: controllers): the one folder a name may name
TRACK_PREFIX = f"{TRACK_FOLDER}/"
#: the longest name (characters): a file name's limit (255 bytes) less the suffix
MAX_NAME = 200


def program_name(requested: str) -> str:
    """The program a requested name means: a trailing ".jks" (JAKA's SDK appends it,
    :func:`~jaka_driver.protocol.programs.without_jks`) or ".jdp" taken off."""
    name = str(requested).strip()
    trimmed = without_jks(name)
    if trimmed != name:
        return trimmed
    return name[:-len(SUFFIX)] if name.endswith(SUFFIX) else name


class FolderPrograms(Programs):
    """The programs of ``folder`` (None: no programs folder; loading then says so)."""

    def __init__(self, folder: Optional[str], on_change: Callable[[], None] = lambda: None):
        self.folder = Path(folder).expanduser() if folder else None
        self._table = UserVariables()
        self._on_change = on_change
        self._watchers: list[Callable[[ProgramStatus], None]] = []
        self._runner = ProgramRunner(self._table, on_change=self._changed)

    def _changed(self, status: ProgramStatus) -> None:
        self._on_change()
        for watcher in list(self._watchers):
            watcher(status)

    def watch(self, on_status) -> bool:
        """Every change, as the runner makes it (in sim time: at the cycle it happens)."""
        self._watchers.append(on_status)
        return True

    def bind(self, executor) -> None:
        self._runner.executor = executor

    def available(self) -> List[str]:
        """The names of the programs in the folder, then the replay programs of its
        ``track/`` folder as ``track/<name>``."""
        if self.folder is None or not self.folder.is_dir():
            return []
        return (sorted(p.stem for p in self.folder.glob(f"*{SUFFIX}") if p.is_file())
                + sorted(f"{TRACK_PREFIX}{p.stem}"
                         for p in (self.folder / TRACK_FOLDER).glob(f"*{SUFFIX}")
                         if p.is_file()))

    def load(self, name: str) -> Result:
        wanted = program_name(name)
        folder, stem = self.folder, wanted
        if wanted.startswith(TRACK_PREFIX):     # a replay program (programs/track.py)
            stem = wanted[len(TRACK_PREFIX):]
            folder = self.folder / TRACK_FOLDER if self.folder is not None else None
        if len(wanted) > MAX_NAME:
            return Result.failure(Code.INVALID_PARAMETER, f"name has {len(wanted)} characters, "
                                  f"at most {MAX_NAME}")
        if not _NAME.fullmatch(stem) or stem in (".", ".."):
            return Result.failure(Code.INVALID_PARAMETER, f"name is {name!r}, expected a "
                                  "program's name (letters, digits, '_', '-', '.'; no path "
                                  f"but {TRACK_PREFIX!r} before a recording's replay)")
        if self.folder is None:
            return Result.failure(Code.WRONG_MODE, "no programs folder is set (the node's "
                                  "~programs parameter, launch argument programs)")
        path = folder / f"{stem}{SUFFIX}"
        if not path.is_file():
            there = ", ".join(self.available()) or "none"
            return Result.failure(Code.INVALID_PARAMETER, f"name is {name!r}: no {path.name} "
                                  f"in {folder} (programs there: {there})")
        try:
            program = parse(path.read_text(encoding="utf-8", errors="replace"), wanted)
        except ProgramError as exc:
            return Result.failure(Code.INVALID_PARAMETER, f"program {wanted!r} cannot be "
                                  f"read: {exc}")
        except OSError as exc:
            return Result.failure(Code.COMMUNICATION_ERROR, f"{path} cannot be read: {exc}")
        return self._runner.load(program)

    def loaded(self) -> Result:
        name = self._runner.status().name
        return Result.success(f"program {name!r} loaded" if name else "no program loaded",
                              name)

    def play(self) -> Result:
        return self._runner.play()

    def pause(self) -> Result:
        return self._runner.pause()

    def resume(self) -> Result:
        return self._runner.resume()

    def stop(self) -> Result:
        return self._runner.stop()

    def status(self) -> ProgramStatus:
        return self._runner.status()

    def state_now(self) -> ProgramState:
        """The state alone, read without a lock (the twin's physics thread records it with
        each sample and must not wait for a lock a request may hold)."""
        return self._runner.state_now

    def variables(self) -> Result:
        listed = self._table.listed()
        return Result.success(f"{len(listed)} user variables", listed)

    def set_variable(self, var_id: int, value: float, alias: str) -> Result:
        return self._table.set(var_id, value, alias)

    def reset(self) -> None:
        """A fresh start: no program running or loaded, no user variables."""
        self._runner.stop()
        self._runner.unload()
        self._table.clear()
