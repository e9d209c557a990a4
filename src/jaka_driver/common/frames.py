"""Tool and user frames by id — the one table the twin, the emulator and the controller backend
keep.

A tool is a pose relative to the flange, a user frame a pose relative to the robot base, both
4x4 in metres. Id 0 is the flange / the base itself and cannot be stored. An id never stored
reads as the identity; whoever keeps the table decides whether that deserves a word: the
controller backend fills it from the controller's own tables (read back by id,
``controller/frames_by_id.py``) and warns once about an id they do not hold.
"""
from __future__ import annotations

import threading
from typing import Callable, Dict, Optional, Tuple

import numpy as np

TOOL = "tool"
USER_FRAME = "user frame"


def _frozen(pose) -> np.ndarray:
    """A read-only copy of ``pose`` (4x4, m): what the table keeps, so that
    :meth:`FrameTable.shared` can hand the kept array out without a copy and nobody can change
    it behind the table."""
    kept = np.array(pose, float)
    kept.setflags(write=False)
    return kept


#: the identity as kept (id 0, and what an id never stored reads as in :meth:`FrameTable.shared`)
_IDENTITY = _frozen(np.eye(4))


class FrameTable:
    """Offsets (4x4, m) by id; thread-safe. ``on_unknown(kind, frame_id)`` is called the first
    time an id that was never stored is read."""

    def __init__(self, on_unknown: Optional[Callable[[str, int], None]] = None):
        self._lock = threading.Lock()
        self._frames: Dict[str, Dict[int, np.ndarray]] = {TOOL: {0: _IDENTITY},
                                                          USER_FRAME: {0: _IDENTITY}}
        self._on_unknown = on_unknown
        self._reported: set = set()

    def store(self, kind: str, frame_id: int, pose: np.ndarray) -> None:
        """Keep ``pose`` as ``kind`` (:data:`TOOL` or :data:`USER_FRAME`) ``frame_id``; id 0
        stays the identity."""
        if int(frame_id) == 0:
            return
        with self._lock:
            self._frames[kind][int(frame_id)] = _frozen(pose)

    def get(self, kind: str, frame_id: int) -> np.ndarray:
        """The stored pose of ``kind`` ``frame_id`` (a copy), the identity if never stored."""
        return self._kept(kind, frame_id).copy()

    def _kept(self, kind: str, frame_id: int) -> np.ndarray:
        """The kept (read-only) pose of ``kind`` ``frame_id``, the identity if never stored
        (said once to ``on_unknown``)."""
        with self._lock:
            pose = self._frames[kind].get(int(frame_id))
            first = pose is None and (kind, int(frame_id)) not in self._reported
            if first:
                self._reported.add((kind, int(frame_id)))
        if pose is None:
            if first and self._on_unknown is not None:
                self._on_unknown(kind, int(frame_id))
            return _IDENTITY
        return pose

    def active(self, tool_id: int, user_id: int) -> Tuple[np.ndarray, np.ndarray]:
        """(flange→tool, base→user) of the given active ids (copies)."""
        return self.get(TOOL, tool_id), self.get(USER_FRAME, user_id)

    def shared(self, tool_id: int, user_id: int) -> Tuple[np.ndarray, np.ndarray]:
        """:meth:`active` without the copies: the kept arrays, read-only. The same array comes
        back until that frame is stored again, so a reader caching what it computed from a
        frame can tell an unchanged one by identity (the twin's state, once per request)."""
        return self._kept(TOOL, tool_id), self._kept(USER_FRAME, user_id)
