"""The arm's mounting on a controller: ``set_installation_angle`` (deg, as JAKA's SDK sends it),
read back with ``get_installation_angle`` (docs/protocol.md, "Mounting"). No SDK function polls
the read-back after the set; the backend reads it back once, so that the answer says what the
controller now holds. The angle is also read at every connection (a pendant may have changed
it): the sensor's compensated reading is computed under the gravity it gives
(:attr:`.status_view.StatusView.gravity`). A controller that does not answer it is taken as
upright, and the log says so."""
from __future__ import annotations

import logging
import math

import numpy as np

from ..common.installation import Installation
from ..common.results import Code, CommandRefused, Result
from ..common.transforms import quat_to_matrix
from ..protocol import installation as wire
from .commander import Commander, answers
from .status_view import StatusView

log = logging.getLogger(__name__)


class ControllerMounting:
    """The installation angle through ``send``."""

    def __init__(self, send: Commander, view: StatusView):
        self.send = send
        self.view = view

    def read_at_connection(self) -> None:
        """The controller's angle, kept for the sensor's compensation; never raises."""
        try:
            held = self._read()
        except CommandRefused as refusal:
            log.info("get_installation_angle failed (%s): the arm is taken as upright",
                     refusal.message)
            held = Installation()
        if held.tilt_x > 1e-3:
            log.info("the controller's arm is mounted %s", held.describe())

    @answers
    def set(self, mounting: Installation) -> Result:
        self.send.accepted(wire.set_installation_angle(mounting.tilt_x, mounting.rot_z))
        held = self._read()
        if not np.allclose(held.rotation, mounting.rotation, atol=1e-4):
            raise CommandRefused(Code.CONTROLLER_REJECTED, "the controller acknowledged "
                                 f"set_installation_angle but reads back {held.describe()}")
        return Result.success(f"installation angle set: {held.describe()}")

    @answers
    def get(self) -> Result:
        held = self._read()
        return Result.success(held.describe(), held)

    def _read(self) -> Installation:
        """The controller's angle: from the quaternion (RPY as a cross-check is not needed:
        both are the same rotation), as tilt about x and rotation about z."""
        reading = self.send.read(wire.get_installation_angle(), wire.reply_installation_angle)
        r = quat_to_matrix(reading.quaternion)
        # R = Rz(z)·Rx(x): column 0 is (cos z, sin z, 0); row 2 is (0, sin x, cos x)
        tilt = math.atan2(r[2, 1], r[2, 2])
        rot = math.atan2(r[1, 0], r[0, 0]) % (2.0 * math.pi)
        held = Installation(tilt, rot)
        self.view.gravity = held.gravity
        return held
