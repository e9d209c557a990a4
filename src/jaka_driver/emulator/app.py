"""The emulator assembled: the MuJoCo twin, the controller logic, the handlers and the sockets.

Use it in-process (tests, notebooks)::

    from jaka_driver.emulator import Emulator

    with Emulator("zu5", command_port=0, status_port=0) as emu:   # 0: free ports
        print(emu.command_port, emu.status_port)

    # another controller generation, its push period and start state overridden
    Emulator("zu5", command_port=0, status_port=0, profile="zu5s-1.5.14", period=0.008,
             start="enabled")

    # the programs JAKA's program commands load and play (the twin's format, docs/programs.md)
    Emulator("zu5", command_port=0, status_port=0, programs="/path/to/programs")

or as a program: ``python -m jaka_driver.emulator --model zu5`` (:mod:`.__main__`).
"""
from __future__ import annotations

import dataclasses
import logging
from pathlib import Path
from typing import Optional, Union

from ..common.models import RobotModel, load_model, repo_root
from ..programs import FolderPrograms
from ..sim import SimBackend
from .handlers import CommandHandlers
from .program_steps import ControllerSteps
from .profiles import DEFAULT_PROFILE, START_STATES, ControllerProfile, profile_named
from .server import EmulatorServer
from .status_packet import status_fields
from .twin_controller import TwinController

log = logging.getLogger(__name__)


def default_programs() -> str:
    """The folder of this package's example programs (``config/programs``)."""
    return str(repo_root() / "config" / "programs")


class Emulator:
    """A JAKA controller emulated on the twin of ``model`` (a name such as ``"zu5"`` or a
    :class:`~jaka_driver.common.models.RobotModel`), serving ``host`` on the three ports.

    ``profile`` names the controller generation (:data:`~.profiles.PROFILES`; default a
    controller on fw 1.7.2, the one JAKA's SDK and ROS 2 driver are written for; the recorded Zu
    5s on fw 1.5.14 is ``"zu5s-1.5.14"``); ``period`` (s between status packets) and ``start``
    (:data:`~.profiles.START_STATES`) override the profile's. ``programs``: the folder of the
    programs it serves (the twin's format, docs/programs.md; default :func:`default_programs`,
    this package's examples; None: none), run by the twin's engine on this controller's
    rules. ``force_sensor``: the arm carries the flange force/torque sensor (the twin's, of the
    model's configuration), and the emulator answers JAKA's torque-sensor and force-control
    commands from it (:mod:`.force_commands`); without it, as a controller whose arm has none.
    ``gripper``: the tool on the twin's tool connector (``none``, ``dh_pgi`` the DH gripper
    driven by Modbus frames on RS485 channel 1, ``suction`` the cup on tool DO 0), reached only
    through JAKA's TIO commands (:mod:`.tool_io_commands`)."""

    def __init__(self, model: Union[str, RobotModel] = "zu5", host: str = "127.0.0.1",
                 command_port: int = 10001, status_port: int = 10000, *,
                 data_port: Optional[int] = None, profile: Union[str, ControllerProfile] =
                 DEFAULT_PROFILE, period: Optional[float] = None, start: Optional[str] = None,
                 scene: Optional[str] = None, io_loopback: bool = False,
                 programs: Optional[str] = "default", force_sensor: bool = False,
                 gripper: str = "none"):
        self.profile = profile_named(profile) if isinstance(profile, str) else profile
        self.start_state = self.profile.start if start is None else start
        if self.start_state not in START_STATES:
            raise ValueError(f"start must be one of {START_STATES}; got {start!r}")
        period = self.profile.period if period is None else float(period)
        if not 0.001 <= period <= 1.0:
            raise ValueError(f"period must be in [0.001, 1] s; got {period!r}")
        self.model = load_model(model) if isinstance(model, str) else model
        # The twin gets the IO of the profile's controller cabinet, as its packets show it.
        self.model = dataclasses.replace(self.model, io_sizes=self.profile.io_sizes)
        #: the arm: the MuJoCo twin, through its face (the contract and ``backend.twin``)
        if programs == "default":
            programs = default_programs()
        if programs is not None and not Path(programs).expanduser().is_dir():
            raise ValueError(f"programs folder {programs} is not a folder")
        self.backend = SimBackend(self.model, scene=scene, io_loopback=io_loopback,
                                  programs=FolderPrograms(programs),
                                  force_sensor=bool(force_sensor), gripper=gripper)
        self.controller = TwinController(self.backend, self.profile)
        # each step of a program passes this controller's rules, as its commands do
        self.backend.programs.bind(ControllerSteps(self.controller))
        if data_port is None:   # free ports for tests stay free ports: no fixed 10004 then
            data_port = 0 if command_port == 0 else 10004
        self.handlers = CommandHandlers(self.controller)
        self.server = EmulatorServer(self.handlers, lambda: status_fields(self.controller),
                                     host, command_port, status_port, period, data_port,
                                     arm=self.backend)

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

    @property
    def period(self) -> float:
        """s between two status packets on the status port."""
        return self.server.period

    def start(self) -> "Emulator":
        self.backend.start()
        self.controller.apply_start(self.start_state)
        try:
            self.server.start()
        except OSError:
            self.backend.shutdown()
            raise
        log.info("%s on %s: commands %d, status %d, data_request %d; profile %s (%s); "
                 "started %s, a packet every %g ms", self.controller.identity, self.host,
                 self.command_port, self.status_port, self.data_port, self.profile.name,
                 self.profile.describe(), self.start_state, self.period * 1000)
        return self

    def stop(self) -> None:
        self.handlers.network.close()     # the connections it closes are no network loss
        self.server.stop()
        self.controller.close()
        self.backend.shutdown()

    def drop_clients(self) -> None:
        """Close every client connection (the ports keep listening)."""
        self.server.drop_clients()

    def __enter__(self) -> "Emulator":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
