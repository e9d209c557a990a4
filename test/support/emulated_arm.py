"""The controller path end to end, for tests: an emulator (the twin behind JAKA's protocol) on free
ports of 127.0.0.1, a RobotDriver on the controller backend talking to it, and what the
emulator's twin planned for each move. One set-up for the tests that drive it, so each says only
what it checks."""
from __future__ import annotations

import shutil
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, List

import pytest

from jaka_driver.common.models import repo_root
from jaka_driver.controller import ControllerBackend
from jaka_driver.driver import RobotDriver
from jaka_driver.emulator import Emulator

#: The link timeouts (s) of a test's controller backend on the emulator (ControllerBackend's
#: ``call_timeout`` and ``stall_timeout``; the node's ``~stall_timeout``). The emulator shares
#: the busy two-core machine with the driver and the test, and its threads can pause past the
#: driver's timeouts for a real controller (1 s for a reply, 0.5 s without a status packet),
#: which would count the link as lost in a test that is not about the link; the emulator itself
#: waits as long (5 s, emulator.status_push.STALL_LIMIT) before it drops a reader that does not
#: read. The tests of the link itself (test_controller_reconnects) keep the driver's own.
LINK_TIMEOUTS = dict(call_timeout=5.0, stall_timeout=5.0)

#: The emulator's twin paces its 8 ms cycles to the wall clock and, after a stall, catches up
#: at most this long (s: STALL_CYCLES cycles, jaka_driver.sim.physics) faster than real time,
#: so a move can end on the wall clock that much before its plan's duration has passed.
CATCH_UP = 25 * 0.008


@contextmanager
def emulator(model: str = "zu5", **options) -> Iterator[Emulator]:
    """The emulator of ``model`` on free ports (``options`` to :class:`Emulator`: ``start``,
    ``profile``, ``period`` …; by default its default profile and start state), stopped on
    leaving."""
    with Emulator(model, command_port=0, status_port=0, **options) as emu:
        yield emu


@pytest.fixture(scope="module")
def emu(request) -> Iterator[Emulator]:
    """The emulator a test module's tests share (test/integration/conftest.py offers it): zu5 on
    free ports, in its default profile and start state, or with the options of the module's
    ``EMULATOR`` (``EMULATOR = dict(start="enabled")``)."""
    with emulator(**getattr(request.module, "EMULATOR", {})) as shared:
        yield shared


@contextmanager
def driver_on_emulator(model: str = "zu5", *, programs: str | None = "default",
                       force_sensor: bool = False, scene=None, **driver_args):
    """``(emulator, driver)``: the emulator of ``model`` (its default profile; ``programs`` its
    programs folder, default the package's examples; ``force_sensor``: its arm carries the
    twin's force/torque sensor and the backend is told so; ``scene`` the twin's workcell) and a
    started RobotDriver on a ControllerBackend connected to it (``driver_args`` to
    RobotDriver); the driver is shut down and the emulator stopped on leaving."""
    with emulator(model, programs=programs, force_sensor=force_sensor, scene=scene) as emu:
        backend = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                                    force_sensor=force_sensor, **LINK_TIMEOUTS)
        driver = RobotDriver(backend, **driver_args)
        driver.start()
        try:
            yield emu, driver
        finally:
            driver.shutdown()


@contextmanager
def planned_moves(backend) -> Iterator[List[float]]:
    """The duration (s) of every joint and linear move ``backend`` starts, as it planned it, in
    order: on the emulator's twin (``emu.backend``), the time the controller takes to play the
    move; on a ControllerBackend, the time the driver expects it to take. What the code decided,
    where a clock read by the test would add when it noticed the end (the next status packet,
    a busy machine's scheduling) to it."""
    planned: List[float] = []
    names = ("start_joint_move", "start_linear_move")
    for name in names:
        start = getattr(backend, name)

        def recording(*args, _start=start, **kwargs):
            result = _start(*args, **kwargs)
            if result.ok:
                planned.append(float(result.value[1]))
            return result
        setattr(backend, name, recording)
    try:
        yield planned
    finally:
        for name in names:
            delattr(backend, name)        # the class's method again


#: A program that counts the cycles a supervisor asks for: user variables 1 ``cycles`` (2) and
#: 2 ``done`` (0), and no motion — a variable set from outside and seen by the program, quickly.
COUNT_CYCLES = """# counts the cycles a supervisor asks for
var 1 cycles = 2
var 2 done = 0
repeat cycles
  set done = done + 1
end
"""


@contextmanager
def emulator_with_programs(folder: str) -> Iterator[Emulator]:
    """The zu5 emulator, enabled, running the programs of ``folder`` (:func:`programs_folder`)."""
    with Emulator("zu5", command_port=0, status_port=0, start="enabled",
                  programs=folder) as emulator:
        yield emulator


@contextmanager
def sdk_logged_in(emu: Emulator):
    """JAKA's SDK (support.jaka_sdk_model) logged in to ``emu``; on leaving, any program it
    started is aborted and it logs out."""
    from .jaka_sdk_model import RC_OK, JakaSdk
    handle = JakaSdk("127.0.0.1", emu.command_port, emu.data_port)
    assert handle.login_in()[0] == RC_OK
    try:
        yield handle
    finally:
        handle.program_abort()
        handle.close()


def programs_folder(folder: Path) -> str:
    """``folder`` holding the package's ``three_moves.jdp`` and ``count_cycles.jdp``
    (:data:`COUNT_CYCLES`): the programs the tests through the emulator play."""
    shutil.copy(repo_root() / "config" / "programs" / "three_moves.jdp", folder)
    (folder / "count_cycles.jdp").write_text(COUNT_CYCLES)
    return str(folder)
