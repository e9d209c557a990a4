"""``jaka_emulator``: the MuJoCo twin behind JAKA's real TCP protocol — what URSim is to the UR
driver. Lets the controller backend, and any third-party JAKA TCP client, be tested end to end
without hardware. No ROS needed.

* :mod:`.app` — :class:`Emulator`, everything assembled.
* :mod:`.server` — the two ports (commands 10001, status 10000).
* :mod:`.framing` — splitting the command stream into requests.
* :mod:`.handlers` — one handler per ``cmdName``; :data:`EMULATOR_COMMANDS` (fault injection).
* :mod:`.twin_controller` — controller behaviour on the twin, SI units.
* :mod:`.status_packet` — the status packet's fields.
* :mod:`.process` — :class:`EmulatorProcess`, the emulator as a subprocess (tests).
* ``python -m jaka_driver.emulator`` / ``rosrun jaka_driver jaka_emulator`` — :mod:`.__main__`.
"""
from .app import Emulator
from .handlers import EMULATOR_COMMANDS, CommandHandlers
from .server import EmulatorServer

__all__ = ["Emulator", "EmulatorServer", "CommandHandlers", "EMULATOR_COMMANDS"]
