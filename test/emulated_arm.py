"""The controller path end to end, for tests: a RobotDriver on the controller backend, talking
over 127.0.0.1 to an emulator (the twin behind JAKA's protocol) on free ports. One set-up for the
tests that drive it, so each says only what it checks."""
from __future__ import annotations

import shutil
from contextlib import contextmanager
from pathlib import Path

from jaka_driver.common.models import repo_root
from jaka_driver.controller import ControllerBackend
from jaka_driver.driver import RobotDriver
from jaka_driver.emulator import Emulator


@contextmanager
def driver_on_emulator(model: str = "zu5", *, programs: str | None = "default",
                       **driver_args):
    """``(emulator, driver)``: the emulator of ``model`` (its default profile; ``programs`` its
    programs folder, default the package's examples) and a started RobotDriver on a
    ControllerBackend connected to it (``driver_args`` to RobotDriver); the driver is shut down
    and the emulator stopped on leaving."""
    with Emulator(model, command_port=0, status_port=0, programs=programs) as emu:
        backend = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port)
        driver = RobotDriver(backend, **driver_args)
        driver.start()
        try:
            yield emu, driver
        finally:
            driver.shutdown()


#: A program that counts the cycles a supervisor asks for: user variables 1 ``cycles`` (2) and
#: 2 ``done`` (0), and no motion — a variable set from outside and seen by the program, quickly.
COUNT_CYCLES = """# counts the cycles a supervisor asks for
var 1 cycles = 2
var 2 done = 0
repeat cycles
  set done = done + 1
end
"""


def programs_folder(folder: Path) -> str:
    """``folder`` holding the package's ``three_moves.jdp`` and ``count_cycles.jdp``
    (:data:`COUNT_CYCLES`): the programs the tests through the emulator play."""
    shutil.copy(repo_root() / "config" / "programs" / "three_moves.jdp", folder)
    (folder / "count_cycles.jdp").write_text(COUNT_CYCLES)
    return str(folder)
