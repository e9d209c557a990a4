"""Trajectory recording — teaching by demonstration — as a backend offers it: the facet
``backend.recording`` (:class:`Recording`), never None. A backend without it offers
:class:`NoRecording`, which refuses every request with -9 and says why.

JAKA's SDK has eight functions for it (docs/interface.md, "Trajectory recording"), and this
facet has one method for each:

* :meth:`Recording.set_config` / :meth:`Recording.config` — ``set_traj_config`` /
  ``get_traj_config``: the sampling thresholds (a point is kept whenever the tool has moved
  ``xyz_interval`` or turned ``rpy_interval`` since the last kept point) and the replay's speed
  and acceleration (:class:`TrajConfig`);
* :meth:`Recording.start` / :meth:`Recording.stop` — ``set_traj_sample_mode`` 1 with a name /
  0; :meth:`Recording.sampling` — ``get_traj_sample_status``;
* :meth:`Recording.names`, :meth:`Recording.rename`, :meth:`Recording.remove` —
  ``get_exist_traj_file_name``, ``rename_traj_file_name``, ``remove_traj_file``;
* :meth:`Recording.generate` — ``generate_traj_exe_file``: the recording as a program the
  program services load as ``track/<name>`` (:data:`TRACK_FOLDER`) and play.

**The rules**, written once here for every backend (docs/design.md, "Where a new capability
lives"): a name is a program's name (:func:`checked_name`: letters, digits, ``_ - .``, no path,
at most :data:`MAX_NAME` characters — JAKA's header gives 100), the configuration's values are
sane (:func:`checked_config`: thresholds 0.01 mm / 0.01° or more, as the wire's 2 decimals
carry them), and the twin's facet refuses starting while it records, and
renaming, removing or generating a recording that does not exist or is being recorded.

Units: :class:`TrajConfig` holds SI (m, rad, m/s, m/s²); JAKA's SDK and the services speak mm,
deg, mm/s, mm/s² (:meth:`TrajConfig.from_request`, :meth:`TrajConfig.request_units`).
Thread-safe, like the backend. A refused request changes nothing.
"""
from __future__ import annotations

import math
import re
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Optional

from ..common.results import Code, CommandRefused, Result

#: JAKA's header: a recording's name has at most 100 characters
MAX_NAME = 100
#: the folder (under the programs folder) of the programs generated from recordings:
#: ``program_load("track/<name>")`` loads one
TRACK_FOLDER = "track"
_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.\-]*")
#: mm and deg: the largest sampling thresholds accepted (a threshold beyond them keeps no
#: point of a demonstration worth the name)
MAX_XYZ_INTERVAL_MM = 1000.0
MAX_RPY_INTERVAL_DEG = 180.0
#: mm and deg: the smallest thresholds — JAKA's SDK writes them with 2 decimals, so a smaller
#: one would reach a controller as 0
MIN_INTERVAL = 0.01


@dataclass(frozen=True)
class TrajConfig:
    """``set_traj_config``'s four values, SI: ``xyz_interval`` m and ``rpy_interval`` rad (a
    point is kept when the tool has moved or turned this much since the last kept point),
    ``speed`` m/s and ``accel`` m/s² (the replay's linear moves). The defaults are those of
    JAKA's example (0.1 mm, 0.2°, 25 mm/s, 100 mm/s²)."""

    xyz_interval: float = 0.1e-3
    rpy_interval: float = math.radians(0.2)
    speed: float = 25e-3
    accel: float = 100e-3

    @classmethod
    def from_request(cls, xyz_mm: float, rpy_deg: float, vel_mm_s: float,
                     acc_mm_s2: float) -> "TrajConfig":
        """From the request's units (JAKA's SDK's): mm, deg, mm/s, mm/s²."""
        return cls(float(xyz_mm) * 1e-3, math.radians(float(rpy_deg)), float(vel_mm_s) * 1e-3,
                   float(acc_mm_s2) * 1e-3)

    def request_units(self) -> tuple:
        """(xyz_interval mm, rpy_interval deg, vel mm/s, acc mm/s²)."""
        return (self.xyz_interval * 1e3, math.degrees(self.rpy_interval), self.speed * 1e3,
                self.accel * 1e3)

    def describe(self) -> str:
        x, r, v, a = self.request_units()
        return (f"xyz_interval {x:g} mm, rpy_interval {r:g} deg, vel {v:g} mm/s, "
                f"acc {a:g} mm/s²")


def checked_name(field: str, name) -> str:
    """``name`` as a recording's (and a program's) name, or a -2 refusal naming ``field``, the
    value and the rule."""
    if not isinstance(name, str):
        raise CommandRefused(Code.INVALID_PARAMETER, f"{field} is {name!r}, expected a name")
    text = name.strip()
    if len(text) > MAX_NAME:
        raise CommandRefused(Code.INVALID_PARAMETER, f"{field} has {len(text)} characters, at "
                             f"most {MAX_NAME}")
    if not _NAME.fullmatch(text) or text in (".", ".."):
        raise CommandRefused(Code.INVALID_PARAMETER, f"{field} is {name!r}, expected a "
                             "program's name (letters, digits, '_', '-', '.'; no path)")
    return text


def checked_config(config: TrajConfig, max_speed: float, max_accel: float) -> TrajConfig:
    """``config`` if every value is sane — thresholds from :data:`MIN_INTERVAL` to
    :data:`MAX_XYZ_INTERVAL_MM` / :data:`MAX_RPY_INTERVAL_DEG`, the replay's speed and
    acceleration above 0 and at most the arm's (``max_speed`` m/s, ``max_accel`` m/s²) —, or a
    -2 refusal naming the field, the value and the limit in the request's units."""
    x, r, v, a = config.request_units()
    for field, value, low, limit, unit in (
            ("xyz_interval", x, MIN_INTERVAL, MAX_XYZ_INTERVAL_MM, "mm"),
            ("rpy_interval", r, MIN_INTERVAL, MAX_RPY_INTERVAL_DEG, "deg"),
            ("vel", v, 0.0, max_speed * 1e3, "mm/s"),
            ("acc", a, 0.0, max_accel * 1e3, "mm/s²")):
        if not math.isfinite(value) or not low - 1e-9 <= value <= limit + 1e-9 or value <= 0:
            least = f"at least {low:g}" if low else "above 0"
            raise CommandRefused(Code.INVALID_PARAMETER, f"{field} is {value:g} {unit}, "
                                 f"expected {least} and at most {limit:g} {unit}")
    return config


class Recording(ABC):
    """Record the tool's path, keep recordings, and make programs of them (see the module)."""

    #: None when the backend records; otherwise why not (every request is then refused)
    absent: Optional[str] = None

    @abstractmethod
    def set_config(self, config: TrajConfig) -> Result:
        """Sampling thresholds and the replay's speed and acceleration (already checked)."""

    @abstractmethod
    def config(self) -> Result:
        """``value``: the :class:`TrajConfig` in force."""

    @abstractmethod
    def start(self, name: str) -> Result:
        """Start recording as ``name`` (refused while recording; an existing recording of that
        name is replaced when this one stops)."""

    @abstractmethod
    def stop(self) -> Result:
        """Stop recording and keep the recording (success also when none is being made)."""

    @abstractmethod
    def sampling(self) -> Result:
        """``value``: True while recording."""

    @abstractmethod
    def names(self) -> Result:
        """``value``: the names of the recordings kept, sorted."""

    @abstractmethod
    def rename(self, src: str, dest: str) -> Result:
        """Rename recording ``src`` to ``dest`` (its generated program follows it)."""

    @abstractmethod
    def remove(self, name: str) -> Result:
        """Remove recording ``name`` (and the program generated from it)."""

    @abstractmethod
    def generate(self, name: str) -> Result:
        """Write the replay program of recording ``name``, loaded as ``track/<name>``."""


class NoRecording(Recording):
    """A backend that cannot record: every request is refused with -9 and ``reason``."""

    def __init__(self, reason: str):
        self.absent = reason
        self._refusal = Result.failure(Code.WRONG_MODE, reason)

    def _refuse(self, *_args) -> Result:
        return self._refusal

    set_config = config = start = stop = sampling = names = rename = remove = generate = _refuse
