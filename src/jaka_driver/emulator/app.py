"""The emulator assembled: the MuJoCo twin, the controller logic, the handlers and the sockets.

Use it in-process (tests, notebooks)::

    from jaka_driver.emulator import Emulator

    with Emulator("zu5", command_port=0, status_port=0) as emu:   # 0: free ports
        print(emu.command_port, emu.status_port)

or as a program: ``python -m jaka_driver.emulator --model zu5`` (:mod:`.__main__`).
"""
from __future__ import annotations

import dataclasses
import logging
from typing import Optional, Union

from ..models import RobotModel, load_model
from ..sim.backend import SimBackend
from .handlers import CommandHandlers
from .server import STATUS_PERIOD, EmulatorServer
from .status_packet import CONTROLLER_IO_SIZES, status_fields
from .twin_controller import TwinController

log = logging.getLogger(__name__)


class Emulator:
    """A JAKA controller emulated on the twin of ``model`` (a name such as ``"zu5"`` or a
    :class:`~jaka_driver.models.RobotModel`), serving ``host`` on the two ports."""

    def __init__(self, model: Union[str, RobotModel] = "zu5", host: str = "127.0.0.1",
                 command_port: int = 10001, status_port: int = 10000, *,
                 data_port: Optional[int] = None,
                 period: float = STATUS_PERIOD, scene: Optional[str] = None,
                 io_loopback: bool = False):
        self.model = load_model(model) if isinstance(model, str) else model
        # The twin gets the IO of a real controller cabinet, as the packets show it.
        self.model = dataclasses.replace(self.model, io_sizes=CONTROLLER_IO_SIZES)
        self.twin = SimBackend(self.model, scene=scene, io_loopback=io_loopback)
        self.controller = TwinController(self.twin)
        if data_port is None:   # free ports for tests stay free ports: no fixed 10004 then
            data_port = 0 if command_port == 0 else 10004
        self.handlers = CommandHandlers(self.controller)
        self.server = EmulatorServer(self.handlers, lambda: status_fields(self.controller),
                                     host, command_port, status_port, period, data_port)

    @property
    def host(self) -> str:
        return self.server.host

    @property
    def command_port(self) -> int:
        return self.server.command_port

    @property
    def status_port(self) -> int:
        return self.server.status_port

    @property
    def data_port(self) -> int:
        return self.server.data_port

    def start(self) -> "Emulator":
        self.twin.start()
        try:
            self.server.start()
        except OSError:
            self.twin.shutdown()
            raise
        log.info("%s on %s: commands %d, status %d, data_request %d; get_version answers %s",
                 self.controller.identity, self.host, self.command_port, self.status_port,
                 self.data_port, self.controller.version)
        return self

    def stop(self) -> None:
        self.server.stop()
        self.controller.close()
        self.twin.shutdown()

    def drop_clients(self) -> None:
        """Close every client connection (the ports keep listening)."""
        self.server.drop_clients()

    def __enter__(self) -> "Emulator":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
