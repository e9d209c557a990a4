"""The controller path end to end, for tests: a RobotDriver on the controller backend, talking
over 127.0.0.1 to an emulator (the twin behind JAKA's protocol) on free ports. One set-up for the
tests that drive it, so each says only what it checks."""
from __future__ import annotations

from contextlib import contextmanager

from jaka_driver.controller import ControllerBackend
from jaka_driver.driver import RobotDriver
from jaka_driver.emulator import Emulator


@contextmanager
def driver_on_emulator(model: str = "zu5", force_sensor: bool = False, scene=None,
                       **driver_args):
    """``(emulator, driver)``: the emulator of ``model`` (its default profile; ``force_sensor``:
    its arm carries the twin's force/torque sensor and the backend is told so; ``scene`` the
    twin's workcell) and a started RobotDriver on a ControllerBackend connected to it
    (``driver_args`` to RobotDriver); the driver is shut down and the emulator stopped on
    leaving."""
    with Emulator(model, command_port=0, status_port=0, force_sensor=force_sensor,
                  scene=scene) as emu:
        backend = ControllerBackend(emu.model, "127.0.0.1", emu.command_port, emu.status_port,
                                    force_sensor=force_sensor)
        driver = RobotDriver(backend, **driver_args)
        driver.start()
        try:
            yield emu, driver
        finally:
            driver.shutdown()
