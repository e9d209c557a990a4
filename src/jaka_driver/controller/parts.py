"""What the controller backend's request parts work with, declared once: :class:`RequestPart`,
the base of :class:`~.moves.MoveCommands` and :class:`~.servo_commands.ServoCommands`.

Each part is handed, at construction, everything it uses — the arm's model, the link and its
requests, the status view, the one slot of what runs now, the arm's identity, the local
kinematics and the arm's settings — and uses nothing else of the backend.
"""
from __future__ import annotations

from typing import Callable

from ..common.models import RobotModel
from ..kinematics import Kinematics
from .arm_identity import ArmIdentity
from .arm_settings import ArmSettings
from .commander import Commander
from .connection import ControllerLink
from .running_motion import RunningMotion
from .status_view import StatusView


class RequestPart:
    """A part serving the requests of one subject on a controller of ``model``: requests
    through ``send`` over ``link``, the latest packet from ``view``, what runs and servo mode
    in ``motion``, motion allowed by ``identity``, ``kinematics()`` the local kinematics (read
    when used: it follows the controller's parameters), the active frames and the speed ratio
    from ``settings``."""

    def __init__(self, model: RobotModel, send: Commander, link: ControllerLink,
                 view: StatusView, motion: RunningMotion, identity: ArmIdentity,
                 kinematics: Callable[[], Kinematics], settings: ArmSettings):
        hand_in(self, model, send, link, view, motion, identity, kinematics)
        self.settings = settings


def hand_in(part, model: RobotModel, send: Commander, link: ControllerLink, view: StatusView,
            motion: RunningMotion, identity: ArmIdentity,
            kinematics: Callable[[], Kinematics]) -> None:
    """Give ``part`` what every part of the backend works with (:class:`RequestPart`'s
    attributes but the arm's settings: the force facet has its own ``settings()``)."""
    part.model = model
    part.send = send
    part.link = link
    part.view = view
    part.motion = motion
    part.identity = identity
    part.kinematics = kinematics
