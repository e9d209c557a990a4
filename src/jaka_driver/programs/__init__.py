"""Robot programs in the driver's own format, and the engine that runs them.

JAKA's program files are not documented, so the twin (and, through it, the emulator) runs
programs of a small documented text format of our own — docs/programs.md: joint, linear and
circular moves, waits, IO set and wait, user variables, loops; one statement a line, the line
numbers those of the file.

* :mod:`.language` — a program as the runner executes it; :class:`ProgramError`;
* :mod:`.parser` — :func:`parse`: text → program, errors with line, column, what was expected;
* :mod:`.executor` — :class:`Executor`, what carries out the steps, and :class:`MoveHold`;
* :mod:`.runner` — :class:`ProgramRunner`: play, pause, resume, stop, state, current line;
* :mod:`.variables` — :class:`UserVariables`, as a controller keeps them;
* :mod:`.folder` — :class:`FolderPrograms`, the twin's ``backend.programs``: programs from a
  folder, by name.
"""
from .executor import Executor, MoveHold
from .folder import FolderPrograms, program_name
from .language import Program, ProgramError
from .parser import parse
from .runner import ProgramRunner
from .variables import UserVariables

__all__ = ["Executor", "MoveHold", "FolderPrograms", "program_name", "Program",
           "ProgramError", "parse", "ProgramRunner", "UserVariables"]
