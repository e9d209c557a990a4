"""The cameras a backend offers as ``backend.cameras`` (:class:`Cameras`), never None: the
twin renders its configured cameras (jaka_driver.sim.cameras); a backend without cameras —
a controller, whose real cameras have drivers of their own — offers :class:`NoCameras`, which
refuses every request with -9 and says how to get one.

A camera is described by its :class:`~jaka_driver.common.camera_spec.CameraSpec` (where it
is, its resolution, field of view and rate); what it sees comes as frames (:class:`CameraFrame`)
to the listeners (:meth:`Cameras.listen`), only while the camera streams
(:meth:`Cameras.stream`: the node streams a camera while somebody subscribes to it).

Frames: colour ``rgb`` (h, w, 3) uint8 and ``depth`` (h, w) float32 in m along the optical
axis (z of the optical frame; NaN where nothing is seen), rendered together from one copy of
one cycle's state, stamped with that cycle's time (s: the samples' stamp — sim time when the
twin owns time).
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Callable, NamedTuple, Optional

import numpy as np

from ..common.camera_spec import CameraSpec
from ..common.results import Code, Result


class CameraFrame(NamedTuple):
    """One picture of camera ``name``: of the state of the cycle ending at ``stamp`` (s,
    the samples' clock) — cycle number ``cycle`` — whose joints were ``joints`` (rad);
    ``rgb`` (h, w, 3) uint8, ``depth`` (h, w) float32 m (NaN: nothing seen);
    ``render_time`` s of wall time its rendering took."""

    name: str
    stamp: float
    cycle: int
    joints: np.ndarray
    rgb: np.ndarray
    depth: np.ndarray
    render_time: float


class CameraStats(NamedTuple):
    """What camera ``name`` did since it was made: frames ``rendered``, frames ``dropped``
    (due while the renderer was still busy), render times (s, wall) of the recent frames."""

    name: str
    rendered: int
    dropped: int
    render_times: tuple


Listener = Callable[[CameraFrame], None]


class Cameras(ABC):
    """The cameras of a backend (see the module). Thread-safe."""

    @property
    @abstractmethod
    def absent(self) -> Optional[str]:
        """Why this backend has no camera (None: it has the cameras :meth:`specs` lists)."""

    @abstractmethod
    def specs(self) -> tuple[CameraSpec, ...]:
        """Every camera, as configured (empty without cameras)."""

    @abstractmethod
    def stream(self, name: str, on: bool) -> Result:
        """Render camera ``name`` at its rate from the next due cycle on (True) or stop (False:
        no frame of it reaches a listener once this has answered); the name already checked
        against :meth:`specs`."""

    @abstractmethod
    def listen(self, listener: Listener) -> Result:
        """Call ``listener`` with every frame of every streaming camera, from the rendering
        thread (it must be quick: the next frame waits for it)."""

    @abstractmethod
    def stats(self, name: str) -> CameraStats:
        """What camera ``name`` rendered and dropped."""


class NoCameras(Cameras):
    """A backend without cameras: every request refused with -9 and ``reason``."""

    def __init__(self, reason: str):
        self._reason = reason

    @property
    def absent(self) -> Optional[str]:
        return self._reason

    def specs(self) -> tuple[CameraSpec, ...]:
        return ()

    def stream(self, name: str, on: bool) -> Result:
        return Result.failure(Code.WRONG_MODE, self._reason)

    def listen(self, listener: Listener) -> Result:
        return Result.failure(Code.WRONG_MODE, self._reason)

    def stats(self, name: str) -> CameraStats:
        return CameraStats(name, 0, 0, ())


#: How to get a camera: the end of every "no camera" refusal.
HOW_TO_ADD = ("the twin renders cameras: run backend:=sim with a scene file's cameras: list "
              "(docs/twin.md, \"Cameras\") or wrist_camera:=true; a real cell's cameras have "
              "drivers of their own")
