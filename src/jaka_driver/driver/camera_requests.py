"""The door's camera requests, offered by :class:`~.robot_driver.RobotDriver` as
``driver.cameras`` (:class:`CameraRequests`) on the backend's cameras
(jaka_driver.backend.cameras), whichever backend it is.

Order of checks: a camera at all (-9, saying how to get one) → the camera's name (-2, naming
the cameras there are) → the facet's own (the renderer unavailable, -9). A refused request
changes nothing. Cameras move nothing: the arm's state is not checked. Starting and stopping a
stream is not a reply a client waits on to send its next command: it opens no reaction window
in simulated time (``react=False``).
"""
from __future__ import annotations

from ..backend.cameras import CameraStats, Listener
from ..common.camera_spec import CameraSpec
from ..common.results import Code, CommandRefused, Result
from .door import RequestPart, answers


class CameraRequests(RequestPart):
    """Camera requests through ``door`` (see the module)."""

    @property
    def _cameras(self):
        return self.backend.cameras

    def specs(self) -> tuple[CameraSpec, ...]:
        """Every camera as configured (empty without cameras): a read, never refused."""
        return self._cameras.specs()

    def _named(self, name: str) -> CameraSpec:
        absent = self._cameras.absent
        if absent is not None:
            raise CommandRefused(Code.WRONG_MODE, absent)
        for spec in self._cameras.specs():
            if spec.name == name:
                return spec
        names = ", ".join(s.name for s in self._cameras.specs())
        raise CommandRefused(Code.INVALID_PARAMETER, f"camera is {name!r}, expected one of "
                             f"{names}")

    @answers(react=False)
    def stream(self, name: str, on: bool) -> Result:
        """Render camera ``name`` at its rate (``on``) or stop it."""
        self._named(name)
        return self._cameras.stream(name, bool(on))

    @answers(react=False)
    def listen(self, listener: Listener) -> Result:
        """``listener`` gets every frame of every streaming camera (from the rendering
        thread)."""
        absent = self._cameras.absent
        if absent is not None:
            raise CommandRefused(Code.WRONG_MODE, absent)
        return self._cameras.listen(listener)

    def stats(self, name: str) -> CameraStats:
        """Frames rendered and dropped, render times (a read, never refused)."""
        return self._cameras.stats(name)
