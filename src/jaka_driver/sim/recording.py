"""Trajectory recording on the twin: the ``backend.recording`` facet
(:class:`~jaka_driver.backend.recording.Recording`) of :class:`~.backend.SimBackend`.

While a recording runs, :meth:`SimRecording.sample` — one of the physics loop's per-cycle
checks — reads the tool's pose from the cycle's measured joints, whatever moves the arm (drag
mode, tool drive under a push, jogs, moves, programs, servo streams), and keeps a point
whenever the tool has moved ``xyz_interval`` or turned ``rpy_interval`` since the last kept
point (:class:`PathSampler`; the pose it starts at, the latest sample's, is always kept). The pose is the tool that
was active when the recording started in the user frame active then, so a frame changed
meanwhile does not bend the path. In simulated time the same requests keep the same points,
bit for bit: the sampling runs in the cycle, never in a thread of its own.

Stopping writes the recording into the programs folder (``track/<name>.track``); generating
writes its replay program ``track/<name>`` (:mod:`jaka_driver.programs.track`), which the
twin's program engine loads and plays with all its checks. A reset of the twin ends a
recording under way (keeping what it recorded) and restores the default configuration.
"""
from __future__ import annotations

import threading
from pathlib import Path
from typing import Callable, List, Optional

import numpy as np

from ..backend.recording import Recording, TrajConfig, checked_config, checked_name
from ..common.results import Code, CommandRefused, Result
from ..common.transforms import matrix_to_pose_mm
from ..programs.folder import TRACK_PREFIX
from ..programs.track import KeptPoint, TrackFolder

#: refusal of every file request without a programs folder
NO_FOLDER = ("no programs folder is set: recordings live in its track/ folder (the node's "
             "~programs parameter, launch argument programs; the emulator's --programs)")


class PathSampler:
    """The points of one recording: :meth:`offer` each cycle's pose; a point is kept when the
    position has moved ``xyz_interval`` m or the orientation turned ``rpy_interval`` rad since
    the last kept one."""

    def __init__(self, config: TrajConfig):
        self._xyz = config.xyz_interval
        self._rpy = config.rpy_interval
        self._started: Optional[float] = None       # s, the first offer's stamp
        self.points: List[KeptPoint] = []
        self._last: Optional[np.ndarray] = None     # 4x4 of the last kept point

    def offer(self, stamp: float, q: np.ndarray, tcp: np.ndarray) -> bool:
        """``tcp`` (4x4, m) at joints ``q`` (rad), ``stamp`` s; True if kept."""
        if self._started is None:
            self._started = stamp
        last = self._last
        if last is not None:
            moved = float(np.linalg.norm(tcp[:3, 3] - last[:3, 3]))
            cos = (float(np.trace(last[:3, :3].T @ tcp[:3, :3])) - 1.0) / 2.0
            turned = float(np.arccos(min(1.0, max(-1.0, cos))))
            if moved < self._xyz and turned < self._rpy:
                return False
        self._last = tcp.copy()
        self.points.append(KeptPoint(stamp - self._started, matrix_to_pose_mm(tcp),
                                     np.array(q, float)))
        return True


class _Take:
    """A recording under way: its name, the frames it is in, its sampler."""

    def __init__(self, name: str, tool: np.ndarray, user: np.ndarray, frames: str,
                 sampler: PathSampler, config: TrajConfig):
        self.name, self.tool, self.user, self.frames = name, tool, user, frames
        self.sampler, self.config = sampler, config


class SimRecording(Recording):
    """Recording on the twin (see the module): ``programs`` the programs folder (None: none),
    ``kinematics`` the arm's, ``frames()`` the active (tool, user) 4x4s and ``frame_ids()``
    their ids, ``physics`` the loop (its latest sample: a recording keeps the pose it starts
    at), ``max_speed`` / ``max_accel`` the arm's TCP
    limits (m/s, m/s²)."""

    def __init__(self, programs: Optional[Path], kinematics, frames: Callable, frame_ids:
                 Callable, physics, max_speed: float, max_accel: float):
        self._store = TrackFolder(programs)
        self._kin = kinematics
        self._frames = frames
        self._frame_ids = frame_ids
        self._physics = physics
        self._limits = (max_speed, max_accel)
        self._lock = threading.Lock()
        self._config = TrajConfig()
        self._take: Optional[_Take] = None

    # ---- the physics thread -----------------------------------------------------------------
    def sample(self, d) -> None:
        """A cycle has run (``d`` its MjData): offer the tool's pose to the recording, if any."""
        take = self._take
        if take is None:
            return
        q = d.qpos[:6]
        tcp = self._kin.tcp_pose(q, take.tool, take.user)
        with self._lock:
            if self._take is take:
                take.sampler.offer(float(d.time), q, tcp)

    # ---- the facet ----------------------------------------------------------------------------
    def set_config(self, config: TrajConfig) -> Result:
        try:
            checked_config(config, *self._limits)
        except CommandRefused as refusal:
            return refusal.result()
        with self._lock:
            self._config = config
        return Result.success(f"trajectory recording: {config.describe()}")

    def config(self) -> Result:
        config = self._config
        return Result.success(config.describe(), config)

    def start(self, name: str) -> Result:
        try:
            name = checked_name("filename", name)
        except CommandRefused as refusal:
            return refusal.result()
        if self._store.folder is None:
            return Result.failure(Code.WRONG_MODE, NO_FOLDER)
        tool, user = self._frames()
        tool_id, user_id = self._frame_ids()
        frames = f"tool {tool_id}, user frame {user_id}"
        with self._lock:
            if self._take is not None:
                return Result.failure(Code.BUSY, f"filename is {name!r}: already recording "
                                      f"{self._take.name!r} (set_traj_sample_mode 0 stops it)")
            config = self._config
            take = self._take = _Take(name, tool.copy(), user.copy(), frames,
                                      PathSampler(config), config)
            now = self._physics.sample()          # stamped wall0 + d.time, as below
            take.sampler.offer(now.stamp - self._physics.wall0, now.q,
                               self._kin.tcp_pose(now.q, take.tool, take.user))
        return Result.success(f"recording {name!r} ({config.describe()}; {frames})")

    def stop(self) -> Result:
        with self._lock:
            take, self._take = self._take, None
        if take is None:
            return Result.success("not recording")
        points = take.sampler.points
        try:
            path = self._store.save(take.name, points, take.config, take.frames)
        except OSError as exc:
            return Result.failure(Code.COMMUNICATION_ERROR, f"recording {take.name!r} could "
                                  f"not be written: {exc}")
        return Result.success(f"recorded {take.name!r}: {len(points)} kept points in {path}",
                              len(points))

    def sampling(self) -> Result:
        take = self._take
        return Result.success(f"recording {take.name!r}" if take else "not recording",
                              take is not None)

    def names(self) -> Result:
        names = self._store.names()
        return Result.success(f"{len(names)} recordings", names)

    def _existing(self, field: str, name: str) -> str:
        """``name`` checked, kept in the folder and not being recorded; else a refusal."""
        name = checked_name(field, name)
        if self._store.folder is None:
            raise CommandRefused(Code.WRONG_MODE, NO_FOLDER)
        take = self._take
        if take is not None and take.name == name:
            raise CommandRefused(Code.BUSY, f"{field} is {name!r}: it is being recorded "
                                 "(set_traj_sample_mode 0 stops it)")
        if not self._store.exists(name):
            there = ", ".join(self._store.names()) or "none"
            raise CommandRefused(Code.INVALID_PARAMETER, f"{field} is {name!r}: no recording "
                                 f"of that name (recordings: {there})")
        return name

    def rename(self, src: str, dest: str) -> Result:
        try:
            src = self._existing("src", src)
            dest = checked_name("dest", dest)
            take = self._take
            if self._store.exists(dest) or (take is not None and take.name == dest):
                raise CommandRefused(Code.INVALID_PARAMETER, f"dest is {dest!r}: a recording "
                                     "of that name exists (remove it first)")
        except CommandRefused as refusal:
            return refusal.result()
        self._store.rename(src, dest)
        return Result.success(f"recording {src!r} is now {dest!r}")

    def remove(self, name: str) -> Result:
        try:
            name = self._existing("fileName", name)
        except CommandRefused as refusal:
            return refusal.result()
        self._store.remove(name)
        return Result.success(f"recording {name!r} removed")

    def generate(self, name: str) -> Result:
        try:
            name = self._existing("fileName", name)
            points = self._store.load(name)
        except CommandRefused as refusal:
            return refusal.result()
        except (OSError, ValueError) as exc:
            return Result.failure(Code.INVALID_PARAMETER, f"fileName is {name!r}: the "
                                  f"recording cannot be read: {exc}")
        if not points:
            return Result.failure(Code.INVALID_PARAMETER, f"fileName is {name!r}: the "
                                  "recording kept no point")
        try:
            self._store.write_program(name, points, self._config)
        except ValueError as exc:
            return Result.failure(Code.INVALID_PARAMETER, f"fileName is {name!r}: {exc}")
        except OSError as exc:
            return Result.failure(Code.COMMUNICATION_ERROR, f"fileName is {name!r}: the "
                                  f"program cannot be written: {exc}")
        return Result.success(f"program {TRACK_PREFIX}{name} generated: {len(points)} kept "
                              f"points at {self._config.describe()}",
                              f"{TRACK_PREFIX}{name}")

    def reset(self) -> None:
        """A fresh start: a recording under way ends (what it kept is written), and the
        configuration is the default again."""
        self.stop()
        with self._lock:
            self._config = TrajConfig()
