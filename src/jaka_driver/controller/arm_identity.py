"""What the controller says the arm is, read at every connection: the identity strings of
``get_version`` and the arm's own kinematic parameters of ``get_dh_param`` (docs/protocol.md,
"Identity" and "Kinematic parameters").

The parameters are logged beside the model's own chain (``kinematics.controller_dh``), with a
warning when the two differ by more than a calibration explains
(:data:`~jaka_driver.kinematics.controller_dh.CALIBRATION_TOLERANCE`): then the arm connected is
not the ``model`` the driver was started with, and the driver's own kinematics (limits, the
twin-side checks, rviz) describe another arm. Both are only read, logged and shown in
:meth:`ArmIdentity.describe` (diagnostics); the driver's kinematics stay the model's.
"""
from __future__ import annotations

import logging
import threading
from typing import Callable, Dict, Optional

from ..kinematics.controller_dh import (CALIBRATION_TOLERANCE, DHParameters, chain_difference,
                                        dh_of_model)
from ..common.models import RobotModel
from ..common.results import CommandRefused
from ..protocol import commands
from ..protocol.fields import Field

log = logging.getLogger(__name__)

#: describe() names of the identity keys of get_version
_IDENTITY_NAMES = {Field.VERSION: "controller version", Field.CONTROLLER_ID: "controller id",
                   Field.CONTROLLER_GUARANTEE: "controller guarantee",
                   Field.ROBOT_ID: "robot id", Field.ROBOT_NAME: "robot name",
                   Field.SCB_VERSION: "scb version", Field.SERVO_VERSION: "servo version"}

#: ``read(request, accessor)`` → the accessor's value; raises CommandRefused (Commander.read).
Reader = Callable[[dict, Callable], object]


class ArmIdentity:
    """The identity and kinematic parameters of the controller's arm, next to ``model``'s."""

    def __init__(self, model: RobotModel):
        self.model = model
        self._lock = threading.Lock()
        self.identity: Dict[str, str] = {}
        self.dh: Optional[DHParameters] = None
        """the controller's parameters (SI), None until read"""
        self.difference: Optional[float] = None
        """worst flange-position difference (m) between them and the model's chain"""
        self._model_dh: Optional[DHParameters] = None

    @property
    def version(self) -> str:
        return self.identity.get(Field.VERSION, "")

    @property
    def model_dh(self) -> DHParameters:
        if self._model_dh is None:
            self._model_dh = dh_of_model(self.model)
        return self._model_dh

    @property
    def is_other_arm(self) -> bool:
        """The controller's parameters are not a calibration of the model's chain."""
        return self.difference is not None and self.difference > CALIBRATION_TOLERANCE

    def read(self, read: Reader) -> None:
        """Read both from the controller (at a connection); what a controller cannot answer is
        logged and left unknown."""
        try:
            identity = read(commands.get_version(), commands.reply_identity)
        except CommandRefused as refusal:
            log.info("get_version unavailable: %s", refusal.message)
        else:
            with self._lock:
                self.identity = dict(identity)
            log.info("controller: %s", ", ".join(f"{_IDENTITY_NAMES[k]} {v}" for k, v in
                                                 identity.items()) or "no identity given")
        try:
            raw = read(commands.get_dh_param(), commands.reply_dh_param)
            dh = DHParameters.from_sdk(raw.alpha, raw.a, raw.d, raw.joint_homeoff)
        except CommandRefused as refusal:
            log.warning("the controller's kinematic parameters could not be read (%s); the "
                        "arm cannot be checked against model %s", refusal.message,
                        self.model.name)
            return
        except ValueError as exc:
            log.warning("the controller's kinematic parameters are unusable (%s)", exc)
            return
        self._compare(dh)

    def _compare(self, dh: DHParameters) -> None:
        difference = chain_difference(dh, self.model_dh)
        with self._lock:
            self.dh, self.difference = dh, difference
        log.info("kinematic parameters of the controller (get_dh_param): %s", dh.describe())
        log.info("kinematic parameters of model %s: %s", self.model.name,
                 self.model_dh.describe())
        if difference > CALIBRATION_TOLERANCE:
            log.warning("the arm connected is not a %s: its kinematic parameters put the flange "
                        "up to %.1f mm from where model %s puts it, more than a calibration "
                        "explains (%.1f mm). Start the driver with the arm's model; its own "
                        "kinematics (limits, planning, rviz) describe the %s", self.model.name,
                        difference * 1000.0, self.model.name, CALIBRATION_TOLERANCE * 1000.0,
                        self.model.name)
        else:
            log.info("the controller's kinematic parameters are model %s's within %.2f mm "
                     "(a calibration; tolerance %.1f mm)", self.model.name, difference * 1000.0,
                     CALIBRATION_TOLERANCE * 1000.0)

    def describe(self) -> dict:
        with self._lock:
            info = {_IDENTITY_NAMES[k]: v for k, v in self.identity.items()}
            dh, difference = self.dh, self.difference
        if dh is None:
            info["controller dh_param"] = "not read"
        else:
            info["controller dh_param"] = dh.describe()
            info["dh difference to the model (mm)"] = round(difference * 1000.0, 3)
            info["arm matches the model"] = difference <= CALIBRATION_TOLERANCE
        return info
