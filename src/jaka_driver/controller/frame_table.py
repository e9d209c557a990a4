"""The tool and user frames of a controller, as far as this driver knows them.

JAKA's TCP protocol can store and activate frames but not read their offsets back
(docs/protocol.md, "Frames"), so the backend keeps the offsets it has set itself. The *active* ids come
from the status stream (``current_tool_id``/``current_user_id``), which also sees a change made
on the teach pendant; an active id this driver never set has an unknown offset — the identity
is assumed and a warning is logged once per id.
"""
from __future__ import annotations

import logging
import threading
from typing import Dict, Tuple

import numpy as np

log = logging.getLogger(__name__)


class FrameTable:
    """Offsets (4x4, m) by id: tools relative to the flange, user frames relative to the base.
    Id 0 is the flange / the base itself."""

    def __init__(self):
        self._lock = threading.Lock()
        self._frames: Dict[str, Dict[int, np.ndarray]] = {"tool": {0: np.eye(4)},
                                                          "user frame": {0: np.eye(4)}}
        self._warned: set = set()

    def store(self, kind: str, frame_id: int, pose: np.ndarray) -> None:
        """``kind`` is ``"tool"`` or ``"user frame"``."""
        with self._lock:
            self._frames[kind][int(frame_id)] = np.array(pose, float)

    def active(self, tool_id: int, user_id: int) -> Tuple[np.ndarray, np.ndarray]:
        """(flange→tool, base→user) of the given active ids."""
        return self._get("tool", tool_id), self._get("user frame", user_id)

    def _get(self, kind: str, frame_id: int) -> np.ndarray:
        with self._lock:
            pose = self._frames[kind].get(int(frame_id))
            first = pose is None and (kind, frame_id) not in self._warned
            if first:
                self._warned.add((kind, frame_id))
        if pose is not None:
            return pose
        if first:
            log.warning("%s %d is active but was set outside this driver: the protocol cannot "
                        "read its offset, so the identity is assumed in conversions; set it "
                        "again with set_%s", kind, frame_id,
                        "toolframe" if kind == "tool" else "userframe")
        return np.eye(4)
