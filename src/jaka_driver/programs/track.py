"""Recordings and their replay programs as files in the programs folder (docs/twin.md,
"Trajectory recording"): the twin's store behind ``backend.recording``.

Everything lives in the folder ``track/`` of the programs folder, as on a JAKA controller,
whose ``generate_traj_exe_file`` writes the program ``program_load("track/<name>")`` loads:

* ``track/<name>.track`` — the recording: the points kept, one a line: the time since the
  recording started (s), the tool's pose (mm + rotation vector rad, the tool active when it was
  recorded in the user frame active then) and the joints (rad); ``#`` lines say what it is;
* ``track/<name>.jdp`` — its replay program, in the format of docs/programs.md: a joint move
  to the first kept point's joints at :data:`APPROACH_SPEED` (so the replay starts from the
  recorded arm configuration, wherever the arm stands), then one ``linear_move`` through each
  later point at the configured speed and acceleration.

Names are checked by the caller (jaka_driver.backend.recording.checked_name): a name is a file
name, never a path, so nothing outside the folder is read or written.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import List, Optional, Sequence

import numpy as np

from ..backend.recording import TRACK_FOLDER, TrajConfig
from .folder import SUFFIX
from .parser import MAX_BYTES

#: a recording's file suffix
RECORDING_SUFFIX = ".track"
#: rad/s: the replay program's joint move to the first kept point
APPROACH_SPEED = 0.5


@dataclass(frozen=True)
class KeptPoint:
    """One point of a recording: ``elapsed`` s since it started, ``pose_mm`` (6: mm + rotation
    vector rad), ``joints`` (6, rad)."""

    elapsed: float
    pose_mm: np.ndarray
    joints: np.ndarray


class TrackFolder:
    """The recordings and replay programs under ``programs`` (the programs folder; None: none
    is set, and :attr:`folder` is None)."""

    def __init__(self, programs: Optional[Path]):
        self.folder = Path(programs) / TRACK_FOLDER if programs is not None else None

    def _path(self, name: str, suffix: str) -> Path:
        return self.folder / f"{name}{suffix}"

    def names(self) -> List[str]:
        if self.folder is None or not self.folder.is_dir():
            return []
        return sorted(p.stem for p in self.folder.glob(f"*{RECORDING_SUFFIX}") if p.is_file())

    def exists(self, name: str) -> bool:
        return self.folder is not None and self._path(name, RECORDING_SUFFIX).is_file()

    def save(self, name: str, points: Sequence[KeptPoint], config: TrajConfig,
             frames: str) -> Path:
        """Write recording ``name`` (replacing one of that name); ``frames`` says which tool and
        user frame its poses are in."""
        self.folder.mkdir(parents=True, exist_ok=True)
        lines = [f"# recording {name}: {len(points)} kept points; {config.describe()}; "
                 f"{frames}",
                 "# elapsed_s x_mm y_mm z_mm rx ry rz (rotation vector rad) j1 .. j6 (rad)"]
        lines += [" ".join([f"{p.elapsed:.3f}"] + [f"{v:.4f}" for v in p.pose_mm[:3]]
                           + [f"{v:.6f}" for v in p.pose_mm[3:]]
                           + [f"{v:.6f}" for v in p.joints]) for p in points]
        path = self._path(name, RECORDING_SUFFIX)
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        return path

    def load(self, name: str) -> List[KeptPoint]:
        """The kept points of recording ``name``; ValueError for a line that is not one."""
        points = []
        text = self._path(name, RECORDING_SUFFIX).read_text(encoding="utf-8")
        for number, line in enumerate(text.splitlines(), 1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            values = np.array([float(v) for v in line.split()])
            if values.shape != (13,) or not np.all(np.isfinite(values)):
                raise ValueError(f"line {number} of {name}{RECORDING_SUFFIX} is not a kept "
                                 "point (13 numbers)")
            points.append(KeptPoint(float(values[0]), values[1:7], values[7:13]))
        return points

    def rename(self, src: str, dest: str) -> None:
        """Rename recording ``src`` and its program, if generated, to ``dest``."""
        for suffix in (RECORDING_SUFFIX, SUFFIX):
            path = self._path(src, suffix)
            if path.is_file():
                path.rename(self._path(dest, suffix))

    def remove(self, name: str) -> None:
        """Remove recording ``name`` and its program, if generated."""
        for suffix in (RECORDING_SUFFIX, SUFFIX):
            self._path(name, suffix).unlink(missing_ok=True)

    def write_program(self, name: str, points: Sequence[KeptPoint], config: TrajConfig) -> Path:
        """Write the replay program of ``points`` as ``track/<name>`` (see the module);
        ValueError when it would be longer than a program may be (the parser's ``MAX_BYTES``)."""
        _, _, vel, acc = config.request_units()
        first = points[0]
        lines = [f"# {TRACK_FOLDER}/{name}: the replay of recording {name}, {len(points)} kept "
                 "points (generate_traj_exe_file)",
                 "# poses mm + rotation vector: the tool and user frame active when recorded",
                 f"joint_move {_numbers(first.joints, 6)} speed {APPROACH_SPEED:g}"
                 "      # to the first kept point"]
        lines += [f"linear_move {_numbers(p.pose_mm[:3], 4, p.pose_mm[3:], 6)} "
                  f"speed {vel:.6g} accel {acc:.6g}" for p in points[1:]]
        text = "\n".join(lines) + "\n"
        size = len(text.encode("utf-8"))
        if size > MAX_BYTES:
            raise ValueError(f"its replay of {len(points)} kept points would be {size} bytes, "
                             f"a program has at most {MAX_BYTES}: record with a larger "
                             "xyz_interval or rpy_interval")
        self.folder.mkdir(parents=True, exist_ok=True)
        path = self._path(name, SUFFIX)
        path.write_text(text, encoding="utf-8")
        return path


def _numbers(values, places: int, more=(), more_places: int = 6) -> str:
    """``[a, b, …]`` with ``places`` decimals (``more`` after them with ``more_places``)."""
    parts = [f"{v:.{places}f}" for v in values] + [f"{v:.{more_places}f}" for v in more]
    return "[" + ", ".join(parts) + "]"
