"""The arm's mounting over JAKA's commands, answered from the twin: ``set_installation_angle``
(``angleX``, ``angleZ`` in deg) turns the twin's gravity, ``get_installation_angle`` reads it back
as ``[[s, x, y, z], [rx, ry, rz deg]]`` (docs/protocol.md, "Mounting"). A value outside JAKA's
ranges (tilt 0–180°, rotation 0–360°) is a wrong request ("1"); while the arm moves the command
is refused ("2"), as the driver refuses it.
"""
from __future__ import annotations

import math
from typing import Callable, Dict, Mapping

from ..common.installation import installation
from ..protocol.fields import Cmd, Field
from ..protocol.installation import installation_reply
from .replies import Answer, Rejected
from .twin_controller import TwinController
from .wire_fields import number


class MountingCommands:
    """``set_installation_angle`` / ``get_installation_angle`` on ``controller``'s twin."""

    def __init__(self, controller: TwinController):
        self.c = controller

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        return {Cmd.SET_INSTALLATION_ANGLE: self._set,
                Cmd.GET_INSTALLATION_ANGLE: self._get}

    def _set(self, req: Mapping) -> Answer:
        tilt = math.radians(number(req, Field.ANGLE_X, lo=0.0, hi=180.0))
        rot = math.radians(number(req, Field.ANGLE_Z, lo=0.0, hi=360.0))
        with self.c.lock:
            self.c.require_still("set_installation_angle")
            result = self.c.backend.set_installation_angle(installation(tilt, rot))
        if not result.ok:
            raise Rejected(f"set_installation_angle: {result.message}")
        return Answer()

    def _get(self, req: Mapping) -> Answer:
        mounting = self.c.backend.installation_angle().value
        return Answer(installation_reply(mounting.quaternion, mounting.rpy))
