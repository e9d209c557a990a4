"""Trajectory recording on a controller: the ``backend.recording`` facet
(:class:`~jaka_driver.backend.recording.Recording`) of the controller backend, on JAKA's eight
commands written as JAKA's SDK writes them (:mod:`jaka_driver.protocol.recording`;
docs/protocol.md, "Trajectory recording"). The controller records, keeps the recordings and
writes the replay program ``track/<name>``, which the program services then load and play.

The configuration is read back after it is set (``get_traj_config``, once: JAKA's SDK polls
nothing here): a controller that acknowledges but keeps other values did not do it (2).
Stopping sends ``set_traj_sample_mode`` 0 with the name the recording was started with (JAKA's
SDK sends nothing without a name). A refusal of the controller comes back as 2 with its
message; the link's failures as the commander maps them (-1, -3). Thread-safe.
"""
from __future__ import annotations

import threading

from ..backend.recording import TRACK_FOLDER, Recording, TrajConfig
from ..common.results import Code, CommandRefused, Result
from ..protocol import recording as wire
from .commander import Commander, answers

#: a read-back matches what was sent within these (mm or deg: the wire's 2 decimals; mm/s and
#: mm/s²: a reply's 6 decimals)
INTERVAL_MATCH = 0.0051
SPEED_MATCH = 1e-3


class ControllerRecording(Recording):
    """The controller's trajectory recording through ``send`` (see the module)."""

    def __init__(self, send: Commander):
        self.send = send
        self._lock = threading.Lock()
        self._name = ""           # the recording this driver started last

    @answers
    def set_config(self, config: TrajConfig) -> Result:
        sent = config.request_units()
        self.send.accepted(wire.set_traj_config(*sent))
        read = self.send.read(wire.get_traj_config(), wire.reply_traj_config)
        for field, want, got, match in zip(("xyz_interval", "rpy_interval", "vel", "acc"),
                                           sent, read, (INTERVAL_MATCH, INTERVAL_MATCH,
                                                        SPEED_MATCH, SPEED_MATCH)):
            if abs(want - got) > match:
                raise CommandRefused(Code.CONTROLLER_REJECTED, f"the controller acknowledged "
                                     f"set_traj_config but get_traj_config reads {field} "
                                     f"{got:g}, not {want:g}")
        return Result.success(f"trajectory recording: {config.describe()}")

    @answers
    def config(self) -> Result:
        read = self.send.read(wire.get_traj_config(), wire.reply_traj_config)
        config = TrajConfig.from_request(*read)
        return Result.success(config.describe(), config)

    @answers
    def start(self, name: str) -> Result:
        self.send.accepted(wire.set_traj_sample_mode(True, name))
        with self._lock:
            self._name = name
        return Result.success(f"recording {name!r}")

    @answers
    def stop(self) -> Result:
        with self._lock:
            name = self._name
        self.send.accepted(wire.set_traj_sample_mode(False, name))
        return Result.success(f"recording {name!r} stopped" if name else "recording stopped")

    @answers
    def sampling(self) -> Result:
        on = self.send.read(wire.get_traj_sample_status(), wire.reply_traj_sample_status)
        return Result.success("recording" if on else "not recording", on)

    @answers
    def names(self) -> Result:
        names = self.send.read(wire.get_exist_traj_file_name(), wire.reply_traj_file_names)
        return Result.success(f"{len(names)} recordings", sorted(names))

    @answers
    def rename(self, src: str, dest: str) -> Result:
        self.send.accepted(wire.rename_traj_file_name(src, dest))
        return Result.success(f"recording {src!r} is now {dest!r}")

    @answers
    def remove(self, name: str) -> Result:
        self.send.accepted(wire.remove_traj_file(name))
        return Result.success(f"recording {name!r} removed")

    @answers
    def generate(self, name: str) -> Result:
        self.send.accepted(wire.generate_traj_exe_file(name))
        program = f"{TRACK_FOLDER}/{name}"
        return Result.success(f"program {program} generated", program)
