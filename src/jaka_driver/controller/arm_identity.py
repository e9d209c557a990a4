"""What the controller says the arm is, read at every connection: the identity strings of
``get_version`` and the arm's own kinematic parameters of ``get_dh_param`` (docs/protocol.md,
"Identity" and "Kinematic parameters") — and which chain the driver's own kinematics use.

The parameters are compared with the ``model``'s chain (``kinematics.controller_dh``). Within
what a calibration explains (:data:`~jaka_driver.kinematics.controller_dh.CALIBRATION_TOLERANCE`)
they are the arm's own: the driver's local kinematics (the whole-path check of ``linear_move``)
use them (:attr:`ArmIdentity.kinematic_model`). Beyond it the arm is not the ``model`` given:
one error line names the model the numbers look like, and every motion is refused
(:meth:`ArmIdentity.require_motion`, -9) until the ``kinematics`` choice says which is right:

* ``auto`` (default): the controller's parameters when they are a calibration of the model's
  chain; motion refused when they are another arm's;
* ``controller``: the controller's parameters whatever they are (the model's limits, speeds and
  payload stay);
* ``model``: the model's nominal chain; the controller's parameters are only logged.

A controller that does not answer ``get_dh_param`` leaves the model's chain in use.
"""
from __future__ import annotations

import logging
import threading
from typing import Callable, Dict, Optional

import numpy as np

from ..common.models import RobotModel
from ..common.results import Code, CommandRefused
from ..kinematics.calibrated_chain import with_dh
from ..kinematics.controller_dh import (CALIBRATION_TOLERANCE, DHParameters, chain_difference,
                                        dh_of_model, nearest_models)
from ..protocol import commands
from ..protocol.fields import Field

log = logging.getLogger(__name__)

#: describe() names of the identity keys of get_version
_IDENTITY_NAMES = {Field.VERSION: "controller version", Field.CONTROLLER_ID: "controller id",
                   Field.CONTROLLER_GUARANTEE: "controller guarantee",
                   Field.ROBOT_ID: "robot id", Field.ROBOT_NAME: "robot name",
                   Field.SCB_VERSION: "scb version", Field.SERVO_VERSION: "servo version"}

#: The ``kinematics`` choices (the node's ``~kinematics``), see the module doc.
KINEMATICS_CHOICES = ("auto", "controller", "model")

#: ``read(request, accessor)`` → the accessor's value; raises CommandRefused (Commander.read).
Reader = Callable[[dict, Callable], object]


class ArmIdentity:
    """The identity and kinematic parameters of the controller's arm, next to ``model``'s;
    ``kinematics`` one of :data:`KINEMATICS_CHOICES`."""

    def __init__(self, model: RobotModel, kinematics: str = "auto"):
        if kinematics not in KINEMATICS_CHOICES:
            raise ValueError(f"kinematics is {kinematics!r}; expected one of "
                             f"{', '.join(KINEMATICS_CHOICES)}")
        self.model = model
        self.choice = kinematics
        self._lock = threading.Lock()
        self.identity: Dict[str, str] = {}
        self.dh: Optional[DHParameters] = None
        """the controller's parameters (SI), None until read"""
        self.difference: Optional[float] = None
        """worst flange-position difference (m) between them and the model's chain"""
        self._model_dh: Optional[DHParameters] = None
        self.kinematic_model: RobotModel = model
        """the model whose chain the driver's local kinematics use: ``model``, or ``model``
        with the controller's parameters (:func:`~jaka_driver.kinematics.calibrated_chain.
        with_dh`)"""
        self.refusal: Optional[str] = None
        """why motion is refused (the arm is another model's and nobody said which is right),
        or None"""

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
        log.info("kinematic parameters of the controller (get_dh_param): %s", dh.describe())
        log.info("kinematic parameters of model %s: %s", self.model.name,
                 self.model_dh.describe())
        name = self.model.name
        refusal = None
        if difference <= CALIBRATION_TOLERANCE:
            use_controller = self.choice != "model"
            log.info("the controller's kinematic parameters are model %s's within %.2f mm (a "
                     "calibration; tolerance %.1f mm): the driver's kinematics use %s", name,
                     difference * 1000.0, CALIBRATION_TOLERANCE * 1000.0,
                     "them" if use_controller else f"{name}'s nominal chain (~kinematics model)")
        else:
            use_controller = self.choice == "controller"
            looks_like, match = _looks_like(dh)
            if self.choice == "auto":
                refusal = (f"the arm is {looks_like}, not model:={name} (its kinematic "
                           f"parameters are {difference * 1000.0:.1f} mm from {name}'s); restart "
                           f"with model:={match}, or with kinematics:=controller or kinematics:=model")
                log.error("model:=%s does not match the arm: the controller's kinematic "
                          "parameters (get_dh_param) are %s, %.1f mm from %s's chain at the "
                          "flange, more than a calibration explains (%.1f mm). Every motion is "
                          "refused until you restart with model:=%s, or with "
                          "kinematics:=controller (the controller's parameters with %s's "
                          "limits) or kinematics:=model (%s's chain)", name, looks_like, difference * 1000.0, name,
                          CALIBRATION_TOLERANCE * 1000.0, match, name, name)
            else:
                log.warning("model:=%s does not match the arm (the controller's kinematic "
                            "parameters are %s, %.1f mm from %s's chain); ~kinematics %s: the "
                            "driver's kinematics use %s and motion is allowed", name,
                            looks_like, difference * 1000.0, name, self.choice,
                            "the controller's parameters" if use_controller
                            else f"{name}'s chain")
        kinematic_model = self.model
        if use_controller:
            try:
                kinematic_model = with_dh(self.model, dh)
            except (ValueError, np.linalg.LinAlgError) as exc:
                log.warning("the controller's kinematic parameters cannot be built into a "
                            "chain (%s); the driver's kinematics use %s's", exc, name)
        with self._lock:
            self.dh, self.difference = dh, difference
            self.kinematic_model, self.refusal = kinematic_model, refusal

    def require_motion(self, what: str) -> None:
        """Raise the refusal (-9) of a motion request ``what`` while the arm is another
        model's and nobody said which is right."""
        refusal = self.refusal
        if refusal is not None:
            raise CommandRefused(Code.WRONG_MODE, f"{what} refused: {refusal}")

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
        info["kinematics"] = (f"{self.choice}: " + (
            "motion refused, the arm is another model's" if self.refusal else
            "the controller's parameters" if self.kinematic_model is not self.model else
            f"{self.model.name}'s chain"))
        return info


def _looks_like(dh: DHParameters) -> tuple[str, str]:
    """(which models' chain ``dh`` is, within a calibration, or the nearest — for a log line;
    the model to restart with, or ``<the arm's model>`` when none matches)."""
    ranked = nearest_models(dh)
    same = [name for name, difference in ranked if difference <= CALIBRATION_TOLERANCE]
    if not same:
        name, difference = ranked[0]
        return (f"no JAKA model's (the nearest, {name}, is {difference * 1000.0:.1f} mm off)",
                "<the arm's model>")
    first = f"a {same[0]}'s"
    if len(same) > 1:
        first += f" (the same chain as {', '.join(same[1:])})"
    return first, same[0]
