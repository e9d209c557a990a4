"""``jaka_emulator``: the MuJoCo twin behind JAKA's real TCP protocol — what URSim is to the UR
driver. Lets the controller backend, and any third-party JAKA TCP client, be tested end to end
without hardware. No ROS needed.

* :mod:`.app` — :class:`Emulator`, everything assembled.
* :mod:`.profiles` — the controller generations (``--profile``).
* :mod:`.server` — the three ports (commands 10001, status 10000, data_request 10004);
  :mod:`.framing` splits a request port's stream, :mod:`.status_push` feeds the status
  subscribers.
* :mod:`.handlers` — dispatch by ``cmdName``; :data:`EMULATOR_COMMANDS` (fault injection). The
  handlers by subject: :mod:`.arm_commands`, :mod:`.setting_commands`, :mod:`.io_commands`,
  :mod:`.program_commands`, :mod:`.sensor_commands`, :mod:`.force_commands` (an arm with the
  sensor, ``--force-sensor``); :mod:`.wire_fields` reads request fields,
  :mod:`.replies` writes replies (and holds :class:`~.replies.Rejected`, a refusal).
* :mod:`.twin_controller` — a controller's rules on the twin, SI units, assembled by concern:
  :mod:`.arm_rules` (state refusals, power, limits), :mod:`.arm_moves` (queued moves, jogs,
  stop, programs), :mod:`.servo_mode`, :mod:`.arm_settings` (frames, payload, drag, collision,
  servo filter), :mod:`.arm_io` (IO, the outside world's faults, the packet's readings);
  :mod:`.motion_queue` — its motion queue and the thread that starts each move;
  :mod:`.torque_sensor` — the torque sensor's stored settings and the packet's ``torqsensor``.
* :mod:`.status_packet` — the status packet's fields.
* :mod:`.process` — :class:`EmulatorProcess`, the emulator as a subprocess (tests), waiting
  for the line :mod:`.ready_line` describes.
* ``python -m jaka_driver.emulator`` / ``rosrun jaka_driver jaka_emulator`` — :mod:`.__main__`.
"""
from .app import Emulator
from .handlers import EMULATOR_COMMANDS, CommandHandlers
from .server import EmulatorServer

__all__ = ["Emulator", "EmulatorServer", "CommandHandlers", "EMULATOR_COMMANDS"]
