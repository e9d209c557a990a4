"""The emulator's command port: one handler per ``cmdName``, wire request in, wire reply out.

Requests are read as a JAKA controller reads them (docs/protocol.md: joints deg, poses mm +
RPY deg, speeds deg/s or mm/s, IO index from 1, keys in any order, unknown extra keys ignored;
:mod:`.wire_fields`) and converted once to the SI values of
:class:`~.twin_controller.TwinController`. Every request gets exactly one reply (:mod:`.replies`):
``errorCode`` "0" on success, "1" for a wrong request (unknown command, missing or malformed
field, malformed JSON), "2" for a command refused in the current state, or what a real
controller was recorded answering — never an exception, never a silent close.

The handlers, by subject: :mod:`.arm_commands` (power, motion, servo, kinematics, drag),
:mod:`.setting_commands` (identity, frames, payload, speed, filters), :mod:`.io_commands`,
:mod:`.program_commands`, :mod:`.recording_commands` (trajectory recording, from the twin's),
:mod:`.tool_io_commands` (the tool connector, on the twin's),
:mod:`.mounting_commands` (the installation angle),
:mod:`.network_watch` (what happens to the motion when a client's connection is lost),
:mod:`.sensor_commands` (the torque sensor's settings; on an arm
with the sensor, :mod:`.force_commands` answers from the twin's sensor), and here the
emulator-only commands (a real controller answers them "unknown command"; they all start with
``emulator_`` — see :data:`EMULATOR_COMMANDS`).
"""
from __future__ import annotations

import logging
from collections import Counter
from typing import Any, Callable, Dict, Mapping, Optional, Tuple

from ..protocol.fields import Cmd, Field
from .arm_commands import ArmCommands
from .force_commands import ForceCommands
from .framing import Malformed
from .io_commands import IoCommands
from .mounting_commands import MountingCommands
from .network_watch import NetworkWatch
from .program_commands import ProgramCommands
from .recording_commands import RecordingCommands
from .replies import ERROR_REFUSED, Answer, RecordedReply, Rejected, error_reply, success_reply
from .sensor_commands import SensorCommands
from .setting_commands import SettingCommands
from .tool_io_commands import ToolIoCommands
from .twin_controller import TwinController
from .wire_fields import flag, shown

log = logging.getLogger(__name__)

#: Emulator-only commands and what they do.
EMULATOR_COMMANDS = {
    "emulator_emergency_stop": '{"pressed": 1} presses the e-stop (power cut, arm halts), '
                               '{"pressed": 0} releases it',
    "emulator_protective_stop": 'protective stop, as after a collision; optional "reason"',
    "emulator_set_input": 'drive an input: "signal" digital/analog, "type", "index" (from 1), '
                          '"value"',
    "emulator_drop_connections": "reply, then close every client connection on both ports "
                                 "(the listening sockets stay open)",
    "emulator_stats": 'reply "commands": how many times each cmdName was received',
}


class CommandHandlers:
    """Dispatches requests to a :class:`TwinController`; ``counts`` records every ``cmdName``
    received (for ``emulator_stats``)."""

    def __init__(self, controller: TwinController):
        self.c = controller
        self.model = controller.model
        self.counts: Counter = Counter()
        #: set_network_exception_handle, and the command connections it watches
        self.network = NetworkWatch(controller)
        self._table: Dict[str, Callable[[Mapping], Answer]] = {
            **ArmCommands(controller).table(),
            **SettingCommands(controller).table(),
            **IoCommands(controller).table(),
            **ProgramCommands(controller).table(),
            **RecordingCommands(controller.backend.recording).table(),
            **ToolIoCommands(controller.backend.tool_io).table(),
            **self.network.table(),
            **MountingCommands(controller).table(),
            **SensorCommands(controller.sensor, self.model.max_payload_kg).table(),
            # an arm with the sensor answers what it makes a difference to from the twin's
            **(ForceCommands(controller).table() if controller.backend.force.absent is None
               else {}),
            Cmd.QUIT: lambda r: Answer(then="close"),
            "emulator_emergency_stop": lambda r: self._note(self.c.emergency_stop(
                flag(r, "pressed"))),
            "emulator_protective_stop": lambda r: self._note(self.c.protective_stop(
                str(r.get("reason") or "protective stop (emulator_protective_stop)")[:200])),
            "emulator_drop_connections": lambda r: Answer(then="drop_all"),
            "emulator_stats": lambda r: Answer({"commands": dict(self.counts)}),
        }

    @property
    def command_names(self) -> Tuple[str, ...]:
        return tuple(sorted(self._table))

    def handle(self, request: Any) -> Tuple[Dict[str, Any], Optional[str]]:
        """One request (a decoded JSON value or :class:`~.framing.Malformed`) → (reply, then).
        Never raises."""
        if isinstance(request, Malformed):
            return error_reply("", request.reason), None
        if not isinstance(request, dict):
            return error_reply("", "a request must be a JSON object"), None
        name = request.get(Field.CMD_NAME)
        if not isinstance(name, str) or not name:
            return error_reply("", f"the request has no string {Field.CMD_NAME!r}: "
                                   f"{shown(request)}"), None
        self.counts[name[:80]] += 1
        handler = self._table.get(name)
        if handler is None:
            return error_reply(name, f"unknown command {shown(name)}"), None
        try:
            answer = handler(request)
        except Rejected as rejected:
            return error_reply(name, rejected.message, rejected.code), None
        except RecordedReply as recorded:
            return recorded.reply, None
        except Exception as exc:  # noqa: BLE001 - a request must never take the server down
            log.exception("emulator: %s failed", name)
            return error_reply(name, f"{name} failed inside the emulator: {exc!r}",
                               ERROR_REFUSED), None
        return success_reply(name, answer.fields), answer.then

    def wait_before(self, request: Any, limit: float) -> None:
        """Called by the server outside its command lock before :meth:`handle`: a
        ``wait_complete`` request waits here (at most ``limit`` s) until the queue is done, so
        other clients are served meanwhile."""
        if isinstance(request, dict) and request.get(Field.CMD_NAME) == Cmd.WAIT_COMPLETE:
            self.c.wait_idle(limit)

    @staticmethod
    def _note(message: str) -> Answer:
        return Answer({Field.ERROR_MSG: message})

