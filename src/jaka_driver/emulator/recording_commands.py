"""Trajectory recording over JAKA's eight commands (docs/protocol.md, "Trajectory recording"),
answered from the twin's recording facet (``backend.recording``, :class:`~jaka_driver.sim.
recording.SimRecording`): the twin records the tool's path whatever moves it, keeps the
recordings in the ``track/`` folder of the emulator's programs folder (``--programs DIR``), and
``generate_traj_exe_file`` writes the replay program that ``load_program`` then loads as
``track/<name>`` (with JAKA's SDK's ".jks") and ``play_program`` plays through the twin's
program engine on the emulator's controller rules.

Requests and replies as JAKA's SDK 2.1.14 writes and reads them: ``set_traj_config``
(``xyz_interval`` mm, ``rpy_interval`` deg, ``vel`` mm/s, ``acc`` mm/s², unconverted),
``get_traj_config`` (the four as doubles), ``set_traj_sample_mode`` (``filename``, ``mode`` 1
start / 0 stop), ``get_traj_sample_status`` (``sampleStatus`` an int),
``get_exist_traj_file_name`` (``trajTrackFileName`` a list of strings),
``rename_traj_file_name`` (``src``, ``dest``), ``generate_traj_exe_file`` and
``remove_traj_file`` (``fileName``). Every reply's ``errorCode`` is a string; what the twin
refuses is refused with its reason, "1" for a value (a name, a threshold) and "2" for the state
(already recording, a recording being recorded).
"""
from __future__ import annotations

from typing import Callable, Dict, Mapping

from ..backend.recording import Recording, TrajConfig
from ..common.results import Code, Result
from ..protocol.fields import Cmd, Field
from .replies import ERROR_REFUSED, ERROR_REQUEST, Answer, Rejected
from .wire_fields import integer, number, shown_name, text


class RecordingCommands:
    """Handlers of the eight recording commands on ``recording`` (the twin's facet)."""

    def __init__(self, recording: Recording):
        self.recording = recording

    def table(self) -> Dict[str, Callable[[Mapping], Answer]]:
        rec = self.recording
        return {
            Cmd.SET_TRAJ_CONFIG: self._set_config,
            Cmd.GET_TRAJ_CONFIG: self._config,
            Cmd.SET_TRAJ_SAMPLE_MODE: self._sample_mode,
            Cmd.GET_TRAJ_SAMPLE_STATUS: lambda r: Answer(
                {Field.SAMPLE_STATUS: 1 if self._done(r, rec.sampling()) else 0}),
            Cmd.GET_EXIST_TRAJ_FILE_NAME: lambda r: Answer(
                {Field.TRAJ_FILE_NAMES: list(self._done(r, rec.names()))}),
            Cmd.RENAME_TRAJ_FILE_NAME: lambda r: self._answer(r, rec.rename(
                text(r, Field.TRAJ_SRC), text(r, Field.TRAJ_DEST))),
            Cmd.REMOVE_TRAJ_FILE: lambda r: self._answer(r, rec.remove(
                text(r, Field.TRAJ_FILE_NAME))),
            Cmd.GENERATE_TRAJ_EXE_FILE: lambda r: self._answer(r, rec.generate(
                text(r, Field.TRAJ_FILE_NAME))),
        }

    @staticmethod
    def _done(req: Mapping, result: Result):
        """``result``'s value, or the refusal with its reason."""
        if not result.ok:
            code = ERROR_REQUEST if result.code == Code.INVALID_PARAMETER else ERROR_REFUSED
            raise Rejected(f"{shown_name(req)}: {result.message}", code)
        return result.value

    def _answer(self, req: Mapping, result: Result) -> Answer:
        self._done(req, result)
        return Answer()

    def _set_config(self, req: Mapping) -> Answer:
        config = TrajConfig.from_request(*(number(req, key) for key in (
            Field.XYZ_INTERVAL, Field.RPY_INTERVAL, Field.TRAJ_VEL, Field.TRAJ_ACC)))
        return self._answer(req, self.recording.set_config(config))

    def _config(self, req: Mapping) -> Answer:
        config = self._done(req, self.recording.config())
        return Answer(dict(zip((Field.XYZ_INTERVAL, Field.RPY_INTERVAL, Field.TRAJ_VEL,
                                Field.TRAJ_ACC), (float(v) for v in config.request_units()))))

    def _sample_mode(self, req: Mapping) -> Answer:
        on = integer(req, Field.TRAJ_MODE, 0, 1)
        name = text(req, Field.TRAJ_FILENAME, default="")      # a stop needs none
        return self._answer(req, self.recording.start(name) if on else self.recording.stop())
