"""The door's trajectory-recording requests, offered by :class:`~.robot_driver.RobotDriver` as
``driver.recording`` (:class:`RecordingRequests`) on the backend's recording facet
(jaka_driver.backend.recording), whichever backend it is.

Order of checks: recording at all (-9, saying why: nothing a request changes can fix that) →
the request's fields (-2: names as program names, at most 100 characters; the configuration's
values above 0 and within the arm's limits — the rules of jaka_driver.backend.recording, which
the twin's facet applies too) → the facet's own (already recording -10, a recording that does
not exist -2). Recording only watches the arm, so no request here checks the arm's state: an
operator records in drag mode, under tool drive, while a program runs. Units are the
request's (JAKA's SDK's): mm, deg, mm/s, mm/s². Methods answer a :class:`Result` and never
raise; safe from many threads at once.
"""
from __future__ import annotations

from ..backend.recording import TrajConfig, checked_config, checked_name
from ..common.results import Code, CommandRefused, Result
from . import checks as check
from .door import Door, RequestPart, answers


class RecordingRequests(RequestPart):
    """Recording requests through ``door`` (see the module)."""

    def __init__(self, door: Door):
        super().__init__(door)

    @property
    def _facet(self):
        absent = self.backend.recording.absent
        if absent is not None:
            raise CommandRefused(Code.WRONG_MODE, absent)
        return self.backend.recording

    @answers
    def set_config(self, xyz_interval: float, rpy_interval: float, vel: float,
                   acc: float) -> Result:
        """``set_traj_config``: keep a point every ``xyz_interval`` mm or ``rpy_interval`` deg;
        replay at ``vel`` mm/s and ``acc`` mm/s²."""
        facet = self._facet
        values = [check.finite(name, value, unit) for name, value, unit in
                  (("xyz_interval", xyz_interval, "mm"), ("rpy_interval", rpy_interval, "deg"),
                   ("vel", vel, "mm/s"), ("acc", acc, "mm/s²"))]
        config = checked_config(TrajConfig.from_request(*values), self.model.max_tcp_speed,
                                self.model.max_tcp_accel)
        return facet.set_config(config)

    @answers(react=False)
    def config(self) -> Result:
        """``get_traj_config``: ``value`` the :class:`TrajConfig` (SI; ``request_units()``)."""
        return self._facet.config()

    @answers
    def set_sample_mode(self, on: bool, name: str = "") -> Result:
        """``set_traj_sample_mode``: start recording as ``name`` (on), or stop (off; the name
        is not used)."""
        facet = self._facet
        if not on:
            return facet.stop()
        return facet.start(checked_name("filename", name))

    @answers(react=False)
    def sample_status(self) -> Result:
        """``get_traj_sample_status``: ``value`` True while recording."""
        return self._facet.sampling()

    @answers(react=False)
    def names(self) -> Result:
        """``get_exist_traj_file_name``: ``value`` the recordings' names."""
        return self._facet.names()

    @answers
    def rename(self, src: str, dest: str) -> Result:
        facet = self._facet
        return facet.rename(checked_name("src", src), checked_name("dest", dest))

    @answers
    def remove(self, name: str) -> Result:
        facet = self._facet
        return facet.remove(checked_name("fileName", name))

    @answers
    def generate(self, name: str) -> Result:
        """``generate_traj_exe_file``: the replay program, then loaded as ``track/<name>``."""
        facet = self._facet
        return facet.generate(checked_name("fileName", name))
